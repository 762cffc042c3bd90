//! `reports/summary.json` and `reports/index.md`: the claims table, the resolution used and
//! why, the event-rule comparison, the figures with their captions, the findings and the runs;
//! plus the comparison of a fresh validation against the committed summary (`cargo xtask
//! validate --check`). Every number comes from the runs; no wall-clock time is written (the
//! reports must not change when nothing changed; timings live in reports/performance.md).

use crate::claims::{Claim, Runs};
use crate::events_rule::{self, RuleRow};
use crate::facts::{Facts, word};
use crate::figures::Figure;
use crate::reduced::Features;
use crate::runner::{NODES, RunResult, old_merge_gap};
use crate::verify_check::{self, VerifyCheck};
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use stickslip_report::fmt;

/// Agreement of the fig2 onsets across node counts (the evidence for N = [`NODES`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Resolution {
    /// Onsets in µs by node count.
    pub onsets_us: BTreeMap<usize, Vec<f64>>,
    /// Largest |onset(N) − onset(NODES)| over the coarser N and every event, µs.
    pub max_diff_us: f64,
    /// Whether all node counts give the same number of events.
    pub counts_equal: bool,
}

impl Resolution {
    /// From the runs `fig2_n50`, `fig2_n100`, `fig2`.
    pub fn of(runs: &Runs) -> Option<Self> {
        let mut onsets_us = BTreeMap::new();
        for name in ["fig2_n50", "fig2_n100", "fig2"] {
            let r = runs.get(name).ok()?;
            onsets_us.insert(
                r.info.nodes(),
                r.events
                    .onsets_s()
                    .iter()
                    .map(|t| t * 1e6)
                    .collect::<Vec<_>>(),
            );
        }
        let reference = onsets_us.get(&NODES)?.clone();
        let mut max_diff_us = 0.0_f64;
        let mut counts_equal = true;
        for (n, o) in &onsets_us {
            if *n == NODES {
                continue;
            }
            counts_equal &= o.len() == reference.len();
            for (a, b) in o.iter().zip(&reference) {
                max_diff_us = max_diff_us.max((a - b).abs());
            }
        }
        Some(Self {
            onsets_us,
            max_diff_us,
            counts_equal,
        })
    }
}

/// Everything `summary.json` and `index.md` are made from.
#[derive(Debug)]
pub struct Outcome<'a> {
    /// Claims C1–C13.
    pub claims: &'a [Claim],
    /// The runs' outputs.
    pub runs: &'a Runs,
    /// The run results (specs, exit status).
    pub results: &'a BTreeMap<String, RunResult>,
    /// Reduced-size features (from the `fig2_reduced_cli` run), or why there are none.
    pub reduced: Result<&'a Features, String>,
    /// Resolution evidence.
    pub resolution: Option<&'a Resolution>,
    /// The event-rule comparison.
    pub event_rule: &'a [RuleRow],
    /// Event-rule runs that could not be compared, with why.
    pub event_rule_missing: &'a [String],
    /// verify against known errors.
    pub verify_check: &'a [VerifyCheck],
    /// The comparison with the independent implementation, why it failed, or none (not run:
    /// `validate --check`).
    pub independent: Option<&'a Result<crate::independent::Comparison, String>>,
    /// The claims' sensitivity to the melting threshold and the φ floor.
    pub sensitivity: &'a [crate::sensitivity::Row],
    /// The energy books' checks.
    pub energy: &'a crate::energy::EnergyCheck,
    /// The stamp's advance per cycle against its estimate.
    pub advance: &'a crate::advance::AdvanceCheck,
    /// Each claim's margin uncertainty, by id.
    pub margin_errors: &'a BTreeMap<&'static str, crate::uncertainty::MarginError>,
}

fn round(x: f64, digits: i32) -> f64 {
    let p = 10f64.powi(digits);
    (x * p).round() / p
}

/// The summary document.
pub fn summary_json(o: &Outcome<'_>) -> Value {
    let claims: serde_json::Map<String, Value> = o
        .claims
        .iter()
        .map(|c| {
            (
                c.id.to_string(),
                json!({ "pass": c.pass, "value": c.value, "value_text": c.value_text,
                        "criterion": c.criterion, "statement": c.statement, "reason": c.reason,
                        "margin": crate::margins::of(c).map(|m| json!({
                            "value": m.value, "binding": m.binding,
                            "uncertainty": o.margin_errors.get(c.id).map(|e| e.error),
                            "within_noise": o.margin_errors.get(c.id).map(|e| e.within_noise(m.value)),
                        })) }),
            )
        })
        .collect();
    let scenes: serde_json::Map<String, Value> = o
        .results
        .iter()
        .map(|(name, r)| {
            let v = match r.output() {
                Ok(out) => json!({
                    "status": out.info.status.name(),
                    "event_count": out.events.len(),
                    "events": out.events.onsets_s(),
                    "steps": out.info.steps,
                    "nodes": out.info.nodes(),
                    "scheme": word(&out.info.scheme()),
                    "stepping": word(&out.info.stepping()),
                    "operator": out.info.operator().map(|op| word(&op)),
                    "dt": out.info.dt_s(),
                    "end": out.info.end_s(),
                    "overrides": r.spec.overrides(),
                }),
                Err(e) => json!({ "status": "failed", "error": e }),
            };
            (name.clone(), v)
        })
        .collect();
    json!({
        "generated_by": "cargo xtask validate",
        "commit": stickslip_report::provenance::Commit::of_workspace(),
        "all_claims_pass": o.claims.iter().all(|c| c.pass),
        "claims": claims,
        "scenes": scenes,
        "resolution": o.resolution.map(|r| json!({
            "nodes": NODES, "paper_nodes": 2000,
            "fig2_onsets_us": r.onsets_us.iter().map(|(n, v)| (n.to_string(), json!(v.iter().map(|x| round(*x, 3)).collect::<Vec<_>>()))).collect::<serde_json::Map<_, _>>(),
            "max_onset_diff_us": r.max_diff_us, "event_counts_equal": r.counts_equal,
        })),
        "event_rule": events_rule::to_json(o.event_rule),
        "verify_check": verify_check::to_json(o.verify_check),
        "advance_per_cycle": crate::advance::summary(o.advance),
        "energy_books": json!({
            "passes": o.energy.passes(),
            "i3_bound_holds": o.energy.i3_bound_holds(),
            "orders_hold": o.energy.orders_hold(),
        }),
        "reduced": match &o.reduced {
            Ok(f) => json!(f),
            Err(e) => json!({ "error": e }),
        },
    })
}

/// Differences between a fresh summary and the committed one that matter: claim verdicts,
/// event counts per scene, verify's coverage of known errors, and the reduced block. Empty
/// when they agree.
pub fn compare(fresh: &Value, committed: &Value) -> Vec<String> {
    let mut out = Vec::new();
    let ids = |v: &Value| -> Vec<String> {
        v["claims"]
            .as_object()
            .map(|m| m.keys().cloned().collect())
            .unwrap_or_default()
    };
    let mut all = ids(fresh);
    all.extend(ids(committed));
    all.sort();
    all.dedup();
    for id in all {
        let (a, b) = (
            &fresh["claims"][&id]["pass"],
            &committed["claims"][&id]["pass"],
        );
        if a != b {
            out.push(format!("claim {id}: verdict now {a}, committed {b}"));
        }
    }
    let names = |v: &Value| -> Vec<String> {
        v["scenes"]
            .as_object()
            .map(|m| m.keys().cloned().collect())
            .unwrap_or_default()
    };
    let mut scenes = names(fresh);
    scenes.extend(names(committed));
    scenes.sort();
    scenes.dedup();
    for name in scenes {
        let (a, b) = (
            &fresh["scenes"][&name]["event_count"],
            &committed["scenes"][&name]["event_count"],
        );
        if a != b {
            out.push(format!("scene {name}: {a} events now, committed {b}"));
        }
    }
    out.extend(verify_check::compare(fresh, committed));
    if fresh["reduced"] != committed["reduced"] {
        out.push(format!(
            "reduced block differs:\n  now       {}\n  committed {}",
            fresh["reduced"], committed["reduced"]
        ));
    }
    out
}

/// The claims table in plain text (for the terminal).
pub fn claims_table_text(claims: &[Claim]) -> String {
    let mut s = String::new();
    for c in claims {
        let _ = writeln!(
            s,
            "  {:<4} {:<5} {}",
            c.id,
            if c.pass { "PASS" } else { "FAIL" },
            c.value_text
        );
    }
    s
}

fn md_escape(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

fn run_line(r: &RunResult) -> String {
    match r.output() {
        Ok(o) => format!(
            "| `{}` | {}.toml | {} | {} | {} | {} | {} | {} | {} |",
            r.spec.name,
            r.spec.scene,
            o.info.nodes(),
            word(&o.info.scheme()),
            word(&o.info.stepping()),
            o.info.operator().map_or_else(|| "?".into(), |op| word(&op)),
            o.events.len(),
            o.info.steps,
            md_escape(&r.spec.purpose)
        ),
        Err(e) => format!(
            "| `{}` | {}.toml | – | – | – | – | FAILED: {} | – | {} |",
            r.spec.name,
            r.spec.scene,
            md_escape(&fmt::first_line(&e)),
            md_escape(&r.spec.purpose)
        ),
    }
}

fn resolution_section(s: &mut String, o: &Outcome<'_>) {
    let _ = writeln!(s, "## Resolution\n");
    let how = o.runs.get("fig2").map_or_else(
        |e| format!("(fig2 is not available: {})", md_escape(&e)),
        |r| {
            format!(
                "fig2 ran with the {} scheme, {}, and the {} MDR operator (from its run.json).",
                word(&r.info.scheme()),
                r.info.stepping_text(),
                r.info
                    .operator()
                    .map_or_else(|| "?".to_string(), |op| word(&op))
            )
        },
    );
    let _ = writeln!(
        s,
        "All radial scenes run at **N = {NODES} nodes** (`--set contact.nodes={NODES}`); the \
         paper used N = 2000. {how} What a run costs at each N, and against the paper's \
         algorithm, is measured in [performance.md](performance.md)."
    );
    if let Some(r) = o.resolution {
        let coarse: Vec<String> = r
            .onsets_us
            .keys()
            .filter(|n| **n != NODES)
            .map(ToString::to_string)
            .collect();
        let _ = writeln!(
            s,
            "The evidence that N = {NODES} suffices is rerun every time: fig2's melting onsets at \
             N = {} and {NODES} differ by at most **{} µs** (event counts {}).\n",
            coarse.join(", "),
            fmt::sig(r.max_diff_us, 2),
            if r.counts_equal { "equal" } else { "DIFFER" }
        );
        let _ = writeln!(s, "| N | fig2 onsets, µs |\n|---|---|");
        for (n, v) in &r.onsets_us {
            let items: Vec<String> = v.iter().map(|x| format!("{x:.2}")).collect();
            let _ = writeln!(s, "| {n} | {} |", items.join(", "));
        }
        let _ = writeln!(s);
    }
}

/// The report page.
pub fn index_md(o: &Outcome<'_>, figures: &[Figure]) -> String {
    let mut s = String::new();
    let passed = o.claims.iter().filter(|c| c.pass).count();
    let span = match (o.claims.first(), o.claims.last()) {
        (Some(a), Some(b)) => format!("{}–{}", a.id, b.id),
        _ => "(none)".to_string(),
    };
    let _ = writeln!(s, "# Validation report: the paper's claims {span}\n");
    let _ = writeln!(
        s,
        "{}\n",
        stickslip_report::provenance::sentence(
            stickslip_report::provenance::Commit::of_workspace().as_ref()
        )
    );
    let _ = writeln!(
        s,
        "Generated by `cargo xtask validate` (do not edit by hand). It ran every scene of \
         `validation/scenes/` with the `stickslip` binary as a subprocess ({} runs), read the \
         output files through the run library's schema and checked each claim of the paper \
         ([docs/model.md](../docs/model.md#the-papers-claims)) as a measured criterion. \
         **{passed} of {} claims pass.** `cargo xtask validate --check` reruns everything and \
         compares verdicts, event counts, verify's coverage of known errors and the reduced \
         block with `summary.json` without writing.\n",
        o.results.len(),
        o.claims.len()
    );
    let _ = writeln!(
        s,
        "Hard cases (soft substrate, stiff kinetics, huge steps, complete melting, the critical \
         strain, the edge singularity and extreme sizes, noise extremes, the fast rigid drive, \
         the first-order film's fold under a large step): \
         see [hard-cases.md](hard-cases.md), written by the same `cargo xtask validate`.\n"
    );
    let _ = writeln!(s, "## Claims\n");
    let _ = writeln!(
        s,
        "The margin is how far each claim's binding number is from its threshold, as a share of \
         the threshold's room (1 − value/threshold for an upper bound, value/threshold − 1 for \
         a lower one; for strict order, the smallest relative step): 0 would fail, and a \
         margin within a numerical error of 0 would be a verdict within noise. The chart after \
         the table draws them. The ± after each margin is its numerical uncertainty: every run \
         a claim reads is repeated at twice the nodes and at a tenth of the time tolerance (half \
         the step where the steps are fixed), the claims are evaluated again on each refined \
         set, and the largest change of the margin is its uncertainty; a margin within it, or a \
         verdict that a refinement flips, reads \"within noise\". {} of {} verdicts are within \
         noise.\n",
        o.claims
            .iter()
            .filter(|c| {
                crate::margins::of(c).is_some_and(|m| {
                    o.margin_errors
                        .get(c.id)
                        .is_some_and(|e| e.within_noise(m.value))
                })
            })
            .count(),
        o.claims.len()
    );
    let _ = writeln!(
        s,
        "| Claim | Criterion | Measured | Margin (binding number) | Verdict |\n|---|---|---|---|---|"
    );
    for c in o.claims {
        let margin = crate::margins::of(c).map_or_else(
            || "–".to_string(),
            |m| {
                let err = o.margin_errors.get(c.id);
                let plus = err.map_or_else(String::new, |e| {
                    let noise = if e.within_noise(m.value) {
                        format!(
                            ", **within noise**{}",
                            if e.flips.is_empty() {
                                String::new()
                            } else {
                                format!(" (flips at {})", e.flips.join(", "))
                            }
                        )
                    } else {
                        String::new()
                    };
                    format!(" ± {}{noise}", fmt::sig(e.error, 2))
                });
                format!("{}{plus} ({})", fmt::sig(m.value, 2), md_escape(&m.binding))
            },
        );
        let _ = writeln!(
            s,
            "| **{}** {} | {} | {} | {margin} | {} |",
            c.id,
            md_escape(c.statement),
            md_escape(&c.criterion),
            md_escape(&c.value_text),
            if c.pass { "✅ pass" } else { "❌ FAIL" }
        );
    }
    let _ = writeln!(
        s,
        "\n![each claim's margin to its threshold]({})\n",
        crate::figures::MARGINS_SVG
    );
    let _ = writeln!(s, "\nWhy the thresholds are what they are:\n");
    for c in o.claims {
        let _ = writeln!(s, "- **{}**: {}.", c.id, c.reason);
    }
    let _ = writeln!(
        s,
        "\nThe full reasons sit next to the constants in `validation/src/claims.rs` (C1–C10) \
         and `validation/src/claims_first_order.rs` (C11–C13, the first-order film of \
         [docs/model.md](../docs/model.md#the-first-order-film)). Coefficients of variation are \
         sample ones (n − 1).\n"
    );
    s.push_str(&crate::advance::markdown(o.advance));
    resolution_section(&mut s, o);
    s.push_str(&verify_check::markdown(o.verify_check));
    match o.independent {
        Some(Ok(c)) => s.push_str(&crate::independent::report::markdown(c)),
        Some(Err(e)) => {
            let _ = writeln!(
                s,
                "## Independent implementation\n\n*Not compared: {}*\n",
                md_escape(e)
            );
        }
        None => {}
    }
    s.push_str(&crate::sensitivity::markdown(o.sensitivity));
    s.push_str(&crate::energy::markdown(o.energy));
    let _ = writeln!(s, "## Melting events: what the event rule changes\n");
    let (k, gap) = o.runs.get("fig2").map_or((f64::NAN, f64::NAN), |r| {
        (
            r.info
                .scene
                .output
                .as_ref()
                .and_then(|o| o.event_recovery)
                .unwrap_or(f64::NAN),
            r.info.event_merge_gap_s(),
        )
    });
    let _ = writeln!(
        s,
        "An event now ends when the film has recovered: every node back above \
         min(k·threshold, ½(threshold + √(A/a))), k = `output.event_recovery` (fig2's run.json: \
         k = {}, `event_merge_gap` = {} s). Before, a melting less than `event_merge_gap` = \
         1e-5 s after the contact was last fully solid continued the event. Each paper scene \
         below ran with the default settings and again with `--set {}` (the old \
         default value):\n",
        fmt::trim(k),
        fmt::trim(gap),
        old_merge_gap()
    );
    let _ = writeln!(
        s,
        "{}",
        events_rule::markdown(o.event_rule, o.event_rule_missing)
    );
    let _ = writeln!(s, "## Figures\n");
    for fig in figures {
        let _ = writeln!(s, "### {}\n", fig.title);
        match &fig.svg {
            Ok(_) => {
                let _ = writeln!(s, "![{}]({})\n", fig.title, fig.file);
            }
            Err(e) => {
                let _ = writeln!(s, "*Not drawn: {}*\n", md_escape(e));
            }
        }
        for line in fig.caption.lines() {
            let _ = writeln!(s, "{line}  ");
        }
        let _ = writeln!(s);
    }
    let _ = writeln!(s, "## Findings\n");
    for p in crate::findings::all(o.claims, o.runs) {
        let _ = writeln!(s, "- {p}");
    }
    let _ = writeln!(s, "\n## Runs\n");
    let _ = writeln!(
        s,
        "Outputs in `target/validation/<run>/` (series.csv, events.csv, probes.csv, \
         profiles.csv, run.json); N, scheme, stepping, operator and steps as each run.json \
         records them.\n"
    );
    let _ = writeln!(
        s,
        "| run | scene | N | scheme | stepping | operator | events | steps | purpose |\n\
         |---|---|---|---|---|---|---|---|---|"
    );
    for r in o.results.values() {
        let _ = writeln!(s, "{}", run_line(r));
    }
    match &o.reduced {
        Ok(r) => {
            let _ = writeln!(
                s,
                "\n## Reduced-size check\n\n`summary.json` also holds a `reduced` block: {}, run \
                 through the binary (`fig2_reduced_cli`): {} events, onsets {} µs, {} steps. The \
                 test `validation/tests/reduced.rs` runs the same scene and overrides in-process \
                 (`stickslip_run::run_in_memory`), computes the same features and fails when the \
                 committed reports no longer match the code — which also checks, on every `cargo \
                 test`, that the command line records what the run library computes.",
                r.setup,
                r.events,
                fmt::list(&r.onsets_us, 1),
                r.steps
            );
        }
        Err(e) => {
            let _ = writeln!(
                s,
                "\n## Reduced-size check\n\nNot available: {}",
                md_escape(e)
            );
        }
    }
    s
}
