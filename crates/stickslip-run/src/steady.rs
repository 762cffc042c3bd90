//! Steady cycles: whether a run's last stick–slip cycles repeat, so that its regime is that of
//! the steady state and not of the window's end (`time.until = "periodic"` stops there).
//!
//! Cycle k runs from onset k−1 to onset k; its period is the time between them, its advance
//! the stamp's travel X between them, its peak the force peak before onset k. The run is
//! steady when each of the last `cycles` cycles agrees with the last one in all three within
//! `rtol` (relative). A run with fewer than `cycles` + 1 events is not steady.

use serde::{Deserialize, Serialize};
use stickslip_core::sim::events::MeltingEvent;

/// Default number of cycles that must repeat (`time.steady_cycles`'s registry default).
pub const DEFAULT_CYCLES: u64 = match crate::keys::time::STEADY_CYCLES.fixed_default() {
    Some(n) => n.unsigned_abs(),
    None => panic!("time.steady_cycles has a fixed default"),
};
/// Default relative tolerance of the repetition (`time.steady_rtol`'s registry default).
pub const DEFAULT_RTOL: f64 = match crate::keys::time::STEADY_RTOL.fixed_default() {
    Some(v) => v,
    None => panic!("time.steady_rtol has a fixed default"),
};

/// When a run counts as steady, and whether it stops there.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SteadyRule {
    /// Stop at the end of the event that makes the run steady (`time.until = "periodic"`).
    pub stop: bool,
    /// Cycles that must repeat (`time.steady_cycles`).
    pub cycles: u64,
    /// Relative tolerance (`time.steady_rtol`).
    pub rtol: f64,
}

impl Default for SteadyRule {
    fn default() -> Self {
        Self {
            stop: false,
            cycles: DEFAULT_CYCLES,
            rtol: DEFAULT_RTOL,
        }
    }
}

impl SteadyRule {
    /// Whether the last cycles of `events` repeat.
    #[must_use]
    pub fn is_steady(&self, events: &[MeltingEvent]) -> bool {
        let cycles = usize::try_from(self.cycles).unwrap_or(usize::MAX);
        let n = events.len();
        if cycles == 0 || n < cycles + 1 {
            return false;
        }
        let cycle = |k: usize| {
            let (a, b) = (&events[k - 1], &events[k]);
            (
                b.t_onset_s - a.t_onset_s,
                b.x_onset_m - a.x_onset_m,
                b.f_peak_n,
            )
        };
        let last = cycle(n - 1);
        let close = |x: f64, y: f64| (x - y).abs() <= self.rtol * y.abs();
        (n - cycles..n).all(|k| {
            let c = cycle(k);
            close(c.0, last.0) && close(c.1, last.1) && close(c.2, last.2)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::SteadyRule;
    use stickslip_core::sim::events::MeltingEvent;

    fn events(onsets: &[(f64, f64, f64)]) -> Vec<MeltingEvent> {
        onsets
            .iter()
            .enumerate()
            .map(|(k, &(t, x, f))| MeltingEvent {
                k: k + 1,
                t_onset_s: t,
                r_first_m: 0.0,
                x_onset_m: x,
                f_peak_n: f,
                r_min_m: 0.0,
                t_center_s: None,
                max_melted_fraction: 0.0,
                t_end_s: Some(t + 0.1),
                recovery: 1.0,
                f_mean_n: 0.0,
                melted_area: 1.0,
            })
            .collect()
    }

    #[test]
    fn repeating_cycles_are_steady_and_drifting_ones_are_not() {
        let rule = SteadyRule::default();
        // Period 1, advance 2, peak 3 from the second event on: steady after 4 events.
        let regular: Vec<(f64, f64, f64)> = (0..6)
            .map(|k| (f64::from(k), 2.0 * f64::from(k), 3.0))
            .collect();
        assert!(
            !rule.is_steady(&events(&regular[..3])),
            "3 cycles need 4 events"
        );
        assert!(rule.is_steady(&events(&regular[..4])));
        // Shrinking periods (the spring-driven fig2): not steady.
        let shrinking: Vec<(f64, f64, f64)> = (0..8)
            .map(|k| {
                let t: f64 = (0..k).map(|j| 0.9f64.powi(j)).sum();
                (t, t, 3.0)
            })
            .collect();
        assert!(!rule.is_steady(&events(&shrinking)));
        // Within the tolerance: steady; just outside: not.
        let mut near = regular.clone();
        near[5].2 = 3.0 * (1.0 + 0.9e-3);
        assert!(rule.is_steady(&events(&near)));
        near[5].2 = 3.0 * (1.0 + 1.1e-3);
        assert!(!rule.is_steady(&events(&near)));
    }
}
