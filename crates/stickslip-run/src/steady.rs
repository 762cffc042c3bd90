//! Steady cycles: whether a run's last stick–slip cycles repeat, so that its regime is that of
//! the steady state and not of the window's end (`time.until = "periodic"` stops there).
//!
//! Cycle k runs from onset k−1 to onset k; its period is the time between them, its advance
//! the stamp's travel X between them, its peak the force peak before onset k. The run is
//! steady when each of the last `cycles` cycles agrees with the last one in all three within
//! `rtol` (relative). A run with fewer than `cycles` + 1 events is not steady.

use crate::slips::Slip;
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

/// The start of a cycle: time, stamp position, and the peak force that ends the cycle
/// before it.
fn mark_of_event(e: &MeltingEvent) -> (f64, f64, f64) {
    (e.t_onset_s, e.x_onset_m, e.f_peak_n)
}

/// The start of a slip cycle: the slip's start, the stamp there, the drive force's peak.
fn mark_of_slip(s: &Slip) -> (f64, f64, f64) {
    (s.t_start_s, s.x_start_m, s.f_start_n)
}

impl SteadyRule {
    /// Whether the last cycles of `events` repeat.
    #[must_use]
    pub fn is_steady(&self, events: &[MeltingEvent]) -> bool {
        let marks: Vec<_> = events.iter().map(mark_of_event).collect();
        self.marks_repeat(&marks)
    }

    /// Whether the last slip cycles repeat (slip k − 1 to slip k: the time and the stamp's
    /// advance between their starts, and slip k's peak), by the same rule: the stamp's scale
    /// of `time.until = "periodic"`.
    #[must_use]
    pub fn is_steady_slips(&self, slips: &[Slip]) -> bool {
        let marks: Vec<_> = slips.iter().map(mark_of_slip).collect();
        self.marks_repeat(&marks)
    }

    fn marks_repeat(&self, marks: &[(f64, f64, f64)]) -> bool {
        let cycles = usize::try_from(self.cycles).unwrap_or(usize::MAX);
        let n = marks.len();
        if cycles == 0 || n < cycles + 1 {
            return false;
        }
        let cycle = |k: usize| {
            let (a, b) = (marks[k - 1], marks[k]);
            (b.0 - a.0, b.1 - a.1, b.2)
        };
        let last = cycle(n - 1);
        let close = |x: f64, y: f64| (x - y).abs() <= self.rtol * y.abs();
        (n - cycles..n).all(|k| {
            let c = cycle(k);
            close(c.0, last.0) && close(c.1, last.1) && close(c.2, last.2)
        })
    }
}

impl SteadyRule {
    /// Why the last cycles of `events` do not repeat, in words (none when they do): too few
    /// events, or how far the last cycles' periods, advances and peaks spread around the last
    /// one against the tolerance. A film that melts many times within one slip of the stamp
    /// (an h0 = 1 nm contact under a soft spring) has cycles of very different lengths and
    /// never settles on this rule.
    #[must_use]
    pub fn why_not(&self, events: &[MeltingEvent]) -> Option<String> {
        if self.is_steady(events) {
            return None;
        }
        let cycles = usize::try_from(self.cycles).unwrap_or(usize::MAX);
        let n = events.len();
        if cycles == 0 || n < cycles + 1 {
            return Some(format!(
                "{n} meltings, and {} cycles need {} (time.steady_cycles = {})",
                self.cycles,
                cycles.saturating_add(1),
                self.cycles
            ));
        }
        let cycle = |k: usize| {
            let (a, b) = (&events[k - 1], &events[k]);
            [
                b.t_onset_s - a.t_onset_s,
                b.x_onset_m - a.x_onset_m,
                b.f_peak_n,
            ]
        };
        let last = cycle(n - 1);
        let mut spread = [0.0_f64; 3];
        for k in n - cycles..n {
            let c = cycle(k);
            for q in 0..3 {
                if last[q] != 0.0 {
                    spread[q] = spread[q].max(((c[q] - last[q]) / last[q]).abs());
                }
            }
        }
        Some(format!(
            "the last {} cycles differ from the last one by up to {:.3} % in period, {:.3} % in \
             the stamp's advance and {:.3} % in peak force, against time.steady_rtol = {} %",
            self.cycles,
            100.0 * spread[0],
            100.0 * spread[1],
            100.0 * spread[2],
            100.0 * self.rtol
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::SteadyRule;
    use crate::slips::Slip;

    #[test]
    fn repeating_slips_are_steady_on_the_stamps_scale() {
        let slip = |k: usize, t: f64, f: f64| Slip {
            k,
            t_start_s: t,
            t_end_s: t + 0.1,
            f_start_n: f,
            f_end_n: 0.0,
            x_start_m: 2.0 * t,
            x_end_m: 2.0 * t + 0.1,
            meltings: 78,
            dissipated_energy_j: f64::NAN,
        };
        let rule = SteadyRule::default();
        let regular: Vec<Slip> = (0..4)
            .map(|k| slip(k + 1, f64::from(k as u8), 3.0))
            .collect();
        assert!(rule.is_steady_slips(&regular));
        assert!(
            !rule.is_steady_slips(&regular[..3]),
            "3 cycles need 4 slips"
        );
        let mut drifting = regular.clone();
        drifting[3].f_start_n = 3.0 * (1.0 + 1.1e-3);
        assert!(!rule.is_steady_slips(&drifting));
    }
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
                energy: None,
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
        let why = rule.why_not(&events(&near)).unwrap();
        assert!(why.contains("0.110 % in peak force"), "{why}");
        assert!(rule.why_not(&events(&regular[..4])).is_none());
        let few = rule.why_not(&events(&regular[..2])).unwrap();
        assert!(few.starts_with("2 meltings, and 3 cycles need 4"), "{few}");
        assert!(!rule.is_steady(&events(&near)));
    }
}
