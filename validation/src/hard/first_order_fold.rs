//! Hard case 9: the first-order film's fold under a step that strides over it — one node
//! ramped through ε₊ at ε̇ = 1e5 /s with Δt = 1e-6 s (Δε = 0.1 per step): the literal scheme
//! must fail loudly (and be right within a step inside its stability limit), the accurate
//! scheme must keep every melting, never before ε₊ and never more than a step's strain after
//! the reference's, and its adaptive default must find the reference's melting strains.

use super::{
    Attempt, Bench, Case, Check, bounded, check, event_count, failed_loudly, health_text,
    literal_loud_text, outcome, sets,
};
use crate::facts::Facts;
use stickslip_core::preflight::Preflight;
use stickslip_report::fmt::{list, opt, sig};
use stickslip_run::keys::{
    time,
    words::{Scheme, Stepping},
};

/// Δt of case 9's large-step runs, s.
pub const FOLD_DT_S: f64 = 1e-6;
/// Δt of case 9's reference, s.
pub const FOLD_REFERENCE_DT_S: f64 = 1e-10;
/// Δt of case 9's literal run inside its stability limit, s.
pub const FOLD_LITERAL_SMALL_DT_S: f64 = 1e-8;
/// Largest relative deviation of the adaptive run's melting strains from the reference's.
/// Reason: the adaptive steps keep the local error at the tolerance (5e-5), and the global
/// error of a second-order step at tolerance^(2/3) ≈ 1.4e-3 at worst; 1e-3 is that size.
pub const FOLD_ADAPTIVE_REL_TOL: f64 = 1e-3;

/// Case 9: the fold at Δt = 1e-6 s against a Δt = 1e-10 s reference.
#[derive(Debug, Clone)]
pub struct FirstOrderFold {
    /// The preflight of the literal scene at Δt = 1e-6 s, in-process.
    pub preflight: Result<Preflight, String>,
    /// Literal scheme at Δt = 1e-6 s.
    pub literal: Attempt,
    /// Literal scheme at Δt = 1e-8 s (inside its stability limit).
    pub literal_small: Attempt,
    /// Accurate scheme, fixed Δt = 1e-6 s.
    pub accurate: Attempt,
    /// Accurate scheme, fixed Δt = 1e-10 s (reference).
    pub reference: Attempt,
    /// Accurate scheme with adaptive steps from Δt = 1e-6 s.
    pub adaptive: Attempt,
}

/// Runs case 9.
pub fn first_order_fold(b: &Bench) -> FirstOrderFold {
    let lit = sets(&[time::SCHEME.set(Scheme::Literal)]);
    FirstOrderFold {
        preflight: b.preflight("first_order_fold", &lit),
        literal: b.run("first_order_fold_literal", "first_order_fold", &lit),
        literal_small: b.run(
            "first_order_fold_literal_small",
            "first_order_fold",
            &sets(&[
                time::SCHEME.set(Scheme::Literal),
                time::DT.set(FOLD_LITERAL_SMALL_DT_S),
            ]),
        ),
        accurate: b.run("first_order_fold_accurate", "first_order_fold", &[]),
        reference: b.run(
            "first_order_fold_reference",
            "first_order_fold",
            &sets(&[time::DT.set(FOLD_REFERENCE_DT_S)]),
        ),
        adaptive: b.run(
            "first_order_fold_adaptive",
            "first_order_fold",
            &sets(&[time::STEPPING.set(Stepping::Adaptive)]),
        ),
    }
}

/// The strain at each melting: the stamp's advance since the previous melting over h0 (one
/// node on a rigid substrate under the rigid drive: u0 restarts from 0 at each melting, and
/// ε = u0/h0).
pub fn melting_strains(a: &Attempt) -> Vec<f64> {
    let Some(o) = a.out() else {
        return Vec::new();
    };
    let h0 = o.info.film_thickness_m();
    let mut prev = 0.0;
    o.events
        .events()
        .iter()
        .map(|e| {
            let eps = (e.x_onset_m - prev) / h0;
            prev = e.x_onset_m;
            eps
        })
        .collect()
}

/// Largest |x − r|/r over common entries.
fn max_rel(x: &[f64], r: &[f64]) -> f64 {
    x.iter()
        .zip(r)
        .map(|(x, r)| ((x - r) / r).abs())
        .fold(0.0, f64::max)
}

impl FirstOrderFold {
    /// ε₊ of the run's film (run.json's derived eps_melt).
    pub fn eps_plus(&self) -> f64 {
        self.reference
            .out()
            .or_else(|| self.accurate.out())
            .and_then(|o| o.info.derived.eps_melt)
            .unwrap_or(f64::NAN)
    }

    /// The strain one large step adds, V0·Δt/h0.
    pub fn step_strain(&self) -> f64 {
        self.accurate.out().map_or(f64::NAN, |o| {
            o.info.velocity_m_per_s() * FOLD_DT_S / o.info.film_thickness_m()
        })
    }

    /// Explicit Euler's stability number of the literal scene (preflight).
    pub fn euler_number(&self) -> Option<f64> {
        self.preflight.as_ref().ok().and_then(|p| p.euler_number)
    }

    /// Largest difference between the large step's onsets and the reference's, s.
    pub fn max_onset_diff_s(&self) -> f64 {
        let on = |a: &Attempt| a.out().map(|o| o.events.onsets_s()).unwrap_or_default();
        on(&self.accurate)
            .iter()
            .zip(on(&self.reference))
            .map(|(a, r)| (a - r).abs())
            .fold(0.0, f64::max)
    }
}

impl Case for FirstOrderFold {
    fn title(&self) -> String {
        format!("9 first-order film: the fold under a large step ({FOLD_DT_S:e} s)")
    }
    fn scenes(&self) -> String {
        "first_order_fold.toml".into()
    }
    fn literal(&self) -> String {
        format!(
            "{}; at Δt = {FOLD_LITERAL_SMALL_DT_S:e} s: {}",
            literal_loud_text(&self.literal),
            outcome(&self.literal_small)
        )
    }
    fn accurate(&self) -> String {
        format!(
            "{} (reference Δt = {FOLD_REFERENCE_DT_S:e} s: {} events); {}; adaptive from Δt = \
             {FOLD_DT_S:e} s: {}",
            outcome(&self.accurate),
            event_count(&self.reference),
            health_text(&self.accurate),
            outcome(&self.adaptive)
        )
    }
    fn numbers(&self) -> String {
        format!(
            "euler_number = {}; ε₊ = {}, one step adds Δε = {}; melting strains: reference {}, \
             Δt = {FOLD_DT_S:e} s {}, adaptive {}, literal at Δt = {FOLD_LITERAL_SMALL_DT_S:e} s \
             {}; onsets of the large step within {} µs of the reference's",
            opt(self.euler_number(), 3),
            sig(self.eps_plus(), 5),
            sig(self.step_strain(), 2),
            list(&melting_strains(&self.reference), 5),
            list(&melting_strains(&self.accurate), 5),
            list(&melting_strains(&self.adaptive), 5),
            list(&melting_strains(&self.literal_small), 5),
            sig(self.max_onset_diff_s() * 1e6, 3)
        )
    }
    fn checks(&self) -> Vec<Check> {
        let (acc, reference) = (
            melting_strains(&self.accurate),
            melting_strains(&self.reference),
        );
        let (ep, de) = (self.eps_plus(), self.step_strain());
        let in_window = acc.len() == reference.len()
            && acc
                .iter()
                .zip(&reference)
                .all(|(a, r)| *a >= ep && *a <= r + de);
        let lit = melting_strains(&self.literal_small);
        let lit_de = de * FOLD_LITERAL_SMALL_DT_S / FOLD_DT_S;
        let lit_close = lit.len() == reference.len()
            && lit
                .iter()
                .zip(&reference)
                .all(|(l, r)| (l - r).abs() <= lit_de);
        let ad = melting_strains(&self.adaptive);
        let ad_dev = max_rel(&ad, &reference);
        vec![
            check(
                "literal, Δt = 1e-6 s: exit 3 with run.json's failure record (explicit Euler far \
                 beyond its limit)",
                failed_loudly(&self.literal),
                literal_loud_text(&self.literal),
            ),
            check(
                format!(
                    "literal, Δt = {FOLD_LITERAL_SMALL_DT_S:e} s (inside its limit): the \
                     reference's meltings, each within one step's strain"
                ),
                self.literal_small.ok() && lit_close,
                format!(
                    "{}; strains {} against {}",
                    outcome(&self.literal_small),
                    list(&lit, 5),
                    list(&reference, 5)
                ),
            ),
            check(
                format!(
                    "reference (accurate, Δt = {FOLD_REFERENCE_DT_S:e} s): exit 0, ≥ 3 meltings"
                ),
                self.reference.ok() && event_count(&self.reference) >= 3,
                outcome(&self.reference),
            ),
            check(
                format!(
                    "accurate, Δt = {FOLD_DT_S:e} s: exit 0, finite, φ ≥ 0, |F| ≤ 1.01·the peak \
                     force"
                ),
                bounded(&self.accurate, 1.01),
                health_text(&self.accurate),
            ),
            check(
                format!(
                    "accurate, Δt = {FOLD_DT_S:e} s: the reference's meltings, each at a strain \
                     ≥ ε₊ and ≤ the reference's + one step's Δε"
                ),
                self.accurate.ok() && in_window,
                format!(
                    "strains {} in [{}, reference + {}]",
                    list(&acc, 5),
                    sig(ep, 5),
                    sig(de, 2)
                ),
            ),
            check(
                format!(
                    "accurate, adaptive from Δt = {FOLD_DT_S:e} s: the reference's meltings, \
                     strains within {FOLD_ADAPTIVE_REL_TOL:e}"
                ),
                bounded(&self.adaptive, 1.01)
                    && ad.len() == reference.len()
                    && ad_dev <= FOLD_ADAPTIVE_REL_TOL,
                format!(
                    "{}; largest relative deviation {}",
                    outcome(&self.adaptive),
                    sig(ad_dev, 2)
                ),
            ),
        ]
    }
    fn findings(&self) -> Vec<String> {
        let (acc, reference) = (
            melting_strains(&self.accurate),
            melting_strains(&self.reference),
        );
        let ep = self.eps_plus();
        let early = acc
            .iter()
            .zip(&reference)
            .map(|(a, r)| (r - a) / r)
            .fold(f64::NEG_INFINITY, f64::max);
        if acc.is_empty() || !early.is_finite() || early <= 0.0 {
            return Vec::new();
        }
        let delay = reference.iter().map(|r| r / ep - 1.0).fold(0.0, f64::max);
        vec![format!(
            "At Δt = {FOLD_DT_S:e} s the accurate scheme melts the first-order film early: at \
             ε = {} against the reference's {} (up to {} % early), while ε₊ = {}. At this ramp \
             (ε̇ = {} /s) the film creeps through the fold's slow passage and melts {} % beyond \
             ε₊; a step of Δε = {} lands beyond the fold, where the step's frozen strain has no \
             solid branch left, and the exact path melts inside that step, skipping the slow \
             passage. Never before ε₊ and never a melting lost, but the onsets drift (by {} µs \
             after {} meltings); the adaptive default follows the reference. Reproduce: `{}` \
             and `{}`, column x_onset of events.csv.",
            list(&acc, 5),
            list(&reference, 5),
            sig(100.0 * early, 2),
            sig(ep, 5),
            sig(self.step_strain() / FOLD_DT_S, 2),
            sig(100.0 * delay, 2),
            sig(self.step_strain(), 2),
            sig(self.max_onset_diff_s() * 1e6, 3),
            acc.len(),
            self.accurate.command,
            self.reference.command
        )]
    }
    fn figure(&self) -> Option<super::figures::HardFigure> {
        Some(super::figures::HardFigure {
            file: "hard_first_order_fold.svg",
            title: "Case 9: the first-order film's melting strain per event",
            caption: "The strain of each event's first melted node: the reference (Δt = \
                      1e-10 s), the fixed large step (1e-6 s) and the adaptive run, with ε₊. \
                      What to see: the large step melts early but never before ε₊; the \
                      adaptive run follows the reference."
                .into(),
            svg: super::figures::first_order_fold(
                &melting_strains(&self.reference),
                &melting_strains(&self.accurate),
                &melting_strains(&self.adaptive),
                self.eps_plus(),
            ),
        })
    }
    fn attempts(&self) -> Vec<&Attempt> {
        vec![
            &self.literal,
            &self.literal_small,
            &self.accurate,
            &self.reference,
            &self.adaptive,
        ]
    }
}
