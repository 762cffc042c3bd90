//! The comparison with the independent implementation (`validation/independent/independent.py`:
//! NumPy and SciPy, a spectral MDR pair and SciPy's Radau, no code shared with the crates).
//!
//! Each code is run at three resolutions of its own (the independent one's series terms M,
//! stickslip's nodes N, each doubling) and extrapolated to its converged value by Richardson's
//! rule with the observed order, with a GCI-style uncertainty (safety factor 1.25 in the
//! asymptotic range, 3 outside it) plus the time-stepping part (the middle resolution at a ten
//! times looser tolerance against the reference one: the time error hardly depends on the
//! resolution, and the independent code's finest run takes minutes). The two converged values are then
//! compared, quantity by quantity, against the targets below.
//!
//! What this module must not know: any numerics of either code. It reads the independent
//! code's events.csv (an output file of a deliberately separate program) and stickslip's
//! outputs through the run library's schema.

pub mod report;

use crate::runner::Runner;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;
use std::time::Instant;
use stickslip_run::keys::{contact, output, time};

/// The independent code, relative to the workspace root.
pub const SCRIPT: &str = "validation/independent/independent.py";
/// MDR against 3D elasticity (Cerruti's half-space), relative to the workspace root.
pub const MDR3D_SCRIPT: &str = "validation/independent/mdr3d.py";
/// The scenes of the 3D check, with the spectral code's M for their tractions; the quadrature
/// order (Gauss–Legendre points per panel; the change at half of it is reported).
pub const MDR3D_CASES: [(&str, usize); 2] = [("fig2.toml", 24), ("sfa.toml", 32)];
/// Gauss–Legendre points per panel of the 3D check.
pub const MDR3D_ORDER: usize = 96;
/// The angle-averaged 3D displacement must equal MDR's u3D within this (relative to max |u3D|):
/// averaged over the angle, Cerruti's kernel is Boussinesq's, for which MDR is exact, so only
/// the quadrature's error is allowed (measured below 1e-14 at order 96).
pub const MDR3D_MEAN_TOLERANCE: f64 = 1e-8;
/// The independent code's Radau tolerance in the comparison, and the looser one of its
/// time-stepping estimate.
pub const INDEPENDENT_RTOL: [f64; 2] = [1e-11, 1e-10];
/// stickslip's time.tolerance in the comparison, and the looser one of its time-stepping
/// estimate.
pub const OURS_TOLERANCE: [f64; 2] = [5e-8, 5e-7];

/// How a difference is judged.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", content = "value", rename_all = "snake_case")]
pub enum Target {
    /// |difference| ≤ this many seconds.
    AbsoluteS(f64),
    /// |difference| / |value| ≤ this.
    Relative(f64),
}

impl Target {
    /// Whether `difference` of a quantity of size `value` meets the target.
    #[must_use]
    pub fn met(self, difference: f64, value: f64) -> bool {
        match self {
            Self::AbsoluteS(t) => difference.abs() <= t,
            Self::Relative(t) => (difference / value).abs() <= t,
        }
    }
}

/// One scene compared: which events, at which resolutions, against which targets.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Case {
    /// Scene file name in `validation/scenes/`.
    pub scene: String,
    /// The target's name in the terms (I1, I2) or "supporting".
    pub target_name: String,
    /// Events compared (the first `events` onsets).
    pub events: usize,
    /// End time of both codes' runs, s.
    pub end_s: f64,
    /// The independent code's resolutions M (each doubling).
    pub resolutions_m: Vec<usize>,
    /// stickslip's nodes N (each doubling), on its default grid.
    pub nodes: Vec<usize>,
    /// The target for onsets.
    pub onset_target: Target,
    /// The target for f_peak.
    pub f_peak_target: Target,
}

/// The cases of the comparison.
#[must_use]
pub fn cases() -> Vec<Case> {
    let spring = |scene: &str, name: &str| Case {
        scene: scene.to_string(),
        target_name: name.to_string(),
        events: 3,
        end_s: 1e-3,
        resolutions_m: vec![8, 16, 32],
        nodes: vec![1000, 2000, 4000],
        onset_target: Target::AbsoluteS(2e-9),
        f_peak_target: Target::Relative(1e-5),
    };
    vec![
        spring("fig2.toml", "I1"),
        Case {
            end_s: 6e-4,
            ..spring("rigid.toml", "supporting (I1's targets)")
        },
        spring("fig4.toml", "supporting (I1's targets)"),
        Case {
            scene: "sfa.toml".to_string(),
            target_name: "I2".to_string(),
            events: 1,
            end_s: 0.11,
            resolutions_m: vec![16, 32, 64],
            nodes: vec![200, 400, 800],
            onset_target: Target::Relative(1e-4),
            f_peak_target: Target::Relative(1e-4),
        },
    ]
}

/// One code's value of one quantity at each resolution, and its extrapolation.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Convergence {
    /// (resolution, value) at the reference tolerance, resolution rising.
    pub values: Vec<(usize, f64)>,
    /// The middle resolution's value at the looser tolerance.
    pub loose: f64,
    /// Observed order in the resolution (None outside the asymptotic range).
    pub order: Option<f64>,
    /// The converged value (Richardson with the observed order, else the finest value).
    pub value: f64,
    /// Its spatial uncertainty (GCI: 1.25 or 3 times the Richardson error estimate).
    pub spatial: f64,
    /// Its time-stepping uncertainty (middle resolution, looser against reference tolerance).
    pub time: f64,
}

impl Convergence {
    /// Extrapolates `values` (three, resolution doubling) and adds the time part: `loose` is
    /// the middle resolution's value at the looser tolerance.
    #[must_use]
    pub fn of(values: Vec<(usize, f64)>, loose: f64) -> Self {
        let n = values.len();
        let finest = values[n - 1].1;
        let time = (loose - values[n.saturating_sub(2)].1).abs();
        let (order, value, spatial) = if n >= 3 {
            let (v1, v2, v3) = (values[n - 3].1, values[n - 2].1, values[n - 1].1);
            let ratio = values[n - 1].0 as f64 / values[n - 2].0 as f64;
            let (d1, d2) = (v2 - v1, v3 - v2);
            if d2 == 0.0 {
                (None, finest, 0.0)
            } else if d1 * d2 > 0.0 && d2.abs() < d1.abs() {
                let p = (d1 / d2).abs().ln() / ratio.ln();
                let correction = d2 / (ratio.powf(p) - 1.0);
                (Some(p), finest + correction, 1.25 * correction.abs())
            } else {
                (None, finest, 3.0 * d2.abs())
            }
        } else {
            (None, finest, f64::NAN)
        };
        Self {
            values,
            loose,
            order,
            value,
            spatial,
            time,
        }
    }

    /// Spatial and time uncertainty together.
    #[must_use]
    pub fn uncertainty(&self) -> f64 {
        self.spatial + self.time
    }
}

/// One quantity of one event compared.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Quantity {
    /// Event number (1-based).
    pub k: usize,
    /// "t_onset" (s) or "f_peak" (N).
    pub name: String,
    /// The independent code.
    pub independent: Convergence,
    /// stickslip.
    pub stickslip: Convergence,
    /// stickslip's converged value less the independent one's.
    pub difference: f64,
    /// The target.
    pub target: Target,
    /// Whether the difference meets the target.
    pub agrees: bool,
    /// Whether the difference lies within the two uncertainties together.
    pub consistent: bool,
}

/// One case's result.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CaseResult {
    /// The case.
    pub case: Case,
    /// Its quantities, or why the comparison could not be made.
    pub quantities: Result<Vec<Quantity>, String>,
}

/// One row of `mdr3d.py`'s output: one moment and one Poisson's ratio.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Mdr3dRow {
    /// "onset" (the first onset) or "peak" (the largest F before it).
    pub moment: String,
    /// Its time, s.
    pub t_s: f64,
    /// Poisson's ratio ν.
    pub nu: f64,
    /// Largest |angle-averaged 3D displacement − MDR's u3D| / max |u3D| over the radii.
    pub mean_rel_diff: f64,
    /// Its change at half the quadrature order.
    pub mean_rel_diff_change: f64,
    /// The cos 2θ part of the 3D displacement at the edge over h0: ± this strain about MDR's.
    pub delta_eps_edge: f64,
    /// Its change at half the quadrature order.
    pub delta_eps_edge_change: f64,
    /// `delta_eps_edge` / εc.
    pub delta_eps_over_eps_c: f64,
}

/// The 3D check of one scene.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Mdr3d {
    /// Scene file name in `validation/scenes/`.
    pub scene: String,
    /// The spectral code's M for the traction.
    pub resolution_m: usize,
    /// Its rows, or why there are none.
    pub rows: Result<Vec<Mdr3dRow>, String>,
}

/// The whole comparison: what `reports/independent.json` holds.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Comparison {
    /// The commit it was generated at.
    pub commit: Option<stickslip_report::provenance::Commit>,
    /// The Python interpreter's version line.
    pub python: String,
    /// The cases.
    pub cases: Vec<CaseResult>,
    /// MDR against 3D elasticity.
    pub mdr3d: Vec<Mdr3d>,
}

impl Comparison {
    /// Every quantity of every case meets its target, and every 3D check ran with its
    /// angle-averaged displacement equal to MDR's within [`MDR3D_MEAN_TOLERANCE`].
    #[must_use]
    pub fn all_agree(&self) -> bool {
        self.cases.iter().all(|c| {
            c.quantities
                .as_ref()
                .is_ok_and(|q| q.iter().all(|q| q.agrees))
        }) && self.mdr3d.iter().all(|m| {
            m.rows
                .as_ref()
                .is_ok_and(|rows| rows.iter().all(|r| r.mean_rel_diff <= MDR3D_MEAN_TOLERANCE))
        })
    }
}

/// One event as both codes give it.
#[derive(Debug, Clone, Copy)]
struct EventValues {
    t_onset_s: f64,
    f_peak_n: f64,
}

/// What one run of either code gave.
type RunValues = Result<Vec<EventValues>, String>;

/// Reads mdr3d.py's mdr3d.csv.
fn read_mdr3d(path: &Path) -> Result<Vec<Mdr3dRow>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let cells: BTreeMap<&str, &str> = header.iter().copied().zip(l.split(',')).collect();
            let num = |name: &str| {
                cells
                    .get(name)
                    .and_then(|c| c.parse::<f64>().ok())
                    .ok_or_else(|| format!("{}: no number {name} in `{l}`", path.display()))
            };
            Ok(Mdr3dRow {
                moment: (*cells.get("moment").ok_or("no moment")?).to_string(),
                t_s: num("t")?,
                nu: num("nu")?,
                mean_rel_diff: num("mean_rel_diff")?,
                mean_rel_diff_change: num("mean_rel_diff_change")?,
                delta_eps_edge: num("delta_eps_edge")?,
                delta_eps_edge_change: num("delta_eps_edge_change")?,
                delta_eps_over_eps_c: num("delta_eps_over_eps_c")?,
            })
        })
        .collect()
}

/// Runs mdr3d.py on `scene` with the spectral code's `m`.
fn run_mdr3d(python: &Path, root: &Path, out_root: &Path, scene: &str, m: usize) -> Mdr3d {
    let dir = out_root.join(format!("mdr3d_{}", scene.trim_end_matches(".toml")));
    let rows = Command::new(python)
        .arg(root.join(MDR3D_SCRIPT))
        .arg(root.join("validation").join("scenes").join(scene))
        .args(["--resolution", &m.to_string()])
        .args(["--order", &MDR3D_ORDER.to_string()])
        .arg("--out")
        .arg(&dir)
        .output()
        .map_err(|e| format!("cannot start {}: {e}", python.display()))
        .and_then(|out| {
            if out.status.success() {
                read_mdr3d(&dir.join("mdr3d.csv"))
            } else {
                Err(format!(
                    "mdr3d.py on {scene}: {} ({})",
                    String::from_utf8_lossy(&out.stderr).trim(),
                    out.status
                ))
            }
        });
    Mdr3d {
        scene: scene.to_string(),
        resolution_m: m,
        rows,
    }
}

/// Reads the independent code's events.csv (header k,t_onset,f_peak,…).
fn read_independent(path: &Path) -> RunValues {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .ok_or_else(|| format!("{}: no column {name}", path.display()))
    };
    let (ti, fi) = (col("t_onset")?, col("f_peak")?);
    lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            let num = |i: usize| {
                cells
                    .get(i)
                    .and_then(|c| c.parse::<f64>().ok())
                    .ok_or_else(|| format!("{}: bad row `{l}`", path.display()))
            };
            Ok(EventValues {
                t_onset_s: num(ti)?,
                f_peak_n: num(fi)?,
            })
        })
        .collect()
}

/// The Python interpreter's version, or why it cannot run the independent code.
///
/// # Errors
/// The interpreter does not start, or lacks NumPy or SciPy.
pub fn check_python(python: &Path) -> Result<String, String> {
    let out = Command::new(python)
        .args([
            "-c",
            "import sys, numpy, scipy; print(sys.version.split()[0], 'numpy', numpy.__version__, \
             'scipy', scipy.__version__)",
        ])
        .output()
        .map_err(|e| format!("cannot start {}: {e}", python.display()))?;
    if !out.status.success() {
        return Err(format!(
            "{} cannot import numpy and scipy: {}",
            python.display(),
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    Ok(format!(
        "Python {}",
        String::from_utf8_lossy(&out.stdout).trim()
    ))
}

/// A run of either code, queued.
#[derive(Debug, Clone)]
enum Job {
    Independent {
        case: usize,
        m: usize,
        rtol: f64,
    },
    Ours {
        case: usize,
        n: usize,
        tolerance: f64,
    },
    Mdr3d {
        which: usize,
    },
}

impl Job {
    /// The run of case `case` by the independent code (`independent`) or stickslip, at
    /// resolution `r` (M or N), at the reference tolerance or (`loose`) the looser one.
    fn of(case: usize, independent: bool, r: usize, loose: bool) -> Self {
        let k = usize::from(loose);
        if independent {
            Self::Independent {
                case,
                m: r,
                rtol: INDEPENDENT_RTOL[k],
            }
        } else {
            Self::Ours {
                case,
                n: r,
                tolerance: OURS_TOLERANCE[k],
            }
        }
    }

    fn label(&self, cases: &[Case]) -> String {
        match self {
            Self::Independent { case, m, rtol } => {
                format!("independent_{}_m{m}_rtol{rtol:e}", stem(&cases[*case]))
            }
            Self::Ours { case, n, tolerance } => {
                format!("stickslip_{}_n{n}_tol{tolerance:e}", stem(&cases[*case]))
            }
            Self::Mdr3d { which } => format!("mdr3d_{}", MDR3D_CASES[*which].0),
        }
    }
}

fn stem(case: &Case) -> &str {
    case.scene.trim_end_matches(".toml")
}

/// Runs the comparison: every case's runs, `jobs` at a time, outputs under
/// `target/validation/independent/`.
///
/// # Errors
/// The Python interpreter cannot run the independent code.
pub fn compare(runner: &Runner, python: &Path, jobs: usize) -> Result<Comparison, String> {
    let python_version = check_python(python)?;
    let root = runner.root().to_path_buf();
    let cases = cases();
    // The longest jobs first, so that the two workers finish together: the 3D check's
    // quadratures, then the cases from the h0 = 1 nm contact (whose finest spectral run takes
    // minutes) back, each code's finest resolution first.
    let mut queue: Vec<Job> = (0..MDR3D_CASES.len())
        .rev()
        .map(|which| Job::Mdr3d { which })
        .collect();
    for (i, c) in cases.iter().enumerate().rev() {
        for (independent, levels) in [(true, &c.resolutions_m), (false, &c.nodes)] {
            for (j, &r) in levels.iter().enumerate().rev() {
                queue.push(Job::of(i, independent, r, false));
                if j + 2 == levels.len() {
                    queue.push(Job::of(i, independent, r, true));
                }
            }
        }
    }
    let total = queue.len();
    let queue = Mutex::new(queue.into_iter().rev().collect::<Vec<_>>());
    let results: Mutex<BTreeMap<String, (RunValues, f64)>> = Mutex::new(BTreeMap::new());
    let mdr3d: Mutex<BTreeMap<usize, Mdr3d>> = Mutex::new(BTreeMap::new());
    let out_root = runner.out_root().join("independent");
    std::thread::scope(|scope| {
        for _ in 0..jobs.max(1) {
            scope.spawn(|| {
                loop {
                    let Some(job) = queue.lock().expect("queue lock").pop() else {
                        break;
                    };
                    let label = job.label(&cases);
                    let started = Instant::now();
                    if let Job::Mdr3d { which } = job {
                        let (scene, m) = MDR3D_CASES[which];
                        let r = run_mdr3d(python, &root, &out_root, scene, m);
                        mdr3d.lock().expect("mdr3d lock").insert(which, r);
                    } else {
                        let values = run_job(&job, &cases, runner, python, &root, &out_root);
                        let wall = started.elapsed().as_secs_f64();
                        results
                            .lock()
                            .expect("results lock")
                            .insert(label.clone(), (values, wall));
                    }
                    let left = queue.lock().expect("queue lock").len();
                    println!(
                        "validate: independent comparison [{} left of {total}] {label} ({:.0} s)",
                        left,
                        started.elapsed().as_secs_f64()
                    );
                }
            });
        }
    });
    let results = results.into_inner().map_err(|e| e.to_string())?;
    let case_results = cases
        .iter()
        .enumerate()
        .map(|(i, c)| assemble(i, c, &cases, &results))
        .collect();
    Ok(Comparison {
        commit: stickslip_report::provenance::Commit::of(&root),
        python: python_version,
        cases: case_results,
        mdr3d: mdr3d
            .into_inner()
            .map_err(|e| e.to_string())?
            .into_values()
            .collect(),
    })
}

fn run_job(
    job: &Job,
    cases: &[Case],
    runner: &Runner,
    python: &Path,
    root: &Path,
    out_root: &Path,
) -> RunValues {
    let label = job.label(cases);
    match *job {
        Job::Mdr3d { .. } => Err(format!("{label}: not a run of either code")),
        Job::Independent { case, m, rtol } => {
            let c = &cases[case];
            let dir: PathBuf = out_root.join(&label);
            let out = Command::new(python)
                .arg(root.join(SCRIPT))
                .arg(root.join("validation").join("scenes").join(&c.scene))
                .args(["--end", &format!("{:e}", c.end_s)])
                .args(["--events", &c.events.to_string()])
                .args(["--resolution", &m.to_string()])
                .args(["--rtol", &format!("{rtol:e}")])
                .arg("--out")
                .arg(&dir)
                .output()
                .map_err(|e| format!("{label}: cannot start {}: {e}", python.display()))?;
            if !out.status.success() {
                return Err(format!(
                    "{label}: {} ({})",
                    String::from_utf8_lossy(&out.stderr).trim(),
                    out.status
                ));
            }
            read_independent(&dir.join("events.csv"))
        }
        Job::Ours { case, n, tolerance } => {
            let c = &cases[case];
            let scene = root.join("validation").join("scenes").join(&c.scene);
            let sets: Vec<String> = [
                contact::NODES.set(n as i64),
                time::TOLERANCE.set(tolerance),
                time::MAX_EVENTS.set(c.events as i64),
                time::END.set(c.end_s),
                output::PROFILE_TIMES.set(Vec::new()),
                output::PROBE_RADII.set(Vec::new()),
                output::SERIES_INTERVAL.set(c.end_s / 100.0),
            ]
            .iter()
            .map(ToString::to_string)
            .collect();
            let attempt = runner.run(&format!("independent/{label}"), &scene, &sets);
            let out = attempt.result()?;
            Ok(out
                .events
                .events()
                .iter()
                .map(|e| EventValues {
                    t_onset_s: e.t_onset_s,
                    f_peak_n: e.f_peak_n,
                })
                .collect())
        }
    }
}

fn assemble(
    i: usize,
    c: &Case,
    cases: &[Case],
    results: &BTreeMap<String, (RunValues, f64)>,
) -> CaseResult {
    let get = |job: Job| -> Result<Vec<EventValues>, String> {
        let label = job.label(cases);
        match results.get(&label) {
            Some((Ok(v), _)) if v.len() >= c.events => Ok(v.clone()),
            Some((Ok(v), _)) => Err(format!(
                "{label}: {} of {} events before t = {} s",
                v.len(),
                c.events,
                c.end_s
            )),
            Some((Err(e), _)) => Err(e.clone()),
            None => Err(format!("{label}: not run")),
        }
    };
    let quantities = (|| {
        // One code's runs at each level, and the middle level's at the looser tolerance.
        let levels = |independent: bool, levels: &[usize]| -> Result<_, String> {
            let runs: Vec<(usize, Vec<EventValues>)> = levels
                .iter()
                .map(|&r| get(Job::of(i, independent, r, false)).map(|v| (r, v)))
                .collect::<Result<_, _>>()?;
            let middle = levels
                .len()
                .checked_sub(2)
                .map(|j| levels[j])
                .ok_or("too few resolutions")?;
            Ok((runs, get(Job::of(i, independent, middle, true))?))
        };
        let (theirs, theirs_loose) = levels(true, &c.resolutions_m)?;
        let (ours, ours_loose) = levels(false, &c.nodes)?;
        let mut out = Vec::new();
        for k in 0..c.events {
            for (name, pick, target) in [
                (
                    "t_onset",
                    (|e: &EventValues| e.t_onset_s) as fn(&EventValues) -> f64,
                    c.onset_target,
                ),
                ("f_peak", |e: &EventValues| e.f_peak_n, c.f_peak_target),
            ] {
                let series = |runs: &[(usize, Vec<EventValues>)]| {
                    runs.iter().map(|(r, v)| (*r, pick(&v[k]))).collect()
                };
                let independent = Convergence::of(series(&theirs), pick(&theirs_loose[k]));
                let stickslip = Convergence::of(series(&ours), pick(&ours_loose[k]));
                let difference = stickslip.value - independent.value;
                out.push(Quantity {
                    k: k + 1,
                    name: name.to_string(),
                    agrees: target.met(difference, independent.value),
                    consistent: difference.abs()
                        <= independent.uncertainty() + stickslip.uncertainty(),
                    independent,
                    stickslip,
                    difference,
                    target,
                });
            }
        }
        Ok(out)
    })();
    CaseResult {
        case: c.clone(),
        quantities,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn richardson_recovers_a_known_limit_and_order() {
        // v(N) = 1 + 3/N²: order 2, limit 1.
        let v = |n: usize| 1.0 + 3.0 / (n * n) as f64;
        let c = Convergence::of(vec![(10, v(10)), (20, v(20)), (40, v(40))], v(20) + 1e-9);
        assert!((c.order.unwrap() - 2.0).abs() < 1e-9);
        assert!((c.value - 1.0).abs() < 1e-12);
        assert!((c.time - 1e-9).abs() < 1e-15);
        // An oscillating sequence is outside the asymptotic range: the finest value, 3 × Δ.
        let c = Convergence::of(vec![(10, 1.0), (20, 1.1), (40, 1.05)], 1.05);
        assert!(c.order.is_none());
        assert_eq!(c.value, 1.05);
        assert!((c.spatial - 0.15).abs() < 1e-12);
    }

    #[test]
    fn targets_judge_absolute_and_relative_differences() {
        assert!(Target::AbsoluteS(2e-9).met(1.9e-9, 6e-4));
        assert!(!Target::AbsoluteS(2e-9).met(-2.1e-9, 6e-4));
        assert!(Target::Relative(1e-4).met(9e-6, 0.1));
        assert!(!Target::Relative(1e-4).met(1.1e-5, 0.1));
    }

    #[test]
    fn the_independent_codes_events_csv_is_read_by_its_header() {
        let dir = std::env::temp_dir().join(format!("stickslip-indep-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("events.csv");
        std::fs::write(
            &path,
            "k,t_onset,f_peak,r_first,t_end\n1,0.5,2.0,1e-5,nan\n",
        )
        .unwrap();
        let v = read_independent(&path).unwrap();
        assert_eq!(v.len(), 1);
        assert_eq!((v[0].t_onset_s, v[0].f_peak_n), (0.5, 2.0));
        std::fs::write(&path, "k,t_onset\n1,0.5\n").unwrap();
        assert!(
            read_independent(&path)
                .unwrap_err()
                .contains("no column f_peak")
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
