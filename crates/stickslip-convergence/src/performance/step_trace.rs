//! The step trace of one melting cycle of the SFA slip (P7's scene, issue 31): the scene run
//! in-process through the run library's driver with an observer, recording per accepted step
//! its length, the part of the error estimate that limited it, the melted nodes and the
//! attempts rejected before it, from just before the P7 run's first onset to just after its
//! second; its paragraph and figure. [`super::experiment`] runs it and places the paragraph;
//! [`super::report`] places the figure.

use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;
use stickslip_core::sim::{Simulation, StepError};
use stickslip_report::fmt::sig;
use stickslip_report::palette::PALETTE;
use stickslip_report::plot::{Marker, Panel, Scale, Series, decimate, render_svg};
use stickslip_run::Scene;
use stickslip_run::StopReason;
use stickslip_run::driver::{Control, Driver, Limit, NullSink};

/// From this long before the first onset to this long after the second, s.
pub const TRACE_MARGIN_S: f64 = 5e-6;

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

/// The step trace's paragraph.
pub(super) fn section(m: &mut String, t: &StepTrace) {
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
}
