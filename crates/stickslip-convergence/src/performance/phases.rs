//! Where a run's step evaluations go, phase by phase (issue 46's P7: which part of the slip a
//! cheaper integrator must make cheaper). The scene runs in-process through the run
//! library's driver with an observer that records every accepted step; each step is put in
//! one phase, and each phase's evaluations (accepted steps, rejected attempts and onset
//! retakes), time span and limiting error parts are summed:
//!
//! - **cascade**: at least one node melted at the step's end (φ below the threshold);
//! - **recovery**: an event still open with no node melted (the film regrowing to the
//!   recovery level);
//! - **initial stick**: no event open, before the run's first melted node;
//! - **later sticks**: no event open, after it. Their steps are also split by the smallest φ
//!   over the nodes, relative to the solid film's φ_s, which shows the approach to each onset
//!   (the first node's φ falling towards the melting threshold).
//!
//! `cargo run --release -p stickslip-convergence --example p7_phases` prints the table for
//! P7's scene (and any `section.key=value` settings given after it).

use super::step_trace::{ErrorPart, PartCounts};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;
use stickslip_core::sim::Simulation;
use stickslip_run::Scene;
use stickslip_run::StopReason;
use stickslip_run::driver::{Control, Driver, Limit, NullSink};

/// One accepted step, as the classification needs it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhaseRow {
    /// Its length, s.
    pub h_s: f64,
    /// The part of the error estimate that limited it.
    pub part: ErrorPart,
    /// Nodes melted at its end.
    pub melted: usize,
    /// Whether an event was open at its end.
    pub open: bool,
    /// Evaluations it took: 1 plus the attempts rejected and the onset retakes before it.
    pub evaluations: u64,
    /// The smallest φ over the nodes at its end, relative to the solid film's.
    pub phi_min_rel: f64,
}

/// The phases, in the table's order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Phase {
    /// A node melted.
    Cascade,
    /// An event open, no node melted.
    Recovery,
    /// Before the first melted node, no event open.
    InitialStick,
    /// After it, no event open.
    LaterSticks,
}

impl Phase {
    /// Every phase, in the table's order.
    pub const ALL: [Self; 4] = [
        Self::Cascade,
        Self::Recovery,
        Self::InitialStick,
        Self::LaterSticks,
    ];

    /// In the table's words.
    #[must_use]
    pub fn words(self) -> &'static str {
        match self {
            Self::Cascade => "cascade (a node melted)",
            Self::Recovery => "recovery (event open, none melted)",
            Self::InitialStick => "initial stick",
            Self::LaterSticks => "later sticks",
        }
    }
}

/// The later sticks' split by the smallest φ: lower bounds of the bands, relative to φ_s.
pub const APPROACH_BANDS: [f64; 4] = [0.9, 0.5, 0.1, 0.0];

/// One phase's sums.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct PhaseSums {
    /// Evaluations (accepted, rejected and retaken).
    pub evaluations: u64,
    /// Accepted steps.
    pub steps: u64,
    /// Time the steps span, s.
    pub span_s: f64,
    /// Steps by the part of the error that limited them.
    pub limits: PartCounts,
}

impl PhaseSums {
    fn add(&mut self, row: &PhaseRow) {
        self.evaluations += row.evaluations;
        self.steps += 1;
        self.span_s += row.h_s;
        self.limits.add(row.part);
    }
}

/// A run's evaluations by phase.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Phases {
    /// Per phase, in [`Phase::ALL`]'s order.
    pub phases: Vec<(Phase, PhaseSums)>,
    /// The later sticks per band of [`APPROACH_BANDS`] (the same order).
    pub approach: Vec<(f64, PhaseSums)>,
    /// Rises of the melted-node count summed over the run: nodes that melted.
    pub node_meltings: u64,
    /// Wall time of the run, s.
    pub wall_s: f64,
}

impl Phases {
    /// Every phase's evaluations together.
    #[must_use]
    pub fn evaluations(&self) -> u64 {
        self.phases.iter().map(|(_, s)| s.evaluations).sum()
    }

    /// The evaluations of one phase.
    #[must_use]
    pub fn evaluations_of(&self, phase: Phase) -> u64 {
        self.phases
            .iter()
            .filter(|(p, _)| *p == phase)
            .map(|(_, s)| s.evaluations)
            .sum()
    }

    /// The table (markdown) and a line on the cascades' evaluations per node that melted.
    #[must_use]
    pub fn table(&self) -> String {
        let mut out = String::from(
            "| phase | evaluations | steps | span, s | steps limited by |\n|---|---|---|---|---|\n",
        );
        let line = |out: &mut String, name: &str, s: &PhaseSums| {
            let _ = writeln!(
                out,
                "| {name} | {} | {} | {:.3e} | {} |",
                s.evaluations,
                s.steps,
                s.span_s,
                s.limits.words()
            );
        };
        for (phase, sums) in &self.phases {
            line(&mut out, phase.words(), sums);
        }
        for (i, (lower, sums)) in self.approach.iter().enumerate() {
            let upper = if i == 0 {
                "∞".to_string()
            } else {
                format!("{}", APPROACH_BANDS[i - 1])
            };
            line(
                &mut out,
                &format!("later sticks, min φ/φ_s in [{lower}, {upper})"),
                sums,
            );
        }
        let cascade = self
            .phases
            .iter()
            .find(|(p, _)| *p == Phase::Cascade)
            .map_or(0, |(_, s)| s.evaluations);
        let _ = writeln!(
            out,
            "\n{} evaluations in all ({:.2} s wall); {} node meltings, {:.2} cascade \
             evaluations per node that melted.",
            self.evaluations(),
            self.wall_s,
            self.node_meltings,
            cascade as f64 / (self.node_meltings.max(1) as f64)
        );
        out
    }
}

/// Sorts `rows` (in time order) into phases.
#[must_use]
pub fn classify(rows: &[PhaseRow]) -> Phases {
    let mut sums: Vec<(Phase, PhaseSums)> = Phase::ALL
        .iter()
        .map(|&p| (p, PhaseSums::default()))
        .collect();
    let mut approach: Vec<(f64, PhaseSums)> = APPROACH_BANDS
        .iter()
        .map(|&b| (b, PhaseSums::default()))
        .collect();
    let mut melted_before = false;
    let (mut node_meltings, mut melted_prev) = (0_u64, 0_usize);
    for row in rows {
        node_meltings += row.melted.saturating_sub(melted_prev) as u64;
        melted_prev = row.melted;
        let phase = if row.melted > 0 {
            melted_before = true;
            Phase::Cascade
        } else if row.open {
            Phase::Recovery
        } else if melted_before {
            Phase::LaterSticks
        } else {
            Phase::InitialStick
        };
        // `Phase::ALL` lists the phases in their declaration order.
        sums[phase as usize].1.add(row);
        if phase == Phase::LaterSticks
            && let Some(band) = approach
                .iter_mut()
                .find(|(lower, _)| row.phi_min_rel >= *lower)
        {
            band.1.add(row);
        }
    }
    Phases {
        phases: sums,
        approach,
        node_meltings,
        wall_s: 0.0,
    }
}

/// Runs `scene_path` with `sets` to its end and sorts its steps into phases.
///
/// # Errors
/// A scene that does not resolve or start, a failed run.
pub fn measure(scene_path: &Path, sets: &[String]) -> Result<Phases, String> {
    let scene =
        Scene::from_path(scene_path, sets).map_err(|e| format!("{}: {e}", scene_path.display()))?;
    let started = Instant::now();
    let mut sink = NullSink;
    let mut driver = Driver::start(&scene, &mut sink).map_err(|e| format!("phases: {e}"))?;
    let threshold = scene.config.melt_threshold;
    let phi_solid = driver
        .simulation()
        .state()
        .physical
        .phi
        .iter()
        .copied()
        .fold(0.0_f64, f64::max);
    let counters = |sim: &Simulation| {
        let c = &sim.state().counters;
        c.rejected_steps + c.onset_retakes
    };
    let mut extra = counters(driver.simulation());
    let mut t_prev = driver.simulation().time_s();
    let mut rows = Vec::new();
    let mut observe = |sim: &Simulation| {
        let state = sim.state();
        let phi = &state.physical.phi;
        rows.push(PhaseRow {
            h_s: sim.time_s() - t_prev,
            part: ErrorPart::of(&sim.last_step_error()),
            melted: phi.iter().filter(|&&p| p < threshold).count(),
            open: state.events.tracker.is_open(),
            evaluations: 1 + counters(sim) - extra,
            phi_min_rel: phi.iter().copied().fold(f64::INFINITY, f64::min) / phi_solid,
        });
        extra = counters(sim);
        t_prev = sim.time_s();
    };
    let mut control = Control {
        observer: Some(&mut observe),
        ..Control::default()
    };
    match driver.advance(
        &mut sink,
        &mut control,
        Limit::Time(scene.config.time.end_s),
    ) {
        Ok(Some(StopReason::Failure | StopReason::Refused)) => {
            return Err("phases: the run failed".to_string());
        }
        Ok(_) => {}
        Err(e) => return Err(format!("phases: {e}")),
    }
    let mut phases = classify(&rows);
    phases.wall_s = started.elapsed().as_secs_f64();
    Ok(phases)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(melted: usize, open: bool, evaluations: u64, phi_min_rel: f64) -> PhaseRow {
        PhaseRow {
            h_s: 1e-6,
            part: ErrorPart::Phi,
            melted,
            open,
            evaluations,
            phi_min_rel,
        }
    }

    #[test]
    fn steps_fall_in_their_phases_and_bands_and_meltings_are_counted() {
        let rows = [
            row(0, false, 2, 1.0),  // initial stick
            row(0, false, 1, 0.7),  // initial stick (its approach is not split)
            row(1, true, 3, 0.0),   // cascade: one node melted
            row(3, true, 4, 0.0),   // two more
            row(0, true, 1, 0.005), // recovery
            row(0, false, 1, 0.95), // later stick, band ≥ 0.9
            row(0, false, 5, 0.3),  // later stick, band [0.1, 0.5)
            row(2, true, 2, 0.0),   // the next cascade: two more
        ];
        let p = classify(&rows);
        let get = |phase: Phase| &p.phases.iter().find(|(q, _)| *q == phase).unwrap().1;
        assert_eq!(get(Phase::InitialStick).evaluations, 3);
        assert_eq!(get(Phase::InitialStick).steps, 2);
        assert_eq!(get(Phase::Cascade).evaluations, 9);
        assert_eq!(get(Phase::Recovery).evaluations, 1);
        assert_eq!(get(Phase::LaterSticks).evaluations, 6);
        assert_eq!(p.evaluations(), 19);
        assert_eq!(p.node_meltings, 5);
        let band = |lower: f64| {
            p.approach
                .iter()
                .find(|(b, _)| *b == lower)
                .unwrap()
                .1
                .clone()
        };
        assert_eq!(band(0.9).evaluations, 1);
        assert_eq!(band(0.5).evaluations, 0);
        assert_eq!(band(0.1).evaluations, 5);
        assert!((get(Phase::Cascade).span_s - 3e-6).abs() < 1e-18);
        assert!(
            p.table()
                .contains("5 node meltings, 1.80 cascade evaluations")
        );
    }
}
