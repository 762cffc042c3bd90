//! G1's cost: the h0 = 1 nm contact (`sfa.toml` as shipped: K = 5000 N/m, 0 → 0.11 s) at
//! N = 200 on the edge-graded grid against the paper's uniform grid, whole processes.
//!
//! The two grids do not simulate the same window alike: the uniform grid's outermost node
//! delays the first onset by 5 % (0.107 against 0.1017 s), so its 0.11 s hold two meltings
//! where the resolved contact has six. The row therefore gives both: the run to the first
//! melting's end (`time.max_events = 1`, the same physics on both grids: the target), and the
//! whole window with its meltings and the evaluations per melting.

use super::targets::verdict;
use super::{BenchSettings, Timed, timed_scene};
use serde::Serialize;
use std::fmt::Write as _;
use stickslip_report::fmt::{sig, tick};
use stickslip_run::keys::{contact, output, time};

/// The goal: the graded run at most this times the uniform one.
pub const G1_RATIO_GOAL: f64 = 1.5;

/// G1's measurements.
#[derive(Debug, Clone, Default, Serialize)]
pub struct GridCostBench {
    /// Uniform, N = 200, to the first melting's end.
    pub uniform_first: Timed,
    /// Graded (the default exponent), N = 200, to the first melting's end.
    pub graded_first: Timed,
    /// Uniform, the whole window.
    pub uniform_run: Timed,
    /// Graded, the whole window.
    pub graded_run: Timed,
}

impl GridCostBench {
    /// Wall-time ratios graded/uniform: (to the first melting's end, whole window).
    #[must_use]
    pub fn ratios(&self) -> (f64, f64) {
        (
            self.graded_first.wall_s / self.uniform_first.wall_s,
            self.graded_run.wall_s / self.uniform_run.wall_s,
        )
    }

    /// Whether the run to the first melting's end is within [`G1_RATIO_GOAL`].
    #[must_use]
    pub fn met(&self) -> bool {
        self.ratios().0 <= G1_RATIO_GOAL
    }
}

/// Evaluations per melting of a run.
fn per_melting(t: &Timed) -> f64 {
    t.evaluations() as f64 / t.events.max(1) as f64
}

/// Runs G1's cost.
///
/// # Errors
/// A run that failed.
pub fn measure(s: &BenchSettings, progress: &dyn Fn(&str)) -> Result<GridCostBench, String> {
    let scene = s.scene.with_file_name("sfa.toml");
    let repeats = s.repeats.min(5);
    let run = |tag: &str, graded: bool, first: bool| {
        let mut sets = vec![
            output::PROFILE_TIMES.set(Vec::<f64>::new()).to_string(),
            contact::NODES.set(200).to_string(),
        ];
        // Both grids named: the default is the graded one.
        sets.push(format!(
            "{}={}",
            contact::GRID.path,
            if graded { "graded" } else { "uniform" }
        ));
        if first {
            sets.push(time::MAX_EVENTS.set(1).to_string());
        }
        timed_scene(s, &scene, tag, &sets, 2, repeats, &[])
    };
    progress("G1: the h0 = 1 nm contact at N = 200, graded against uniform grid");
    Ok(GridCostBench {
        uniform_first: run("g1_uniform_first", false, true)?,
        graded_first: run("g1_graded_first", true, true)?,
        uniform_run: run("g1_uniform", false, false)?,
        graded_run: run("g1_graded", true, false)?,
    })
}

/// The G1 row of the targets table.
pub(super) fn targets_row(m: &mut String, b: &GridCostBench) {
    let (first, whole) = b.ratios();
    let _ = writeln!(
        m,
        "| G1 cost: the h0 = 1 nm contact (sfa.toml, N = 200) on the graded grid against the \
         uniform one, to the first melting's end (the same physics on both; whole process) | \
         ≤ {}× | {}× ({} s against {} s; {} and {} evaluations). The whole window 0 → 0.11 s: \
         {}× ({} s against {} s), {} meltings against {} (the uniform grid's first onset is \
         late), {} and {} evaluations per melting | {} |",
        tick(G1_RATIO_GOAL),
        sig(first, 3),
        sig(b.graded_first.wall_s, 3),
        sig(b.uniform_first.wall_s, 3),
        b.graded_first.evaluations(),
        b.uniform_first.evaluations(),
        sig(whole, 3),
        sig(b.graded_run.wall_s, 3),
        sig(b.uniform_run.wall_s, 3),
        b.graded_run.events,
        b.uniform_run.events,
        sig(per_melting(&b.graded_run), 4),
        sig(per_melting(&b.uniform_run), 4),
        verdict(b.met()),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_row_gives_both_windows_and_judges_the_first() {
        let b = GridCostBench {
            uniform_first: Timed::of(0.30, 4000, 1),
            graded_first: Timed::of(0.33, 4300, 1),
            uniform_run: Timed::of(0.40, 6000, 2),
            graded_run: Timed::of(1.10, 18000, 6),
        };
        let (first, whole) = b.ratios();
        assert!((first - 1.1).abs() < 1e-12 && (whole - 2.75).abs() < 1e-12);
        assert!(b.met());
        let mut m = String::new();
        targets_row(&mut m, &b);
        assert!(
            m.contains("| ≤ 1.5× | 1.10× (0.330 s against 0.300 s"),
            "{m}"
        );
        assert!(m.contains("6 meltings against 2"), "{m}");
        assert!(m.contains("**met**"), "{m}");
        let slow = GridCostBench {
            graded_first: Timed::of(0.5, 4300, 1),
            ..b
        };
        assert!(!slow.met());
    }
}
