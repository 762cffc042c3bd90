//! The per-run summary and regime (docs/model.md#regimes-and-friction-maps), computed from the
//! run's events and the event tracker's totals (every step counted, not sampled rows).
//!
//! - `n_events`, `t_first_onset`; `period_last` and `x_period_last`: time and stamp advance
//!   between the last two onsets; `f_peak_first`, `f_peak_last`: the peaks that preceded the
//!   first and the last event; `f_mean`: time-mean F over the last complete cycle (between the
//!   last two onsets);
//! - `recovery` R: the largest area-weighted ⟨φ⟩/φ_eq(t) over that cycle, φ_eq the unstrained
//!   solid film at A(t) (√(A(t)/a); φ₊(0) for the first-order film);
//! - `melted_time_fraction`: the share of the time after the first onset during which no node
//!   was solid;
//! - `energy_per_cycle`: the energy dissipated over the last complete cycle (every sink of the
//!   energy books, stickslip_core's `sim::energy`), J; `energy`: the books over the whole run
//!   (drive work, each sink, the stored energy's change and the residual);
//! - `regime`, decided in this order: `sliding` (the film is liquid from the start: A(0) ≤ 0,
//!   unless a first-order film starts as a metastable solid; or no node solid for at least
//!   [`RegimeThresholds::sliding_fraction`] of the time after the first onset), `no_melting`
//!   (no event), `transient` (one event), then by R for two or more events: `stick_slip`
//!   (R ≥ [`RegimeThresholds::stick_slip_recovery`]), `partial` (R ≥
//!   [`RegimeThresholds::smooth_recovery`]), `smooth` (below).
//!
//! One refinement of the regime rules, where they meet the event rule: when the film never
//! regrows above the recovery level after the first melting, no second onset can be told
//! apart, so the run has one event that is still open at its end. If that event's own
//! recovery (the largest ⟨φ⟩/φ_eq since its onset) stays below the smooth threshold, the
//! film hardly recovers: the run is `smooth`, and `recovery` reports that value. An open
//! single event with a larger recovery stays `transient`.
//!
//! Values that do not exist for a run (the period of a run with one event) are `None`
//! (JSON null, an empty cell in map.csv).

use serde::{Deserialize, Serialize};
use stickslip_core::sim::energy::{EnergyBooks, EnergyFlows};
use stickslip_core::sim::events::{CycleEnergy, MeltingEvent};

/// Regime of a run (docs/model.md#regimes-and-friction-maps).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Regime {
    /// The film is melted everywhere most of the time (or from the start: A ≤ 0, and for a
    /// first-order film no metastable solid either).
    Sliding,
    /// No node melts within the run.
    NoMelting,
    /// Exactly one event.
    Transient,
    /// Two or more events and the film re-solidifies fully between them.
    StickSlip,
    /// Two or more events and the film re-solidifies only partly between them.
    Partial,
    /// Two or more events and the film hardly recovers between them.
    Smooth,
}

impl Regime {
    /// All regimes, in the order of the rules.
    pub const ALL: [Self; 6] = [
        Self::Sliding,
        Self::NoMelting,
        Self::Transient,
        Self::StickSlip,
        Self::Partial,
        Self::Smooth,
    ];

    /// The name as written in files.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Sliding => "sliding",
            Self::NoMelting => "no_melting",
            Self::Transient => "transient",
            Self::StickSlip => "stick_slip",
            Self::Partial => "partial",
            Self::Smooth => "smooth",
        }
    }

    /// The regime called `name`.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|r| r.name() == name)
    }
}

/// Thresholds of the regime rules (settable per sweep).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RegimeThresholds {
    /// R at or above which two or more events are `stick_slip` (default 0.9).
    pub stick_slip_recovery: f64,
    /// R below which two or more events are `smooth` (default 0.1); in between: `partial`.
    pub smooth_recovery: f64,
    /// Share of the time after the first onset with no solid node at or above which the run
    /// is `sliding` (default 0.9).
    pub sliding_fraction: f64,
}

impl Default for RegimeThresholds {
    fn default() -> Self {
        Self {
            stick_slip_recovery: 0.9,
            smooth_recovery: 0.1,
            sliding_fraction: 0.9,
        }
    }
}

impl RegimeThresholds {
    /// Checks 0 ≤ smooth ≤ stick-slip ≤ 1 and 0 < sliding ≤ 1.
    ///
    /// # Errors
    /// The offending key (`regime.<field>`), its value and what is allowed.
    pub fn validate(&self) -> Result<(), (String, f64, String)> {
        let ok01 = |v: f64| v.is_finite() && (0.0..=1.0).contains(&v);
        if !ok01(self.smooth_recovery) {
            return Err((
                "regime.smooth_recovery".into(),
                self.smooth_recovery,
                "within [0, 1]".to_string(),
            ));
        }
        if !(ok01(self.stick_slip_recovery) && self.stick_slip_recovery >= self.smooth_recovery) {
            return Err((
                "regime.stick_slip_recovery".into(),
                self.stick_slip_recovery,
                format!(
                    "within [regime.smooth_recovery = {}, 1]",
                    crate::scene::error::human(self.smooth_recovery)
                ),
            ));
        }
        if !(ok01(self.sliding_fraction) && self.sliding_fraction > 0.0) {
            return Err((
                "regime.sliding_fraction".into(),
                self.sliding_fraction,
                "within (0, 1]".to_string(),
            ));
        }
        Ok(())
    }
}

/// The summary of one run (docs/model.md#regimes-and-friction-maps), SI units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunSummary {
    /// Number of melting events.
    pub n_events: usize,
    /// Onset of the first event, s.
    pub t_first_onset: Option<f64>,
    /// Time between the last two onsets, s.
    pub period_last: Option<f64>,
    /// Stamp advance between the last two onsets, m.
    pub x_period_last: Option<f64>,
    /// Peak force before the first event, N.
    pub f_peak_first: Option<f64>,
    /// Peak force before the last event, N.
    pub f_peak_last: Option<f64>,
    /// Time-mean force over the last complete cycle, N.
    pub f_mean: Option<f64>,
    /// Largest ⟨φ⟩/φ_eq over the last complete cycle (φ_eq = √(A/a), or the first-order
    /// film's φ₊(0), at the moment's A).
    pub recovery: Option<f64>,
    /// Share of the time after the first onset with no solid node.
    pub melted_time_fraction: Option<f64>,
    /// The regime.
    pub regime: Regime,
    /// Whether the run's last cycles repeat (the run's `time.steady_cycles` and
    /// `time.steady_rtol`): the regime is then that of the steady state, else of the window's
    /// end.
    #[serde(default)]
    pub steady: bool,
    /// Slips of the stamp that ended within the run (docs/model.md#two-scales-meltings-and-slips).
    #[serde(default)]
    pub n_slips: usize,
    /// The stamp-scale regime (none in files written before it existed).
    #[serde(default)]
    pub stamp_regime: Option<crate::cycles::StampRegime>,
    /// Cycle statistics of meltings and of slips over the settled part.
    #[serde(default)]
    pub cycles: Option<crate::cycles::Cycles>,
    /// Energy dissipated over the last complete cycle (between the last two onsets), J.
    #[serde(default)]
    pub energy_per_cycle: Option<f64>,
    /// The energy books over the whole run, J (none for a run resumed from a checkpoint
    /// written before the books existed).
    #[serde(default)]
    pub energy: Option<CycleEnergy>,
}

impl RunSummary {
    /// A summary of `regime` without numbers (a point refused before it ran; tests).
    #[must_use]
    pub fn without_numbers(regime: Regime) -> Self {
        Self {
            n_events: 0,
            t_first_onset: None,
            period_last: None,
            x_period_last: None,
            f_peak_first: None,
            f_peak_last: None,
            f_mean: None,
            recovery: None,
            melted_time_fraction: None,
            regime,
            steady: false,
            n_slips: 0,
            stamp_regime: None,
            cycles: None,
            energy_per_cycle: None,
            energy: None,
        }
    }
}

/// What [`summarize`] needs from a run.
#[derive(Debug, Clone, Copy)]
pub struct SummaryInput<'a> {
    /// The events, in order.
    pub events: &'a [MeltingEvent],
    /// Time after the first onset with no solid node, s.
    pub no_solid_time_s: f64,
    /// Time the run reached, s.
    pub t_final_s: f64,
    /// Whether the film is liquid from the start (A(0) ≤ 0, and for a first-order film no
    /// metastable solid: [`stickslip_core::landau::LandauParams::starts_solid`]).
    pub starts_liquid: bool,
    /// The energy books since t = 0 (none when resumed from a checkpoint without them).
    pub books: Option<&'a EnergyBooks>,
}

impl SummaryInput<'_> {
    /// Whether the last event is still open (the film has not recovered since).
    fn last_open(&self) -> bool {
        self.events.last().is_some_and(|e| e.t_end_s.is_none())
    }
}

/// The summary and regime of a run.
#[must_use]
pub fn summarize(input: &SummaryInput<'_>, th: &RegimeThresholds) -> RunSummary {
    let ev = input.events;
    let n = ev.len();
    let last_two = (n >= 2).then(|| (&ev[n - 2], &ev[n - 1]));
    let melted_time_fraction = ev.first().and_then(|first| {
        let span = input.t_final_s - first.t_onset_s;
        (span > 0.0).then(|| (input.no_solid_time_s / span).clamp(0.0, 1.0))
    });
    let single_open = n == 1 && input.last_open();
    let recovery = if single_open {
        ev.first().map(|e| e.recovery)
    } else {
        last_two.map(|(a, _)| a.recovery)
    };
    let sliding =
        input.starts_liquid || melted_time_fraction.is_some_and(|f| f >= th.sliding_fraction);
    let regime = if sliding {
        Regime::Sliding
    } else {
        match (n, recovery) {
            (0, _) => Regime::NoMelting,
            (1, Some(r)) if single_open && r < th.smooth_recovery => Regime::Smooth,
            (1, _) => Regime::Transient,
            (_, Some(r)) if r >= th.stick_slip_recovery => Regime::StickSlip,
            (_, Some(r)) if r >= th.smooth_recovery => Regime::Partial,
            _ => Regime::Smooth,
        }
    };
    RunSummary {
        n_events: n,
        t_first_onset: ev.first().map(|e| e.t_onset_s),
        period_last: last_two.map(|(a, b)| b.t_onset_s - a.t_onset_s),
        x_period_last: last_two.map(|(a, b)| b.x_onset_m - a.x_onset_m),
        f_peak_first: ev.first().map(|e| e.f_peak_n),
        f_peak_last: ev.last().map(|e| e.f_peak_n),
        f_mean: last_two.map(|(a, _)| a.f_mean_n),
        recovery,
        melted_time_fraction,
        regime,
        steady: false,
        n_slips: 0,
        stamp_regime: None,
        cycles: None,
        energy_per_cycle: last_two.and_then(|(a, _)| a.energy.map(|e| e.dissipated_j())),
        energy: input.books.map(|b| {
            CycleEnergy::between(
                &(EnergyFlows::default(), b.stored_initial),
                &(b.flows, b.stored),
            )
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Events with onsets 1, 2, …, their recoveries and whether the last has ended.
    fn events(recoveries: &[f64], last_open: bool) -> Vec<MeltingEvent> {
        recoveries
            .iter()
            .enumerate()
            .map(|(i, &r)| MeltingEvent {
                k: i + 1,
                t_onset_s: (i + 1) as f64,
                r_first_m: 1.0,
                x_onset_m: 2.0 * (i + 1) as f64,
                f_peak_n: 10.0 + i as f64,
                r_min_m: 0.0,
                t_center_s: None,
                max_melted_fraction: 1.0,
                t_end_s: (!(last_open && i + 1 == recoveries.len()))
                    .then_some((i + 1) as f64 + 0.1),
                recovery: r,
                f_mean_n: 5.0 + i as f64,
                melted_area: 1.0,
                energy: None,
            })
            .collect()
    }

    fn regime(ev: &[MeltingEvent], no_solid_s: f64, t_final: f64, a: f64) -> RunSummary {
        summarize(
            &SummaryInput {
                events: ev,
                no_solid_time_s: no_solid_s,
                t_final_s: t_final,
                starts_liquid: a <= 0.0,
                books: None,
            },
            &RegimeThresholds::default(),
        )
    }

    #[test]
    fn every_regime_and_its_boundaries() {
        let cases: [(&[f64], bool, f64, f64, Regime); 14] = [
            // Liquid from the start (A ≤ 0): sliding whatever the events.
            (&[0.0], true, 0.0, 0.0, Regime::Sliding),
            (&[0.0], true, 0.0, -1.0, Regime::Sliding),
            // No node solid for ≥ 90 % of the time after the first onset (1 … 11 s): sliding.
            (&[0.5], true, 9.0, 1.0, Regime::Sliding),
            (&[0.5], true, 8.999, 1.0, Regime::Transient),
            (&[], false, 0.0, 1.0, Regime::NoMelting),
            (&[0.95], false, 0.0, 1.0, Regime::Transient),
            // Two or more events: by the recovery of the last complete cycle.
            (&[0.9, 0.0], false, 0.0, 1.0, Regime::StickSlip),
            (&[0.899_999, 1.0], false, 0.0, 1.0, Regime::Partial),
            (&[0.2, 0.899_999, 0.0], false, 0.0, 1.0, Regime::Partial),
            (&[0.1, 1.0], false, 0.0, 1.0, Regime::Partial),
            (&[0.099_999, 1.0], false, 0.0, 1.0, Regime::Smooth),
            (&[0.0, 0.0], true, 0.0, 1.0, Regime::Smooth),
            // One event that never ends: smooth when it hardly recovered, else transient.
            (&[0.05], true, 0.0, 1.0, Regime::Smooth),
            (&[0.1], true, 0.0, 1.0, Regime::Transient),
        ];
        for (rec, open, no_solid, a, expected) in cases {
            let ev = events(rec, open && !rec.is_empty());
            let s = regime(&ev, no_solid, 11.0, a);
            assert_eq!(
                s.regime, expected,
                "recoveries {rec:?}, open {open}, no-solid {no_solid} s, A {a}"
            );
        }
    }

    #[test]
    fn summary_numbers_come_from_the_last_two_onsets() {
        let ev = events(&[0.95, 0.97, 0.99], false);
        let s = regime(&ev, 0.0, 4.0, 1.0);
        assert_eq!(s.n_events, 3);
        assert_eq!(s.t_first_onset, Some(1.0));
        assert_eq!(s.period_last, Some(1.0));
        assert_eq!(s.x_period_last, Some(2.0));
        assert_eq!(s.f_peak_first, Some(10.0));
        assert_eq!(s.f_peak_last, Some(12.0));
        assert_eq!(s.f_mean, Some(6.0));
        assert_eq!(s.recovery, Some(0.97));
        assert_eq!(s.melted_time_fraction, Some(0.0));
        let none = regime(&[], 0.0, 4.0, 1.0);
        assert_eq!(
            (none.t_first_onset, none.period_last, none.recovery),
            (None, None, None)
        );
    }

    #[test]
    fn thresholds_are_checked() {
        let bad = RegimeThresholds {
            stick_slip_recovery: 0.05,
            ..RegimeThresholds::default()
        };
        assert_eq!(bad.validate().unwrap_err().0, "regime.stick_slip_recovery");
        assert!(RegimeThresholds::default().validate().is_ok());
    }
}
