//! The events misfit's σ against the residuals' actual scatter: for each noise seed of a set,
//! the residuals of the true model against the noisy trace (what the fit sees at the truth,
//! without fitting anything), grouped by kind — first onset, intervals, peaks, drops — over
//! the seeds. Each residual is a difference over its σ, so their root mean square is 1 when
//! the σ are right; above 1 the misfit's weights claim more precision than the data have,
//! and the intervals come out narrower than their coverage needs.

use crate::cases::{Case, Sizes};
use crate::prepared::prepare;
use serde::{Deserialize, Serialize};
use std::path::Path;
use stickslip_studies::fit::MisfitKind;
use stickslip_studies::fit::misfit::Target;

/// One kind of residual over the seeds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SigmaRow {
    /// `first onset`, `intervals`, `peaks` or `drops`.
    pub kind: String,
    /// Residuals of that kind over all seeds.
    pub count: usize,
    /// Their mean.
    pub mean: f64,
    /// Their root mean square (1 when their σ are right).
    pub rms: f64,
}

/// The check of one set.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SigmaCheck {
    /// The set.
    pub case: String,
    /// Seeds.
    pub seeds: usize,
    /// Per kind.
    pub rows: Vec<SigmaRow>,
}

/// The kinds of an events misfit's residuals, in its order, for `n` data events.
#[must_use]
pub fn kinds(n: usize) -> Vec<&'static str> {
    let mut k = vec!["first onset"];
    k.extend(std::iter::repeat_n("intervals", n.saturating_sub(1)));
    k.extend(std::iter::repeat_n("peaks", n));
    k.extend(std::iter::repeat_n("drops", n));
    k.push("extra events");
    k
}

/// The rows of residual vectors `per_seed` (each with its data events' count).
#[must_use]
pub fn rows(per_seed: &[(usize, Vec<f64>)]) -> Vec<SigmaRow> {
    let order = ["first onset", "intervals", "peaks", "drops"];
    order
        .iter()
        .map(|&kind| {
            let v: Vec<f64> = per_seed
                .iter()
                .flat_map(|(n, r)| {
                    kinds(*n)
                        .into_iter()
                        .zip(r.iter().copied())
                        .filter(move |(k, _)| *k == kind)
                        .map(|(_, x)| x)
                })
                .collect();
            let count = v.len();
            let n = count.max(1) as f64;
            SigmaRow {
                kind: kind.to_string(),
                count,
                mean: v.iter().sum::<f64>() / n,
                rms: (v.iter().map(|x| x * x).sum::<f64>() / n).sqrt(),
            }
        })
        .collect()
}

/// The check of `case` over the seeds 1…`sizes.seeds` (the coverage's traces), σF estimated
/// from each trace as its fit estimates it.
///
/// # Errors
/// A case that cannot be prepared, or a trace without events.
pub fn check(root: &Path, case: Case, sizes: &Sizes) -> Result<SigmaCheck, String> {
    let p = prepare(root, case)?;
    let mut per_seed = Vec::new();
    for seed in 1..=sizes.seeds as u64 {
        let trace = p.trace(p.case.samples, seed)?;
        let target = Target::new(trace, MisfitKind::Events, None).map_err(|e| e.to_string())?;
        let r = target.compare(&p.curve, 0.0).residuals;
        per_seed.push((target.events.len(), r));
    }
    Ok(SigmaCheck {
        case: p.case.id,
        seeds: sizes.seeds,
        rows: rows(&per_seed),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn residuals_are_grouped_by_kind_in_the_misfits_order() {
        // Two events: first onset, one interval, two peaks, two drops, the extra events.
        assert_eq!(
            kinds(2),
            [
                "first onset",
                "intervals",
                "peaks",
                "peaks",
                "drops",
                "drops",
                "extra events"
            ]
        );
        let r = rows(&[
            (2, vec![1.0, -2.0, 3.0, 3.0, 0.5, -0.5, 0.0]),
            (2, vec![-1.0, 2.0, 3.0, 3.0, 0.5, -0.5, 0.0]),
        ]);
        assert_eq!(r[0].count, 2);
        assert!((r[0].rms - 1.0).abs() < 1e-15 && r[0].mean.abs() < 1e-15);
        assert!((r[1].rms - 2.0).abs() < 1e-15);
        assert!((r[2].rms - 3.0).abs() < 1e-15 && (r[2].mean - 3.0).abs() < 1e-15);
        assert!((r[3].rms - 0.5).abs() < 1e-15 && r[3].mean.abs() < 1e-15);
    }
}
