//! Hard case 1: a soft substrate (or, equivalently, a thin film), where the paper's lagged
//! elastic sweep has a contraction factor ρ > 1: the literal scheme must refuse before the
//! first step, naming ρ; the accurate scheme must run and converge in N.

use super::{
    Attempt, Bench, Case, Check, bounded, check, derived, event_count, failed_loudly,
    failure_value, health, health_text, literal_loud_text, onsets, outcome, sets, us_list, with,
};
use stickslip_core::preflight::Preflight;
use stickslip_report::fmt::{opt, sig};
use stickslip_report::stats::interp;
use stickslip_run::keys::{contact, time, words::Scheme};

/// Case 1: ρ > 1 from a soft substrate (or a thin film).
#[derive(Debug, Clone)]
pub struct SoftSubstrate {
    /// Literal scheme at G* = 1e8 Pa.
    pub literal: Attempt,
    /// Literal scheme with a thin film instead: G* = 1e9 Pa, h0 = 1e-8 m (same ρ).
    pub thin_film_literal: Attempt,
    /// The preflight of the literal scene, in-process.
    pub preflight: Result<Preflight, String>,
    /// Accurate runs at N = 50, 100, 200.
    pub accurate: Vec<(usize, Attempt)>,
}

/// Node counts of the case-1 refinement.
pub const SOFT_NODES: [usize; 3] = [50, 100, 200];
/// Time at which case 1 also compares F across N (stick phase), s.
pub const SOFT_F_TIME_S: f64 = 7e-4;

/// Runs case 1.
pub fn soft_substrate(b: &Bench) -> SoftSubstrate {
    let literal_sets = sets(&[time::SCHEME.set(Scheme::Literal)]);
    SoftSubstrate {
        literal: b.run("soft_literal", "soft_substrate", &literal_sets),
        thin_film_literal: b.run(
            "thin_film_literal",
            "soft_substrate",
            &with(
                &literal_sets,
                &sets(&[contact::G_EFF.set(1e9), contact::FILM_THICKNESS.set(1e-8)]),
            ),
        ),
        preflight: b.preflight("soft_substrate", &literal_sets),
        accurate: SOFT_NODES
            .iter()
            .map(|&n| {
                (
                    n,
                    b.run(
                        &format!("soft_accurate_n{n}"),
                        "soft_substrate",
                        &sets(&[contact::NODES.set(n as i64)]),
                    ),
                )
            })
            .collect(),
    }
}

impl SoftSubstrate {
    /// First onsets at N = 50, 100, 200 (NaN where missing), s.
    pub fn first_onsets_s(&self) -> Vec<f64> {
        self.accurate
            .iter()
            .map(|(_, a)| onsets(a).first().copied().unwrap_or(f64::NAN))
            .collect()
    }

    /// F at [`SOFT_F_TIME_S`] for N = 50, 100, 200, N.
    pub fn f_at_time_n(&self) -> Vec<f64> {
        self.accurate
            .iter()
            .map(|(_, a)| {
                a.out().map_or(f64::NAN, |o| {
                    interp(&o.series.t_s, &o.series.f_n, SOFT_F_TIME_S)
                })
            })
            .collect()
    }

    /// |onset(50) − onset(100)| and |onset(100) − onset(200)|, s.
    pub fn onset_differences_s(&self) -> (f64, f64) {
        let o = self.first_onsets_s();
        ((o[0] - o[1]).abs(), (o[1] - o[2]).abs())
    }

    /// The preflight's lagged-sweep contraction factor of the literal scene.
    pub fn preflight_rho(&self) -> Option<f64> {
        self.preflight
            .as_ref()
            .ok()
            .map(|p| p.lagged_sweep_contraction)
    }
}

/// Exit 3 before the first step, run.json's failure naming the contraction factor ≥ 1.
fn refusal_ok(a: &Attempt) -> bool {
    failed_loudly(a)
        && a.failure().is_some_and(|f| {
            f.step == 0
                && f.quantity == "lagged-sweep contraction factor"
                && failure_value(a).is_some_and(|v| v >= 1.0)
        })
}

impl Case for SoftSubstrate {
    fn title(&self) -> String {
        "1 soft substrate / thin film (ρ > 1)".into()
    }
    fn scenes(&self) -> String {
        "soft_substrate.toml".into()
    }
    fn literal(&self) -> String {
        format!(
            "{}; thin film (h0 = 1e-8 m, G* = 1e9 Pa): {}",
            literal_loud_text(&self.literal),
            literal_loud_text(&self.thin_film_literal)
        )
    }
    fn accurate(&self) -> String {
        let worst = self
            .accurate
            .iter()
            .filter_map(|(_, a)| health(a))
            .map(|h| h.f_ratio())
            .fold(0.0, f64::max);
        let all_ok = self.accurate.iter().all(|(_, a)| a.ok());
        let ns: Vec<String> = SOFT_NODES.iter().map(ToString::to_string).collect();
        format!(
            "{} at N = {}; bounded (max |F| = {}·τmax·πa0²); first onset converges",
            if all_ok { "runs" } else { "FAILS" },
            ns.join(", "),
            sig(worst, 3)
        )
    }
    fn numbers(&self) -> String {
        let (d1, d2) = self.onset_differences_s();
        let f = self.f_at_time_n();
        format!(
            "ρ = {} (preflight: {}); first onset at N = 50/100/200: {} µs, differences {} → {} µs \
             (observed order {}); F({} ms) = {} mN",
            opt(failure_value(&self.literal), 4),
            opt(self.preflight_rho(), 4),
            us_list(&self.first_onsets_s()),
            sig(d1 * 1e6, 3),
            sig(d2 * 1e6, 3),
            sig((d1 / d2).log2(), 2),
            sig(SOFT_F_TIME_S * 1e3, 2),
            f.iter()
                .map(|x| sig(x * 1e3, 5))
                .collect::<Vec<_>>()
                .join(" / ")
        )
    }
    fn checks(&self) -> Vec<Check> {
        let rho = failure_value(&self.literal);
        let rho_thin = failure_value(&self.thin_film_literal);
        let run_json_rho = derived(&self.literal).map(|d| d.lagged_sweep_contraction);
        let mut c = vec![
            check(
                "literal: exit 3 before the first step, run.json's failure naming the \
                 lagged-sweep contraction factor ≥ 1",
                refusal_ok(&self.literal),
                literal_loud_text(&self.literal),
            ),
            check(
                "literal, thin film instead of soft substrate: the same refusal with the same ρ",
                refusal_ok(&self.thin_film_literal)
                    && matches!((rho, rho_thin), (Some(a), Some(b)) if (a - b).abs() <= 1e-9 * a),
                format!("ρ = {} and {}", opt(rho, 4), opt(rho_thin, 4)),
            ),
            check(
                "the preflight (in-process) gives lagged_sweep_contraction ≥ 1, equal to \
                 run.json's",
                self.preflight_rho()
                    .zip(run_json_rho)
                    .is_some_and(|(c, d)| c >= 1.0 && (c - d).abs() <= 1e-12 * d),
                format!(
                    "preflight {}, run.json {}",
                    self.preflight
                        .as_ref()
                        .map_or_else(Clone::clone, |p| sig(p.lagged_sweep_contraction, 6)),
                    opt(run_json_rho, 6)
                ),
            ),
        ];
        for (n, a) in &self.accurate {
            c.push(check(
                format!("accurate N = {n}: exit 0, finite, φ ≥ 0, |F| ≤ τmax·π·a0²"),
                bounded(a, 1.0),
                format!("{}; {}", outcome(a), health_text(a)),
            ));
        }
        let counts: Vec<usize> = self.accurate.iter().map(|(_, a)| event_count(a)).collect();
        c.push(check(
            "accurate: at least one melting, the same number of events at every N",
            counts[0] >= 1 && counts.iter().all(|&k| k == counts[0]),
            format!("{counts:?}"),
        ));
        let (d1, d2) = self.onset_differences_s();
        c.push(check(
            "accurate: the first onset converges, |t(100) − t(200)| < |t(50) − t(100)|",
            d2 < d1,
            format!("{} → {} µs", sig(d1 * 1e6, 3), sig(d2 * 1e6, 3)),
        ));
        let f = self.f_at_time_n();
        let (e1, e2) = ((f[0] - f[1]).abs(), (f[1] - f[2]).abs());
        c.push(check(
            format!(
                "accurate: F at {} ms (stick phase) converges, |F(100) − F(200)| < |F(50) − F(100)|",
                sig(SOFT_F_TIME_S * 1e3, 2)
            ),
            e2 < e1,
            format!("{} → {} µN", sig(e1 * 1e6, 3), sig(e2 * 1e6, 3)),
        ));
        c
    }
    fn attempts(&self) -> Vec<&Attempt> {
        let mut v = vec![&self.literal, &self.thin_film_literal];
        v.extend(self.accurate.iter().map(|(_, a)| a));
        v
    }
}
