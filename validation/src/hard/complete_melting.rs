//! Hard case 4: complete melting — A = 0 and A < 0 from the start, and A(t) → 0 by fast
//! heating: εc = φ0 = 0 (not NaN), one melting that never ends, F = 0, and φ decaying
//! algebraically as 1/√(2γ·b·t) once A has reached 0.

use super::{
    Attempt, Bench, Case, Check, Health, check, derived, event_count, health, outcome, sets, with,
};
use stickslip_report::fmt::{self, opt, sig};
use stickslip_run::keys::{temperature, time, words::Scheme};

/// Case 4: A = 0 and A < 0 from the start, and A(t) → 0 by fast heating.
#[derive(Debug, Clone)]
pub struct Melting {
    /// A0 = 0 and A0 = −1e5 Pa: (A0, literal, accurate).
    pub from_start: Vec<(f64, Attempt, Attempt)>,
    /// Heating to A = 0: literal.
    pub heating_literal: Attempt,
    /// Heating to A = 0: accurate.
    pub heating_accurate: Attempt,
}

/// Runs case 4.
pub fn melting(b: &Bench) -> Melting {
    let lit = sets(&[time::SCHEME.set(Scheme::Literal)]);
    Melting {
        from_start: [0.0, -1e5]
            .iter()
            .map(|&a0| {
                let s = sets(&[temperature::A0.set(a0)]);
                (
                    a0,
                    b.run(
                        &format!("melt_literal_a{a0:e}"),
                        "melt_from_start",
                        &with(&s, &lit),
                    ),
                    b.run(&format!("melt_accurate_a{a0:e}"), "melt_from_start", &s),
                )
            })
            .collect(),
        heating_literal: b.run("heating_literal", "heating_to_zero", &lit),
        heating_accurate: b.run("heating_accurate", "heating_to_zero", &[]),
    }
}

/// run.json's derived εc and φ0.
fn eps_phi(a: &Attempt) -> (Option<f64>, Option<f64>) {
    (derived(a).map(|d| d.eps_c), derived(a).map(|d| d.phi0))
}

/// What a complete-melting run must show.
fn melted_throughout(a: &Attempt) -> bool {
    a.ok()
        && eps_phi(a) == (Some(0.0), Some(0.0))
        && a.out().is_some_and(|o| {
            let s = &o.series;
            Health::of(o).finite
                && s.f_n.iter().chain(&s.f_1d_n).all(|&f| f == 0.0)
                && s.melted_fraction.iter().all(|&m| m >= 0.999)
                && o.events.len() == 1
                && o.events.events()[0].t_onset_s == 0.0
        })
}

/// Heating: (onset, max |F| after the contact is fully melted, φ(end), 1/√(2γ·b·t_end)).
fn heating_numbers(a: &Attempt) -> Option<(f64, f64, f64, f64)> {
    let o = a.out()?;
    let s = &o.series;
    let first_full = s.melted_fraction.iter().position(|&m| m >= 0.999)?;
    let f_after = s.f_n[first_full..]
        .iter()
        .fold(0.0_f64, |m, f| m.max(f.abs()));
    let gamma = o.info.scene.lubricant.as_ref()?.gamma?;
    let b = o.info.derived.b;
    let t_end = *s.t_s.last()?;
    Some((
        o.events.events().first()?.t_onset_s,
        f_after,
        *s.phi_mean.last()?,
        1.0 / (2.0 * gamma * b * t_end).sqrt(),
    ))
}

fn heating_ok(a: &Attempt) -> bool {
    a.ok()
        && event_count(a) == 1
        && health(a).is_some_and(|h| h.finite && h.phi_min >= 0.0)
        && a.out()
            .is_some_and(|o| o.series.melted_fraction.last().is_some_and(|&m| m >= 0.999))
        && heating_numbers(a)
            .is_some_and(|(_, f, phi, pred)| f == 0.0 && (phi / pred - 1.0).abs() <= 0.1)
}

impl Case for Melting {
    fn title(&self) -> String {
        "4 complete melting: A ≤ 0 from the start, A(t) → 0".into()
    }
    fn scenes(&self) -> String {
        "melt_from_start.toml, heating_to_zero.toml".into()
    }
    fn literal(&self) -> String {
        let mut v: Vec<String> = self
            .from_start
            .iter()
            .map(|(a0, l, _)| format!("A0 = {} Pa: {}", sig(*a0, 3), outcome(l)))
            .collect();
        v.push(format!("heating: {}", outcome(&self.heating_literal)));
        v.join("; ")
    }
    fn accurate(&self) -> String {
        let mut v: Vec<String> = self
            .from_start
            .iter()
            .map(|(a0, _, a)| format!("A0 = {} Pa: {}", sig(*a0, 3), outcome(a)))
            .collect();
        v.push(format!("heating: {}", outcome(&self.heating_accurate)));
        v.join("; ")
    }
    fn numbers(&self) -> String {
        let mut v: Vec<String> = self
            .from_start
            .iter()
            .map(|(a0, _, a)| {
                let max_f = a.out().map_or(f64::NAN, |o| {
                    o.series.f_n.iter().fold(0.0_f64, |m, f| m.max(f.abs()))
                });
                let (e, p) = eps_phi(a);
                format!(
                    "A0 = {a0:e} Pa: run.json εc = {}, φ0 = {}, max |F| = {} N",
                    opt(e, 4),
                    opt(p, 4),
                    sig(max_f, 3)
                )
            })
            .collect();
        for (name, a) in [
            ("literal", &self.heating_literal),
            ("accurate", &self.heating_accurate),
        ] {
            if let Some((onset, f, phi, pred)) = heating_numbers(a) {
                v.push(format!(
                    "heating ({name}): melts at {}, max |F| once fully melted = {} N, φ(end) = \
                     {} against 1/√(2γbt) = {}",
                    fmt::time(onset, 6),
                    sig(f, 3),
                    sig(phi, 4),
                    sig(pred, 4)
                ));
            }
        }
        v.join("; ")
    }
    fn checks(&self) -> Vec<Check> {
        let mut c = Vec::new();
        for (a0, l, a) in &self.from_start {
            for (scheme, run) in [("literal", l), ("accurate", a)] {
                let (e, p) = eps_phi(run);
                c.push(check(
                    format!(
                        "A0 = {a0:e}, {scheme}: exit 0, εc = φ0 = 0 (not NaN), one event at t = 0, \
                         melted_fraction = 1 and F = F_1d = 0 throughout, finite"
                    ),
                    melted_throughout(run),
                    format!("{}; εc = {}, φ0 = {}", outcome(run), opt(e, 4), opt(p, 4)),
                ));
            }
        }
        for (scheme, run) in [
            ("literal", &self.heating_literal),
            ("accurate", &self.heating_accurate),
        ] {
            c.push(check(
                format!(
                    "heating to A = 0, {scheme}: exit 0, one melting that never ends, F = 0 once \
                     fully melted, φ(end) within 10 % of 1/√(2γ·b·t), finite, φ ≥ 0"
                ),
                heating_ok(run),
                format!(
                    "{}; {}",
                    outcome(run),
                    heating_numbers(run).map_or_else(
                        || "no melting".into(),
                        |(on, f, phi, pred)| format!(
                            "melts at {}, max |F| after {} N, φ(end) = {} against {}",
                            fmt::time(on, 6),
                            sig(f, 3),
                            sig(phi, 4),
                            sig(pred, 4)
                        )
                    )
                ),
            ));
        }
        c
    }
    fn attempts(&self) -> Vec<&Attempt> {
        let mut v: Vec<&Attempt> = self
            .from_start
            .iter()
            .flat_map(|(_, l, a)| [l, a])
            .collect();
        v.push(&self.heating_literal);
        v.push(&self.heating_accurate);
        v
    }
}
