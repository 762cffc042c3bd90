//! Hard case 7: noise extremes — σ = 0 (φ = 0 an exact fixed point, reachable by underflow)
//! and σ up to 1e6 (kicks far larger than φ0): φ ≥ 0 and finite everywhere in the accurate
//! scheme; the literal scheme may fail, loudly.

use super::{
    Attempt, Bench, Case, Check, check, event_count, failed_loudly, failure_value, health,
    health_text, literal_loud_text, outcome, sets, with,
};
use stickslip_report::fmt::{self, sig};
use stickslip_run::keys::{noise, time, words::Scheme};

/// Case 7: σ = 0 with φ reaching exactly 0, and very large σ.
#[derive(Debug, Clone)]
pub struct NoiseExtremes {
    /// noise_zero.toml, accurate (σ = 0).
    pub zero_accurate: Attempt,
    /// noise_zero.toml, accurate with σ = 1 (comparison).
    pub unit_accurate: Attempt,
    /// noise_zero.toml, literal.
    pub zero_literal: Attempt,
    /// noise_large.toml at σ = 1e4 and 1e6: (σ, literal, accurate).
    pub large: Vec<(f64, Attempt, Attempt)>,
    /// noise_zero.toml, accurate (σ = 0), at the scene's Δt divided by each of
    /// [`ZERO_REFINEMENTS`]: (Δt, run).
    pub zero_refined: Vec<(f64, Attempt)>,
}

/// The scene's fixed step of noise_zero.toml, s.
pub const ZERO_DT_S: f64 = 1e-8;
/// Divisors of [`ZERO_DT_S`] for the σ = 0 event count's convergence in Δt. Reason: the stiff
/// kinetics (γ = 1e5 /(Pa·s)) under the fast rigid drive resolve the melt–regrow cycles only
/// below about 2e-10 s (measured: 39, 36, 43, 46, 49, 51, 52, 52, 52 events from Δt = 1e-8 s
/// halving to 3.9e-11 s); the two finest must agree.
pub const ZERO_REFINEMENTS: [u32; 8] = [2, 4, 8, 16, 32, 64, 128, 256];

/// σ values of noise_large runs, s^-1/2.
pub const LARGE_SIGMAS: [f64; 2] = [1e4, 1e6];

/// Runs case 7.
pub fn noise_extremes(b: &Bench) -> NoiseExtremes {
    let lit = sets(&[time::SCHEME.set(Scheme::Literal)]);
    NoiseExtremes {
        zero_accurate: b.run("noise_zero_accurate", "noise_zero", &[]),
        unit_accurate: b.run(
            "noise_unit_accurate",
            "noise_zero",
            // As text: the report quotes this `--set` as written ("=1", not the typed "=1e0").
            &["lubricant.noise.sigma=1".to_string()],
        ),
        zero_literal: b.run("noise_zero_literal", "noise_zero", &lit),
        zero_refined: ZERO_REFINEMENTS
            .iter()
            .map(|&k| {
                let dt = ZERO_DT_S / f64::from(k);
                (
                    dt,
                    b.run(
                        &format!("noise_zero_accurate_dt{k}"),
                        "noise_zero",
                        &sets(&[time::DT.set(dt)]),
                    ),
                )
            })
            .collect(),
        large: LARGE_SIGMAS
            .iter()
            .map(|&sigma| {
                let s = sets(&[noise::SIGMA.set(sigma)]);
                (
                    sigma,
                    b.run(
                        &format!("noise_large_literal_{sigma:e}"),
                        "noise_large",
                        &with(&s, &lit),
                    ),
                    b.run(
                        &format!("noise_large_accurate_{sigma:e}"),
                        "noise_large",
                        &s,
                    ),
                )
            })
            .collect(),
    }
}

/// σ = 0 run: (events, final melted fraction, nodes with φ exactly 0 in the last profile,
/// nodes in it, time from which the contact stays fully melted to the end).
pub fn stuck_melted(a: &Attempt) -> Option<(usize, f64, usize, usize, Option<f64>)> {
    let o = a.out()?;
    let s = &o.series;
    let last = o.profiles.blocks().into_iter().last()?;
    let zeros = last.phi.iter().filter(|&&p| p == 0.0).count();
    let since = s
        .melted_fraction
        .iter()
        .rposition(|&m| m < 0.999)
        .map_or(Some(0.0), |i| s.t_s.get(i + 1).copied());
    Some((
        o.events.len(),
        *s.melted_fraction.last()?,
        zeros,
        last.phi.len(),
        since,
    ))
}

/// The run's end time in words.
fn span(a: &Attempt) -> String {
    a.out()
        .map_or_else(|| "the run".to_string(), |o| fmt::time(o.info.end_s(), 2))
}

impl NoiseExtremes {
    /// σ = 0's event counts from the scene's Δt down, (Δt, events).
    fn zero_counts(&self) -> Vec<(f64, usize)> {
        std::iter::once((ZERO_DT_S, event_count(&self.zero_accurate)))
            .chain(
                self.zero_refined
                    .iter()
                    .map(|(dt, a)| (*dt, event_count(a))),
            )
            .collect()
    }

    fn zero_counts_text(&self) -> String {
        self.zero_counts()
            .iter()
            .map(|(dt, n)| format!("{n} at {} s", sig(*dt, 3)))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The converged count (the two finest agree) and the largest Δt from which every finer
    /// one gives it.
    fn zero_converged(&self) -> Option<(usize, f64)> {
        let counts = self.zero_counts();
        let ok = self.zero_refined.iter().all(|(_, a)| a.ok());
        let (_, last) = *counts.last()?;
        let (_, before) = counts[counts.len().checked_sub(2)?];
        if !ok || last != before {
            return None;
        }
        let from = counts
            .iter()
            .rev()
            .take_while(|(_, n)| *n == last)
            .last()
            .map(|(dt, _)| *dt)?;
        Some((last, from))
    }
}

impl Case for NoiseExtremes {
    fn title(&self) -> String {
        "7 noise extremes: σ = 0 with φ = 0, σ up to 1e6".into()
    }
    fn scenes(&self) -> String {
        "noise_zero.toml, noise_large.toml".into()
    }
    fn literal(&self) -> String {
        let mut v = vec![format!("σ = 0: {}", literal_loud_text(&self.zero_literal))];
        v.extend(
            self.large
                .iter()
                .map(|(s, l, _)| format!("σ = {s:e}: {}", literal_loud_text(l))),
        );
        v.join("; ")
    }
    fn accurate(&self) -> String {
        let mut v = vec![format!(
            "σ = 0: {} (σ = 1: {})",
            outcome(&self.zero_accurate),
            outcome(&self.unit_accurate)
        )];
        v.extend(
            self.large
                .iter()
                .map(|(s, _, a)| format!("σ = {s:e}: {}, {}", outcome(a), health_text(a))),
        );
        v.join("; ")
    }
    fn numbers(&self) -> String {
        let zero = stuck_melted(&self.zero_accurate).map_or_else(
            || "–".into(),
            |(ev, mf, zeros, n, since)| {
                format!(
                    "σ = 0: {ev} events, melted fraction at the end {}, φ = 0 exactly at \
                     {zeros} of {n} nodes at the end{}",
                    sig(mf, 3),
                    since.map_or_else(String::new, |t| format!(
                        ", fully melted from {} on",
                        fmt::time(t, 4)
                    ))
                )
            },
        );
        let unit = format!(
            "σ = 1: {} events in {}",
            event_count(&self.unit_accurate),
            span(&self.unit_accurate)
        );
        let large: Vec<String> = self
            .large
            .iter()
            .map(|(s, _, a)| {
                format!(
                    "σ = {s:e}: φ ∈ [{}, {}]",
                    health(a).map_or_else(|| "–".into(), |h| sig(h.phi_min, 3)),
                    health(a).map_or_else(|| "–".into(), |h| sig(h.phi_max, 3))
                )
            })
            .collect();
        format!(
            "{zero}; σ = 0 against Δt: {}; {unit}; {}",
            self.zero_counts_text(),
            large.join("; ")
        )
    }
    fn checks(&self) -> Vec<Check> {
        let fine = |a: &Attempt| a.ok() && health(a).is_some_and(|h| h.finite && h.phi_min >= 0.0);
        let mut c = vec![
            check(
                "σ = 0, accurate: exit 0, finite, φ ≥ 0",
                fine(&self.zero_accurate),
                format!(
                    "{}; {}",
                    outcome(&self.zero_accurate),
                    health_text(&self.zero_accurate)
                ),
            ),
            check(
                format!(
                    "σ = 1, accurate: exit 0, the film melts and re-solidifies ≥ 5 times in {}",
                    span(&self.unit_accurate)
                ),
                fine(&self.unit_accurate) && event_count(&self.unit_accurate) >= 5,
                outcome(&self.unit_accurate),
            ),
            check(
                format!(
                    "σ = 0, accurate: the event count converges in Δt (the same count at the two \
                     finest of Δt/{}, …, Δt/{}); at the scene's Δt it is reported, not judged",
                    ZERO_REFINEMENTS[0],
                    ZERO_REFINEMENTS[ZERO_REFINEMENTS.len() - 1]
                ),
                self.zero_converged().is_some(),
                self.zero_counts_text(),
            ),
            check(
                "σ = 0, literal (soft substrate and stiff kinetics): exit 3, run.json's failure \
                 naming it",
                failed_loudly(&self.zero_literal),
                literal_loud_text(&self.zero_literal),
            ),
        ];
        for (s, l, a) in &self.large {
            c.push(check(
                format!("σ = {s:e}, accurate: exit 0, finite, φ ≥ 0 everywhere"),
                fine(a),
                format!("{}; {}", outcome(a), health_text(a)),
            ));
            c.push(check(
                format!(
                    "σ = {s:e}, literal: exit 0 with φ ≥ 0, or exit 3, run.json's failure naming \
                     it"
                ),
                fine(l) || failed_loudly(l),
                literal_loud_text(l),
            ));
        }
        c
    }
    fn findings(&self) -> Vec<String> {
        let mut f = Vec::new();
        if let Some((n, from)) = self.zero_converged() {
            let at_scene = event_count(&self.zero_accurate);
            if at_scene != n {
                f.push(format!(
                    "Case 7, σ = 0: at the scene's fixed Δt = {} s the accurate scheme is stable \
                     and keeps φ ≥ 0, but its event count ({at_scene}) is not converged: the \
                     count converges to {n} from Δt = {} s on ({}). The stiff kinetics \
                     (γ = 1e5 /(Pa·s)) under the 10 m/s rigid drive melt and regrow a node within \
                     a few ns, so a 10 ns step merges or misses cycles. φ_min = {} is the \
                     accurate scheme's representable floor (φ² = 1e-300, still a normal f64): a \
                     molten node is kept there, not at 0, so that it can regrow without noise. \
                     Reproduce: `{}` with `--set time.dt=…`.",
                    sig(ZERO_DT_S, 2),
                    sig(from, 3),
                    self.zero_counts_text(),
                    sig(stickslip_core::sim::PHI_REPRESENTABLE_MIN, 2),
                    self.zero_accurate.command
                ));
            }
        }
        if let Some((ev, mf, zeros, n, since)) = stuck_melted(&self.zero_accurate)
            && zeros > 0
            && event_count(&self.unit_accurate) > ev
        {
            let unit_mf = stuck_melted(&self.unit_accurate).map_or(f64::NAN, |x| x.1);
            f.push(format!(
                "With σ = 0 (the same holds for kind = \"off\") melted nodes stay melted for \
                 good once the accurate scheme's exact Landau step has underflowed φ to exactly \
                 0: {ev} event(s) in {}, φ = 0 exactly at {zeros} of {n} nodes and melted \
                 fraction {} at the end{}, against {} events and melted fraction {} with σ = 1. \
                 In exact arithmetic φ² = y0·e^(−2γcΔt) stays positive and grows back once \
                 c < 0; the underflow turns the unstable fixed point φ = 0 into a trap. \
                 noise.rs documents that only the floor protects a molten node. Reproduce: `{}` \
                 (and the same with `--set lubricant.noise.sigma=1`).",
                span(&self.zero_accurate),
                sig(mf, 3),
                since.map_or_else(String::new, |t| format!(
                    " (fully melted from {} on)",
                    fmt::time(t, 4)
                )),
                event_count(&self.unit_accurate),
                sig(unit_mf, 3),
                self.zero_accurate.command
            ));
        }
        for (s, l, _) in &self.large {
            if let Some(fl) = l.failure()
                && fl.quantity == "phi"
                && fl.reason.contains("explicit Euler")
                && !fl.reason.contains("noise")
            {
                let dt = l
                    .out()
                    .and_then(|o| o.info.scene.time.as_ref().and_then(|t| t.dt))
                    .unwrap_or(f64::NAN);
                f.push(format!(
                    "Literal scheme, σ = {s:e}: the failure is loud (exit 3 at step {}, node {}, φ \
                     = {}), but run.json's reason blames the time step (\"{}\") while the cause \
                     is the noise: a kick of σ·√Δt = {} takes φ far from equilibrium, where \
                     explicit Euler's local stiffness is much larger. Reproduce: `{}`.",
                    fl.step,
                    fl.node,
                    failure_value(l).map_or_else(|| "?".into(), |v| sig(v, 3)),
                    fmt::first_line(&fl.reason),
                    sig(s * dt.sqrt(), 3),
                    l.command
                ));
            }
        }
        f
    }
    fn attempts(&self) -> Vec<&Attempt> {
        let mut v = vec![&self.zero_accurate, &self.unit_accurate, &self.zero_literal];
        v.extend(self.zero_refined.iter().map(|(_, a)| a));
        v.extend(self.large.iter().flat_map(|(_, l, a)| [l, a]));
        v
    }
}
