//! P7–P8 (issue 31): the SFA contact (`validation/scenes/sfa.toml`, beside the fig2 scene)
//! with a soft drive spring, run by the CLI as a user runs it — step evaluations, wall time,
//! loop time per evaluation and its meltings against a tighter-tolerance reference computed
//! here, each also with `numerics.phi_error_floor`, and with the cascades' steps at a looser
//! tolerance — the step trace of one melting cycle of its slip ([`super::step_trace`]), and
//! where P7's evaluations go, phase by phase ([`super::phases`]).
//!
//! This module writes the P7 and P8 rows of the targets table and the section "P7–P8: the SFA
//! contact" (with the step trace's paragraph); [`super::report`] places them. Every number
//! comes from the measurements in [`SfaBench`] or the goals below.

use super::phases::{self, Phase, Phases};
use super::step_trace::{self, StepTrace};
use super::targets::verdict;
use super::{BenchSettings, Timed, timed_scene};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;
use stickslip_report::fmt::{sig, tick};
use stickslip_run::keys::words::GridChoice;
use stickslip_run::keys::{contact, drive, numerics, output, time};

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
/// P7–P8: the run also taken with this `numerics.event_phi_error_floor` (the floor for the
/// steps of a melting event only; the default is 0), beside the default's verdict.
pub const EVENT_PHI_ERROR_FLOOR: f64 = 0.1;

/// P7–P8: the run also taken with a cascade's steps at this multiple of the tolerance
/// (`numerics.event_tolerance_factor`) and `numerics.phi_error_floor` = [`PHI_ERROR_FLOOR`]:
/// the goal-oriented tolerance, today's stepper's cheapest settings that keep P7's meltings
/// (measured: the same meltings up to 300, not at 1000), beside the default's verdict.
pub const CASCADE_TOLERANCE_FACTOR: f64 = 100.0;

/// The settings of the cascade-tolerance variant (see [`CASCADE_TOLERANCE_FACTOR`]).
#[must_use]
pub fn cascade_tolerance_sets() -> Vec<String> {
    vec![
        numerics::EVENT_TOLERANCE_FACTOR
            .set(CASCADE_TOLERANCE_FACTOR)
            .to_string(),
        numerics::PHI_ERROR_FLOOR.set(PHI_ERROR_FLOOR).to_string(),
    ]
}

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
    /// The run again with `numerics.event_phi_error_floor` = [`EVENT_PHI_ERROR_FLOOR`], once,
    /// 2 threads (not part of the verdict either).
    pub event_floored: Option<Timed>,
    /// The run again with [`cascade_tolerance_sets`], once, 2 threads (not part of the verdict
    /// either).
    pub cascade_tolerance: Option<Timed>,
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
            event_floored: None,
            cascade_tolerance: None,
        }
    }

    /// The floored run's largest onset deviation from the reference, s (none without the run,
    /// or when the counts differ).
    #[must_use]
    pub fn floored_max_onset_deviation_s(&self) -> Option<f64> {
        self.max_onset_deviation_of(self.floored.as_ref()?)
    }

    /// A variant run's largest onset deviation from the reference, s (none when the counts
    /// differ).
    fn max_onset_deviation_of(&self, variant: &Timed) -> Option<f64> {
        onset_deviations(
            &variant.event_values.onsets_s,
            &self.reference.event_values.onsets_s,
        )
        .into_iter()
        .reduce(f64::max)
    }

    /// The floored run's result in words: `116139 evaluations (3.54 s, 1.93× fewer), 78
    /// meltings, largest onset deviation 4.1 µs` (none without the run).
    #[must_use]
    pub fn floored_result(&self) -> Option<String> {
        Some(self.result_of(self.floored.as_ref()?))
    }

    /// The event-floored run's result in words, as [`SfaTarget::floored_result`]'s.
    #[must_use]
    pub fn event_floored_result(&self) -> Option<String> {
        Some(self.result_of(self.event_floored.as_ref()?))
    }

    /// The cascade-tolerance run's result in words, as [`SfaTarget::floored_result`]'s, with
    /// its wall time against the default run's in the same bench run.
    #[must_use]
    pub fn cascade_tolerance_result(&self) -> Option<String> {
        let variant = self.cascade_tolerance.as_ref()?;
        Some(format!(
            "{}; {}× less wall time than the default settings' run",
            self.result_of(variant),
            sig(self.wall_s / variant.wall_s.max(f64::MIN_POSITIVE), 3)
        ))
    }

    /// A variant run's result in words (see [`SfaTarget::floored_result`]).
    fn result_of(&self, variant: &Timed) -> String {
        let deviation = self.max_onset_deviation_of(variant).map_or_else(
            || "onsets not paired (the counts differ)".into(),
            |d| format!("largest onset deviation {} µs", sig(1e6 * d, 2)),
        );
        format!(
            "{} evaluations ({} s, {}× fewer), {} meltings, {deviation}",
            variant.evaluations(),
            sig(variant.wall_s, 3),
            sig(
                self.evaluations as f64 / variant.evaluations().max(1) as f64,
                3
            ),
            variant.events,
        )
    }

    /// `; with numerics.phi_error_floor = 0.1: …; with numerics.event_phi_error_floor = 0.1:
    /// …; with numerics.event_tolerance_factor = 100 and …: …` for the targets table (each
    /// empty without its run).
    fn floored_words(&self) -> String {
        let floored = self
            .floored_result()
            .map(|w| format!("; with numerics.phi_error_floor = {PHI_ERROR_FLOOR}: {w}"));
        let event = self.event_floored_result().map(|w| {
            format!("; with numerics.event_phi_error_floor = {EVENT_PHI_ERROR_FLOOR}: {w}")
        });
        let cascade = self.cascade_tolerance_result().map(|w| {
            format!(
                "; with numerics.event_tolerance_factor = {} and numerics.phi_error_floor = \
                 {PHI_ERROR_FLOOR}: {w}",
                tick(CASCADE_TOLERANCE_FACTOR)
            )
        });
        floored.into_iter().chain(event).chain(cascade).collect()
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
    /// P7's evaluations by phase, in-process: the default settings and
    /// [`cascade_tolerance_sets`] (empty with `--quick`).
    pub p7_phases: [Phases; 2],
}

/// The small outputs and soft spring of P7–P8 up to `end_s`, on the uniform grid the targets
/// are defined on (the scene's default grid is graded toward the edge).
pub fn sfa_sets(end_s: f64) -> Vec<String> {
    vec![
        drive::STIFFNESS.set(SFA_STIFFNESS).to_string(),
        contact::GRID.set(GridChoice::Uniform).to_string(),
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
    // One run of the scene with `sets` and `extra`, once on 2 threads, judged against `onsets_s`.
    let once = |name: &str, extra: &[String], onsets_s: &[f64]| {
        let with = [sets.as_slice(), extra].concat();
        timed_scene(s, scene, name, &with, 2, 1, onsets_s)
    };
    let tolerance = time::TOLERANCE.set(reference_tolerance).to_string();
    let reference = once(&format!("{tag}_reference"), &[tolerance], &[])?;
    let onsets_s = &reference.event_values.onsets_s;
    let run = once(tag, &[], onsets_s)?;
    let floor = numerics::PHI_ERROR_FLOOR.set(PHI_ERROR_FLOOR).to_string();
    let floored = once(&format!("{tag}_floored"), &[floor], onsets_s)?;
    let event_floor = numerics::EVENT_PHI_ERROR_FLOOR
        .set(EVENT_PHI_ERROR_FLOOR)
        .to_string();
    let event_floored = once(&format!("{tag}_event_floored"), &[event_floor], onsets_s)?;
    let cascade_tolerance = once(
        &format!("{tag}_cascade_tolerance"),
        &cascade_tolerance_sets(),
        onsets_s,
    )?;
    Ok(SfaTarget {
        floored: Some(floored),
        event_floored: Some(event_floored),
        cascade_tolerance: Some(cascade_tolerance),
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
    let step_trace = step_trace::trace(&scene, &p7.settings, &p7.run.event_values.onsets_s)?;
    let p7_phases = if s.quick {
        [Phases::default(), Phases::default()]
    } else {
        progress("P7: its evaluations by phase, in-process, with either settings");
        let cheap = [p7.settings.clone(), cascade_tolerance_sets()].concat();
        [
            phases::measure(&scene, &p7.settings)?,
            phases::measure(&scene, &cheap)?,
        ]
    };
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
        p7_phases,
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
        "| P7 the SFA contact ({}, K = {} N/m, time.end = {} s; N = {} on the uniform grid, tolerance {}) against \
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
        "| P8 the SFA contact at V0 = {} m/s (K = {} N/m, time.end = {} s; N = {} on the uniform grid) against its \
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
    if p7.event_floored.is_some() || p8.event_floored.is_some() {
        let _ = writeln!(
            m,
            "Both again with `numerics.event_phi_error_floor` = {EVENT_PHI_ERROR_FLOOR} instead \
             (the same floor for the steps that start while a melting event is open only; the \
             stick from an event's end to the next onset, where the onset's error is made, \
             keeps φ's own scale, so the stick before the first onset is stepped as by \
             default), against the same references; not part of the verdicts either. P7: {}. \
             P8: {}.\n",
            p7.event_floored_result()
                .unwrap_or_else(|| "not run".into()),
            p8.event_floored_result()
                .unwrap_or_else(|| "not run".into()),
        );
    }
    if p7.cascade_tolerance.is_some() || p8.cascade_tolerance.is_some() {
        let _ = writeln!(
            m,
            "Both again with a cascade's steps at {f}× the tolerance \
             (`numerics.event_tolerance_factor` = {f}: a step that starts while a melting event \
             is open; from the event's end to the next onset, where the onset's error is made, \
             the scene's tolerance) and `numerics.phi_error_floor` = {PHI_ERROR_FLOOR}: the \
             goal-oriented tolerance, today's stepper at its cheapest settings that keep P7's \
             meltings, against the same references; not part of the verdicts either. P7: {}. \
             P8: {}.\n",
            p7.cascade_tolerance_result()
                .unwrap_or_else(|| "not run".into()),
            p8.cascade_tolerance_result()
                .unwrap_or_else(|| "not run".into()),
            f = tick(CASCADE_TOLERANCE_FACTOR),
        );
    }
    phases_section(m, &b.p7_phases);
    step_trace::section(m, &b.step_trace);
}

/// "Where P7's evaluations go": the two phase tables and what they leave for the goal
/// (nothing without the phases, as with `--quick`).
fn phases_section(m: &mut String, [default, cheap]: &[Phases; 2]) {
    if default.phases.is_empty() || cheap.phases.is_empty() {
        return;
    }
    let _ = writeln!(
        m,
        "### Where P7's evaluations go\n\n\
         P7's scene run in-process through the driver with an observer (one thread), every \
         accepted step put in one phase: a cascade (a node melted at the step's end), the \
         recovery (an event open, none melted), the stick before the first onset, and the \
         sticks after it, split by the smallest φ over the nodes against the solid film's φ_s \
         (the approach to each onset). Evaluations count accepted steps, rejected attempts and \
         onset retakes; each step is counted once, under the part of the error estimate that \
         limited it.\n\n\
         With the default settings:\n\n{}\n\
         With the cascade tolerance (`numerics.event_tolerance_factor` = {}, \
         `numerics.phi_error_floor` = {PHI_ERROR_FLOOR}):\n\n{}\n{}\n",
        default.table(),
        tick(CASCADE_TOLERANCE_FACTOR),
        cheap.table(),
        phases_words(cheap),
    );
}

/// What the sticks leave of P7's goal once the cascades are cheap, in words.
fn phases_words(p: &Phases) -> String {
    let of = |phase: Phase| p.evaluations_of(phase);
    let sticks = of(Phase::InitialStick) + of(Phase::LaterSticks) + of(Phase::Recovery);
    let goal = if sticks > P7_EVALUATIONS_GOAL {
        format!(
            "{}× the goal of {P7_EVALUATIONS_GOAL} on their own",
            sig(sticks as f64 / P7_EVALUATIONS_GOAL as f64, 3)
        )
    } else {
        format!(
            "{} of the goal of {P7_EVALUATIONS_GOAL}, leaving {} for the cascades",
            sig(sticks as f64 / P7_EVALUATIONS_GOAL as f64, 2),
            P7_EVALUATIONS_GOAL - sticks
        )
    };
    format!(
        "With the cascade tolerance the cascades take {} evaluations ({} per node that \
         melted) and the sticks and recoveries {} of the {} ({} before the first onset, {} \
         after it): {goal}.",
        of(Phase::Cascade),
        sig(of(Phase::Cascade) as f64 / p.node_meltings.max(1) as f64, 3),
        sticks,
        p.evaluations(),
        of(Phase::InitialStick),
        of(Phase::LaterSticks) + of(Phase::Recovery),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A run whose phases took `evaluations` in the order of [`Phase::ALL`].
    fn phases_of(evaluations: [u64; 4], node_meltings: u64) -> Phases {
        Phases {
            phases: Phase::ALL
                .iter()
                .zip(evaluations)
                .map(|(&p, e)| {
                    (
                        p,
                        phases::PhaseSums {
                            evaluations: e,
                            ..phases::PhaseSums::default()
                        },
                    )
                })
                .collect(),
            node_meltings,
            ..Phases::default()
        }
    }

    #[test]
    fn the_phases_words_say_what_the_sticks_leave_of_the_goal() {
        let over = phases_words(&phases_of([20_000, 10, 8_000, 26_000], 13_500));
        assert!(over.contains("the cascades take 20000 evaluations (1.48 per node"));
        assert!(over.contains(
            "recoveries 34010 of the 54010 (8000 before the first onset, 26010 after it)"
        ));
        assert!(
            over.contains("1.13× the goal of 30000 on their own"),
            "{over}"
        );
        let under = phases_words(&phases_of([5_000, 0, 4_000, 16_000], 10_000));
        assert!(
            under.contains("0.67 of the goal of 30000, leaving 10000 for the cascades"),
            "{under}"
        );
        let mut m = String::new();
        phases_section(&mut m, &[Phases::default(), Phases::default()]);
        assert!(m.is_empty(), "no section without the phases (--quick)");
    }

    #[test]
    fn onsets_pair_only_with_equal_counts() {
        assert!(onset_deviations(&[1.0, 2.0], &[1.0]).is_empty());
        let d = onset_deviations(&[1.0, 2.5], &[1.5, 2.0]);
        assert_eq!(d, [0.5, 0.5]);
    }
}
