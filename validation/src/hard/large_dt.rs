//! Hard case 3: Δt = 1e-6 s, a hundred times the paper's: the literal scheme must fail loudly;
//! the accurate scheme must keep the number and timing of the events of a Δt = 1e-8 s
//! reference, with fixed and with adaptive steps.

use super::{
    Attempt, Bench, Case, Check, bounded, check, event_count, failed_loudly, health_text,
    literal_loud_text, onsets, outcome, radius_m, sets,
};
use stickslip_core::preflight::Preflight;
use stickslip_report::fmt::{opt, sig};
use stickslip_report::stats::mean;
use stickslip_run::keys::{
    output, time,
    words::{Scheme, Stepping},
};

/// Case 3: Δt = 1e-6 s against a Δt = 1e-8 s reference at the same N.
#[derive(Debug, Clone)]
pub struct LargeDt {
    /// The preflight of the literal scene at Δt = 1e-6 s, in-process.
    pub preflight: Result<Preflight, String>,
    /// Literal scheme at Δt = 1e-6 s.
    pub literal: Attempt,
    /// Accurate scheme at Δt = 1e-6 s.
    pub accurate: Attempt,
    /// Accurate scheme at Δt = 1e-8 s (reference).
    pub reference: Attempt,
    /// Accurate scheme with adaptive steps starting from Δt = 1e-6 s.
    pub adaptive: Attempt,
}

/// Runs case 3.
pub fn large_dt(b: &Bench) -> LargeDt {
    let lit = sets(&[time::SCHEME.set(Scheme::Literal)]);
    LargeDt {
        preflight: b.preflight("large_dt", &lit),
        literal: b.run("large_dt_literal", "large_dt", &lit),
        accurate: b.run("large_dt_accurate", "large_dt", &[]),
        reference: b.run(
            "large_dt_reference",
            "large_dt",
            &sets(&[time::DT.set(1e-8), output::SERIES_INTERVAL.set(1e-7)]),
        ),
        adaptive: b.run(
            "large_dt_adaptive",
            "large_dt",
            &sets(&[time::STEPPING.set(Stepping::Adaptive)]),
        ),
    }
}

/// Δt of case 3's large-step run, s.
pub const LARGE_DT_S: f64 = 1e-6;

impl LargeDt {
    /// Explicit Euler's stability number of the literal scene (preflight).
    pub fn euler_number(&self) -> Option<f64> {
        self.preflight.as_ref().ok().and_then(|p| p.euler_number)
    }

    /// Largest |onset − reference onset| over common events, s.
    pub fn max_onset_diff_s(&self) -> f64 {
        onsets(&self.accurate)
            .iter()
            .zip(onsets(&self.reference))
            .map(|(a, r)| (a - r).abs())
            .fold(0.0, f64::max)
    }

    /// Mean melted_area per event (the area the front swept): (Δt = 1e-6 s, reference).
    pub fn melted_fractions(&self) -> (f64, f64) {
        let m = |a: &Attempt| {
            let v: Vec<f64> = a
                .out()
                .map(|o| o.events.events().iter().map(|e| e.melted_area).collect())
                .unwrap_or_default();
            mean(&v)
        };
        (m(&self.accurate), m(&self.reference))
    }

    /// r_first of the first event / a0: (Δt = 1e-6 s, reference).
    pub fn first_radius_fraction(&self) -> (f64, f64) {
        let r = |a: &Attempt| {
            a.out()
                .and_then(|o| o.events.events().first().map(|e| e.r_first_m / radius_m(a)))
                .unwrap_or(f64::NAN)
        };
        (r(&self.accurate), r(&self.reference))
    }
}

impl Case for LargeDt {
    fn title(&self) -> String {
        format!("3 Δt far too large ({LARGE_DT_S:e} s)")
    }
    fn scenes(&self) -> String {
        "large_dt.toml".into()
    }
    fn literal(&self) -> String {
        literal_loud_text(&self.literal)
    }
    fn accurate(&self) -> String {
        format!(
            "{} (reference Δt = 1e-8 s: {} events); {}; adaptive from Δt = {LARGE_DT_S:e} s: {}",
            outcome(&self.accurate),
            event_count(&self.reference),
            health_text(&self.accurate),
            outcome(&self.adaptive)
        )
    }
    fn numbers(&self) -> String {
        let (m, mr) = self.melted_fractions();
        let (r, rr) = self.first_radius_fraction();
        format!(
            "euler_number = {}; onsets within {} µs of the reference (Δt = {} µs); melted area \
             per event {} % against {} %; first melting at r = {}·a0 against {}·a0",
            opt(self.euler_number(), 3),
            sig(self.max_onset_diff_s() * 1e6, 3),
            sig(LARGE_DT_S * 1e6, 2),
            sig(100.0 * m, 3),
            sig(100.0 * mr, 3),
            sig(r, 3),
            sig(rr, 3)
        )
    }
    fn checks(&self) -> Vec<Check> {
        vec![
            check(
                "literal: exit 3, run.json's failure naming φ (explicit Euler beyond its limit)",
                failed_loudly(&self.literal)
                    && self.literal.failure().is_some_and(|f| f.quantity == "phi"),
                literal_loud_text(&self.literal),
            ),
            check(
                "reference (accurate, Δt = 1e-8 s): exit 0 with several meltings",
                self.reference.ok() && event_count(&self.reference) >= 3,
                outcome(&self.reference),
            ),
            check(
                format!(
                    "accurate, Δt = {LARGE_DT_S:e} s: exit 0, finite, φ ≥ 0, |F| ≤ 1.01·τmax·π·a0²"
                ),
                bounded(&self.accurate, 1.01),
                format!(
                    "{}; {}",
                    outcome(&self.accurate),
                    health_text(&self.accurate)
                ),
            ),
            check(
                format!("accurate, Δt = {LARGE_DT_S:e} s: the reference's number of events"),
                self.accurate.ok() && event_count(&self.accurate) == event_count(&self.reference),
                format!(
                    "{} against {}",
                    event_count(&self.accurate),
                    event_count(&self.reference)
                ),
            ),
            check(
                format!(
                    "accurate, Δt = {LARGE_DT_S:e} s: every onset within 5·Δt of the reference's"
                ),
                self.accurate.ok() && self.max_onset_diff_s() <= 5.0 * LARGE_DT_S,
                format!(
                    "max difference {} µs",
                    sig(self.max_onset_diff_s() * 1e6, 3)
                ),
            ),
            check(
                format!(
                    "accurate, adaptive from Δt = {LARGE_DT_S:e} s: exit 0, bounded, the \
                     reference's number of events"
                ),
                bounded(&self.adaptive, 1.01)
                    && event_count(&self.adaptive) == event_count(&self.reference),
                format!(
                    "{}; {}",
                    outcome(&self.adaptive),
                    health_text(&self.adaptive)
                ),
            ),
        ]
    }
    fn findings(&self) -> Vec<String> {
        let mut f = Vec::new();
        let (m, mr) = self.melted_fractions();
        if m > 2.0 * mr {
            f.push(format!(
                "At Δt = {LARGE_DT_S:e} s the accurate scheme gets the number and timing of the \
                 events right, but each melting spreads over {} % of the contact area on average \
                 against {} % at Δt = 1e-8 s: the front's progress across the contact is still \
                 resolved only step by step, so the melted area of an event depends on Δt. Not \
                 a stability problem, but events.csv's melted_area should not be trusted at \
                 large Δt. Reproduce: `{}` and `{}`, column melted_area of events.csv.",
                sig(100.0 * m, 3),
                sig(100.0 * mr, 3),
                self.accurate.command,
                self.reference.command
            ));
        }
        let (r, rr) = self.first_radius_fraction();
        if r < 0.9 && rr >= 0.9 {
            f.push(format!(
                "At Δt = {LARGE_DT_S:e} s the first melting is first seen at r = {}·a0, not at the \
                 edge ({}·a0 at Δt = 1e-8 s): within one step the front has already run \
                 inwards. Reproduce: `{}`.",
                sig(r, 3),
                sig(rr, 3),
                self.accurate.command
            ));
        }
        f
    }
    fn figure(&self) -> Option<super::figures::HardFigure> {
        Some(super::figures::HardFigure {
            file: "hard_large_dt.svg",
            title: "Case 3: F(t) at Δt = 1e-6 s against the Δt = 1e-8 s reference",
            caption: "The accurate scheme's friction force at a hundred times the paper's step \
                      (fixed: circles; adaptive from that step: crosses) over its reference's \
                      curve. What to see: every event kept, at its time; the literal scheme \
                      has no curve here because it fails at once (the table above)."
                .into(),
            svg: super::figures::large_dt(&self.reference, &self.accurate, &self.adaptive),
        })
    }
    fn attempts(&self) -> Vec<&Attempt> {
        vec![
            &self.literal,
            &self.accurate,
            &self.reference,
            &self.adaptive,
        ]
    }
}
