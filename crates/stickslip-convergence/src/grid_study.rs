//! Spatial convergence at the user's scale: the first onset and its peak force of three
//! contacts (fig2, the SFA contact with a 1 nm film, a second nanometre contact) on the
//! uniform grid and on the edge-graded one, N refined by doubling; a reference extrapolated in
//! N and in the tolerance; and the total (space + time) error of every (grid, N, tolerance)
//! against its cost, from which the cheapest setting for a given total error is read.
//!
//! Every run goes through the run library's driver with a null sink and stops at its first
//! event (`time.max_events = 1`): the quantities are the first onset and the peak force before
//! it, the two a first resolution choice is made on (`stickslip verify --target`).

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::Instant;
use stickslip_run::driver::{Control, NullSink};
use stickslip_run::keys::{Setting, contact, time, words::GridChoice};
use stickslip_run::{ResolvedScene, Scene};
use stickslip_studies::verify::celik;

/// One contact of the study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GridScene {
    /// Short name (`fig2`, `sfa`, `asperity`).
    pub name: String,
    /// The scene file, relative to the workspace root.
    pub file: String,
    /// The tolerance of the spatial sequences (small enough that the time error is far below
    /// the spatial one at the finest N).
    pub tolerance: f64,
    /// The target of the first onset's error at N = 200, s (the G1, G2, G4).
    pub onset_target_s: f64,
    /// The target of the peak force's relative error at N = 200 (none: not a target).
    pub f_peak_target_rel: Option<f64>,
    /// time.end for the study's runs, s (none: the scene's): long enough that the coarsest
    /// uniform grid's late first onset still falls inside.
    #[serde(default)]
    pub end_s: Option<f64>,
}

/// Levels of the study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GridSettings {
    /// The contacts.
    pub scenes: Vec<GridScene>,
    /// N of the uniform grid's sequence.
    pub uniform_nodes: Vec<usize>,
    /// N of the graded grids' sequences.
    pub graded_nodes: Vec<usize>,
    /// The graded grids' exponents.
    pub powers: Vec<f64>,
    /// Tolerances of the total-error grid (each at every N of `cost_nodes`, on the uniform grid
    /// and the graded one with the default exponent).
    pub cost_tolerances: Vec<f64>,
    /// N of the total-error grid.
    pub cost_nodes: Vec<usize>,
    /// Timing repeats per total-error point (the median is kept).
    pub repeats: usize,
}

/// The default exponent of the graded grid (the key registry's, at the study's N).
pub const DEFAULT_POWER: f64 = 3.0;

impl GridSettings {
    /// The full study.
    pub fn full() -> Self {
        Self {
            scenes: default_scenes(),
            uniform_nodes: vec![50, 100, 200, 400, 800, 1600, 3200],
            graded_nodes: vec![50, 100, 200, 400, 800, 1600],
            powers: vec![2.0, DEFAULT_POWER],
            cost_tolerances: vec![5e-4, 5e-5, 5e-6, 5e-7],
            cost_nodes: vec![50, 100, 200, 400, 800],
            repeats: 3,
        }
    }

    /// A smoke study of a few seconds.
    pub fn quick() -> Self {
        Self {
            scenes: default_scenes().into_iter().take(2).collect(),
            uniform_nodes: vec![50, 100, 200, 400],
            graded_nodes: vec![50, 100, 200, 400],
            powers: vec![DEFAULT_POWER],
            cost_tolerances: vec![5e-5, 5e-6],
            cost_nodes: vec![50, 100],
            repeats: 1,
        }
    }
}

fn default_scenes() -> Vec<GridScene> {
    vec![
        GridScene {
            name: "fig2".into(),
            file: "validation/scenes/fig2.toml".into(),
            tolerance: 5e-9,
            onset_target_s: 0.5e-9,
            f_peak_target_rel: None,
            end_s: None,
        },
        GridScene {
            name: "sfa".into(),
            file: "validation/scenes/sfa.toml".into(),
            tolerance: 5e-7,
            onset_target_s: 1e-4,
            f_peak_target_rel: Some(2e-3),
            end_s: Some(0.3),
        },
        GridScene {
            name: "asperity".into(),
            file: "validation/resolution/asperity.toml".into(),
            tolerance: 5e-7,
            onset_target_s: 1e-4,
            f_peak_target_rel: Some(2e-3),
            end_s: Some(0.3),
        },
    ]
}

/// Which grid.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GridKind {
    /// r_i = i·a0/N.
    Uniform,
    /// r_i = a0·(1 − (1 − i/N)^p).
    Graded {
        /// p.
        power: f64,
    },
}

impl GridKind {
    /// The settings that select it.
    fn overrides(self) -> Vec<Setting> {
        match self {
            Self::Uniform => vec![contact::GRID.set(GridChoice::Uniform)],
            Self::Graded { power } => vec![
                contact::GRID.set(GridChoice::Graded),
                contact::GRADING.set(power),
            ],
        }
    }

    /// As the report names it.
    pub fn label(self) -> String {
        match self {
            Self::Uniform => "uniform".into(),
            Self::Graded { power } => format!("graded p = {power}"),
        }
    }
}

/// One run to the first event.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GridRun {
    /// The scene's name.
    pub scene: String,
    /// The grid.
    pub grid: GridKind,
    /// N.
    pub nodes: usize,
    /// time.tolerance.
    pub tolerance: f64,
    /// The first onset, s (none: no event or a failure).
    pub t_onset_s: Option<f64>,
    /// The peak force before it, N.
    pub f_peak_n: Option<f64>,
    /// The radius of the first melted node, m.
    pub r_first_m: Option<f64>,
    /// Accepted steps.
    pub steps: u64,
    /// Wall seconds (the median of the repeats).
    pub wall_s: f64,
    /// Whether it belongs to the total-error grid (else to a spatial sequence).
    pub cost_point: bool,
}

/// One spatial sequence of one observable: values, observed orders, Celik's extrapolation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sequence {
    /// The scene's name.
    pub scene: String,
    /// The grid.
    pub grid: GridKind,
    /// `t_onset` or `f_peak`.
    pub observable: String,
    /// N per level.
    pub nodes: Vec<usize>,
    /// The value per level (s or N).
    pub values: Vec<f64>,
    /// Observed orders between consecutive triples (log2 of the ratio of differences), one
    /// per triple of levels.
    pub orders: Vec<Option<f64>>,
    /// Celik's extrapolation from the finest three levels.
    pub extrapolated: Option<f64>,
    /// Celik's apparent order of the finest three levels.
    pub order: Option<f64>,
    /// GCI of the finest level, in the observable's unit.
    pub gci: Option<f64>,
}

/// The converged value of one scene's observable.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Reference {
    /// The scene's name.
    pub scene: String,
    /// `t_onset` or `f_peak`.
    pub observable: String,
    /// The value: the graded grid's N extrapolation (default exponent) at the study's tightest
    /// tolerance, corrected by the tolerance extrapolation at its finest N.
    pub value: f64,
    /// Its uncertainty: the N extrapolation's GCI, the tolerance correction's GCI, and the
    /// distance to the uniform grid's extrapolation.
    pub uncertainty: f64,
    /// The uniform grid's own N extrapolation, for comparison.
    pub uniform_extrapolated: Option<f64>,
    /// The tolerance correction that was added.
    pub tolerance_correction: f64,
}

/// One target's verdict.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Target {
    /// Its name (`G1 onset`, …).
    pub name: String,
    /// What it asks.
    pub asks: String,
    /// The measured value.
    pub measured: f64,
    /// The bound.
    pub bound: f64,
    /// Whether it is met (measured plus the reference's uncertainty within the bound).
    pub met: bool,
}

/// The whole study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GridStudy {
    /// Its levels.
    pub settings: GridSettings,
    /// Every run.
    pub runs: Vec<GridRun>,
    /// Every spatial sequence.
    pub sequences: Vec<Sequence>,
    /// The references.
    pub references: Vec<Reference>,
    /// The targets' verdicts.
    pub targets: Vec<Target>,
    /// Wall seconds of the whole study.
    pub wall_s: f64,
}

/// The workspace root (two levels above this crate).
fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn scene_of(s: &GridScene, grid: GridKind, nodes: usize, tolerance: f64) -> ResolvedScene {
    let mut sets = grid.overrides();
    sets.extend([
        contact::NODES.set(nodes as i64),
        time::TOLERANCE.set(tolerance),
        time::MAX_EVENTS.set(1),
    ]);
    if let Some(end) = s.end_s {
        sets.push(time::END.set(end));
    }
    let sets: Vec<String> = sets.iter().map(ToString::to_string).collect();
    Scene::from_path(&workspace_root().join(&s.file), &sets)
        .unwrap_or_else(|e| panic!("{}: {e}", s.file))
}

/// Runs one point `repeats` times (the median wall time kept).
fn run_point(
    s: &GridScene,
    grid: GridKind,
    nodes: usize,
    tolerance: f64,
    repeats: usize,
    cost_point: bool,
) -> GridRun {
    let scene = scene_of(s, grid, nodes, tolerance);
    let mut walls = Vec::new();
    let mut last = None;
    for _ in 0..repeats.max(1) {
        let start = Instant::now();
        let outcome = stickslip_run::driver::run(&scene, &mut NullSink, &mut Control::default());
        walls.push(start.elapsed().as_secs_f64());
        last = Some(outcome);
    }
    walls.sort_by(f64::total_cmp);
    let wall_s = walls[walls.len() / 2];
    let (t_onset_s, f_peak_n, r_first_m, steps) = match last {
        Some(Ok(o)) if o.failure.is_none() => (
            o.summary.t_first_onset,
            o.summary.f_peak_first,
            o.events.first().map(|e| e.r_first_m),
            o.counts.accepted_steps,
        ),
        Some(Ok(o)) => (None, None, None, o.counts.accepted_steps),
        _ => (None, None, None, 0),
    };
    GridRun {
        scene: s.name.clone(),
        grid,
        nodes,
        tolerance,
        t_onset_s,
        f_peak_n,
        r_first_m,
        steps,
        wall_s,
        cost_point,
    }
}

/// Observed orders of consecutive triples of a doubling sequence.
fn triple_orders(values: &[f64]) -> Vec<Option<f64>> {
    values
        .windows(3)
        .map(|w| {
            let (d1, d2) = (w[1] - w[0], w[2] - w[1]);
            (d1 != 0.0 && d2 != 0.0 && d1.signum() == d2.signum()).then(|| (d1 / d2).abs().log2())
        })
        .collect()
}

fn sequence(
    scene: &str,
    grid: GridKind,
    observable: &str,
    runs: &[&GridRun],
    pick: Pick,
) -> Sequence {
    let pairs: Vec<(usize, f64)> = runs
        .iter()
        .filter_map(|r| pick(r).map(|v| (r.nodes, v)))
        .collect();
    let nodes: Vec<usize> = pairs.iter().map(|p| p.0).collect();
    let values: Vec<f64> = pairs.iter().map(|p| p.1).collect();
    let (extrapolated, order, gci) = match pairs.len() {
        n if n >= 3 => {
            let f = &pairs[n - 3..];
            let h = [
                1.0 / f[2].0 as f64,
                1.0 / f[1].0 as f64,
                1.0 / f[0].0 as f64,
            ];
            match celik::three_grid(h, [f[2].1, f[1].1, f[0].1]) {
                Ok(c) if !c.oscillatory => (Some(c.phi_ext), Some(c.p), Some(c.gci_fine_abs)),
                _ => (None, None, None),
            }
        }
        _ => (None, None, None),
    };
    Sequence {
        scene: scene.to_string(),
        grid,
        observable: observable.to_string(),
        nodes,
        orders: triple_orders(&values),
        values,
        extrapolated,
        order,
        gci,
    }
}

fn onset(r: &GridRun) -> Option<f64> {
    r.t_onset_s
}

fn f_peak(r: &GridRun) -> Option<f64> {
    r.f_peak_n
}

/// Reads one observable of a run.
pub type Pick = fn(&GridRun) -> Option<f64>;

/// The observables of the study: name and accessor.
pub const OBSERVABLES: [(&str, Pick); 2] = [("t_onset", onset), ("f_peak", f_peak)];

/// Runs the study; `log` receives a line per run.
pub fn study(settings: &GridSettings, log: &mut dyn FnMut(&str)) -> GridStudy {
    let start = Instant::now();
    let mut runs = Vec::new();
    let mut sequences = Vec::new();
    let mut references = Vec::new();
    let default = GridKind::Graded {
        power: DEFAULT_POWER,
    };
    for s in &settings.scenes {
        let mut grids = vec![(GridKind::Uniform, &settings.uniform_nodes)];
        grids.extend(
            settings
                .powers
                .iter()
                .map(|&power| (GridKind::Graded { power }, &settings.graded_nodes)),
        );
        for &(grid, levels) in &grids {
            let mut these = Vec::new();
            for &n in levels {
                let r = run_point(s, grid, n, s.tolerance, 1, false);
                log(&format!(
                    "[{:7.1} s] grid {} {} N={n} tol={:e}: onset {:?} s, {:.2} s",
                    start.elapsed().as_secs_f64(),
                    s.name,
                    grid.label(),
                    s.tolerance,
                    r.t_onset_s,
                    r.wall_s
                ));
                these.push(r);
            }
            let refs: Vec<&GridRun> = these.iter().collect();
            for (name, pick) in OBSERVABLES {
                sequences.push(sequence(&s.name, grid, name, &refs, pick));
            }
            runs.extend(these);
        }
        // The tolerance correction at the graded grid's finest N: the tolerance ×100, ×10, ×1.
        let finest = *settings.graded_nodes.last().unwrap_or(&200);
        let tol_runs: Vec<GridRun> = [100.0, 10.0]
            .into_iter()
            .map(|f| run_point(s, default, finest, s.tolerance * f, 1, false))
            .collect();
        for (name, pick) in OBSERVABLES {
            let at = |tol: f64| {
                runs.iter()
                    .chain(&tol_runs)
                    .find(|r| {
                        r.scene == s.name
                            && r.grid == default
                            && r.nodes == finest
                            && (r.tolerance / tol - 1.0).abs() < 1e-9
                    })
                    .and_then(pick)
            };
            let (Some(fine), Some(mid), Some(coarse)) = (
                at(s.tolerance),
                at(s.tolerance * 10.0),
                at(s.tolerance * 100.0),
            ) else {
                continue;
            };
            let correction = match celik::three_grid([1.0, 10.0, 100.0], [fine, mid, coarse]) {
                Ok(c) if !c.oscillatory => (c.phi_ext - fine, c.gci_fine_abs),
                _ => (0.0, (fine - mid).abs()),
            };
            let graded = sequences
                .iter()
                .find(|q| q.scene == s.name && q.grid == default && q.observable == name);
            let uniform = sequences
                .iter()
                .find(|q| q.scene == s.name && q.grid == GridKind::Uniform && q.observable == name);
            let Some(ext) = graded.and_then(|q| q.extrapolated) else {
                continue;
            };
            let uniform_extrapolated = uniform.and_then(|q| q.extrapolated);
            let value = ext + correction.0;
            let uncertainty = graded.and_then(|q| q.gci).unwrap_or(0.0)
                + correction.1
                + uniform_extrapolated.map_or(0.0, |u| (u + correction.0 - value).abs());
            references.push(Reference {
                scene: s.name.clone(),
                observable: name.to_string(),
                value,
                uncertainty,
                uniform_extrapolated,
                tolerance_correction: correction.0,
            });
        }
        runs.extend(tol_runs);
        // The total-error grid.
        for grid in [GridKind::Uniform, default] {
            for &n in &settings.cost_nodes {
                for &tol in &settings.cost_tolerances {
                    let r = run_point(s, grid, n, tol, settings.repeats, true);
                    log(&format!(
                        "[{:7.1} s] cost {} {} N={n} tol={tol:e}: {:.3} s",
                        start.elapsed().as_secs_f64(),
                        s.name,
                        grid.label(),
                        r.wall_s
                    ));
                    runs.push(r);
                }
            }
        }
    }
    let targets = targets(settings, &runs, &sequences, &references);
    GridStudy {
        settings: settings.clone(),
        runs,
        sequences,
        references,
        targets,
        wall_s: start.elapsed().as_secs_f64(),
    }
}

/// The reference of `scene`'s `observable`.
pub fn reference<'a>(
    refs: &'a [Reference],
    scene: &str,
    observable: &str,
) -> Option<&'a Reference> {
    refs.iter()
        .find(|r| r.scene == scene && r.observable == observable)
}

/// The spatial-sequence run of `scene` on `grid` at N.
pub fn sequence_run<'a>(
    runs: &'a [GridRun],
    scene: &GridScene,
    grid: GridKind,
    nodes: usize,
) -> Option<&'a GridRun> {
    runs.iter().find(|r| {
        !r.cost_point
            && r.scene == scene.name
            && r.grid == grid
            && r.nodes == nodes
            && (r.tolerance / scene.tolerance - 1.0).abs() < 1e-9
    })
}

fn targets(
    settings: &GridSettings,
    runs: &[GridRun],
    sequences: &[Sequence],
    references: &[Reference],
) -> Vec<Target> {
    let default = GridKind::Graded {
        power: DEFAULT_POWER,
    };
    let mut out = Vec::new();
    for s in &settings.scenes {
        let Some(run) = sequence_run(runs, s, default, 200) else {
            continue;
        };
        if let (Some(v), Some(rf)) = (run.t_onset_s, reference(references, &s.name, "t_onset")) {
            let measured = (v - rf.value).abs() + rf.uncertainty;
            out.push(Target {
                name: format!("{} first onset at N = 200", s.name),
                asks: format!(
                    "graded (p = {DEFAULT_POWER}) first onset within {:e} s of the converged \
                     value (the distance plus the reference's uncertainty)",
                    s.onset_target_s
                ),
                measured,
                bound: s.onset_target_s,
                met: measured <= s.onset_target_s,
            });
        }
        if let (Some(bound), Some(v), Some(rf)) = (
            s.f_peak_target_rel,
            run.f_peak_n,
            reference(references, &s.name, "f_peak"),
        ) {
            let measured = ((v - rf.value).abs() + rf.uncertainty) / rf.value.abs();
            out.push(Target {
                name: format!("{} peak force at N = 200", s.name),
                asks: format!(
                    "graded peak force within {} % of the converged value",
                    bound * 100.0
                ),
                measured,
                bound,
                met: measured <= bound,
            });
        }
        if s.name == "fig2" {
            // The onset's observed order in N around N = 200.
            if let Some(q) = sequences
                .iter()
                .find(|q| q.scene == s.name && q.grid == default && q.observable == "t_onset")
            {
                let around: Vec<f64> = q
                    .nodes
                    .windows(3)
                    .zip(&q.orders)
                    .filter(|(w, _)| w[1] == 200)
                    .filter_map(|(_, o)| *o)
                    .collect();
                if let Some(&order) = around.first() {
                    out.push(Target {
                        name: "fig2 onset's order in N".into(),
                        asks: "observed order of the first onset in N (levels 100, 200, 400) ≥ 1.8"
                            .into(),
                        measured: order,
                        bound: 1.8,
                        met: order >= 1.8,
                    });
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(nodes: usize, v: f64) -> GridRun {
        GridRun {
            scene: "s".into(),
            grid: GridKind::Uniform,
            nodes,
            tolerance: 1e-6,
            t_onset_s: Some(v),
            f_peak_n: None,
            r_first_m: None,
            steps: 0,
            wall_s: 0.0,
            cost_point: false,
        }
    }

    #[test]
    fn a_second_order_sequence_gives_order_two_and_its_limit() {
        let runs: Vec<GridRun> = [50, 100, 200, 400]
            .into_iter()
            .map(|n| run(n, 1.0 + 3.0 / (n * n) as f64))
            .collect();
        let refs: Vec<&GridRun> = runs.iter().collect();
        let q = sequence("s", GridKind::Uniform, "t_onset", &refs, onset);
        assert_eq!(q.orders.len(), 2);
        for o in &q.orders {
            assert!((o.unwrap() - 2.0).abs() < 1e-9, "{o:?}");
        }
        assert!((q.extrapolated.unwrap() - 1.0).abs() < 1e-12);
        assert!((q.order.unwrap() - 2.0).abs() < 1e-9);
        // A level without the observable is left out, not read as zero.
        let peak = sequence("s", GridKind::Uniform, "f_peak", &refs, f_peak);
        assert!(peak.values.is_empty() && peak.extrapolated.is_none());
    }

    #[test]
    fn oscillating_differences_give_no_order() {
        assert_eq!(triple_orders(&[1.0, 2.0, 1.5]), vec![None]);
        assert_eq!(triple_orders(&[1.0, 1.0, 1.5]), vec![None]);
    }
}
