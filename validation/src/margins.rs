//! Each claim's margin to its threshold: how far its binding number is from failing, as a
//! share of the threshold (positive: passes; negative: fails; 0.5 means half the threshold's
//! room is left). For a criterion of strict order (intervals shrinking, amplitudes falling) the
//! margin is the smallest relative step, 1 − the largest ratio of successive values. Read from
//! the claims' structured values, with the thresholds of `claims` and `claims_first_order`.

use crate::claims::{
    C1_MIN_DROP, C1_MIN_EVENTS, C4_EDGE_BAND, C5_MAX_MELT_FRACTION, C6_ONSET_TOL, C8_X_TOL,
    C9_MAX_CV_X, C9_MAX_DAMPING_RATIO, C10_MAX_CV, Claim,
};
use crate::claims_first_order::{C11_REL_TOL, C12_MIN_FACTOR};
use serde_json::Value;

/// A claim's binding margin and the criterion it comes from.
#[derive(Debug, Clone, PartialEq)]
pub struct Margin {
    /// The claim's id.
    pub id: &'static str,
    /// The margin (share of the threshold's room; negative when failing).
    pub value: f64,
    /// Which number binds.
    pub binding: String,
}

fn num(v: &Value, path: &[&str]) -> Option<f64> {
    let mut x = v;
    for p in path {
        x = x.get(p)?;
    }
    x.as_f64()
}

fn list(v: &Value, path: &[&str]) -> Vec<f64> {
    let mut x = v;
    for p in path {
        match x.get(p) {
            Some(y) => x = y,
            None => return Vec::new(),
        }
    }
    x.as_array()
        .map(|a| a.iter().filter_map(Value::as_f64).collect())
        .unwrap_or_default()
}

/// 1 − the largest ratio of successive values (strictly decreasing: positive).
fn falling(xs: &[f64]) -> Option<f64> {
    xs.windows(2)
        .map(|w| 1.0 - w[1] / w[0])
        .min_by(f64::total_cmp)
}

/// The least of `candidates`, with its name.
fn least(id: &'static str, candidates: Vec<(Option<f64>, String)>) -> Option<Margin> {
    candidates
        .into_iter()
        .filter_map(|(v, name)| v.filter(|x| x.is_finite()).map(|x| (x, name)))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(value, binding)| Margin { id, value, binding })
}

/// The margin of `claim`, when its numbers have one.
#[must_use]
pub fn of(claim: &Claim) -> Option<Margin> {
    let v = &claim.value;
    let edge = 1.0 - C4_EDGE_BAND;
    match claim.id {
        "C1" => least(
            "C1",
            vec![
                (
                    num(v, &["fig2", "events"])
                        .map(|e| (e - C1_MIN_EVENTS as f64) / C1_MIN_EVENTS as f64),
                    "events".into(),
                ),
                (
                    num(v, &["fig2", "min_drop"]).map(|d| (d - C1_MIN_DROP) / C1_MIN_DROP),
                    "smallest drop".into(),
                ),
            ],
        ),
        "C2" => least(
            "C2",
            ["fig2", "fig4"]
                .iter()
                .map(|r| {
                    (
                        num(v, &[r, "max_ratio"]).map(|m| 1.0 - m),
                        format!("{r}: largest Δ(k+1)/Δk"),
                    )
                })
                .collect(),
        ),
        "C3" => least(
            "C3",
            vec![
                (
                    num(v, &["fig2", "first_interval_us"])
                        .zip(num(v, &["fig2", "longest_later_interval_us"]))
                        .map(|(a, b)| a / b - 1.0),
                    "first interval against the longest later".into(),
                ),
                (
                    num(v, &["fig2", "rate_F_min_later_N_per_s"])
                        .zip(num(v, &["fig2", "rate_F_first_N_per_s"]))
                        .map(|(a, b)| a / b - 1.0),
                    "growth of F".into(),
                ),
                (
                    num(v, &["fig2", "rate_eps_min_later_per_s"])
                        .zip(num(v, &["fig2", "rate_eps_first_per_s"]))
                        .map(|(a, b)| a / b - 1.0),
                    "growth of ⟨ε⟩".into(),
                ),
            ],
        ),
        "C4" | "C13" => {
            let runs: &[&str] = if claim.id == "C4" {
                &["fig2", "fig3"]
            } else {
                &["fig2_first_order"]
            };
            least(
                claim.id,
                runs.iter()
                    .map(|r| {
                        (
                            num(v, &[r, "min_r_first_over_a0"]).map(|x| (x - edge) / edge),
                            format!("{r}: outermost first melted radius"),
                        )
                    })
                    .collect(),
            )
        }
        "C5" => least(
            "C5",
            vec![(
                num(v, &["fig3", "ratio"]).map(|r| 1.0 - r / C5_MAX_MELT_FRACTION),
                "longest melted spell / shortest interval".into(),
            )],
        ),
        "C6" => least(
            "C6",
            vec![(
                num(v, &["homogeneous_vs_fig2", "max_onset_shift_over_interval"])
                    .map(|r| 1.0 - r / C6_ONSET_TOL),
                "largest onset shift / interval".into(),
            )],
        ),
        "C7" => least(
            "C7",
            [
                ("f_peak_mN", "f_peak"),
                ("amp_F_mN", "F amplitude"),
                ("amp_phi", "⟨φ⟩ amplitude"),
                ("amp_eps", "⟨ε⟩ amplitude"),
                ("intervals_us", "intervals"),
            ]
            .iter()
            .map(|(k, name)| {
                (
                    falling(&list(v, &["fig4", k])),
                    format!("{name}: smallest fall"),
                )
            })
            .collect(),
        ),
        "C8" => least(
            "C8",
            vec![
                (
                    num(v, &["melt", "max_abs_F_N"])
                        .zip(num(v, &["melt", "F_tolerance_N"]))
                        .map(|(f, t)| 1.0 - f / t),
                    "max |F|".into(),
                ),
                (
                    num(v, &["melt", "max_rel_X_error"]).map(|e| 1.0 - e / C8_X_TOL),
                    "X against the free stamp".into(),
                ),
            ],
        ),
        "C9" => least(
            "C9",
            vec![
                (
                    num(v, &["fig2", "cv_x"]).map(|c| 1.0 - c / C9_MAX_CV_X),
                    "fig2: CV of the X-distances".into(),
                ),
                (
                    num(v, &["fig4", "last_over_first_f_peak"])
                        .map(|r| 1.0 - r / C9_MAX_DAMPING_RATIO),
                    "fig4: last/first f_peak".into(),
                ),
            ],
        ),
        "C10" => least(
            "C10",
            vec![(
                num(v, &["rigid", "cv"]).map(|c| 1.0 - c / C10_MAX_CV),
                "CV of the intervals".into(),
            )],
        ),
        "C11" => {
            let worst = v.as_object().map(|m| {
                m.values()
                    .filter_map(|t| t.get("rel_dev").and_then(Value::as_object))
                    .flat_map(|d| d.values().filter_map(Value::as_f64))
                    .fold(0.0, f64::max)
            });
            least(
                "C11",
                vec![(
                    worst.map(|d| 1.0 - d / C11_REL_TOL),
                    "largest deviation from theory".into(),
                )],
            )
        }
        "C12" => {
            let ratios: Vec<(Option<f64>, String)> = v
                .get("first_vs_second_order")
                .and_then(|c| c.get("ratio_first_over_second"))
                .and_then(Value::as_object)
                .map(|m| {
                    m.iter()
                        .map(|(k, r)| {
                            (
                                r.as_f64().map(|x| x / C12_MIN_FACTOR - 1.0),
                                format!("first/second-order {k}"),
                            )
                        })
                        .collect()
                })
                .unwrap_or_default();
            least("C12", ratios)
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn claim(id: &'static str, value: Value) -> Claim {
        Claim {
            id,
            statement: "",
            criterion: String::new(),
            reason: String::new(),
            value,
            value_text: String::new(),
            pass: true,
        }
    }

    #[test]
    fn margins_are_shares_of_the_thresholds_room() {
        let c = claim("C10", json!({ "rigid": { "cv": 0.0025 } }));
        assert!((of(&c).unwrap().value - 0.75).abs() < 1e-12);
        let c = claim(
            "C2",
            json!({ "fig2": { "max_ratio": 0.9 }, "fig4": { "max_ratio": 0.95 } }),
        );
        let m = of(&c).unwrap();
        assert!((m.value - 0.05).abs() < 1e-12 && m.binding.starts_with("fig4"));
        let c = claim("C7", json!({ "fig4": { "f_peak_mN": [1.0, 0.8, 0.79] } }));
        assert!((of(&c).unwrap().value - (1.0 - 0.79 / 0.8)).abs() < 1e-12);
        // A failing number gives a negative margin.
        let c = claim(
            "C9",
            json!({ "fig2": { "cv_x": 0.06 }, "fig4": { "last_over_first_f_peak": 0.3 } }),
        );
        assert!(of(&c).unwrap().value < 0.0);
        assert!(of(&claim("C99", json!({}))).is_none());
    }
}
