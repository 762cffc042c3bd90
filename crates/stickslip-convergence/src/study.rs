//! One convergence study: an observable refined along one resolution, its errors, observed
//! orders and (without an exact answer) the Celik three-grid estimate.
//!
//! This is the record written to `reports/convergence.json`, one object per study with at
//! least `{"observable", "scheme", "refined", "levels", "errors", "observed_order", "gci"}`.

use crate::celik::{self, Celik, CelikFailure};
use serde::{Deserialize, Serialize};

/// Which resolution a study refines.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Refined {
    /// The number of radial nodes N (spacing h = a0/N).
    #[serde(rename = "N")]
    Nodes,
    /// The time step Δt.
    #[serde(rename = "dt")]
    Dt,
}

impl Refined {
    /// "N" or "dt".
    pub fn as_str(&self) -> &'static str {
        match self {
            Self::Nodes => "N",
            Self::Dt => "dt",
        }
    }

    /// The spacing of a level: 1/N for nodes (h = a0/N up to the constant a0), Δt itself.
    pub fn spacing(&self, level: f64) -> f64 {
        match self {
            Self::Nodes => 1.0 / level,
            Self::Dt => level,
        }
    }
}

/// How the errors of a study were obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ErrorKind {
    /// Against an exact answer.
    Exact,
    /// Against the Celik extrapolated value of the three finest levels.
    VsExtrapolated,
    /// Against the finest level (used when the extrapolation is not trustworthy).
    VsFinest,
}

/// One study; see the module documentation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Study {
    /// Family: `operator`, `stepper` or `simulation`.
    pub study: String,
    /// What is measured (e.g. `forward`, `onset`, `f_peak`, `force_stick_rms`).
    pub observable: String,
    /// Scheme, quadrature, stepper or integrator.
    pub scheme: String,
    /// The refined resolution.
    pub refined: Refined,
    /// Levels of the refined resolution (N, or Δt in s), coarse to fine.
    pub levels: Vec<f64>,
    /// What is held fixed and any other qualifier (pair, norm, event number, case).
    pub fixed: String,
    /// Event number for per-event observables.
    pub event: Option<usize>,
    /// Unit of `values`, `errors` and the absolute GCI.
    pub unit: String,
    /// Values of the observable per level (self-convergence studies only).
    pub values: Option<Vec<Option<f64>>>,
    /// Error per level (`null` where the level failed or the error is undefined).
    pub errors: Vec<Option<f64>>,
    /// What the errors are measured against.
    pub error_kind: ErrorKind,
    /// Observed order per refinement: from successive errors (exact answers) or, without an
    /// exact answer, the Celik order of each three consecutive levels.
    pub observed_order: Vec<Option<f64>>,
    /// Theoretical order, where one is claimed.
    pub theory_order: Option<f64>,
    /// The theory in words (`2`, `1/2`, `exact`, `none: O(1) at the edge`).
    pub theory: String,
    /// Celik three-grid result on the three finest valid levels.
    pub gci: Option<Celik>,
    /// Why `gci` is missing.
    pub gci_failure: Option<CelikFailure>,
    /// Remarks (failed levels, oscillation).
    pub note: String,
    /// F(t) studies only: max over levels of |F − F_finest|/F_finest at half the first onset
    /// time, i.e. deep in the first stick phase.
    #[serde(default)]
    pub early_stick_rel_diff: Option<f64>,
}

fn finite(v: f64) -> Option<f64> {
    v.is_finite().then_some(v)
}

impl Study {
    /// A study against an exact answer: `errors` per level, orders from successive errors.
    #[allow(clippy::too_many_arguments)]
    pub fn exact(
        study: &str,
        observable: &str,
        scheme: &str,
        refined: Refined,
        levels: Vec<f64>,
        fixed: &str,
        unit: &str,
        errors: Vec<f64>,
        theory: (Option<f64>, &str),
    ) -> Self {
        let h: Vec<f64> = levels.iter().map(|&l| refined.spacing(l)).collect();
        let orders = h
            .windows(2)
            .zip(errors.windows(2))
            .map(|(h, e)| {
                (e[0] > 0.0 && e[1] > 0.0)
                    .then(|| celik::observed_orders(h, e)[0])
                    .and_then(finite)
            })
            .collect();
        Self {
            study: study.to_string(),
            observable: observable.to_string(),
            scheme: scheme.to_string(),
            refined,
            levels,
            fixed: fixed.to_string(),
            event: None,
            unit: unit.to_string(),
            values: None,
            errors: errors.into_iter().map(finite).collect(),
            error_kind: ErrorKind::Exact,
            observed_order: orders,
            theory_order: theory.0,
            theory: theory.1.to_string(),
            gci: None,
            gci_failure: None,
            note: String::new(),
            early_stick_rel_diff: None,
        }
    }

    /// A study without an exact answer: `values` per level (`None` where the level failed).
    /// Celik's procedure on the three finest valid levels gives p, φext and the GCI; the
    /// errors are |φ − φext| when that succeeded without oscillation, else |φ − φ_finest|.
    #[allow(clippy::too_many_arguments)]
    pub fn self_convergence(
        study: &str,
        observable: &str,
        scheme: &str,
        refined: Refined,
        levels: Vec<f64>,
        fixed: &str,
        unit: &str,
        values: Vec<Option<f64>>,
        theory: (Option<f64>, &str),
    ) -> Self {
        let values: Vec<Option<f64>> = values.into_iter().map(|v| v.and_then(finite)).collect();
        let valid: Vec<usize> = (0..levels.len()).filter(|&i| values[i].is_some()).collect();
        let h = |i: usize| refined.spacing(levels[i]);
        let v = |i: usize| values[i].unwrap_or(f64::NAN);
        let mut observed_order = vec![None; levels.len().saturating_sub(2)];
        for k in 0..observed_order.len() {
            if values[k].is_some() && values[k + 1].is_some() && values[k + 2].is_some() {
                observed_order[k] =
                    celik::three_grid([h(k + 2), h(k + 1), h(k)], [v(k + 2), v(k + 1), v(k)])
                        .ok()
                        .map(|c| c.p);
            }
        }
        let mut note = Vec::new();
        let failed: Vec<String> = (0..levels.len())
            .filter(|&i| values[i].is_none())
            .map(|i| format!("{:e}", levels[i]))
            .collect();
        if !failed.is_empty() {
            note.push(format!("no value at level(s) {}", failed.join(", ")));
        }
        let (gci, gci_failure) = if valid.len() >= 3 {
            let [a, b, c] = [
                valid[valid.len() - 1],
                valid[valid.len() - 2],
                valid[valid.len() - 3],
            ];
            match celik::three_grid([h(a), h(b), h(c)], [v(a), v(b), v(c)]) {
                Ok(g) => (Some(g), None),
                Err(e) => (None, Some(e)),
            }
        } else {
            (None, Some(CelikFailure::NonFinite))
        };
        let finest = valid.last().map(|&i| v(i));
        let (errors, error_kind) = match gci {
            Some(g) if !g.oscillatory => (
                values
                    .iter()
                    .map(|x| x.map(|x| (x - g.phi_ext).abs()))
                    .collect(),
                ErrorKind::VsExtrapolated,
            ),
            _ => {
                if gci.is_some_and(|g| g.oscillatory) {
                    note.push("oscillatory convergence on the finest three levels".to_string());
                }
                (
                    values
                        .iter()
                        .zip(0..)
                        .map(|(x, i)| {
                            if Some(i) == valid.last().copied() {
                                None
                            } else {
                                x.zip(finest).map(|(x, f)| (x - f).abs())
                            }
                        })
                        .collect(),
                    ErrorKind::VsFinest,
                )
            }
        };
        Self {
            study: study.to_string(),
            observable: observable.to_string(),
            scheme: scheme.to_string(),
            refined,
            levels,
            fixed: fixed.to_string(),
            event: None,
            unit: unit.to_string(),
            values: Some(values),
            errors,
            error_kind,
            observed_order,
            theory_order: theory.0,
            theory: theory.1.to_string(),
            gci,
            gci_failure,
            note: note.join("; "),
            early_stick_rel_diff: None,
        }
    }

    /// Sets the event number.
    pub fn with_event(mut self, k: usize) -> Self {
        self.event = Some(k);
        self
    }

    /// Appends a remark.
    pub fn with_note(mut self, note: &str) -> Self {
        if !note.is_empty() {
            if !self.note.is_empty() {
                self.note.push_str("; ");
            }
            self.note.push_str(note);
        }
        self
    }

    /// The last finite error, if any.
    pub fn finest_error(&self) -> Option<f64> {
        self.errors.iter().rev().find_map(|e| *e)
    }

    /// Observed orders that are defined.
    pub fn defined_orders(&self) -> Vec<f64> {
        self.observed_order.iter().filter_map(|p| *p).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn self_convergence_recovers_manufactured_limit() {
        let levels = vec![125.0, 250.0, 500.0, 1000.0];
        let values: Vec<Option<f64>> = levels.iter().map(|&n: &f64| Some(2.0 + 7.0 / n)).collect();
        let s = Study::self_convergence(
            "simulation",
            "x",
            "accurate",
            Refined::Nodes,
            levels,
            "",
            "s",
            values,
            (Some(1.0), "1"),
        );
        let g = s.gci.unwrap();
        assert!((g.p - 1.0).abs() < 1e-6 && (g.phi_ext - 2.0).abs() < 1e-9);
        assert_eq!(s.error_kind, ErrorKind::VsExtrapolated);
        for (e, n) in s.errors.iter().zip([125.0, 250.0, 500.0, 1000.0]) {
            assert!((e.unwrap() - 7.0 / n).abs() < 1e-9);
        }
        for p in s.observed_order {
            assert!((p.unwrap() - 1.0).abs() < 1e-6);
        }
    }

    #[test]
    fn failed_levels_are_skipped() {
        let levels = vec![4e-8, 2e-8, 1e-8, 5e-9];
        let values = vec![None, Some(1.0 + 2e-8), Some(1.0 + 1e-8), Some(1.0 + 5e-9)];
        let s = Study::self_convergence(
            "simulation",
            "x",
            "literal",
            Refined::Dt,
            levels,
            "",
            "s",
            values,
            (None, "1"),
        );
        assert!(s.note.contains("4e-8"));
        assert_eq!(s.observed_order[0], None);
        assert!((s.observed_order[1].unwrap() - 1.0).abs() < 1e-5);
        assert!(s.gci.is_some());
    }
}
