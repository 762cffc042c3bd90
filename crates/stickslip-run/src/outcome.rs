//! What a run hands back: status, why it stopped, the failure if any, events, summary,
//! counters and timing. Sinks turn it into files (run.json, events.csv) or keep it in memory.

use crate::summary::RunSummary;
use serde::{Deserialize, Serialize};
use stickslip_core::preflight::{Finding, Preflight};
use stickslip_core::sim::NumericalFailure;
use stickslip_core::sim::events::MeltingEvent;

/// Where a run stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RunStatus {
    /// Started, not ended (or killed without a trace).
    Running,
    /// Stopped by a signal; a checkpoint is there to resume from.
    Interrupted,
    /// Finished.
    Ok,
    /// Stopped by a numerical failure or refused before the first step.
    Failed,
}

impl RunStatus {
    /// The name as written.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Running => "running",
            Self::Interrupted => "interrupted",
            Self::Ok => "ok",
            Self::Failed => "failed",
        }
    }
}

/// Step counters of a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct StepCounts {
    /// Steps taken (with adaptive stepping: the accepted ones).
    pub steps: u64,
    /// Adaptive stepping: accepted steps (0 with fixed steps).
    pub accepted_steps: u64,
    /// Adaptive stepping: rejected attempts (0 with fixed steps).
    pub rejected_steps: u64,
    /// Adaptive stepping: steps accepted at time.dt_min above the tolerance.
    pub forced_steps: u64,
    /// Adaptive stepping: accepted attempts that brought a melting onset and were taken again
    /// ending at the located melting time (0 with fixed steps). Step evaluations are
    /// accepted + rejected + onset retakes.
    #[serde(default)]
    pub onset_retakes: u64,
    /// Coupling-solver iterations summed over all steps (accurate scheme).
    pub coupling_iterations: u64,
}

/// Why the loop stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// `time.end` reached.
    End,
    /// `time.max_events` events have ended.
    MaxEvents,
    /// An event stayed open for `time.max_open_event`.
    OpenEvent,
    /// The last cycles repeat (`time.until = "periodic"`).
    Periodic,
    /// A numerical failure.
    Failure,
    /// Refused before the first step (the preflight's verdict, e.g. a diverging lagged sweep).
    Refused,
    /// Interrupted (a signal, Ctrl-C, or the caller's poll).
    Interrupted,
}

impl StopReason {
    /// The name as written to run.json.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::End => "end",
            Self::MaxEvents => "max_events",
            Self::OpenEvent => "open_event",
            Self::Periodic => "periodic",
            Self::Failure => "failure",
            Self::Refused => "refused",
            Self::Interrupted => "interrupted",
        }
    }

    /// The run's status for this stop.
    #[must_use]
    pub fn status(self) -> RunStatus {
        match self {
            Self::End | Self::MaxEvents | Self::OpenEvent | Self::Periodic => RunStatus::Ok,
            Self::Failure | Self::Refused => RunStatus::Failed,
            Self::Interrupted => RunStatus::Interrupted,
        }
    }
}

/// The result of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunOutcome {
    /// Why it stopped.
    pub stop: StopReason,
    /// The failure (stop = `Failure`).
    pub failure: Option<NumericalFailure>,
    /// Melting events.
    pub events: Vec<MeltingEvent>,
    /// Slips of the stamp that ended.
    pub slips: Vec<crate::slips::Slip>,
    /// Summary and regime (docs/model.md#regimes-and-friction-maps).
    pub summary: RunSummary,
    /// Step counters.
    pub counts: StepCounts,
    /// Time reached, s.
    pub t_final_s: f64,
    /// Wall-clock time of the loop, s (summed over the processes of a resumed run).
    pub wall_seconds: f64,
    /// Rows written to series.csv (and probes.csv).
    pub series_rows: u64,
    /// The preflight (at t = 0).
    pub preflight: Preflight,
    /// Notes and warnings of the preflight and unusual values.
    pub warnings: Vec<Finding>,
}

impl RunOutcome {
    /// The run's status.
    #[must_use]
    pub fn status(&self) -> RunStatus {
        self.stop.status()
    }

    /// The one-line summary printed at the end of a run.
    #[must_use]
    pub fn summary_line(&self) -> String {
        let s = &self.summary;
        let us = show_time;
        let mut parts = vec![format!("{} events, regime {}", s.n_events, s.regime.name())];
        if let Some(t) = s.t_first_onset {
            parts.push(format!("first onset {}", us(t)));
        }
        if let Some(p) = s.period_last {
            parts.push(format!("last period {}", us(p)));
        }
        let peaks: Vec<f64> = self.events.iter().map(|e| e.f_peak_n).collect();
        if let (Some(lo), Some(hi)) = (
            peaks.iter().copied().reduce(f64::min),
            peaks.iter().copied().reduce(f64::max),
        ) {
            parts.push(format!("peak force {:.4e} … {:.4e} N", lo, hi));
        }
        if let Some(e) = s.energy_per_cycle {
            parts.push(format!(
                "dissipated {e:.4e} J per cycle (the last complete one)"
            ));
        }
        if let Some(b) = &s.energy {
            parts.push(format!(
                "{:.4e} J in all (drive's work {:.4e} J; energy books' residual {:.1e} J)",
                b.dissipated_j(),
                b.flows.drive_work_j,
                b.residual_j
            ));
        }
        let mut line = parts.join(", ");
        if let Some(regime) = s.stamp_regime {
            // The stamp's scale: its slips, the largest of them, its regime, and how often the
            // film melts and the stamp slips once settled.
            let n = s.n_slips;
            line.push_str(&format!(
                "; stamp: {n} slip{}",
                if n == 1 { "" } else { "s" }
            ));
            if let Some(big) = self
                .slips
                .iter()
                .max_by(|a, b| a.drop_n().total_cmp(&b.drop_n()))
            {
                line.push_str(&format!(
                    " (the largest: drop {:.4e} N, jump {:.4e} m, {} melting{})",
                    big.drop_n(),
                    big.jump_m(),
                    big.meltings,
                    if big.meltings == 1 { "" } else { "s" }
                ));
            }
            line.push_str(&format!(", stamp regime {}", regime.name()));
            if regime == crate::cycles::StampRegime::Transient {
                // Not a verdict: the window was too short to tell.
                line.push_str(" (undecided: a longer time.end or time.travel decides)");
            }
            if let Some(c) = &s.cycles {
                let every = |stats: &crate::cycles::CycleStats, what: &str| {
                    stats
                        .interval_s
                        .map(|i| format!("{what} every {} (median)", us(i.median)))
                };
                let settled: Vec<String> =
                    [every(&c.slips, "slips"), every(&c.meltings, "meltings")]
                        .into_iter()
                        .flatten()
                        .collect();
                if !settled.is_empty() {
                    line.push_str(&format!(
                        "; settled from {}: {}",
                        us(c.settled_from_s),
                        settled.join(", ")
                    ));
                }
            }
        }
        line
    }
}

/// A time in the unit that fits it (s, ms, µs, ns) with six significant digits: "2.50000 s",
/// "944.464 ms", "13.4302 µs".
#[must_use]
pub fn show_time(t_s: f64) -> String {
    let a = t_s.abs();
    let (scale, unit) = if a >= 1.0 || a == 0.0 || !a.is_finite() {
        (1.0, "s")
    } else if a >= 1e-3 {
        (1e3, "ms")
    } else if a >= 1e-6 {
        (1e6, "µs")
    } else {
        (1e9, "ns")
    };
    let v = t_s * scale;
    // Six significant digits: the decimals left after the integer part's digits.
    let digits = if v == 0.0 || !v.is_finite() {
        0
    } else {
        (v.abs().log10().floor() as i32 + 1).clamp(1, 6)
    };
    let decimals = if digits == 0 {
        0
    } else {
        usize::try_from(6 - digits).unwrap_or(0)
    };
    format!("{v:.decimals$} {unit}")
}

#[cfg(test)]
mod time_tests {
    use super::show_time;

    #[test]
    fn times_print_in_the_unit_that_fits_them() {
        assert_eq!(show_time(0.9444635584), "944.464 ms");
        assert_eq!(show_time(2.5), "2.50000 s");
        assert_eq!(show_time(14.798e-3), "14.7980 ms");
        assert_eq!(show_time(13.4302e-6), "13.4302 µs");
        assert_eq!(show_time(2.2e-8), "22.0000 ns");
        assert_eq!(show_time(1234.5), "1234.50 s");
        assert_eq!(show_time(0.0), "0 s");
    }
}
