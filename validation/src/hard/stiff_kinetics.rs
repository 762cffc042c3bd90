//! Hard case 2: Landau kinetics 100 and 10 000 times faster than fig2's at the paper's Δt:
//! explicit Euler (literal) beyond its stability limit must fail loudly within a few steps;
//! the accurate scheme's exact Landau step must stay stable, the film melting each time the
//! stamp has advanced εc·h0.

use super::{
    Attempt, Bench, Case, Check, bounded, check, derived, event_count, failed_loudly,
    failure_value, health_text, literal_loud_text, outcome, sets, with,
};
use crate::facts::Facts;
use stickslip_core::preflight::Preflight;
use stickslip_report::fmt::{opt, sig};
use stickslip_report::stats::{diffs, mean};
use stickslip_run::keys::{lubricant, time, words::Scheme};

/// Case 2 at one γ.
#[derive(Debug, Clone)]
pub struct StiffRun {
    /// γ, 1/(Pa·s).
    pub gamma: f64,
    /// The preflight of the literal scene at this γ, in-process.
    pub preflight: Result<Preflight, String>,
    /// Literal scheme.
    pub literal: Attempt,
    /// Accurate scheme.
    pub accurate: Attempt,
}

/// Case 2: γ × 100 and × 10 000 at Δt = 1e-8 s.
#[derive(Debug, Clone)]
pub struct StiffKinetics {
    /// γ = 1e3 and 1e5.
    pub runs: Vec<StiffRun>,
}

/// γ values of case 2, 1/(Pa·s).
pub const STIFF_GAMMAS: [f64; 2] = [1e3, 1e5];

/// Runs case 2.
pub fn stiff_kinetics(b: &Bench) -> StiffKinetics {
    StiffKinetics {
        runs: STIFF_GAMMAS
            .iter()
            .map(|&g| {
                let gs = sets(&[lubricant::GAMMA.set(g)]);
                let lit = with(&gs, &sets(&[time::SCHEME.set(Scheme::Literal)]));
                StiffRun {
                    gamma: g,
                    preflight: b.preflight("stiff_kinetics", &lit),
                    literal: b.run(&format!("stiff_literal_g{g:e}"), "stiff_kinetics", &lit),
                    accurate: b.run(&format!("stiff_accurate_g{g:e}"), "stiff_kinetics", &gs),
                }
            })
            .collect(),
    }
}

impl StiffRun {
    /// Explicit Euler's stability number Δt·2γ·A·b/a of the literal scene (preflight).
    pub fn euler_number(&self) -> Option<f64> {
        self.preflight.as_ref().ok().and_then(|p| p.euler_number)
    }

    /// Stamp travel between successive onsets divided by εc·h0 (mean, max deviation from 1).
    pub fn travel_per_event(&self) -> Option<(f64, f64)> {
        let o = self.accurate.out()?;
        let eps_c = derived(&self.accurate)?.eps_c;
        let h0 = o.info.film_thickness_m();
        let x: Vec<f64> = o.events.events().iter().map(|e| e.x_onset_m).collect();
        let d: Vec<f64> = diffs(&x).iter().map(|dx| dx / (eps_c * h0)).collect();
        if d.is_empty() {
            return None;
        }
        let dev = d.iter().map(|r| (r - 1.0).abs()).fold(0.0, f64::max);
        Some((mean(&d), dev))
    }

    fn travel_text(&self) -> String {
        self.travel_per_event().map_or_else(
            || "–".into(),
            |(m, d)| format!("{}·εc·h0 (max deviation {})", sig(m, 4), sig(d, 2)),
        )
    }
}

impl Case for StiffKinetics {
    fn title(&self) -> String {
        "2 stiff kinetics (γ × 100, × 10 000)".into()
    }
    fn scenes(&self) -> String {
        "stiff_kinetics.toml".into()
    }
    fn literal(&self) -> String {
        self.runs
            .iter()
            .map(|r| format!("γ = {:e}: {}", r.gamma, literal_loud_text(&r.literal)))
            .collect::<Vec<_>>()
            .join("; ")
    }
    fn accurate(&self) -> String {
        self.runs
            .iter()
            .map(|r| {
                format!(
                    "γ = {:e}: {}, {}",
                    r.gamma,
                    outcome(&r.accurate),
                    health_text(&r.accurate)
                )
            })
            .collect::<Vec<_>>()
            .join("; ")
    }
    fn numbers(&self) -> String {
        self.runs
            .iter()
            .map(|r| {
                format!(
                    "γ = {:e}: euler_number = {}; accurate travel between meltings {}",
                    r.gamma,
                    opt(r.euler_number(), 4),
                    r.travel_text()
                )
            })
            .collect::<Vec<_>>()
            .join("; ")
    }
    fn checks(&self) -> Vec<Check> {
        let mut c = Vec::new();
        for r in &self.runs {
            let g = r.gamma;
            c.push(check(
                format!("γ = {g:e}: the preflight gives euler_number = Δt·2γ·A·b/a > 2"),
                r.euler_number().is_some_and(|e| e > 2.0),
                opt(r.euler_number(), 4),
            ));
            c.push(check(
                format!(
                    "γ = {g:e}, literal: exit 3 within 100 steps, run.json's failure naming φ \
                     (< 0 or non-finite)"
                ),
                failed_loudly(&r.literal)
                    && r.literal.failure().is_some_and(|f| {
                        let v = failure_value(&r.literal).unwrap_or(f64::NAN);
                        f.quantity == "phi" && (v < 0.0 || !v.is_finite()) && f.step <= 100
                    }),
                literal_loud_text(&r.literal),
            ));
            c.push(check(
                format!("γ = {g:e}, accurate: exit 0, finite, φ ≥ 0, |F| ≤ τmax·π·a0²"),
                bounded(&r.accurate, 1.0),
                format!("{}; {}", outcome(&r.accurate), health_text(&r.accurate)),
            ));
            c.push(check(
                format!(
                    "γ = {g:e}, accurate: ≥ 5 meltings, the stamp advancing εc·h0 between them \
                     (mean within 2 %, each within 5 %)"
                ),
                event_count(&r.accurate) >= 5
                    && r.travel_per_event()
                        .is_some_and(|(m, d)| (m - 1.0).abs() <= 0.02 && d <= 0.05),
                format!(
                    "{} events, travel per event {}",
                    event_count(&r.accurate),
                    r.travel_text()
                ),
            ));
        }
        c
    }
    fn attempts(&self) -> Vec<&Attempt> {
        self.runs
            .iter()
            .flat_map(|r| [&r.literal, &r.accurate])
            .collect()
    }
}
