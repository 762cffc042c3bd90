//! The tolerance study of the default adaptive stepping: for `time.tolerance` one per decade
//! (and the default), fig2's first and all onsets, t_end, f_peak and F(t) against a same-N
//! reference ([`crate::same_n`]: fixed steps h, h/2, h/4, Richardson on the two finest), with
//! the step counts and wall time of every run, the log–log slopes of error against tolerance
//! and against step evaluations per quantity, and the spatial (N) error of the reference
//! itself (its N against the study's finest N).
//!
//! The controller before the redesign (step doubling, three evaluations per attempt, commit
//! `f2dbd70`) is not built here: its runs were measured once with its own binary, and the
//! outputs are kept in `data/old_controller.json` with the commands that produced them; this
//! module measures those outputs against the same reference ([`OldComparison`]).

use crate::fig2::{RunRecord, RunSpec, run};
use crate::same_n::{EventErrors, EventValues, SameNReference, event_errors};
use crate::simulation::{rms_on, stick_mask};
use serde::{Deserialize, Serialize};
use stickslip_core::config::Scheme;

/// The default `time.tolerance`.
pub const DEFAULT_TOLERANCE: f64 = 5e-5;

/// The quantities compared, in the order of [`TolPoint::error`].
pub const QUANTITIES: [&str; 6] = [
    "first onset (s)",
    "all onsets, max (s)",
    "t_end, max (s)",
    "f_peak, max rel.",
    "F(t) stick RMS rel.",
    "F(t) max rel.",
];

/// Short names of [`QUANTITIES`] for JSON and figures.
pub const KEYS: [&str; 6] = ["onset1", "onsets", "t_end", "f_peak", "F_stick", "F_max"];

/// Levels of the tolerance study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ToleranceSettings {
    /// Node counts (the first is the headline N, the last the finest).
    pub nodes: Vec<usize>,
    /// Tolerances, loose to tight.
    pub tolerances: Vec<f64>,
    /// Fixed steps of the same-N references, coarse to fine (ratio 2), s.
    pub ref_dts_s: [f64; 3],
    /// Timing repeats per point at the first N (one at the others).
    pub repeats: usize,
}

impl ToleranceSettings {
    /// The full study: N = 200 and 2000 (capped by `max_nodes`), tolerances 1e-2 … 1e-7 and
    /// the default, references with Δt = 1e-8, 5e-9, 2.5e-9 s.
    #[must_use]
    pub fn full(max_nodes: usize, repeats: usize) -> Self {
        Self {
            nodes: [200, 2000]
                .into_iter()
                .filter(|&n| n <= max_nodes)
                .collect(),
            tolerances: vec![1e-2, 1e-3, 1e-4, DEFAULT_TOLERANCE, 1e-5, 1e-6, 1e-7],
            ref_dts_s: [1e-8, 5e-9, 2.5e-9],
            repeats,
        }
    }

    /// The smoke study: N = 50 and 100, tolerances 1e-2 … 1e-5, coarser references.
    #[must_use]
    pub fn quick() -> Self {
        Self {
            nodes: vec![50, 100],
            tolerances: vec![1e-2, 1e-3, 1e-4, DEFAULT_TOLERANCE, 1e-5],
            ref_dts_s: [2e-8, 1e-8, 5e-9],
            repeats: 1,
        }
    }
}

/// The event quantities of a recorded run.
#[must_use]
pub fn values(r: &RunRecord) -> EventValues {
    EventValues {
        onsets_s: r.events.iter().map(|e| e.onset_s).collect(),
        t_ends_s: r.events.iter().map(|e| e.t_end_s).collect(),
        f_peaks_n: r.events.iter().map(|e| e.f_peak_n).collect(),
    }
}

/// A reference read as a run's event quantities (to compare references of two N).
#[must_use]
pub fn reference_values(r: &SameNReference) -> EventValues {
    EventValues {
        onsets_s: r.onsets_s.clone(),
        t_ends_s: r
            .t_ends_s
            .iter()
            .map(|&t| t.is_finite().then_some(t))
            .collect(),
        f_peaks_n: r.f_peaks_n.clone(),
    }
}

/// The same-N reference of fig2 at `nodes` from fixed steps `dts_s` (coarse to fine).
///
/// # Panics
/// If the finest run fails.
#[track_caller]
pub fn reference(
    nodes: usize,
    dts_s: [f64; 3],
    progress: &mut dyn FnMut(&RunRecord),
) -> SameNReference {
    let runs: Vec<RunRecord> = dts_s
        .iter()
        .map(|&dt| {
            let r = run(&RunSpec::fig2(Scheme::Accurate, nodes, dt));
            progress(&r);
            r
        })
        .collect();
    assert!(runs[2].failure.is_none(), "{:?}", runs[2].failure);
    let v: Vec<EventValues> = runs.iter().map(values).collect();
    let mask = stick_mask(&v[2].onsets_s, runs[2].force_samples_n.len());
    let mut r = SameNReference::from_levels(nodes, dts_s, [&v[0], &v[1], &v[2]]).with_force(
        [
            &runs[0].force_samples_n,
            &runs[1].force_samples_n,
            &runs[2].force_samples_n,
        ],
        &mask,
    );
    r.wall_s = runs.iter().map(|r| r.wall_s).collect();
    r
}

/// Relative F(t) errors of `samples` against the reference's: (stick-phase RMS, max over the
/// whole run), both over max |F_ref| on the stick phases; None when the run ended early.
#[must_use]
pub fn force_errors(samples: &[f64], reference: &SameNReference) -> (Option<f64>, Option<f64>) {
    let f = &reference.force_n;
    if samples.len() < f.len() || f.is_empty() {
        return (None, None);
    }
    let mask = stick_mask(&reference.onsets_s, f.len());
    let scale = mask.iter().fold(0.0_f64, |m, &j| m.max(f[j].abs()));
    let max = (0..f.len())
        .map(|j| (samples[j] - f[j]).abs())
        .fold(0.0_f64, f64::max)
        / scale;
    (Some(rms_on(&mask, samples, f, scale)), Some(max))
}

/// One adaptive run of the study, measured against its same-N reference.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TolPoint {
    /// Nodes N.
    pub nodes: usize,
    /// `time.tolerance`.
    pub tolerance: f64,
    /// Accepted steps.
    pub steps: u64,
    /// Rejected attempts.
    pub rejected_steps: u64,
    /// Onset steps taken again to end at the located melting time.
    pub onset_retakes: u64,
    /// Evaluations of the accurate step (steps + rejected + retakes).
    pub evaluations: u64,
    /// Median wall seconds (building the simulation and stepping it).
    pub wall_s: f64,
    /// Every timing, s.
    pub walls_s: Vec<f64>,
    /// Events of the run.
    pub events: usize,
    /// Event errors against the reference.
    pub errors: EventErrors,
    /// F(t) stick-phase RMS error, relative to max F.
    pub force_stick_rel: Option<f64>,
    /// F(t) largest error over the whole run, relative to max F.
    pub force_max_rel: Option<f64>,
    /// The core's message if the run failed.
    pub failure: Option<String>,
}

impl TolPoint {
    /// Error of quantity `q` (index into [`QUANTITIES`]).
    #[must_use]
    pub fn error(&self, q: usize) -> Option<f64> {
        let e = &self.errors;
        [
            e.first_onset_s,
            e.max_onset_s,
            e.max_t_end_s,
            e.max_f_peak_rel,
            self.force_stick_rel,
            self.force_max_rel,
        ][q]
    }
}

/// The reference's own uncertainty in quantity `q` (same units as [`TolPoint::error`]).
#[must_use]
pub fn reference_uncertainty(r: &SameNReference, q: usize) -> Option<f64> {
    match q {
        0 | 1 => Some(r.onset_uncertainty_s),
        2 => Some(r.t_end_uncertainty_s),
        3 => Some(r.f_peak_uncertainty_rel),
        _ => r.force_uncertainty_rel,
    }
}

/// A log–log slope of one quantity's error at one N.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Slope {
    /// Nodes N.
    pub nodes: usize,
    /// Key of the quantity ([`KEYS`]).
    pub quantity: String,
    /// `tolerance` or `evaluations`.
    pub against: String,
    /// Least-squares slope of log error against log x (None: fewer than 2 points).
    pub slope: Option<f64>,
    /// Points fitted: errors above [`FLOOR_FACTOR`] × the reference's uncertainty.
    pub points: usize,
    /// Points left out as within the reference's reach.
    pub left_out: usize,
}

/// Errors within this factor of the reference's uncertainty are left out of the slopes.
pub const FLOOR_FACTOR: f64 = 3.0;

/// The slope of `points` (x, error) with errors above `floor`; (slope, used, left out).
#[must_use]
pub fn fitted_slope(points: &[(f64, f64)], floor: f64) -> (Option<f64>, usize, usize) {
    let used: Vec<(f64, f64)> = points
        .iter()
        .copied()
        .filter(|&(x, e)| x > 0.0 && e > floor && e.is_finite())
        .collect();
    let slope = (used.len() >= 2).then(|| stickslip_report::stats::log_log_slope(&used));
    (slope, used.len(), points.len() - used.len())
}

/// The slopes of every quantity at `nodes` against tolerance and evaluations.
#[must_use]
pub fn slopes(points: &[TolPoint], reference: &SameNReference) -> Vec<Slope> {
    let mine: Vec<&TolPoint> = points
        .iter()
        .filter(|p| p.nodes == reference.nodes)
        .collect();
    let mut out = Vec::new();
    for (q, key) in KEYS.iter().enumerate() {
        let floor = FLOOR_FACTOR * reference_uncertainty(reference, q).unwrap_or(0.0);
        for against in ["tolerance", "evaluations"] {
            let pts: Vec<(f64, f64)> = mine
                .iter()
                .filter_map(|p| {
                    let x = if against == "tolerance" {
                        p.tolerance
                    } else {
                        p.evaluations as f64
                    };
                    Some((x, p.error(q)?))
                })
                .collect();
            let (slope, used, left_out) = fitted_slope(&pts, floor);
            out.push(Slope {
                nodes: reference.nodes,
                quantity: (*key).to_string(),
                against: against.to_string(),
                slope,
                points: used,
                left_out,
            });
        }
    }
    out
}

/// The spatial error of the reference at `nodes` against the one at the finest N.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpatialError {
    /// The reference's N.
    pub nodes: usize,
    /// The finer N it is measured against.
    pub finer_nodes: usize,
    /// Event differences.
    pub errors: EventErrors,
    /// F(t) stick-phase RMS difference, relative to max F.
    pub force_stick_rel: Option<f64>,
}

/// One point of the controller before the redesign, as measured with its binary.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OldRun {
    /// `time.tolerance`.
    pub tolerance: f64,
    /// Accepted steps (run.json `accepted_steps`).
    pub accepted_steps: u64,
    /// Rejected attempts (run.json `rejected_steps`).
    pub rejected_steps: u64,
    /// Loop wall seconds of each repeat (run.json `wall_seconds`).
    pub loop_s: Vec<f64>,
    /// Event quantities (events.csv).
    pub events: EventValues,
    /// The current binary at the same tolerance in the same session: loop wall seconds of
    /// each repeat, and its accepted and rejected steps.
    pub new_loop_s: Vec<f64>,
    /// See `new_loop_s`.
    pub new_accepted_steps: u64,
    /// See `new_loop_s`.
    pub new_rejected_steps: u64,
}

/// The measurements of the controller before the redesign (`data/old_controller.json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OldController {
    /// What this file is.
    pub label: String,
    /// The commit whose binary was run.
    pub commit: String,
    /// Evaluations of the step per attempt (step doubling: the whole step and two halves).
    pub evaluations_per_attempt: u64,
    /// Nodes N.
    pub nodes: usize,
    /// How the numbers were produced.
    pub commands: Vec<String>,
    /// When and where.
    pub measured: String,
    /// The runs, loose to tight.
    pub runs: Vec<OldRun>,
}

/// The data file, compiled in.
const OLD_CONTROLLER: &str = include_str!("../data/old_controller.json");

/// The controller before the redesign as measured.
///
/// # Panics
/// If the committed data file does not parse (a test reads it).
#[must_use]
pub fn old_controller() -> OldController {
    serde_json::from_str(OLD_CONTROLLER).expect("data/old_controller.json")
}

/// One old-controller run measured against the study's reference at its N.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OldPoint {
    /// `time.tolerance`.
    pub tolerance: f64,
    /// Evaluations: (accepted + rejected) × evaluations per attempt.
    pub evaluations: u64,
    /// Median loop wall seconds.
    pub loop_s: f64,
    /// Median loop wall seconds of the current binary, same session and tolerance.
    pub new_loop_s: f64,
    /// Evaluations of the current binary in that session (accepted + rejected; onset
    /// retakes are not in run.json).
    pub new_evaluations: u64,
    /// Event errors against the reference.
    pub errors: EventErrors,
}

/// The old controller against the reference at its N.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OldComparison {
    /// Where the data come from (label, commit, commands, when).
    pub source: OldController,
    /// Its points.
    pub points: Vec<OldPoint>,
}

/// Measures the old controller's runs against `reference` (None: another N).
#[must_use]
pub fn compare_old(old: OldController, reference: &SameNReference) -> Option<OldComparison> {
    (old.nodes == reference.nodes).then(|| {
        let med = stickslip_report::stats::median;
        let points = old
            .runs
            .iter()
            .map(|r| OldPoint {
                tolerance: r.tolerance,
                evaluations: (r.accepted_steps + r.rejected_steps) * old.evaluations_per_attempt,
                loop_s: med(&r.loop_s),
                new_loop_s: med(&r.new_loop_s),
                new_evaluations: r.new_accepted_steps + r.new_rejected_steps,
                errors: event_errors(&r.events, reference),
            })
            .collect();
        OldComparison {
            source: old,
            points,
        }
    })
}

/// The whole tolerance study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ToleranceStudy {
    /// Levels.
    pub settings: ToleranceSettings,
    /// One same-N reference per N.
    pub references: Vec<SameNReference>,
    /// Spatial error of each reference but the finest against the finest.
    pub spatial: Vec<SpatialError>,
    /// Every adaptive run.
    pub points: Vec<TolPoint>,
    /// Slopes per N and quantity.
    pub slopes: Vec<Slope>,
    /// The controller before the redesign (when its N is among the study's).
    pub old: Option<OldComparison>,
}

/// Runs the study.
pub fn study(s: &ToleranceSettings, progress: &mut dyn FnMut(&RunRecord)) -> ToleranceStudy {
    let mut references = Vec::new();
    let mut points = Vec::new();
    for (i, &nodes) in s.nodes.iter().enumerate() {
        let reference = reference(nodes, s.ref_dts_s, progress);
        for &tol in &s.tolerances {
            let repeats = if i == 0 { s.repeats.max(1) } else { 1 };
            let mut walls = Vec::new();
            let mut first = None;
            for _ in 0..repeats {
                let r = run(&RunSpec::adaptive(nodes, tol));
                progress(&r);
                walls.push(r.wall_s);
                first.get_or_insert(r);
            }
            let r = first.expect("one run");
            let (force_stick_rel, force_max_rel) = force_errors(&r.force_samples_n, &reference);
            points.push(TolPoint {
                nodes,
                tolerance: tol,
                steps: r.steps,
                rejected_steps: r.rejected_steps,
                onset_retakes: r.onset_retakes,
                evaluations: r.evaluations(),
                wall_s: stickslip_report::stats::median(&walls),
                walls_s: walls,
                events: r.events.len(),
                errors: event_errors(&values(&r), &reference),
                force_stick_rel,
                force_max_rel,
                failure: r.failure.clone(),
            });
        }
        references.push(reference);
    }
    let slopes = references.iter().flat_map(|r| slopes(&points, r)).collect();
    let spatial = spatial_errors(&references);
    let old = references
        .iter()
        .find_map(|r| compare_old(old_controller(), r));
    ToleranceStudy {
        settings: s.clone(),
        references,
        spatial,
        points,
        slopes,
        old,
    }
}

/// Each reference but the last against the last (the finest N).
#[must_use]
pub fn spatial_errors(references: &[SameNReference]) -> Vec<SpatialError> {
    let Some((finest, coarser)) = references.split_last() else {
        return Vec::new();
    };
    coarser
        .iter()
        .map(|r| SpatialError {
            nodes: r.nodes,
            finer_nodes: finest.nodes,
            errors: event_errors(&reference_values(r), finest),
            force_stick_rel: force_errors(&r.force_n, finest).0,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slopes_leave_out_errors_within_the_floor() {
        // e = tol^(2/3) above 2e-6; the fit leaves out what is below 5e-6 (1e-8: 4.6e-6).
        let pts: Vec<(f64, f64)> = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9]
            .iter()
            .map(|&t: &f64| (t, t.powf(2.0 / 3.0).max(2e-6)))
            .collect();
        let (s, used, out) = fitted_slope(&pts, 5e-6);
        assert_eq!((used, out), (6, 2));
        assert!((s.unwrap() - 2.0 / 3.0).abs() < 1e-9);
        assert_eq!(fitted_slope(&pts[..1], 0.0).0, None);
    }
}
