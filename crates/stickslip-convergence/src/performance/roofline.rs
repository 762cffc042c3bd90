//! The roofline target: the accurate stepper's evaluation at N = 2000 against the floor of one
//! evaluation on this machine (`stickslip_benches::evaluation_floor`: the fused node pass with
//! one vectorised exponential per node, and the two MDR applies), both timed in-process.
//!
//! The evaluation is one fixed step of fig2 (Δt = 2e-8 s, nothing recorded) warmed into its
//! first stick phase (t = 0.3 ms), the same as the criterion bench `step_per_n/accurate/2000`:
//! in the stick phase one step is one evaluation (no rejections, no retakes). Each figure is
//! the median over [`REPEATS`] timings of [`BATCH`] calls, with its min–max. The same step on
//! a rigid substrate, which solves no coupling, splits the evaluation into its node side and
//! its coupling, each against its part of the floor.

use super::spread::min_max;
use super::targets::verdict;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::hint::black_box;
use std::time::Instant;
use stickslip_benches::evaluation_floor::Floor;
use stickslip_core::config::Substrate;
use stickslip_report::fmt::{sig, tick};
use stickslip_report::stats::median;
use stickslip_run::keys::contact;

/// Nodes.
pub const NODES: usize = 2000;
/// The goal: the evaluation within this factor of the floor.
pub const GOAL: f64 = 2.0;
/// Timings per figure.
pub const REPEATS: usize = 7;
/// Calls per timing.
pub const BATCH: usize = 200;

/// One timed figure: µs per call.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct PerCall {
    /// Median, µs.
    pub median_us: f64,
    /// Every timing, µs per call.
    pub all_us: Vec<f64>,
}

impl PerCall {
    fn of(all_us: Vec<f64>) -> Self {
        Self {
            median_us: median(&all_us),
            all_us,
        }
    }

    fn text(&self) -> String {
        let (lo, hi) = min_max(&self.all_us);
        format!(
            "{} µs ({}–{})",
            sig(self.median_us, 3),
            sig(lo, 3),
            sig(hi, 3)
        )
    }
}

/// The roofline's measurements.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct RooflineBench {
    /// The fused node pass.
    pub node_pass: PerCall,
    /// The forward and back transforms.
    pub two_applies: PerCall,
    /// Both in sequence: the floor.
    pub floor: PerCall,
    /// The stepper's evaluation (one fixed step in the stick phase).
    pub evaluation: PerCall,
    /// The same step on a rigid substrate, which solves no coupling: the evaluation's node
    /// side; the rest is the coupling's (empty in a report written before it was measured).
    #[serde(default)]
    pub rigid_evaluation: PerCall,
    /// Threads the evaluation's compliance ran on (0 in a report written before it was
    /// recorded); the floor's two applies run on one.
    #[serde(default)]
    pub evaluation_compliance_threads: usize,
}

impl RooflineBench {
    /// Evaluation / floor (medians).
    #[must_use]
    pub fn ratio(&self) -> f64 {
        self.evaluation.median_us / self.floor.median_us
    }
}

/// µs per call of `f`, [`REPEATS`] timings of [`BATCH`] calls after one warm-up batch.
fn time_calls(mut f: impl FnMut()) -> PerCall {
    for _ in 0..BATCH {
        f();
    }
    let all = (0..REPEATS)
        .map(|_| {
            let start = Instant::now();
            for _ in 0..BATCH {
                f();
            }
            1e6 * start.elapsed().as_secs_f64() / BATCH as f64
        })
        .collect();
    PerCall::of(all)
}

/// Measures the floor and the evaluation (a few seconds).
#[must_use]
pub fn measure(progress: &dyn Fn(&str)) -> RooflineBench {
    progress("Roofline: the evaluation at N = 2000 against the floor of one evaluation");
    let mut floor = Floor::fig2(NODES);
    let node_pass = time_calls(|| {
        black_box(floor.node_pass(black_box(1.5e6)));
    });
    let two_applies = time_calls(|| {
        black_box(floor.two_applies());
    });
    let both = time_calls(|| {
        black_box(floor.evaluation(black_box(1.5e6)));
    });
    let mut driver = stickslip_benches::warmed(&[contact::NODES.set(NODES as i64)]);
    let evaluation = time_calls(|| stickslip_benches::step(&mut driver));
    let evaluation_compliance_threads = driver.simulation().compliance_threads();
    let mut rigid = stickslip_benches::warmed(&[
        contact::NODES.set(NODES as i64),
        contact::SUBSTRATE.set(Substrate::Rigid),
    ]);
    let rigid_evaluation = time_calls(|| stickslip_benches::step(&mut rigid));
    RooflineBench {
        node_pass,
        two_applies,
        floor: both,
        evaluation,
        rigid_evaluation,
        evaluation_compliance_threads,
    }
}

/// The targets table's row.
pub(super) fn targets_row(m: &mut String, r: &RooflineBench) {
    // The evaluation's two sides, each against its part of the floor: the same step on a
    // rigid substrate (no coupling) against the node pass, the rest against the two applies.
    let sides = if r.rigid_evaluation.median_us > 0.0 {
        let coupling_us = r.evaluation.median_us - r.rigid_evaluation.median_us;
        format!(
            "; of the evaluation, the node side (the same step on a rigid substrate) {}, {}× \
             the node pass, and the coupling the rest, {} µs, {}× the two applies",
            r.rigid_evaluation.text(),
            sig(r.rigid_evaluation.median_us / r.node_pass.median_us, 3),
            sig(coupling_us, 3),
            sig(coupling_us / r.two_applies.median_us, 3)
        )
    } else {
        String::new()
    };
    let threads = match r.evaluation_compliance_threads {
        0 => String::new(),
        1 => ", its compliance on one thread".to_string(),
        t => format!(", its compliance on {t} threads as a run's, the floor's applies on one"),
    };
    let _ = writeln!(
        m,
        "| Roofline: the accurate stepper's evaluation at N = {NODES} (one fixed step of fig2 in \
         its stick phase, in-process{threads}) against the floor of one evaluation (a fused node pass \
         with one vectorised exponential per node, and the two MDR applies) | ≤ {}× | {}× ({} \
         against {}; node pass {}, two applies {}{sides}) | {} |",
        tick(GOAL),
        sig(r.ratio(), 3),
        r.evaluation.text(),
        r.floor.text(),
        r.node_pass.text(),
        r.two_applies.text(),
        verdict(r.ratio() <= GOAL)
    );
}
