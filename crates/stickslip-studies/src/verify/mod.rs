//! The error of every summary number of a scene (`stickslip verify`): the scene runs at its
//! own settings and at refined ones, space (N, 2N, 4N) and time (the tolerance, /10, /100; or
//! Δt, Δt/2, Δt/4 for fixed steps) apart, and each quantity gets its value, extrapolated value,
//! observed and theoretical orders, an uncertainty ([`estimate`]), whether the levels are in
//! the asymptotic range, whether a discrete quantity (event count, regime) changed between
//! levels, and a verdict against a relative accuracy.
//!
//! This module holds the levels, the quantities and the verdicts; the command line and Python
//! print and write what it returns.

pub mod celik;
pub mod estimate;
pub mod levels;
pub mod target;

use estimate::Estimate;
use levels::LevelResult;
use serde::{Deserialize, Deserializer, Serialize};
use stickslip_core::config::{ContactModel, Scheme};
use stickslip_run::driver::{Control, NullSink, StartError};
use stickslip_run::keys::{contact, time};
use stickslip_run::scene::{ResolvedScene, SceneError};
use stickslip_run::summary::RunSummary;

/// Onsets reported one by one, at most (the rest are summarised by the last period).
pub const MAX_ONSETS: usize = 10;
/// Refinement ratio of the tolerance between time levels.
pub const TOLERANCE_RATIO: f64 = 10.0;
/// Order in the tolerance of the adaptive stepping's global error: a local error per step of
/// the order of the tolerance in a second-order step gives a global one of order tol^(2/3).
pub const ADAPTIVE_ORDER: f64 = 2.0 / 3.0;
/// Order of the accurate scheme in Δt, and of the forces in the node spacing a0/N.
pub const SCHEME_ORDER: f64 = 2.0;
/// Order of event times (onsets, periods, the stamp's advance) in the node spacing on the
/// uniform grid: the first node to melt is the outermost, r = a0 − a0/N, which moves with N,
/// and near the edge u3D varies like (a0 − r)·ln(a0 − r) (the convergence report measures
/// 0.87–0.89). On the edge-graded grid the outermost node is a0·N^(−p) from the edge and event
/// times are second order like the forces (reports/convergence.md, section 8).
pub const EVENT_TIME_SPACE_ORDER: f64 = 1.0;

/// The theoretical order in 1/N of the quantity `name` on the uniform grid, or the graded one.
pub(crate) fn space_order(name: &str, graded: bool) -> f64 {
    let event_time = name.starts_with("onset_")
        || matches!(name, "t_first_onset" | "period_last" | "x_period_last");
    if event_time && !graded {
        EVENT_TIME_SPACE_ORDER
    } else {
        SCHEME_ORDER
    }
}

/// What is refined.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    /// The nodes: N, 2N, 4N.
    Space,
    /// The time stepping: tolerance /10, /100, or Δt /2, /4.
    Time,
}

/// One run of the refinement.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Level {
    /// What it refines (the scene's own run is the first of each axis).
    pub axis: Axis,
    /// Nodes.
    pub nodes: usize,
    /// The adaptive tolerance, or none with fixed steps.
    pub tolerance: Option<f64>,
    /// The fixed step, s (with fixed steps).
    pub dt_s: Option<f64>,
    /// Steps taken.
    pub steps: u64,
    /// Wall time, s.
    pub wall_s: f64,
    /// The run's status (`ok`, `failed`).
    pub status: String,
}

/// Verdict of one quantity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// The uncertainty is within the requested relative accuracy.
    Within,
    /// Converged (asymptotic levels) but the uncertainty exceeds the requested accuracy.
    Outside,
    /// The levels are not in the asymptotic range and the cautious bound exceeds the
    /// requested accuracy: no small number can be given.
    NotConverged,
    /// A discrete quantity differs between levels.
    Changed,
}

/// One quantity's error.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Quantity {
    /// Its name (`t_first_onset`, `onset_3`, `n_events`, `regime`, …).
    pub name: String,
    /// Its unit.
    pub unit: String,
    /// The value at the scene's own settings (for `regime`, 0; see `text`).
    pub value: f64,
    /// A discrete quantity's value as text (`regime`: its name).
    pub text: Option<String>,
    /// Extrapolated value: the scene's value corrected by both refinements' extrapolations.
    pub extrapolated: Option<f64>,
    /// Uncertainty of `value` (space and time added), in its unit; infinite for a quantity a
    /// level did not have (written as null in verify.json, read back as infinite).
    #[serde(deserialize_with = "infinite_if_null")]
    pub uncertainty: f64,
    /// The spatial refinement's estimate (none for one node).
    pub space: Option<Estimate>,
    /// The temporal refinement's estimate.
    pub time: Option<Estimate>,
    /// Whether every refinement is in the asymptotic range.
    pub asymptotic: bool,
    /// A discrete quantity that differs between the levels.
    pub changed: bool,
    /// The verdict against `rtol`.
    pub verdict: Verdict,
    /// Its value at each level, in the order of [`VerifyReport::levels`] (none where that run
    /// did not have it or failed, and for the regime; the event count as a number).
    pub values: Vec<Option<f64>>,
}

/// A number that verify.json may hold as null (JSON has no infinity: serde_json writes a
/// non-finite number as null): null reads back as infinite.
fn infinite_if_null<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::INFINITY))
}

/// What `verify` found (verify.json: written by the command line with serde, and read back
/// through this type).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct VerifyReport {
    /// The scene's name.
    pub scene: String,
    /// The requested relative accuracy.
    pub rtol: f64,
    /// Every quantity.
    pub quantities: Vec<Quantity>,
    /// The runs made, the scene's own first.
    pub levels: Vec<Level>,
}

impl VerifyReport {
    /// Whether every quantity is within `rtol`.
    #[must_use]
    pub fn all_within(&self) -> bool {
        self.quantities.iter().all(|q| q.verdict == Verdict::Within)
    }
}

/// Why verify could not run.
#[derive(Debug, thiserror::Error)]
pub enum VerifyError {
    /// A bad option.
    #[error("{option} = {value} is invalid; allowed: {allowed}")]
    Option {
        /// The option.
        option: &'static str,
        /// Its value.
        value: String,
        /// What is allowed.
        allowed: &'static str,
    },
    /// A refined scene that does not resolve (e.g. 4N beyond the node limit).
    #[error("the refined scene ({what}) is invalid: {error}")]
    Scene {
        /// Which refinement.
        what: String,
        /// Why.
        error: Box<SceneError>,
    },
    /// The scene's own run failed numerically: there is nothing to verify.
    #[error(
        "the scene's own run failed numerically ({what}): {reason}; verify needs a run that \
         finishes (`stickslip run` shows where it fails)"
    )]
    Failed {
        /// Which run.
        what: String,
        /// The failure, as the run reports it.
        reason: String,
    },
    /// Interrupted (Ctrl-C, SIGTERM): the levels that ended are kept when the verify has an
    /// output directory.
    #[error(
        "interrupted with {finished} of {levels} level runs finished{}",
        match kept {
            Some(dir) => format!(
                "; they are kept in {0}: the same command with --out {0} runs only the rest",
                dir.display()
            ),
            None => String::new(),
        }
    )]
    Interrupted {
        /// Level runs that had ended.
        finished: usize,
        /// Level runs in all.
        levels: usize,
        /// Where they are kept.
        kept: Option<std::path::PathBuf>,
    },
    /// A run that could not start.
    #[error("a run could not start ({what}): {error}")]
    Start {
        /// Which run.
        what: String,
        /// Why.
        error: Box<StartError>,
    },
}

/// The scenes of the refinements: the scene's own first, then space (2N, 4N; none for one
/// node) and time (finer tolerances, or halved fixed steps).
///
/// # Errors
/// [`VerifyError::Scene`] when a refined scene does not resolve.
pub fn level_scenes(scene: &ResolvedScene) -> Result<Vec<(Axis, ResolvedScene)>, VerifyError> {
    let mut out = vec![(Axis::Space, scene.clone())];
    out.extend(refined_levels(scene, 2)?);
    Ok(out)
}

/// The first refinement along each axis: 2N (radial contacts only), then a tenth of the
/// tolerance (or half the fixed step). What `boundary` and a sweep's spot checks rerun.
///
/// # Errors
/// As [`level_scenes`].
pub fn refinements(scene: &ResolvedScene) -> Result<Vec<(Axis, ResolvedScene)>, VerifyError> {
    refined_levels(scene, 1)
}

/// The first `depth` refinements along space, then along time (only what is resolved is
/// asked for: a spot check resolves two scenes, not four).
fn refined_levels(
    scene: &ResolvedScene,
    depth: i32,
) -> Result<Vec<(Axis, ResolvedScene)>, VerifyError> {
    let c = &scene.config;
    let with = |what: String, settings: Vec<stickslip_run::keys::Setting>| {
        scene
            .with_settings(&settings)
            .map_err(|error| VerifyError::Scene {
                what,
                error: Box::new(error),
            })
    };
    let mut out = Vec::new();
    if c.contact.model == ContactModel::Radial {
        for k in 1..=depth {
            let n = c.contact.nodes << k;
            out.push((
                Axis::Space,
                with(format!("N = {n}"), vec![contact::NODES.set(n as i64)])?,
            ));
        }
    }
    for k in 1..=depth {
        let (what, settings) = match c.time.adaptive {
            Some(a) => {
                let tol = a.tolerance / TOLERANCE_RATIO.powi(k);
                (
                    format!("time.tolerance = {tol:e}"),
                    vec![time::TOLERANCE.set(tol)],
                )
            }
            None => {
                let dt = c.time.dt_s / 2f64.powi(k);
                (format!("time.dt = {dt:e}"), vec![time::DT.set(dt)])
            }
        };
        out.push((Axis::Time, with(what, settings)?));
    }
    Ok(out)
}

/// A quantity's values in one run: continuous ones as numbers, discrete ones as text.
#[derive(Debug, Clone, PartialEq)]
enum Value {
    Number(f64),
    Text(String),
}

/// The continuous quantities of a run by name, with their units, from its summary and its
/// onsets (the first [`MAX_ONSETS`]): the names and values verify reports, so that a run read
/// back from its files (run.json's summary, events.csv) gives the numbers verify compares.
#[must_use]
pub fn numbers(s: &RunSummary, onsets_s: &[f64]) -> Vec<(String, &'static str, Option<f64>)> {
    let mut out = vec![
        ("t_first_onset".to_string(), "s", s.t_first_onset),
        ("period_last".to_string(), "s", s.period_last),
        ("x_period_last".to_string(), "m", s.x_period_last),
        ("f_peak_first".to_string(), "N", s.f_peak_first),
        ("f_peak_last".to_string(), "N", s.f_peak_last),
        ("f_mean".to_string(), "N", s.f_mean),
        ("recovery".to_string(), "–", s.recovery),
        ("energy_per_cycle".to_string(), "J", s.energy_per_cycle),
    ];
    for (k, t) in onsets_s.iter().take(MAX_ONSETS).enumerate() {
        out.push((format!("onset_{}", k + 1), "s", Some(*t)));
    }
    out
}

/// The quantities of a run, by name, with their units: the discrete ones (event count,
/// regime) and [`numbers`].
fn quantities(o: &LevelResult) -> Vec<(String, &'static str, Option<Value>)> {
    let s = &o.summary;
    let mut out = vec![
        (
            "n_events".to_string(),
            "–",
            Some(Value::Text(s.n_events.to_string())),
        ),
        (
            "regime".to_string(),
            "–",
            Some(Value::Text(s.regime.name().to_string())),
        ),
    ];
    out.extend(
        numbers(s, &o.onsets_s)
            .into_iter()
            .map(|(name, unit, v)| (name, unit, v.map(Value::Number))),
    );
    out
}

/// The spacing of a level along its axis: a0/N in space; the tolerance, or Δt, in time.
fn spacing(axis: Axis, scene: &ResolvedScene) -> f64 {
    match axis {
        Axis::Space => 1.0 / scene.config.contact.nodes as f64,
        Axis::Time => scene
            .config
            .time
            .adaptive
            .map_or(scene.config.time.dt_s, |a| a.tolerance),
    }
}

/// Runs every level (`jobs` at a time) and estimates every quantity's error against `rtol`.
///
/// # Errors
/// A bad option, a refined scene that does not resolve, or a run that cannot start.
pub fn verify(scene: &ResolvedScene, rtol: f64, jobs: usize) -> Result<VerifyReport, VerifyError> {
    check_rtol(rtol)?;
    verify_levels(scene, &level_scenes(scene)?, rtol, jobs)
}

fn check_rtol(rtol: f64) -> Result<(), VerifyError> {
    if rtol.is_finite() && rtol > 0.0 && rtol < 1.0 {
        Ok(())
    } else {
        Err(VerifyError::Option {
            option: "rtol",
            value: stickslip_run::keys::human(rtol),
            allowed: "finite, > 0 and < 1 (a relative accuracy)",
        })
    }
}

/// As [`verify`], with the levels of [`level_scenes`] already resolved (a caller that has
/// them, e.g. to state their cost first, need not resolve them again).
///
/// # Errors
/// As [`verify`].
pub fn verify_levels(
    scene: &ResolvedScene,
    scenes: &[(Axis, ResolvedScene)],
    rtol: f64,
    jobs: usize,
) -> Result<VerifyReport, VerifyError> {
    verify_kept(scene, scenes, rtol, jobs, Keep::default())
}

/// Where a verify keeps its finished levels and what interrupts it.
#[derive(Clone, Copy, Default)]
pub struct Keep<'a> {
    /// The output directory: finished levels are kept under it ([`levels`]) and reused.
    pub dir: Option<&'a std::path::Path>,
    /// Set by Ctrl-C or SIGTERM: the runs stop, the finished levels stay kept.
    pub interrupt: Option<&'a std::sync::atomic::AtomicBool>,
    /// Called with (level, reused) as each level's result is known.
    pub on_level: Option<&'a (dyn Fn(usize, bool) + Sync)>,
}

/// As [`verify_levels`], keeping each finished level under `keep.dir` as it ends, reusing
/// those kept by an earlier, interrupted verify of the same scene, and stopping on
/// `keep.interrupt`.
///
/// # Errors
/// As [`verify`]; [`VerifyError::Interrupted`] when interrupted.
pub fn verify_kept(
    scene: &ResolvedScene,
    scenes: &[(Axis, ResolvedScene)],
    rtol: f64,
    jobs: usize,
    keep: Keep<'_>,
) -> Result<VerifyReport, VerifyError> {
    check_rtol(rtol)?;
    let results = run_all(scenes, jobs.max(1), keep)?;
    report_of(scene, scenes, &results, rtol)
}

/// The report from the levels' outcomes. A refined level that failed numerically has none of
/// the quantities (each is then "changed", its uncertainty infinite): a failed run's "no
/// events" is no value.
///
/// # Errors
/// [`VerifyError::Failed`] when the scene's own run failed.
fn report_of(
    scene: &ResolvedScene,
    scenes: &[(Axis, ResolvedScene)],
    outcomes: &[LevelResult],
    rtol: f64,
) -> Result<VerifyReport, VerifyError> {
    if let Some(f) = outcomes.first().and_then(|o| o.failure.as_ref()) {
        return Err(VerifyError::Failed {
            what: format!("N = {}", scene.config.contact.nodes),
            reason: f.clone(),
        });
    }
    let levels = scenes
        .iter()
        .zip(outcomes)
        .map(|((axis, s), o)| Level {
            axis: *axis,
            nodes: s.config.contact.nodes,
            tolerance: s.config.time.adaptive.map(|a| a.tolerance),
            dt_s: s
                .config
                .time
                .adaptive
                .is_none()
                .then_some(s.config.time.dt_s),
            steps: o.steps,
            wall_s: o.wall_s,
            status: o.status.clone(),
        })
        .collect();
    let time_order = if scene.config.time.adaptive.is_some() {
        ADAPTIVE_ORDER
    } else if scene.config.time.scheme == Scheme::Literal {
        1.0
    } else {
        SCHEME_ORDER
    };
    // The scene's own run, then the axes' other two levels each.
    let space: Vec<usize> = (0..scenes.len())
        .filter(|&i| i == 0 || scenes[i].0 == Axis::Space)
        .collect();
    let time: Vec<usize> = std::iter::once(0)
        .chain((0..scenes.len()).filter(|&i| scenes[i].0 == Axis::Time))
        .collect();
    let per_run: Vec<_> = outcomes
        .iter()
        .map(|o| {
            if o.failure.is_some() {
                Vec::new()
            } else {
                quantities(o)
            }
        })
        .collect();
    let mut out = Vec::new();
    for (name, unit, base) in &per_run[0] {
        let Some(base) = base else { continue };
        let find = |i: usize| {
            per_run[i]
                .iter()
                .find(|(n, _, _)| n == name)
                .and_then(|(_, _, v)| v.clone())
        };
        let all: Vec<Option<Value>> = (0..scenes.len()).map(find).collect();
        // Per level: a number, or a count (the event count; the regime has no number).
        let values: Vec<Option<f64>> = all
            .iter()
            .map(|v| match v {
                Some(Value::Number(x)) => Some(*x),
                Some(Value::Text(t)) => t.parse().ok(),
                None => None,
            })
            .collect();
        let q = match base {
            Value::Text(t) => {
                let changed = all.iter().any(|v| v.as_ref() != Some(base));
                Quantity {
                    name: name.clone(),
                    unit: (*unit).to_string(),
                    value: t.parse().unwrap_or(0.0),
                    text: Some(t.clone()),
                    extrapolated: None,
                    uncertainty: 0.0,
                    space: None,
                    time: None,
                    asymptotic: !changed,
                    changed,
                    verdict: if changed {
                        Verdict::Changed
                    } else {
                        Verdict::Within
                    },
                    values,
                }
            }
            Value::Number(v) => {
                let along = |idx: &[usize], order: f64| -> Option<Estimate> {
                    if idx.len() != 3 {
                        return None;
                    }
                    let mut phi = [0.0; 3];
                    let mut h = [0.0; 3];
                    for (j, &i) in idx.iter().enumerate() {
                        phi[j] = match &all[i] {
                            Some(Value::Number(x)) => *x,
                            _ => return None,
                        };
                        h[j] = spacing(scenes[i].0, &scenes[i].1);
                    }
                    Some(estimate::estimate(h, phi, order))
                };
                let graded = !scene.config.contact.grid.is_uniform();
                let s = along(&space, space_order(name, graded));
                let t = along(&time, time_order);
                // A level without the quantity (an event that did not happen there): the
                // quantity is not converged at all.
                let missing = (space.len() == 3 && s.is_none()) || t.is_none();
                let parts: Vec<Estimate> = s.iter().chain(t.iter()).cloned().collect();
                let (uncertainty, asymptotic) = estimate::combine(&parts);
                let extrapolated = (!missing).then(|| {
                    v + parts
                        .iter()
                        .map(|e| e.extrapolated.map_or(0.0, |x| x - e.value))
                        .sum::<f64>()
                });
                let bound = rtol * v.abs();
                let verdict = if missing {
                    Verdict::Changed
                } else if uncertainty <= bound {
                    Verdict::Within
                } else if asymptotic {
                    Verdict::Outside
                } else {
                    Verdict::NotConverged
                };
                Quantity {
                    name: name.clone(),
                    unit: (*unit).to_string(),
                    value: *v,
                    text: None,
                    extrapolated,
                    uncertainty: if missing { f64::INFINITY } else { uncertainty },
                    space: s,
                    time: t,
                    asymptotic: asymptotic && !missing,
                    changed: missing,
                    verdict,
                    values,
                }
            }
        };
        out.push(q);
    }
    Ok(VerifyReport {
        scene: scene.name.clone(),
        rtol,
        quantities: out,
        levels,
    })
}

/// Runs `scenes`, `jobs` at a time; the outcomes in their order.
/// Runs every level not already kept under `keep.dir`, keeping each as it ends.
fn run_all(
    scenes: &[(Axis, ResolvedScene)],
    jobs: usize,
    keep: Keep<'_>,
) -> Result<Vec<LevelResult>, VerifyError> {
    let work = |i: usize| -> Result<Option<LevelResult>, StartError> {
        let scene = &scenes[i].1;
        if let Some(kept) = keep.dir.and_then(|d| levels::load(d, i, scene)) {
            if let Some(f) = keep.on_level {
                f(i, true);
            }
            return Ok(Some(kept));
        }
        let mut control = Control {
            interrupt: keep.interrupt,
            ..Control::default()
        };
        let o = stickslip_run::driver::run(scene, &mut NullSink, &mut control)?;
        if o.stop == stickslip_run::outcome::StopReason::Interrupted {
            return Ok(None);
        }
        let r = LevelResult::of(scene, &o);
        // Kept as soon as it ends; a level that cannot be kept is still used now.
        if let Some(d) = keep.dir {
            levels::save(d, i, &r).ok();
        }
        if let Some(f) = keep.on_level {
            f(i, false);
        }
        Ok(Some(r))
    };
    let mut out = Vec::with_capacity(scenes.len());
    let mut interrupted = false;
    for (i, r) in crate::pool::map(scenes.len(), jobs, &work, &mut || {})
        .into_iter()
        .enumerate()
    {
        match r {
            Ok(Some(r)) => out.push(r),
            Ok(None) => interrupted = true,
            Err(error) => {
                return Err(VerifyError::Start {
                    what: format!("{:?} level {i}", scenes[i].0),
                    error: Box::new(error),
                });
            }
        }
    }
    if interrupted {
        return Err(VerifyError::Interrupted {
            finished: out.len(),
            levels: scenes.len(),
            kept: keep.dir.map(std::path::Path::to_path_buf),
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use stickslip_run::scene::Scene;

    fn homogeneous() -> ResolvedScene {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../validation/scenes/homogeneous.toml"
        );
        Scene::from_path(std::path::Path::new(path), &[] as &[&str]).unwrap()
    }

    #[test]
    fn a_homogeneous_scene_refines_time_only_and_bounds_its_onsets() {
        let scene = homogeneous();
        let scenes = level_scenes(&scene).unwrap();
        assert_eq!(
            scenes.iter().map(|(a, _)| *a).collect::<Vec<_>>(),
            [Axis::Space, Axis::Time, Axis::Time]
        );
        let r = verify(&scene, 1e-3, 2).unwrap();
        assert_eq!(r.levels.len(), 3);
        let onset = r
            .quantities
            .iter()
            .find(|q| q.name == "t_first_onset")
            .expect("an onset");
        assert!(onset.space.is_none() && onset.time.is_some());
        // The bound covers the distance to the finest level.
        let t = onset.time.as_ref().unwrap();
        assert!(onset.uncertainty >= 0.0 && onset.uncertainty.is_finite());
        assert!(t.order_theoretical > 0.0);
        let n = r.quantities.iter().find(|q| q.name == "n_events").unwrap();
        // verify.json gives the event count of every level.
        assert!(n.values.iter().all(Option::is_some), "{:?}", n.values);
        let regime = r.quantities.iter().find(|q| q.name == "regime").unwrap();
        assert!(regime.values.iter().all(Option::is_none));
        assert_eq!(
            n.verdict,
            if n.changed {
                Verdict::Changed
            } else {
                Verdict::Within
            }
        );
    }

    #[test]
    fn verify_json_reads_back_through_the_report_type() {
        let scene = homogeneous();
        let mut r = verify(&scene, 1e-3, 2).unwrap();
        // A quantity a level did not have: infinite, written as null.
        r.quantities[2].uncertainty = f64::INFINITY;
        let json = serde_json::to_string(&r).unwrap();
        let back: VerifyReport = serde_json::from_str(&json).unwrap();
        assert_eq!(back.quantities.len(), r.quantities.len());
        assert_eq!(back.levels.len(), r.levels.len());
        for (a, b) in back.quantities.iter().zip(&r.quantities) {
            assert_eq!((&a.name, &a.unit, a.verdict), (&b.name, &b.unit, b.verdict));
            assert_eq!(
                a.uncertainty.to_bits(),
                b.uncertainty.to_bits(),
                "{}",
                a.name
            );
            assert_eq!(a.value.to_bits(), b.value.to_bits(), "{}", a.name);
        }
        // The numbers verify compares are those of the run's files: run.json's summary and
        // events.csv's onsets.
        let (_, files) = stickslip_run::run_in_memory(&scene, &mut Control::default()).unwrap();
        let summary = files.info.summary.as_ref().expect("a summary");
        for (name, _, v) in numbers(summary, &files.events.onsets_s()) {
            let q = r.quantities.iter().find(|q| q.name == name);
            assert_eq!(q.map(|q| q.value), v, "{name}");
        }
    }

    #[test]
    fn a_failed_level_is_no_value_and_a_failed_scene_is_no_report() {
        let scene = homogeneous();
        let scenes = level_scenes(&scene).unwrap();
        let mut outcomes = run_all(&scenes, 2, Keep::default()).unwrap();
        let failure = "made up for the test".to_string();
        // A refined level that failed: every quantity misses it and is "changed".
        outcomes[1].failure = Some(failure.clone());
        let r = report_of(&scene, &scenes, &outcomes, 0.5).unwrap();
        assert!(!r.all_within());
        for q in &r.quantities {
            assert_eq!(q.verdict, Verdict::Changed, "{}", q.name);
            assert!(q.values[1].is_none(), "{}", q.name);
        }
        // The scene's own run failed: nothing to verify, said as such.
        outcomes[0].failure = Some(failure);
        let e = report_of(&scene, &scenes, &outcomes, 0.5).unwrap_err();
        assert!(matches!(e, VerifyError::Failed { .. }), "{e}");
        assert!(e.to_string().contains("made up for the test"), "{e}");
    }

    #[test]
    fn an_interrupted_verify_keeps_its_finished_levels_and_the_rerun_reuses_them() {
        let scene = homogeneous();
        let scenes = level_scenes(&scene).unwrap();
        let tmp = tempfile::tempdir().unwrap();
        let whole = verify_levels(&scene, &scenes, 1e-3, 1).unwrap();
        // Interrupted as soon as the first level has ended (one job: the rest are cut).
        let flag = std::sync::atomic::AtomicBool::new(false);
        let stop = |_: usize, _: bool| flag.store(true, std::sync::atomic::Ordering::Relaxed);
        let keep = Keep {
            dir: Some(tmp.path()),
            interrupt: Some(&flag),
            on_level: Some(&stop),
        };
        let e = verify_kept(&scene, &scenes, 1e-3, 1, keep).unwrap_err();
        assert!(
            matches!(e, VerifyError::Interrupted { finished: 1, levels, .. } if levels == scenes.len()),
            "{e}"
        );
        assert!(e.to_string().contains("runs only the rest"), "{e}");
        assert_eq!(levels::count(tmp.path()), 1);
        // The rerun reuses level 0, runs the others, and reports what an uninterrupted one does.
        let reused = std::sync::Mutex::new(Vec::new());
        let note = |k: usize, r: bool| reused.lock().unwrap().push((k, r));
        let keep = Keep {
            dir: Some(tmp.path()),
            interrupt: None,
            on_level: Some(&note),
        };
        let again = verify_kept(&scene, &scenes, 1e-3, 1, keep).unwrap();
        let mut seen = reused.into_inner().unwrap();
        seen.sort_unstable();
        assert_eq!(seen[0], (0, true));
        assert!(seen[1..].iter().all(|&(_, r)| !r), "{seen:?}");
        for (a, b) in again.quantities.iter().zip(&whole.quantities) {
            assert_eq!(a.value.to_bits(), b.value.to_bits(), "{}", a.name);
            assert_eq!(
                a.uncertainty.to_bits(),
                b.uncertainty.to_bits(),
                "{}",
                a.name
            );
        }
        // A record of another scene is not reused.
        let other = scene.with_overrides(&["lubricant.gamma=11"]).unwrap();
        assert!(levels::load(tmp.path(), 0, &other).is_none());
        assert!(levels::load(tmp.path(), 0, &scenes[0].1).is_some());
    }

    #[test]
    fn bad_rtol_is_refused() {
        let scene = homogeneous();
        for bad in [0.0, -1.0, f64::NAN, 1.0] {
            let e = verify(&scene, bad, 1).unwrap_err().to_string();
            assert!(e.starts_with("rtol = "), "{e}");
        }
    }
}
