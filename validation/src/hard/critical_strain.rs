//! Hard case 5: the strain driven exactly onto the critical strain εc (binary-exact ramp), and
//! A0 just below and above: φ at the critical moment must be smooth across εc, the onsets
//! ordered in A, the melting just past the quasi-static threshold, F bounded.

use super::{Attempt, Bench, Case, Check, Health, check, derived, health, outcome, sets, with};
use crate::facts::Facts;
use std::f64::consts::PI;
use stickslip_report::fmt::sig;
use stickslip_run::keys::{temperature, time, words::Scheme};

/// A0 of near_critical.toml, Pa: with b = a = 1e6 Pa, εc = √(A·b)/a = 2 exactly.
pub const NEAR_CRITICAL_A0_PA: f64 = 4e6;
/// The profile time of near_critical.toml: 2^-12 s, when the strain is exactly εc.
pub const NEAR_CRITICAL_PROFILE_S: f64 = 2.441_406_25e-4;

/// One A0 variant of case 5.
#[derive(Debug, Clone)]
pub struct CriticalVariant {
    /// A0 / A0(exact critical).
    pub factor: f64,
    /// Literal scheme.
    pub literal: Attempt,
    /// Accurate scheme.
    pub accurate: Attempt,
}

/// Case 5: the strain ramped exactly through εc.
#[derive(Debug, Clone)]
pub struct NearCritical {
    /// A0·(1 − 1e-6), A0, A0·(1 + 1e-6).
    pub variants: Vec<CriticalVariant>,
}

/// Relative offsets of A0 in case 5.
pub const CRITICAL_FACTORS: [f64; 3] = [1.0 - 1e-6, 1.0, 1.0 + 1e-6];

/// Runs case 5.
pub fn near_critical(b: &Bench) -> NearCritical {
    NearCritical {
        variants: CRITICAL_FACTORS
            .iter()
            .enumerate()
            .map(|(i, &factor)| {
                // The exact A0 is the scene's own; the variants override it.
                let s = if factor == 1.0 {
                    Vec::new()
                } else {
                    sets(&[temperature::A0.set(NEAR_CRITICAL_A0_PA * factor)])
                };
                CriticalVariant {
                    factor,
                    literal: b.run(
                        &format!("near_critical_literal_{i}"),
                        "near_critical",
                        &with(&s, &sets(&[time::SCHEME.set(Scheme::Literal)])),
                    ),
                    accurate: b.run(&format!("near_critical_accurate_{i}"), "near_critical", &s),
                }
            })
            .collect(),
    }
}

/// Per run of case 5: φ when the strain is exactly εc, first onset, ε at the onset / εc,
/// max F / stationary maximum, ε*/εc (quasi-static melting strain at the threshold).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CriticalNumbers {
    /// φ in the profile at 2^-12 s.
    pub phi_critical: f64,
    /// First onset, s.
    pub onset_s: f64,
    /// Strain at the onset / εc.
    pub eps_onset_over_c: f64,
    /// Quasi-static strain at which φ_eq = threshold, / εc.
    pub eps_star_over_c: f64,
    /// max |F| / (π·a0²·(2/3)·A·εc/√3).
    pub f_ratio: f64,
}

/// The numbers of one run of case 5, from its outputs and run.json.
pub fn critical_numbers(a: &Attempt) -> Option<CriticalNumbers> {
    let o = a.out()?;
    let p = o.profiles.nearest(NEAR_CRITICAL_PROFILE_S)?;
    let e = o.events.events().first()?;
    let d = derived(a)?;
    let a_pa = o.info.scene.lubricant.as_ref()?.a?;
    let h0 = o.info.film_thickness_m();
    let thr = o.info.melt_threshold();
    let tau_peak = 2.0 / 3.0 * d.a * d.eps_c / 3f64.sqrt();
    Some(CriticalNumbers {
        phi_critical: *p.phi.first()?,
        onset_s: e.t_onset_s,
        eps_onset_over_c: e.x_onset_m / h0 / d.eps_c,
        eps_star_over_c: (1.0 - a_pa * thr * thr / d.a).sqrt(),
        f_ratio: Health::of(o).f_max_n / (PI * o.info.radius_m().powi(2) * tau_peak),
    })
}

impl NearCritical {
    fn numbers_of(&self, literal: bool) -> Vec<Option<CriticalNumbers>> {
        self.variants
            .iter()
            .map(|v| critical_numbers(if literal { &v.literal } else { &v.accurate }))
            .collect()
    }

    fn scheme_checks(&self, literal: bool) -> Vec<Check> {
        let name = if literal { "literal" } else { "accurate" };
        let runs: Vec<&Attempt> = self
            .variants
            .iter()
            .map(|v| if literal { &v.literal } else { &v.accurate })
            .collect();
        let nums = self.numbers_of(literal);
        let mut c = vec![check(
            format!("{name}: exit 0 for A0·(1 − 1e-6), A0, A0·(1 + 1e-6); finite, φ ≥ 0"),
            runs.iter()
                .all(|a| a.ok() && health(a).is_some_and(|h| h.finite && h.phi_min >= 0.0)),
            runs.iter()
                .map(|a| outcome(a))
                .collect::<Vec<_>>()
                .join("; "),
        )];
        let Some(n) = nums.iter().copied().collect::<Option<Vec<_>>>() else {
            c.push(check(
                format!("{name}: profile at 2^-12 s and a melting event in every run"),
                false,
                format!("{nums:?}"),
            ));
            return c;
        };
        let phi: Vec<f64> = n.iter().map(|x| x.phi_critical).collect();
        let first = phi[2] - phi[0];
        let second = (phi[0] - 2.0 * phi[1] + phi[2]).abs();
        c.push(check(
            format!(
                "{name}: φ when ε = εc(A0) exactly increases with A and is smooth across εc \
                 (|second difference| ≤ 1 % of the first)"
            ),
            phi[0] < phi[1] && phi[1] < phi[2] && second <= 0.01 * first,
            format!("φ = {phi:?}"),
        ));
        let on: Vec<f64> = n.iter().map(|x| x.onset_s).collect();
        if literal {
            // The fixed step quantises the onset to Δt; the shift a 1e-6 change of A makes (the
            // accurate scheme's, εc ∝ √A) is far below it, so the literal scheme cannot resolve
            // the perturbation: its onsets must agree to within one Δt, not increase.
            let dt = runs[1]
                .out()
                .and_then(|o| o.info.scene.time.as_ref().and_then(|t| t.dt))
                .unwrap_or(f64::NAN);
            let shift = self
                .numbers_of(false)
                .iter()
                .map(|x| x.map(|x| x.onset_s))
                .collect::<Option<Vec<f64>>>()
                .map_or(f64::NAN, |a| a[2] - a[0]);
            c.push(check(
                format!(
                    "{name}: onsets within one fixed step Δt of each other: the perturbation's \
                     shift (the accurate scheme's, A0·(1 − 1e-6) to A0·(1 + 1e-6)) is below Δt, \
                     so the literal scheme does not resolve it"
                ),
                on[2] - on[0] <= dt && shift < dt,
                format!(
                    "onsets {on:?} s; spread {} s; Δt = {} s; the accurate shift {} s",
                    sig(on[2] - on[0], 3),
                    sig(dt, 3),
                    sig(shift, 3)
                ),
            ));
        } else {
            c.push(check(
                format!("{name}: melting onsets strictly increasing in A (larger A, larger εc)"),
                on[0] < on[1] && on[1] < on[2],
                format!("onsets {on:?} s"),
            ));
        }
        c.push(check(
            format!(
                "{name}: the film melts after the strain passes the quasi-static threshold ε* \
                 and before 1.1·εc"
            ),
            n.iter()
                .all(|x| x.eps_onset_over_c >= x.eps_star_over_c && x.eps_onset_over_c <= 1.1),
            format!(
                "ε_onset/εc = {:?}, ε*/εc = {}",
                n.iter().map(|x| x.eps_onset_over_c).collect::<Vec<_>>(),
                n[1].eps_star_over_c
            ),
        ));
        c.push(check(
            format!("{name}: max |F| ≤ 1.01·π·a0²·(2/3)·A·εc/√3"),
            n.iter().all(|x| x.f_ratio <= 1.01),
            format!("{:?}", n.iter().map(|x| x.f_ratio).collect::<Vec<_>>()),
        ));
        c
    }
}

impl Case for NearCritical {
    fn title(&self) -> String {
        "5 near-critical: the strain driven exactly onto εc".into()
    }
    fn scenes(&self) -> String {
        "near_critical.toml".into()
    }
    fn literal(&self) -> String {
        self.variants
            .iter()
            .map(|v| outcome(&v.literal))
            .collect::<Vec<_>>()
            .join("; ")
    }
    fn accurate(&self) -> String {
        self.variants
            .iter()
            .map(|v| outcome(&v.accurate))
            .collect::<Vec<_>>()
            .join("; ")
    }
    fn numbers(&self) -> String {
        let fmt = |literal: bool| {
            let n = self.numbers_of(literal);
            let phi: Vec<String> = n
                .iter()
                .map(|x| x.map_or_else(|| "–".into(), |x| sig(x.phi_critical, 9)))
                .collect();
            let on: Vec<String> = n
                .iter()
                .map(|x| x.map_or_else(|| "–".into(), |x| sig(x.onset_s * 1e6, 9)))
                .collect();
            let eps = n
                .get(1)
                .copied()
                .flatten()
                .map_or_else(|| "–".into(), |x| sig(x.eps_onset_over_c, 5));
            format!(
                "φ when ε = εc(A0) {} (A0·(1 − 1e-6), A0, A0·(1 + 1e-6)); onsets {} µs; \
                 ε_onset = {}·εc",
                phi.join(" < "),
                on.join(", "),
                eps
            )
        };
        format!("accurate: {}; literal: {}", fmt(false), fmt(true))
    }
    fn checks(&self) -> Vec<Check> {
        let mut c = self.scheme_checks(false);
        c.extend(self.scheme_checks(true));
        c
    }
    fn findings(&self) -> Vec<String> {
        vec![
            "The initial strain is not a scene key: the engine always starts from u0 = 0, \
             φ = √(A/a). Case 5 ramps the strain instead (homogeneous node, rigid substrate, \
             rigid drive, binary-exact steps), so that the strain equals εc exactly at one \
             step's end; a key such as `contact.initial_strain` would be needed to start a run \
             at ε ≈ εc."
                .to_string(),
        ]
    }
    fn attempts(&self) -> Vec<&Attempt> {
        self.variants
            .iter()
            .flat_map(|v| [&v.literal, &v.accurate])
            .collect()
    }
}
