//! Sensitivity of the claims that depend on the model's own choices: the melting threshold
//! (default 0.01) and the φ floor (default 1e-6) that stands in for thermal noise. Claims C4,
//! C5 and C13 and the melting front's speed are evaluated again with one of them changed at a
//! time: threshold 1e-3 and 5e-2, floor 1e-8, 1e-7, 1e-5 and 1e-4 (each against the default
//! runs of the validation). A claim whose verdict flips under a variation says so in the
//! claims table.
//!
//! The runs are fig2, fig3 (fig2 with probes sampled every 2e-8 s, for C4's probe order and
//! C5) and fig2_first_order at the validation's N, with the one key changed.

use crate::claims::{Claim, Part, Runs, c4_events_part, c4_probes_part, c5_part};
use crate::claims_first_order::{c13_speed_part, front_speeds};
use crate::runner::{RunSpec, fig3_overrides};
use std::fmt::Write as _;
use stickslip_report::fmt;
use stickslip_run::keys::{lubricant, noise};

/// One variation of the model's choices.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Variation {
    /// Label in run names and the report.
    pub label: &'static str,
    /// The melting threshold (None: the default).
    pub threshold: Option<f64>,
    /// The φ floor (None: the default).
    pub floor: Option<f64>,
}

/// The variations, one key at a time.
pub const VARIATIONS: [Variation; 6] = [
    Variation {
        label: "threshold1e-3",
        threshold: Some(1e-3),
        floor: None,
    },
    Variation {
        label: "threshold5e-2",
        threshold: Some(5e-2),
        floor: None,
    },
    Variation {
        label: "floor1e-8",
        threshold: None,
        floor: Some(1e-8),
    },
    Variation {
        label: "floor1e-7",
        threshold: None,
        floor: Some(1e-7),
    },
    Variation {
        label: "floor1e-5",
        threshold: None,
        floor: Some(1e-5),
    },
    Variation {
        label: "floor1e-4",
        threshold: None,
        floor: Some(1e-4),
    },
];

/// The claims this module re-evaluates.
pub const CLAIMS: [&str; 3] = ["C4", "C5", "C13"];

impl Variation {
    fn sets(&self) -> Vec<String> {
        let mut v = Vec::new();
        if let Some(t) = self.threshold {
            v.push(lubricant::MELT_THRESHOLD.set(t).to_string());
        }
        if let Some(f) = self.floor {
            v.push(noise::FLOOR.set(f).to_string());
        }
        v
    }

    /// The run name of `scene` under this variation.
    #[must_use]
    pub fn run(&self, scene: &str) -> String {
        format!("sens_{}_{scene}", self.label)
    }

    /// The changed key in words.
    #[must_use]
    pub fn text(&self) -> String {
        match (self.threshold, self.floor) {
            (Some(t), _) => format!("threshold {}", fmt::trim(t)),
            (_, Some(f)) => format!("floor {f:e}"),
            _ => "default".into(),
        }
    }
}

/// The runs of every variation.
#[must_use]
pub fn specs() -> Vec<RunSpec> {
    let mut all = Vec::new();
    for v in VARIATIONS {
        let purpose = format!("sensitivity of C4, C5, C13 to the {}", v.text());
        let mut fig2 = RunSpec::new(&v.run("fig2"), "fig2", &purpose);
        fig2.sets = v.sets();
        let mut fig3 = RunSpec::new(&v.run("fig3"), "fig3", &purpose);
        fig3.sets = v.sets();
        fig3.after = Some((v.run("fig2"), fig3_overrides));
        let mut first = RunSpec::new(&v.run("fig2_first_order"), "fig2_first_order", &purpose);
        first.sets = v.sets();
        all.extend([fig2, fig3, first]);
    }
    all
}

/// One variation's verdicts.
#[derive(Debug, Clone)]
pub struct Row {
    /// The variation (None: the default runs).
    pub variation: Option<Variation>,
    /// (claim, its parts' verdict, the parts' text).
    pub claims: Vec<(&'static str, bool, String)>,
    /// Mean front speed of fig2's events, m/s.
    pub front_speed_m_per_s: f64,
    /// Events of fig2.
    pub events: usize,
}

fn verdict(parts: Vec<Result<Part, String>>) -> (bool, String) {
    let parts: Vec<Part> = parts
        .into_iter()
        .map(|p| p.unwrap_or_else(Part::fail))
        .collect();
    (
        !parts.is_empty() && parts.iter().all(|p| p.pass),
        parts
            .iter()
            .map(|p| p.text.clone())
            .collect::<Vec<_>>()
            .join("; "),
    )
}

fn row(runs: &Runs, variation: Option<Variation>) -> Row {
    let name = |scene: &str| variation.map_or_else(|| scene.to_string(), |v| v.run(scene));
    let (fig2, fig3, first) = (
        runs.get(&name("fig2")),
        runs.get(&name("fig3")),
        runs.get(&name("fig2_first_order")),
    );
    let c4 = verdict(vec![
        fig2.clone().map(c4_events_part),
        fig3.clone().map(c4_events_part),
        fig3.clone().map(c4_probes_part),
    ]);
    let c5 = verdict(vec![fig3.map(c5_part)]);
    let c13 = verdict(vec![
        first.clone().map(c4_events_part),
        first.clone().map(c4_probes_part),
        first.and_then(|f| fig2.clone().map(|s| c13_speed_part(f, s))),
    ]);
    let speeds = fig2.as_ref().map(|r| front_speeds(r)).unwrap_or_default();
    Row {
        variation,
        claims: vec![
            ("C4", c4.0, c4.1),
            ("C5", c5.0, c5.1),
            ("C13", c13.0, c13.1),
        ],
        front_speed_m_per_s: if speeds.is_empty() {
            f64::NAN
        } else {
            speeds.iter().sum::<f64>() / speeds.len() as f64
        },
        events: fig2.map_or(0, |r| r.events.len()),
    }
}

/// The default runs' row, then one per variation.
#[must_use]
pub fn evaluate(runs: &Runs) -> Vec<Row> {
    std::iter::once(row(runs, None))
        .chain(VARIATIONS.iter().map(|v| row(runs, Some(*v))))
        .collect()
}

/// The variations under which `claim`'s verdict differs from the default runs'.
#[must_use]
pub fn flips(rows: &[Row], claim: &str) -> Vec<String> {
    let verdict_of = |r: &Row| r.claims.iter().find(|c| c.0 == claim).map(|c| c.1);
    let Some(base) = rows.first().and_then(verdict_of) else {
        return Vec::new();
    };
    rows.iter()
        .skip(1)
        .filter(|r| verdict_of(r) != Some(base))
        .filter_map(|r| r.variation.map(|v| v.text()))
        .collect()
}

/// Appends to C4's, C5's and C13's measured text whether their verdict holds under every
/// variation, or under which it flips.
pub fn annotate(claims: &mut [Claim], rows: &[Row]) {
    for c in claims.iter_mut().filter(|c| CLAIMS.contains(&c.id)) {
        let f = flips(rows, c.id);
        let note = if f.is_empty() {
            " — the verdict holds for threshold 1e-3…5e-2 and floor 1e-8…1e-4 (Sensitivity)"
                .to_string()
        } else {
            format!(
                " — **the verdict flips** under {} (Sensitivity)",
                f.join(", ")
            )
        };
        c.value_text.push_str(&note);
    }
}

/// The report's section.
#[must_use]
pub fn markdown(rows: &[Row]) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "## Sensitivity to the model's own choices\n");
    let _ = writeln!(
        s,
        "The melting threshold (0.01) and the φ floor (1e-6, the deterministic stand-in for \
         thermal noise) are the model's choices, not the paper's data. C4, C5 and C13 and the \
         melting front's speed depend on them, so fig2, fig3 and fig2_first_order ran again \
         with one of them changed (runs `sens_<variation>_<scene>`).\n"
    );
    let _ = writeln!(
        s,
        "| variation | fig2 events | fig2 front speed (m/s) | C4 | C5 | C13 |\n|---|---|---|---|---|---|"
    );
    let mark = |p: bool| if p { "✅ pass" } else { "❌ FAIL" };
    for r in rows {
        let cell = |id: &str| {
            r.claims
                .iter()
                .find(|c| c.0 == id)
                .map_or("–", |c| mark(c.1))
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} |",
            r.variation.map_or_else(
                || "default (threshold 0.01, floor 1e-6)".into(),
                |v| v.text()
            ),
            r.events,
            fmt::sig(r.front_speed_m_per_s, 4),
            cell("C4"),
            cell("C5"),
            cell("C13")
        );
    }
    let _ = writeln!(s);
    for id in CLAIMS {
        let f = flips(rows, id);
        let _ = writeln!(
            s,
            "- **{id}**: {}",
            if f.is_empty() {
                "the same verdict under every variation.".to_string()
            } else {
                format!("the verdict flips under {}.", f.join(", "))
            }
        );
    }
    let speeds: Vec<f64> = rows
        .iter()
        .map(|r| r.front_speed_m_per_s)
        .filter(|v| v.is_finite())
        .collect();
    if let (Some(base), false) = (rows.first(), speeds.is_empty()) {
        let lo = speeds.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = speeds.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let _ = writeln!(
            s,
            "- **Front speed** (fig2, r_first/(t_center − t_onset), mean over events): {} m/s \
             with the defaults, {}–{} m/s over the variations (a spread of {} % of the \
             default).",
            fmt::sig(base.front_speed_m_per_s, 4),
            fmt::sig(lo, 4),
            fmt::sig(hi, 4),
            fmt::sig(100.0 * (hi - lo) / base.front_speed_m_per_s, 2)
        );
    }
    if let Some(base) = rows.first() {
        let moved: Vec<String> = rows
            .iter()
            .skip(1)
            .filter(|r| r.events != base.events)
            .map(|r| {
                format!(
                    "{} events under the {}",
                    r.events,
                    r.variation.map_or_else(String::new, |v| v.text())
                )
            })
            .collect();
        let _ = writeln!(
            s,
            "- **fig2's event count** ({} with the defaults by t = 1.3 ms): {}.\n",
            base.events,
            if moved.is_empty() {
                "the same under every variation".to_string()
            } else {
                moved.join(", ")
            }
        );
    }
    for r in rows.iter().skip(1) {
        for (id, pass, text) in &r.claims {
            if !pass {
                let _ = writeln!(
                    s,
                    "- {} under the {}: {}",
                    id,
                    r.variation.map_or_else(String::new, |v| v.text()),
                    text
                );
            }
        }
    }
    let _ = writeln!(s);
    s
}
