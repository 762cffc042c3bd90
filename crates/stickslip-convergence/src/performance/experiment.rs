//! P7–P8 (issue 31): the SFA contact (`validation/scenes/sfa.toml`, beside the fig2 scene)
//! with a soft drive spring, run by the CLI as a user runs it — step evaluations, wall time,
//! loop time per evaluation and its meltings against a tighter-tolerance reference computed
//! here — and the step trace of one melting cycle of its slip: the same scene run in-process
//! through the run library's driver with an observer, recording per accepted step its length,
//! the part of the error estimate that limited it, the melted nodes and the attempts rejected
//! before it, from just before the P7 run's first onset to just after its second.
//!
//! This module writes the P7 and P8 rows of the targets table, the section "P7–P8: the SFA
//! contact" and the step-trace figure; [`super::report`] places them. Every number comes from
//! the measurements in [`SfaBench`] or the goals below.

use super::targets::verdict;
use super::{BenchSettings, Timed, timed_scene};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;
use stickslip_core::sim::{Simulation, StepError};
use stickslip_report::fmt::{sig, tick};
use stickslip_report::palette::PALETTE;
use stickslip_report::plot::{Marker, Panel, Scale, Series, decimate, render_svg};
use stickslip_run::Scene;
use stickslip_run::StopReason;
use stickslip_run::driver::{Control, Driver, Limit, NullSink};
use stickslip_run::keys::{drive, numerics, output, time};

/// The SFA scene, beside the fig2 scene.
pub const SFA_SCENE: &str = "sfa.toml";
/// P7–P8: the drive spring's stiffness, N/m (the scene's is 10× stiffer).
pub const SFA_STIFFNESS: f64 = 500.0;
/// P7–P8: the interval of series rows, s (small outputs).
pub const SFA_SERIES_INTERVAL_S: f64 = 1e-3;
/// P7: time.end, s.
pub const P7_END_S: f64 = 1.0;
/// P7 with `--quick`: time.end, s (just past the first few meltings: the soft spring loads the
/// contact for most of a second before the first).
pub const P7_QUICK_END_S: f64 = 0.95;
/// P7: the reference's tolerance.
pub const P7_REFERENCE_TOLERANCE: f64 = 5e-7;
/// P7: the goal for the step evaluations of the run.
pub const P7_EVALUATIONS_GOAL: u64 = 30_000;
/// P7: every onset within this of the reference's, s.
pub const P7_ONSET_GOAL_S: f64 = 1e-4;
/// P8: the drive's velocity, m/s.
pub const P8_VELOCITY: f64 = 1e-4;
/// P8: time.end, s.
pub const P8_END_S: f64 = 0.1;
/// P8 with `--quick`: time.end, s (the first two meltings).
pub const P8_QUICK_END_S: f64 = 0.012;
/// P8: the reference's tolerance.
pub const P8_REFERENCE_TOLERANCE: f64 = 5e-6;
/// P8: the goal for the step evaluations of the run.
pub const P8_EVALUATIONS_GOAL: u64 = 250_000;
/// P8: the meltings within this fraction of the reference's.
pub const P8_MELTINGS_GOAL: f64 = 0.02;
/// P7–P8 (and the SFA contact's film-step runs): the run also taken with this
/// `numerics.phi_error_floor` (the default is 0), beside the default's verdict.
pub const PHI_ERROR_FLOOR: f64 = 0.1;
/// Step trace: from this long before the first onset to this long after the second, s.
pub const TRACE_MARGIN_S: f64 = 5e-6;

/// One target on the SFA contact: a run at the default tolerance and its reference.
#[derive(Debug, Clone, Serialize)]
pub struct SfaTarget {
    /// The `--set` overrides on the SFA scene (the reference adds its tolerance).
    pub settings: Vec<String>,
    /// The run at the default tolerance, once, 2 threads.
    pub run: Timed,
    /// The reference: the same with `time.tolerance` = `reference_tolerance`, once.
    pub reference: Timed,
    /// The reference's tolerance.
    pub reference_tolerance: f64,
    /// Step evaluations of the run: accepted steps, rejected attempts and onset retakes.
    pub evaluations: u64,
    /// Whole-process wall time of the run, s.
    pub wall_s: f64,
    /// Loop time per evaluation of the run, µs.
    pub us_per_evaluation: f64,
    /// Meltings (events) of the run.
    pub meltings: usize,
    /// Meltings of the reference.
    pub reference_meltings: usize,
    /// |onset − the reference's| per melting, s (empty when the counts differ).
    pub onset_deviations_s: Vec<f64>,
    /// The largest of `onset_deviations_s`, s (none when the counts differ or nothing melted).
    pub max_onset_deviation_s: Option<f64>,
    /// The run again with `numerics.phi_error_floor` = [`PHI_ERROR_FLOOR`], once, 2 threads
    /// (not part of the verdict, which is the default settings').
    pub floored: Option<Timed>,
}

/// |a − b| per pair of onsets, or nothing when the counts differ.
#[must_use]
pub fn onset_deviations(onsets_s: &[f64], reference_s: &[f64]) -> Vec<f64> {
    if onsets_s.len() != reference_s.len() {
        return Vec::new();
    }
    onsets_s
        .iter()
        .zip(reference_s)
        .map(|(a, b)| (a - b).abs())
        .collect()
}

impl SfaTarget {
    /// From the run and its reference.
    #[must_use]
    pub fn from_runs(
        settings: Vec<String>,
        run: Timed,
        reference: Timed,
        reference_tolerance: f64,
    ) -> Self {
        let onset_deviations_s =
            onset_deviations(&run.event_values.onsets_s, &reference.event_values.onsets_s);
        Self {
            settings,
            evaluations: run.evaluations(),
            wall_s: run.wall_s,
            us_per_evaluation: run.us_per_evaluation(),
            meltings: run.events,
            reference_meltings: reference.events,
            max_onset_deviation_s: onset_deviations_s.iter().copied().reduce(f64::max),
            onset_deviations_s,
            run,
            reference,
            reference_tolerance,
            floored: None,
        }
    }

    /// The floored run's largest onset deviation from the reference, s (none without the run,
    /// or when the counts differ).
    #[must_use]
    pub fn floored_max_onset_deviation_s(&self) -> Option<f64> {
        let f = self.floored.as_ref()?;
        onset_deviations(
            &f.event_values.onsets_s,
            &self.reference.event_values.onsets_s,
        )
        .into_iter()
        .reduce(f64::max)
    }

    /// The floored run's result in words: `116139 evaluations (3.54 s, 1.93× fewer), 78
    /// meltings, largest onset deviation 4.1 µs` (none without the run).
    #[must_use]
    pub fn floored_result(&self) -> Option<String> {
        let f = self.floored.as_ref()?;
        let deviation = self.floored_max_onset_deviation_s().map_or_else(
            || "onsets not paired (the counts differ)".into(),
            |d| format!("largest onset deviation {} µs", sig(1e6 * d, 2)),
        );
        Some(format!(
            "{} evaluations ({} s, {}× fewer), {} meltings, {deviation}",
            f.evaluations(),
            sig(f.wall_s, 3),
            sig(self.evaluations as f64 / f.evaluations().max(1) as f64, 3),
            f.events,
        ))
    }

    /// `; with numerics.phi_error_floor = 0.1: …` for the targets table (empty without the
    /// floored run).
    fn floored_words(&self) -> String {
        self.floored_result()
            .map(|w| format!("; with numerics.phi_error_floor = {PHI_ERROR_FLOOR}: {w}"))
            .unwrap_or_default()
    }

    /// (meltings − the reference's) / the reference's (none when the reference has none).
    #[must_use]
    pub fn melting_difference(&self) -> Option<f64> {
        (self.reference_meltings > 0).then(|| {
            (self.meltings as f64 - self.reference_meltings as f64) / self.reference_meltings as f64
        })
    }

    /// P7's verdict: few evaluations, the reference's meltings, every onset close to its.
    #[must_use]
    pub fn p7_met(&self) -> bool {
        self.evaluations <= P7_EVALUATIONS_GOAL
            && self.meltings > 0
            && self.meltings == self.reference_meltings
            && self
                .max_onset_deviation_s
                .is_some_and(|d| d <= P7_ONSET_GOAL_S)
    }

    /// P8's verdict: few evaluations, the meltings within 2 % of the reference's.
    #[must_use]
    pub fn p8_met(&self) -> bool {
        self.evaluations <= P8_EVALUATIONS_GOAL
            && self
                .melting_difference()
                .is_some_and(|d| d.abs() <= P8_MELTINGS_GOAL)
    }
}

/// The part of a step's error estimate (the largest part limits the step).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ErrorPart {
    /// The film, φ.
    Phi,
    /// The strain.
    Eps,
    /// The stamp's position X.
    X,
    /// The stamp's velocity V.
    V,
}

impl ErrorPart {
    /// All parts, in [`StepError`]'s order.
    pub const ALL: [Self; 4] = [Self::Phi, Self::Eps, Self::X, Self::V];

    /// The largest part of `e` (ties to the earlier part).
    #[must_use]
    pub fn of(e: &StepError) -> Self {
        let mut best = (Self::Phi, e.phi);
        for (part, v) in [(Self::Eps, e.eps), (Self::X, e.x), (Self::V, e.v)] {
            if v > best.1 {
                best = (part, v);
            }
        }
        best.0
    }

    /// In the report's words.
    #[must_use]
    pub fn words(self) -> &'static str {
        match self {
            Self::Phi => "the film φ",
            Self::Eps => "the strain",
            Self::X => "the stamp's position X",
            Self::V => "the stamp's velocity V",
        }
    }

    /// Short, for the figure's legend.
    #[must_use]
    pub fn short(self) -> &'static str {
        match self {
            Self::Phi => "φ",
            Self::Eps => "strain",
            Self::X => "X",
            Self::V => "V",
        }
    }
}

/// Steps counted by the part of the error that limited them.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct PartCounts {
    /// By the film.
    pub phi: u64,
    /// By the strain.
    pub eps: u64,
    /// By the stamp's position.
    pub x: u64,
    /// By the stamp's velocity.
    pub v: u64,
}

impl PartCounts {
    /// Counts one step limited by `part`.
    pub fn add(&mut self, part: ErrorPart) {
        *self.get_mut(part) += 1;
    }

    /// The steps limited by `part`.
    #[must_use]
    pub fn get(&self, part: ErrorPart) -> u64 {
        match part {
            ErrorPart::Phi => self.phi,
            ErrorPart::Eps => self.eps,
            ErrorPart::X => self.x,
            ErrorPart::V => self.v,
        }
    }

    fn get_mut(&mut self, part: ErrorPart) -> &mut u64 {
        match part {
            ErrorPart::Phi => &mut self.phi,
            ErrorPart::Eps => &mut self.eps,
            ErrorPart::X => &mut self.x,
            ErrorPart::V => &mut self.v,
        }
    }

    /// In words: `5290 by the film φ, 1 by the stamp's velocity V` (parts that limited none
    /// left out).
    #[must_use]
    pub fn words(&self) -> String {
        let parts: Vec<String> = ErrorPart::ALL
            .iter()
            .filter(|&&p| self.get(p) > 0)
            .map(|&p| format!("{} by {}", self.get(p), p.words()))
            .collect();
        if parts.is_empty() {
            "none".into()
        } else {
            parts.join(", ")
        }
    }
}

/// One accepted step of the trace.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TraceRow {
    /// Time at the step's end, s.
    pub t_s: f64,
    /// Its length, s.
    pub h_s: f64,
    /// Its estimated error, each part in units of its scale.
    pub error: StepError,
    /// Nodes melted after it (φ below the melt threshold).
    pub melted: usize,
    /// Attempts rejected before it.
    pub rejected: u64,
}

/// The steps through one melting cycle of the SFA slip (the P7 scene, in-process).
#[derive(Debug, Clone, Default, Serialize)]
pub struct StepTrace {
    /// The `--set` overrides the scene was resolved with (P7's).
    pub settings: Vec<String>,
    /// Nodes.
    pub nodes: usize,
    /// The adaptive tolerance.
    pub tolerance: f64,
    /// The P7 run's first onset (events.csv), s.
    pub first_onset_s: f64,
    /// Its second onset, s.
    pub second_onset_s: f64,
    /// Where the trace starts: the first step at or after `first_onset_s` − [`TRACE_MARGIN_S`], s.
    pub from_s: f64,
    /// Where it ends: the first step at or after `second_onset_s` + [`TRACE_MARGIN_S`], s.
    pub to_s: f64,
    /// Accepted steps in the trace.
    pub steps: u64,
    /// Attempts rejected in it.
    pub rejected: u64,
    /// Accepted steps after which at least one node is melted (the melting cascades).
    pub cascade_steps: u64,
    /// Attempts rejected before those.
    pub cascade_rejected: u64,
    /// The cascades: runs of consecutive steps with a node melted.
    pub cascades: usize,
    /// The time the cascade steps span, s.
    pub cascade_duration_s: f64,
    /// Accepted steps with no node melted (before, between and after the cascades).
    pub between_steps: u64,
    /// Attempts rejected before those.
    pub between_rejected: u64,
    /// Cascade steps by the part of the error that limited them.
    pub limited_in_cascade: PartCounts,
    /// The other steps by the part that limited them.
    pub limited_between: PartCounts,
    /// Shortest and longest step, s.
    pub shortest_step_s: f64,
    /// See `shortest_step_s`.
    pub longest_step_s: f64,
    /// Longest step of the cascades, s.
    pub longest_cascade_step_s: f64,
    /// Shortest step with no node melted, s.
    pub shortest_between_step_s: f64,
    /// The most nodes melted at once.
    pub max_melted: usize,
    /// The rises of the melted-node count from step to step, summed: how many nodes melted
    /// one after another in the cascades (a node melting and regrowing inside one step counts
    /// as melted at that step's end).
    pub node_meltings: u64,
    /// Wall time of the in-process run from the start to the trace's end, s.
    pub wall_s: f64,
    /// The steps (for the figure; not written).
    #[serde(skip)]
    pub rows: Vec<TraceRow>,
}

impl StepTrace {
    /// The summary of `rows` (the steps of the trace, in order); the scene, the onsets and the
    /// wall time are left for the caller.
    #[must_use]
    pub fn from_rows(from_s: f64, rows: Vec<TraceRow>) -> Self {
        let mut t = Self {
            from_s,
            to_s: rows.last().map_or(from_s, |r| r.t_s),
            steps: rows.len() as u64,
            shortest_step_s: f64::INFINITY,
            shortest_between_step_s: f64::INFINITY,
            ..Self::default()
        };
        let mut melted_before = false;
        let mut count_before = 0;
        for r in &rows {
            t.node_meltings += r.melted.saturating_sub(count_before) as u64;
            count_before = r.melted;
            let part = ErrorPart::of(&r.error);
            t.rejected += r.rejected;
            t.shortest_step_s = t.shortest_step_s.min(r.h_s);
            t.longest_step_s = t.longest_step_s.max(r.h_s);
            t.max_melted = t.max_melted.max(r.melted);
            let melted = r.melted > 0;
            if melted {
                t.cascade_steps += 1;
                t.cascade_rejected += r.rejected;
                t.cascade_duration_s += r.h_s;
                t.longest_cascade_step_s = t.longest_cascade_step_s.max(r.h_s);
                t.limited_in_cascade.add(part);
                if !melted_before {
                    t.cascades += 1;
                }
            } else {
                t.between_steps += 1;
                t.between_rejected += r.rejected;
                t.shortest_between_step_s = t.shortest_between_step_s.min(r.h_s);
                t.limited_between.add(part);
            }
            melted_before = melted;
        }
        if rows.is_empty() {
            t.shortest_step_s = f64::NAN;
        }
        if t.between_steps == 0 {
            t.shortest_between_step_s = f64::NAN;
        }
        t.rows = rows;
        t
    }

    /// The time after the first cascade's last step, s (the trace's end without one).
    #[must_use]
    pub fn first_cascade_end_s(&self) -> f64 {
        let start = self.rows.iter().position(|r| r.melted > 0);
        start
            .and_then(|i| {
                let after = self.rows[i..].iter().position(|r| r.melted == 0);
                Some(self.rows[i + after? - 1].t_s)
            })
            .unwrap_or(self.to_s)
    }
}

/// What P7, P8 and the step trace measured.
#[derive(Debug, Clone, Serialize)]
pub struct SfaBench {
    /// The scene file (beside the fig2 scene).
    pub scene: String,
    /// P7: K = [`SFA_STIFFNESS`], time.end = [`P7_END_S`], against the reference at
    /// [`P7_REFERENCE_TOLERANCE`].
    pub p7: SfaTarget,
    /// P8: P7's scene at V0 = [`P8_VELOCITY`], time.end = [`P8_END_S`], against the reference
    /// at [`P8_REFERENCE_TOLERANCE`].
    pub p8: SfaTarget,
    /// The steps through P7's first melting cycle.
    pub step_trace: StepTrace,
}

/// The small outputs and soft spring of P7–P8 up to `end_s`.
fn sfa_sets(end_s: f64) -> Vec<String> {
    vec![
        drive::STIFFNESS.set(SFA_STIFFNESS).to_string(),
        time::END.set(end_s).to_string(),
        output::SERIES_INTERVAL
            .set(SFA_SERIES_INTERVAL_S)
            .to_string(),
        output::PROFILE_TIMES.set(vec![end_s]).to_string(),
    ]
}

/// One target: the reference with `reference_tolerance`, then the run, each once.
fn sfa_target(
    s: &BenchSettings,
    scene: &Path,
    tag: &str,
    sets: Vec<String>,
    reference_tolerance: f64,
) -> Result<SfaTarget, String> {
    let mut reference_sets = sets.clone();
    reference_sets.push(time::TOLERANCE.set(reference_tolerance).to_string());
    let reference = timed_scene(
        s,
        scene,
        &format!("{tag}_reference"),
        &reference_sets,
        2,
        1,
        &[],
    )?;
    let onsets_s = &reference.event_values.onsets_s;
    let run = timed_scene(s, scene, tag, &sets, 2, 1, onsets_s)?;
    let mut floored_sets = sets.clone();
    floored_sets.push(numerics::PHI_ERROR_FLOOR.set(PHI_ERROR_FLOOR).to_string());
    let floored = timed_scene(
        s,
        scene,
        &format!("{tag}_floored"),
        &floored_sets,
        2,
        1,
        onsets_s,
    )?;
    Ok(SfaTarget {
        floored: Some(floored),
        ..SfaTarget::from_runs(sets, run, reference, reference_tolerance)
    })
}

/// Runs P7 (and the step trace through its first melting cycle) and P8; `--quick` shortens
/// both (and their references).
///
/// # Errors
/// A run that failed, a scene that does not resolve, or a P7 run with fewer than two onsets.
pub fn measure(s: &BenchSettings, progress: &dyn Fn(&str)) -> Result<SfaBench, String> {
    let scene = s.scene.with_file_name(SFA_SCENE);
    let p7_end_s = if s.quick { P7_QUICK_END_S } else { P7_END_S };
    progress(&format!(
        "P7: the SFA contact to {p7_end_s} s and its reference at tolerance \
         {P7_REFERENCE_TOLERANCE:e}"
    ));
    let p7 = sfa_target(s, &scene, "p7", sfa_sets(p7_end_s), P7_REFERENCE_TOLERANCE)?;
    progress("P7: the step trace through the first melting cycle, in-process");
    let step_trace = trace(&scene, &p7.settings, &p7.run.event_values.onsets_s)?;
    let p8_end_s = if s.quick { P8_QUICK_END_S } else { P8_END_S };
    progress(&format!(
        "P8: the SFA contact at V0 = {P8_VELOCITY:e} m/s to {p8_end_s} s and its reference at \
         tolerance {P8_REFERENCE_TOLERANCE:e}"
    ));
    let mut p8_sets = sfa_sets(p8_end_s);
    p8_sets.push(drive::VELOCITY.set(P8_VELOCITY).to_string());
    let p8 = sfa_target(s, &scene, "p8", p8_sets, P8_REFERENCE_TOLERANCE)?;
    Ok(SfaBench {
        scene: SFA_SCENE.into(),
        p7,
        p8,
        step_trace,
    })
}

/// The step trace: `scene` with `sets`, from [`TRACE_MARGIN_S`] before the first of `onsets_s`
/// to as long after the second, through the driver with an observer.
///
/// # Errors
/// Fewer than two onsets, a scene that does not resolve or start, a failed step.
pub fn trace(scene_path: &Path, sets: &[String], onsets_s: &[f64]) -> Result<StepTrace, String> {
    let [first_onset_s, second_onset_s, ..] = *onsets_s else {
        return Err(format!(
            "step trace: the P7 run has {} onsets, two needed",
            onsets_s.len()
        ));
    };
    let scene =
        Scene::from_path(scene_path, sets).map_err(|e| format!("{}: {e}", scene_path.display()))?;
    let started = Instant::now();
    let mut sink = NullSink;
    let mut driver = Driver::start(&scene, &mut sink).map_err(|e| format!("step trace: {e}"))?;
    let stopped = |r: std::io::Result<Option<StopReason>>| match r {
        Ok(Some(StopReason::Failure | StopReason::Refused)) => {
            Err("step trace: the run failed".to_string())
        }
        Ok(_) => Ok(()),
        Err(e) => Err(format!("step trace: {e}")),
    };
    stopped(driver.advance(
        &mut sink,
        &mut Control::default(),
        Limit::Time(first_onset_s - TRACE_MARGIN_S),
    ))?;
    let threshold = scene.config.melt_threshold;
    let from_s = driver.simulation().time_s();
    let mut rejected = driver.simulation().state().counters.rejected_steps;
    let mut t_prev = from_s;
    let mut rows = Vec::new();
    let mut observe = |sim: &Simulation| {
        let state = sim.state();
        rows.push(TraceRow {
            t_s: sim.time_s(),
            h_s: sim.time_s() - t_prev,
            error: sim.last_step_error(),
            melted: state
                .physical
                .phi
                .iter()
                .filter(|&&p| p < threshold)
                .count(),
            rejected: state.counters.rejected_steps - rejected,
        });
        rejected = state.counters.rejected_steps;
        t_prev = sim.time_s();
    };
    let mut control = Control {
        observer: Some(&mut observe),
        ..Control::default()
    };
    stopped(driver.advance(
        &mut sink,
        &mut control,
        Limit::Time(second_onset_s + TRACE_MARGIN_S),
    ))?;
    Ok(StepTrace {
        settings: sets.to_vec(),
        nodes: scene.config.contact.nodes,
        tolerance: scene.config.time.adaptive.map_or(f64::NAN, |a| a.tolerance),
        first_onset_s,
        second_onset_s,
        wall_s: started.elapsed().as_secs_f64(),
        ..StepTrace::from_rows(from_s, rows)
    })
}

/// `n` of `goal` in words: `3.2× the goal` or `within the goal`.
fn against_goal(n: u64, goal: u64) -> String {
    if n <= goal {
        format!("within the goal of {goal}")
    } else {
        format!(
            "{}× the goal of {goal}",
            sig(n as f64 / goal.max(1) as f64, 3)
        )
    }
}

/// The P7 and P8 rows of the targets table.
pub(super) fn targets_rows(m: &mut String, b: &SfaBench) {
    let (p7, r7) = (&b.p7, &b.p7.run.resolved);
    let _ = writeln!(
        m,
        "| P7 the SFA contact ({}, K = {} N/m, time.end = {} s; N = {}, tolerance {}) against \
         its reference at tolerance {:e} | ≤ {} step evaluations, the reference's meltings, \
         every onset within {} µs | {} evaluations ({} s, {} µs per evaluation); {} meltings \
         against {}; {}{} | {} |",
        b.scene,
        tick(SFA_STIFFNESS),
        tick(r7.end_s),
        r7.nodes,
        r7.tolerance
            .map_or_else(|| "–".into(), |t| format!("{t:e}")),
        p7.reference_tolerance,
        P7_EVALUATIONS_GOAL,
        tick(1e6 * P7_ONSET_GOAL_S),
        p7.evaluations,
        sig(p7.wall_s, 3),
        sig(p7.us_per_evaluation, 3),
        p7.meltings,
        p7.reference_meltings,
        p7.max_onset_deviation_s.map_or_else(
            || "onsets not paired (the counts differ)".into(),
            |d| format!("largest onset deviation {} µs", sig(1e6 * d, 2))
        ),
        p7.floored_words(),
        verdict(p7.p7_met())
    );
    let (p8, r8) = (&b.p8, &b.p8.run.resolved);
    let _ = writeln!(
        m,
        "| P8 the SFA contact at V0 = {} m/s (K = {} N/m, time.end = {} s; N = {}) against its \
         reference at tolerance {:e} | ≤ {} step evaluations, meltings within {} % of the \
         reference's | {} evaluations ({} s, {} µs per evaluation); {} meltings against {} \
         ({} %){} | {} |",
        tick(P8_VELOCITY),
        tick(SFA_STIFFNESS),
        tick(r8.end_s),
        r8.nodes,
        p8.reference_tolerance,
        P8_EVALUATIONS_GOAL,
        tick(100.0 * P8_MELTINGS_GOAL),
        p8.evaluations,
        sig(p8.wall_s, 3),
        sig(p8.us_per_evaluation, 3),
        p8.meltings,
        p8.reference_meltings,
        p8.melting_difference()
            .map_or_else(|| "–".into(), |d| format!("{:+.2}", 100.0 * d)),
        p8.floored_words(),
        verdict(p8.p8_met())
    );
}

/// The run's tolerance as resolved (`–` without one).
fn tolerance_words(t: &SfaTarget) -> String {
    t.run
        .resolved
        .tolerance
        .map_or_else(|| "–".into(), |x| format!("{x:e}"))
}

/// One target's run and reference in a sentence's words.
fn runs_words(t: &SfaTarget) -> String {
    let r = &t.run;
    format!(
        "{} step evaluations ({} accepted, {} rejected, {} retaken to end at a located onset) \
         in {} s (the time loop {} s, {} µs per evaluation) and {} meltings; its reference at \
         time.tolerance = {:e} took {} evaluations in {} s and has {} meltings",
        t.evaluations,
        r.steps,
        r.rejected_steps,
        r.onset_retakes,
        sig(t.wall_s, 3),
        sig(r.loop_s, 3),
        sig(t.us_per_evaluation, 3),
        t.meltings,
        t.reference_tolerance,
        t.reference.evaluations(),
        sig(t.reference.wall_s, 3),
        t.reference_meltings,
    )
}

/// The section "P7–P8: the SFA contact" with the step trace.
pub(super) fn section(m: &mut String, b: &SfaBench) {
    let (p7, p8) = (&b.p7, &b.p8);
    let deviation = match p7.max_onset_deviation_s {
        Some(d) => {
            let k = p7
                .onset_deviations_s
                .iter()
                .position(|&x| x == d)
                .map_or(0, |i| i + 1);
            let within = p7
                .onset_deviations_s
                .iter()
                .filter(|&&x| x <= P7_ONSET_GOAL_S)
                .count();
            format!(
                "the largest onset deviation is {} µs (melting {k} of {}); {within} of the {} \
                 onsets are within {} µs",
                sig(1e6 * d, 3),
                p7.meltings,
                p7.meltings,
                tick(1e6 * P7_ONSET_GOAL_S)
            )
        }
        None => "the counts differ, so the onsets are not paired".into(),
    };
    let _ = writeln!(
        m,
        "## P7–P8: the SFA contact\n\n\
         `{}` (beside fig2's scene) with a soft drive spring, K = {} N/m (`drive.stiffness`), \
         to time.end = {} s with small outputs (a series row every {} ms, one profile at the \
         end), N = {} and the default tolerance {}, once on 2 threads: {}; {deviation}. The \
         evaluations are {}.\n",
        b.scene,
        tick(SFA_STIFFNESS),
        tick(p7.run.resolved.end_s),
        tick(1e3 * SFA_SERIES_INTERVAL_S),
        p7.run.resolved.nodes,
        tolerance_words(p7),
        runs_words(p7),
        against_goal(p7.evaluations, P7_EVALUATIONS_GOAL),
    );
    let difference = p8.melting_difference().map_or_else(
        || "the reference has no meltings".to_string(),
        |d| {
            format!(
                "the counts differ by {} ({} %, the goal allows {} %)",
                p8.meltings.abs_diff(p8.reference_meltings),
                sig(100.0 * d.abs(), 2),
                tick(100.0 * P8_MELTINGS_GOAL)
            )
        },
    );
    let _ = writeln!(
        m,
        "P8, the same scene with the drive at V0 = {} m/s (`drive.velocity`) to time.end = {} \
         s: {}; {difference}. The evaluations are {}.\n",
        tick(P8_VELOCITY),
        tick(p8.run.resolved.end_s),
        runs_words(p8),
        against_goal(p8.evaluations, P8_EVALUATIONS_GOAL),
    );
    if p7.floored.is_some() || p8.floored.is_some() {
        let _ = writeln!(
            m,
            "Both again with `numerics.phi_error_floor` = {PHI_ERROR_FLOOR} (a node's φ error \
             taken relative to max(φ, melt threshold, {PHI_ERROR_FLOOR}·φ_s) instead of \
             max(φ, melt threshold): molten and regrowing nodes, whose stress is below a \
             hundredth of a solid node's there, are no longer followed to relative accuracy), \
             against the same references; not part of the verdicts, which are the default \
             settings'. P7: {}. P8: {}.\n",
            p7.floored_result().unwrap_or_else(|| "not run".into()),
            p8.floored_result().unwrap_or_else(|| "not run".into()),
        );
    }
    trace_section(m, &b.step_trace);
}

/// The step trace's paragraph.
fn trace_section(m: &mut String, t: &StepTrace) {
    let share = |n: u64| sig(100.0 * n as f64 / t.steps.max(1) as f64, 3);
    let _ = writeln!(
        m,
        "### One melting cycle step by step\n\n\
         ![step trace](performance_steptrace.svg)\n\n\
         The P7 scene (N = {}, tolerance {:e}) run in-process through the driver with an \
         observer, from t = {} s ({} µs before the P7 run's first onset at {} s) to {} s ({} \
         µs after its second at {} s), {} s of wall time from the start: {} accepted steps \
         and {} rejected attempts. {} steps ({} %, {} rejected attempts) came while at least \
         one node was melted, in {} cascade(s) spanning {} µs together, with up to {} of the \
         {} nodes melted; {} steps ({} %, {} rejected attempts) with none melted cover the \
         rest of the {} ms. Steps run from {} s to {} s: the cascades' longest is {} s, the \
         shortest with no node melted {} s. The largest part of the error estimate limited \
         the cascade steps {} and the others {}. The melted-node count rose by {} in all: \
         the nodes melt one after another, {} evaluations (accepted and rejected) per node \
         that melted.\n",
        t.nodes,
        t.tolerance,
        sig(t.from_s, 9),
        sig(1e6 * (t.first_onset_s - t.from_s), 3),
        sig(t.first_onset_s, 9),
        sig(t.to_s, 9),
        sig(1e6 * (t.to_s - t.second_onset_s), 3),
        sig(t.second_onset_s, 9),
        sig(t.wall_s, 3),
        t.steps,
        t.rejected,
        t.cascade_steps,
        share(t.cascade_steps),
        t.cascade_rejected,
        t.cascades,
        sig(1e6 * t.cascade_duration_s, 3),
        t.max_melted,
        t.nodes,
        t.between_steps,
        share(t.between_steps),
        t.between_rejected,
        sig(1e3 * (t.to_s - t.from_s), 3),
        sig(t.shortest_step_s, 2),
        sig(t.longest_step_s, 2),
        sig(t.longest_cascade_step_s, 2),
        sig(t.shortest_between_step_s, 2),
        t.limited_in_cascade.words(),
        t.limited_between.words(),
        t.node_meltings,
        sig(
            (t.cascade_steps + t.cascade_rejected) as f64 / t.node_meltings.max(1) as f64,
            3
        ),
    );
}

/// The marker of a part in the figure.
fn marker(part: ErrorPart) -> Marker {
    match part {
        ErrorPart::Phi => Marker::Circle,
        ErrorPart::Eps => Marker::Square,
        ErrorPart::X => Marker::Triangle,
        ErrorPart::V => Marker::Cross,
    }
}

/// Step length against time (after the first onset, in `unit` s), one series per limiting
/// part, of the rows with `t` in `[lo, hi]` s.
fn step_panel(t: &StepTrace, title: &str, x_label: &str, unit: f64, lo: f64, hi: f64) -> Panel {
    let mut panel = Panel::new(title, x_label, "step length (s)")
        .scales(Scale::Linear, Scale::Log)
        .legend_outside();
    for (k, part) in ErrorPart::ALL.into_iter().enumerate() {
        let pts: Vec<(f64, f64)> = t
            .rows
            .iter()
            .filter(|r| r.t_s >= lo && r.t_s <= hi && ErrorPart::of(&r.error) == part)
            .map(|r| ((r.t_s - t.first_onset_s) / unit, r.h_s))
            .collect();
        if pts.is_empty() {
            continue;
        }
        panel.series.push(
            Series::new(
                format!("limited by {}", part.short()),
                decimate(&pts, 300),
                PALETTE[k],
            )
            .points()
            .marker(marker(part)),
        );
    }
    panel
}

/// The step trace: step lengths through the whole cycle, the first cascade zoomed, and the
/// melted nodes there.
pub(super) fn trace_figure(t: &StepTrace) -> Result<String, String> {
    let whole = step_panel(
        t,
        &format!(
            "P7's SFA contact (N = {}, tolerance {:e}): the steps of one melting cycle",
            t.nodes, t.tolerance
        ),
        "time after the first onset (ms)",
        1e-3,
        t.from_s,
        t.to_s,
    )
    .vline(1e3 * (t.second_onset_s - t.first_onset_s), "second onset");
    let zoom_end_s = t.first_cascade_end_s() + TRACE_MARGIN_S;
    let zoom = step_panel(
        t,
        "the first melting cascade",
        "time after the first onset (µs)",
        1e-6,
        t.from_s,
        zoom_end_s,
    )
    .vline(0.0, "first onset");
    let melted: Vec<(f64, f64)> = t
        .rows
        .iter()
        .filter(|r| r.t_s <= zoom_end_s)
        .map(|r| (1e6 * (r.t_s - t.first_onset_s), r.melted as f64))
        .collect();
    let mut nodes = Panel::new(
        "nodes melted (φ below the melt threshold) in the first cascade",
        "time after the first onset (µs)",
        "melted nodes",
    )
    .legend_outside();
    nodes
        .series
        .push(Series::new("melted nodes", melted, PALETTE[4]));
    render_svg(&[whole, zoom, nodes], 1, 900, 380)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(t_s: f64, h_s: f64, phi: f64, v: f64, melted: usize, rejected: u64) -> TraceRow {
        TraceRow {
            t_s,
            h_s,
            error: StepError {
                phi,
                eps: 0.0,
                x: 0.0,
                v,
            },
            melted,
            rejected,
        }
    }

    fn rows() -> Vec<TraceRow> {
        vec![
            row(1.0, 1e-6, 4e-5, 1e-9, 0, 0),
            row(1.1, 1e-7, 1e-9, 3e-5, 0, 1),
            row(1.2, 1e-9, 4e-5, 0.0, 3, 2),
            row(1.3, 2e-9, 4e-5, 0.0, 5, 0),
            row(1.4, 1e-5, 2e-5, 0.0, 0, 0),
            row(1.5, 3e-9, 1e-5, 0.0, 1, 4),
        ]
    }

    #[test]
    fn the_largest_part_limits_ties_to_the_earlier() {
        let e = |phi, eps, x, v| StepError { phi, eps, x, v };
        assert_eq!(ErrorPart::of(&e(1.0, 2.0, 0.5, 0.1)), ErrorPart::Eps);
        assert_eq!(ErrorPart::of(&e(1.0, 1.0, 1.0, 1.0)), ErrorPart::Phi);
        assert_eq!(ErrorPart::of(&e(0.0, 0.0, 0.0, 3.0)), ErrorPart::V);
        assert_eq!(ErrorPart::of(&e(0.0, 0.0, 2.0, 1.0)), ErrorPart::X);
    }

    #[test]
    fn the_trace_summary_counts_cascades_and_limiting_parts() {
        let t = StepTrace::from_rows(0.9, rows());
        assert_eq!((t.steps, t.rejected), (6, 7));
        assert_eq!((t.cascade_steps, t.cascade_rejected, t.cascades), (3, 6, 2));
        assert_eq!((t.between_steps, t.between_rejected), (3, 1));
        assert!((t.cascade_duration_s - 6e-9).abs() < 1e-20);
        assert_eq!(
            t.limited_in_cascade,
            PartCounts {
                phi: 3,
                ..PartCounts::default()
            }
        );
        assert_eq!(
            t.limited_between,
            PartCounts {
                phi: 2,
                v: 1,
                ..PartCounts::default()
            }
        );
        assert_eq!((t.shortest_step_s, t.longest_step_s), (1e-9, 1e-5));
        assert_eq!(t.longest_cascade_step_s, 3e-9);
        assert_eq!(t.shortest_between_step_s, 1e-7);
        assert_eq!(t.max_melted, 5);
        // Melted counts 0, 0, 3, 5, 0, 1: rises 3 + 2 + 1.
        assert_eq!(t.node_meltings, 6);
        assert_eq!((t.from_s, t.to_s), (0.9, 1.5));
        // The first cascade ends with the step at 1.3.
        assert_eq!(t.first_cascade_end_s(), 1.3);
        assert_eq!(
            t.limited_between.words(),
            "2 by the film φ, 1 by the stamp's velocity V"
        );
        let empty = StepTrace::from_rows(0.5, Vec::new());
        assert_eq!((empty.steps, empty.cascades, empty.to_s), (0, 0, 0.5));
        assert!(empty.shortest_step_s.is_nan());
        assert_eq!(empty.limited_in_cascade.words(), "none");
    }

    #[test]
    fn onsets_pair_only_with_equal_counts() {
        assert!(onset_deviations(&[1.0, 2.0], &[1.0]).is_empty());
        let d = onset_deviations(&[1.0, 2.5], &[1.5, 2.0]);
        assert_eq!(d, [0.5, 0.5]);
    }
}
