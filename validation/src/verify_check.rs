//! `stickslip verify` checked against known errors: verify runs a scene at a coarse N through
//! the binary (`stickslip verify … --jobs 1`, a [`Task`] in the runner's pool), its verify.json
//! is read back through the run library's type (`stickslip_studies::verify::VerifyReport`), and
//! each continuous quantity's value is compared with the same quantity of a much finer run of
//! the same scene (a [`RunSpec`] of the run list, read through the schema; the names and
//! values through `stickslip_studies::verify::numbers`, as verify computes them). The true error
//! is |value − reference|; a quantity is covered when verify's uncertainty is at least the true
//! error, or verify says it is not converged (or changed between levels): saying so is honest.
//! Every quantity must be covered for `cargo xtask validate` to pass.
//!
//! This module owns the subjects (which scene, which N, which reference), the verify
//! invocations, the comparison, its block of summary.json (and what `--check` compares of it)
//! and its section of index.md. Like the other reports, it writes no wall-clock time (run
//! costs are stated in steps; the wall seconds are printed on the terminal).

use crate::claims::Runs;
use crate::facts::Facts;
use crate::runner::{RunSpec, Runner, Task};
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;
use std::sync::Mutex;
use stickslip_report::binary::invoke;
use stickslip_report::fmt;
use stickslip_run::keys::contact;
use stickslip_studies::verify::{Level, Verdict, VerifyReport, numbers};

/// N at which verify runs each subject (its levels: N, 2N, 4N, and N at two finer
/// tolerances).
pub const VERIFY_NODES: usize = 200;

/// One scene verify is checked on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Subject {
    /// Scene file stem in `validation/scenes/`.
    pub scene: &'static str,
    /// N of the reference run (at the scene's own time stepping).
    pub reference_nodes: usize,
    /// What the reference is for, in the run list.
    pub why: &'static str,
}

/// The subjects: fig2 against N = 2000 (the paper's N), and the surface-force-apparatus
/// contact of `sfa.toml` (h0 = 1 nm, where N = 200 is far from converged) against N = 3200.
/// The sfa reference keeps the scene's tolerance: at N = 3200 a tolerance ten times tighter took
/// 104 s against 32 s (measured while another build ran), too much for the validation, and it
/// moved the first onset by 9.3 µs and the first peak force by 1.6e-10 N, far below the true
/// errors of N = 200 (5.4 ms, 1.2e-5 N).
pub const SUBJECTS: [Subject; 2] = [
    Subject {
        scene: "fig2",
        reference_nodes: 2000,
        why: "the reference of verify on fig2 at N = 200 (the paper's N)",
    },
    Subject {
        scene: "sfa",
        reference_nodes: 3200,
        why: "the reference of verify on sfa at N = 200 (h0 = 1 nm)",
    },
];

impl Subject {
    /// The reference run's name (`fig2_n2000`).
    #[must_use]
    pub fn reference(&self) -> String {
        format!("{}_n{}", self.scene, self.reference_nodes)
    }

    /// The verify run's name and output directory (`verify_fig2_n200`).
    #[must_use]
    pub fn label(&self) -> String {
        format!("verify_{}_n{VERIFY_NODES}", self.scene)
    }

    /// The reference run for the run list.
    #[must_use]
    pub fn reference_spec(&self) -> RunSpec {
        let mut s = RunSpec::new(&self.reference(), self.scene, self.why);
        s.nodes = self.reference_nodes;
        s
    }
}

/// The reference runs, for the run list (the sfa one is the validation's longest run: first).
#[must_use]
pub fn reference_specs() -> Vec<RunSpec> {
    let mut v: Vec<RunSpec> = SUBJECTS.iter().map(Subject::reference_spec).collect();
    v.sort_by_key(|s| std::cmp::Reverse(s.nodes));
    v
}

/// One `stickslip verify` and what it wrote.
#[derive(Debug, Clone)]
pub struct VerifyRun {
    /// The command line, relative to the workspace root.
    pub command: String,
    /// Wall seconds of the process (printed, never written to the reports).
    pub wall_s: f64,
    /// verify.json read through the run library's type, or why there is none.
    pub report: Result<VerifyReport, String>,
}

/// `stickslip verify SCENE --out DIR --jobs 1 --set contact.nodes=N` (one run at a time: the
/// pool's workers are the parallelism), after removing what an earlier one left in DIR; then
/// reads DIR/verify.json. Exit 0 (every quantity within --rtol) and 4 (some not) both wrote it.
pub fn run_verify(runner: &Runner, scenes: &Path, subject: &Subject) -> VerifyRun {
    let scene = scenes.join(format!("{}.toml", subject.scene));
    let dir = runner.out_root().join(subject.label());
    let set = contact::NODES.set(VERIFY_NODES as i64).to_string();
    let command = format!(
        "stickslip verify {} --out {} --jobs 1 --set {set}",
        runner.relative(&scene),
        runner.relative(&dir)
    );
    if dir.exists() {
        let _ = std::fs::remove_dir_all(&dir);
    }
    let args: Vec<String> = [
        "verify",
        &scene.display().to_string(),
        "--out",
        &dir.display().to_string(),
        "--jobs",
        "1",
        "--set",
        &set,
    ]
    .iter()
    .map(ToString::to_string)
    .collect();
    let (wall_s, report) = match invoke(runner.bin(), &args, &[]) {
        Err(e) => (f64::NAN, Err(e)),
        Ok(p) => {
            let path = dir.join("verify.json");
            let report = match p.code {
                Some(0 | 4) => std::fs::read(&path)
                    .map_err(|e| e.to_string())
                    .and_then(|b| serde_json::from_slice(&b).map_err(|e| e.to_string()))
                    .map_err(|e| format!("{}: {e}", runner.relative(&path))),
                code => Err(format!(
                    "exit {}: no verify.json",
                    code.map_or_else(|| "none".to_string(), |c| c.to_string())
                )),
            };
            (p.wall_s, report)
        }
    };
    VerifyRun {
        command,
        wall_s,
        report,
    }
}

/// The verify runs as tasks of the runner's pool; each puts its result into `store` (by
/// scene) and says its cost.
pub fn tasks<'a>(
    runner: &'a Runner,
    scenes: &'a Path,
    store: &'a Mutex<BTreeMap<String, VerifyRun>>,
) -> Vec<Task<'a>> {
    SUBJECTS
        .iter()
        .map(|subject| Task {
            name: subject.label(),
            work: Box::new(move || {
                let run = run_verify(runner, scenes, subject);
                let line = match &run.report {
                    Ok(r) => format!(
                        "{} levels, {:.2} s ({} s of runs) — verify checked against `{}`",
                        r.levels.len(),
                        run.wall_s,
                        r.levels
                            .iter()
                            .map(|l| format!("{:.2}", l.wall_s))
                            .collect::<Vec<_>>()
                            .join(" + "),
                        subject.reference()
                    ),
                    Err(e) => format!("FAILED: {}", fmt::first_line(e)),
                };
                store
                    .lock()
                    .expect("verify store lock")
                    .insert(subject.scene.to_string(), run);
                line
            }),
        })
        .collect()
}

/// One quantity against the reference.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// Quantity name (verify's).
    pub name: String,
    /// Its unit.
    pub unit: String,
    /// verify's value (the scene at N = [`VERIFY_NODES`]).
    pub value: f64,
    /// The reference run's value.
    pub reference: f64,
    /// verify's uncertainty (infinite when a level lacked the quantity).
    pub uncertainty: f64,
    /// verify's verdict.
    pub verdict: Verdict,
    /// |value − reference|.
    pub true_error: f64,
    /// Uncertainty ≥ true error, or the verdict is not converged or changed.
    pub covered: bool,
}

/// The comparison for one subject.
#[derive(Debug, Clone)]
pub struct SceneCheck {
    /// verify's levels (N, tolerance, steps, wall time).
    pub levels: Vec<Level>,
    /// The reference run's N.
    pub reference_nodes: usize,
    /// How the reference stepped (its run.json).
    pub reference_stepping: String,
    /// The reference run's steps.
    pub reference_steps: u64,
    /// The reference run's wall seconds (printed only).
    pub reference_wall_s: f64,
    /// One row per quantity both have.
    pub rows: Vec<Row>,
    /// verify's continuous quantities the reference does not have.
    pub not_in_reference: Vec<String>,
}

impl SceneCheck {
    /// Quantities covered.
    #[must_use]
    pub fn covered(&self) -> usize {
        self.rows.iter().filter(|r| r.covered).count()
    }

    /// Names of the quantities not covered.
    #[must_use]
    pub fn uncovered(&self) -> Vec<String> {
        self.rows
            .iter()
            .filter(|r| !r.covered)
            .map(|r| r.name.clone())
            .collect()
    }

    /// Every quantity covered, and at least one compared.
    #[must_use]
    pub fn all_covered(&self) -> bool {
        !self.rows.is_empty() && self.rows.iter().all(|r| r.covered)
    }
}

/// One subject's outcome.
#[derive(Debug, Clone)]
pub struct VerifyCheck {
    /// The subject.
    pub subject: Subject,
    /// The verify command line (empty when it did not run).
    pub command: String,
    /// The comparison, or why there is none (verify or the reference failed).
    pub result: Result<SceneCheck, String>,
}

/// Whether a verdict admits that no small uncertainty can be given.
#[must_use]
pub fn says_unconverged(v: Verdict) -> bool {
    matches!(v, Verdict::NotConverged | Verdict::Changed)
}

/// The comparison of verify's `report` with the reference run of `subject` in `runs`.
///
/// # Errors
/// When the reference run failed or has no summary.
pub fn compare_one(
    subject: &Subject,
    report: &VerifyReport,
    runs: &Runs,
) -> Result<SceneCheck, String> {
    let reference = runs.get(&subject.reference())?;
    let summary = reference
        .info
        .summary
        .as_ref()
        .ok_or_else(|| format!("run `{}` has no summary", subject.reference()))?;
    let known = numbers(summary, &reference.events.onsets_s());
    let mut rows = Vec::new();
    let mut not_in_reference = Vec::new();
    for q in report.quantities.iter().filter(|q| q.text.is_none()) {
        let Some(r) = known
            .iter()
            .find(|(n, _, _)| *n == q.name)
            .and_then(|(_, _, v)| *v)
        else {
            not_in_reference.push(q.name.clone());
            continue;
        };
        let true_error = (q.value - r).abs();
        rows.push(Row {
            name: q.name.clone(),
            unit: q.unit.clone(),
            value: q.value,
            reference: r,
            uncertainty: q.uncertainty,
            verdict: q.verdict,
            true_error,
            covered: q.uncertainty >= true_error || says_unconverged(q.verdict),
        });
    }
    Ok(SceneCheck {
        levels: report.levels.clone(),
        reference_nodes: reference.info.nodes(),
        reference_stepping: reference.info.stepping_text(),
        reference_steps: reference.info.steps,
        reference_wall_s: reference.info.wall_seconds,
        rows,
        not_in_reference,
    })
}

/// Every subject's comparison, from the verify runs (by scene) and the runs.
#[must_use]
pub fn evaluate(verify: &BTreeMap<String, VerifyRun>, runs: &Runs) -> Vec<VerifyCheck> {
    SUBJECTS
        .iter()
        .map(|subject| {
            let run = verify.get(subject.scene);
            let result = match run.map(|r| &r.report) {
                None => Err("verify did not run".to_string()),
                Some(Err(e)) => Err(format!("verify failed: {e}")),
                Some(Ok(report)) => compare_one(subject, report, runs),
            };
            VerifyCheck {
                subject: *subject,
                command: run.map(|r| r.command.clone()).unwrap_or_default(),
                result,
            }
        })
        .collect()
}

/// Every subject compared and every quantity covered.
#[must_use]
pub fn all_covered(checks: &[VerifyCheck]) -> bool {
    !checks.is_empty()
        && checks
            .iter()
            .all(|c| c.result.as_ref().is_ok_and(SceneCheck::all_covered))
}

fn verdict_word(v: Verdict) -> &'static str {
    match v {
        Verdict::Within => "within",
        Verdict::Outside => "outside",
        Verdict::NotConverged => "not_converged",
        Verdict::Changed => "changed",
    }
}

/// A finite number, or null (JSON has no infinity).
fn num(x: f64) -> Value {
    if x.is_finite() { json!(x) } else { Value::Null }
}

/// The `verify_check` block of summary.json.
#[must_use]
pub fn to_json(checks: &[VerifyCheck]) -> Value {
    let scenes: serde_json::Map<String, Value> = checks
        .iter()
        .map(|c| {
            let v = match &c.result {
                Err(e) => json!({ "error": e, "reference": c.subject.reference() }),
                Ok(s) => json!({
                    "verify": c.command,
                    "reference": c.subject.reference(),
                    "reference_nodes": s.reference_nodes,
                    "quantities": s.rows.len(),
                    "covered": s.covered(),
                    "uncovered": s.uncovered(),
                    "not_in_reference": s.not_in_reference,
                    "rows": s.rows.iter().map(|r| json!({
                        "name": r.name, "value": r.value, "reference": r.reference,
                        "uncertainty": num(r.uncertainty), "verdict": verdict_word(r.verdict),
                        "true_error": r.true_error, "covered": r.covered,
                    })).collect::<Vec<_>>(),
                }),
            };
            (c.subject.scene.to_string(), v)
        })
        .collect();
    json!({ "all_covered": all_covered(checks), "scenes": scenes })
}

/// What `validate --check` compares of the block: per scene the quantity count, the covered
/// count, the uncovered names and whether it failed; and the overall verdict. Empty when equal.
#[must_use]
pub fn compare(fresh: &Value, committed: &Value) -> Vec<String> {
    let (a, b) = (&fresh["verify_check"], &committed["verify_check"]);
    let mut out = Vec::new();
    if a["all_covered"] != b["all_covered"] {
        out.push(format!(
            "verify check: all covered now {}, committed {}",
            a["all_covered"], b["all_covered"]
        ));
    }
    let names = |v: &Value| -> Vec<String> {
        v["scenes"]
            .as_object()
            .map(|m| m.keys().cloned().collect())
            .unwrap_or_default()
    };
    let mut scenes = names(a);
    scenes.extend(names(b));
    scenes.sort();
    scenes.dedup();
    for s in scenes {
        for key in ["quantities", "covered", "uncovered"] {
            let (x, y) = (&a["scenes"][&s][key], &b["scenes"][&s][key]);
            if x != y {
                out.push(format!("verify check {s}: {key} now {x}, committed {y}"));
            }
        }
        let failed = |v: &Value| v["scenes"][&s].get("error").is_some();
        if failed(a) != failed(b) {
            out.push(format!(
                "verify check {s}: failed now {}, committed {}",
                failed(a),
                failed(b)
            ));
        }
    }
    out
}

/// `x` with `digits` significant digits and its unit (none for a pure number).
fn with_unit(x: f64, unit: &str, digits: usize) -> String {
    if unit == "–" {
        fmt::sig(x, digits)
    } else {
        format!("{} {unit}", fmt::sig(x, digits))
    }
}

/// Enough significant digits for a value and its reference to show their difference.
fn digits_for(r: &Row) -> usize {
    let scale = r.value.abs().max(r.reference.abs());
    if r.true_error > 0.0 && scale > 0.0 {
        ((scale / r.true_error).log10().ceil() as usize + 2).clamp(4, 12)
    } else {
        4
    }
}

/// The levels of a verify run in words: `N = 200, tolerance 5e-5: 3010 steps; …`.
fn levels_text(levels: &[Level]) -> String {
    levels
        .iter()
        .map(|l| {
            let step = match (l.tolerance, l.dt_s) {
                (Some(t), _) => format!("tolerance {t:e}"),
                (None, Some(dt)) => format!("Δt = {dt:e} s"),
                (None, None) => "?".to_string(),
            };
            format!("N = {}, {step}: {} steps", l.nodes, l.steps)
        })
        .collect::<Vec<_>>()
        .join("; ")
}

/// The sentence of one subject, from its rows.
#[must_use]
pub fn sentence(s: &SceneCheck) -> String {
    let by_bound = s
        .rows
        .iter()
        .filter(|r| r.uncertainty >= r.true_error)
        .count();
    let by_verdict_only = s
        .rows
        .iter()
        .filter(|r| r.uncertainty < r.true_error && says_unconverged(r.verdict))
        .count();
    let mut t = format!(
        "verify's uncertainty covers the true error, or verify says not converged, for **{} of \
         {} quantities** ({by_bound} by the uncertainty, {by_verdict_only} by the verdict alone)",
        s.covered(),
        s.rows.len()
    );
    let unc = s.uncovered();
    if unc.is_empty() {
        t.push('.');
    } else {
        let _ = write!(
            t,
            "; **not covered: {}** (a small uncertainty where the truth is far: a fault of \
             verify).",
            unc.join(", ")
        );
    }
    t
}

/// The section of index.md.
#[must_use]
pub fn markdown(checks: &[VerifyCheck]) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "## Verify against known errors\n");
    let _ = writeln!(
        s,
        "`stickslip verify` estimates the error of each summary number from refinements of the \
         scene itself (N, 2N, 4N; the tolerance, /10, /100). Here it runs at N = \
         {VERIFY_NODES} on scenes whose converged values are known from a much finer run, and \
         each continuous quantity's true error |value − reference| is set against verify's \
         uncertainty (the reference keeps the scene's time stepping, stated with it below). A quantity is covered when the uncertainty is at least the true error, or \
         when verify's verdict is `not_converged` or `changed` (saying that no small number can \
         be given is honest). `validate` fails unless every quantity is covered. {}\n",
        if all_covered(checks) {
            "Every quantity is covered."
        } else {
            "**Not every quantity is covered.**"
        }
    );
    for c in checks {
        let _ = writeln!(s, "### {}.toml\n", c.subject.scene);
        let sc = match &c.result {
            Ok(sc) => sc,
            Err(e) => {
                let _ = writeln!(s, "*No comparison: {}*\n", e.replace('|', "\\|"));
                continue;
            }
        };
        let _ = writeln!(
            s,
            "`{}` against the run `{}` (N = {}, {}). {}\n",
            c.command,
            c.subject.reference(),
            sc.reference_nodes,
            sc.reference_stepping,
            sentence(sc)
        );
        let _ = writeln!(
            s,
            "| quantity | value (N = {VERIFY_NODES}) | reference (N = {}) | uncertainty | verdict \
             | true error | covered |\n|---|---|---|---|---|---|---|",
            sc.reference_nodes
        );
        for r in &sc.rows {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {} |",
                r.name,
                with_unit(r.value, &r.unit, digits_for(r)),
                with_unit(r.reference, &r.unit, digits_for(r)),
                with_unit(r.uncertainty, &r.unit, 3),
                verdict_word(r.verdict),
                with_unit(r.true_error, &r.unit, 3),
                if r.covered { "✅ yes" } else { "❌ NO" }
            );
        }
        if !sc.not_in_reference.is_empty() {
            let _ = writeln!(
                s,
                "\nNot compared (the reference has no such quantity): {}.",
                sc.not_in_reference.join(", ")
            );
        }
        let _ = writeln!(
            s,
            "\nCost: verify made {} runs ({}); the reference took {} steps. Wall times are \
             printed by `cargo xtask validate`, not written here.\n",
            sc.levels.len(),
            levels_text(&sc.levels),
            sc.reference_steps
        );
    }
    s
}

/// Lines for the terminal, with the wall seconds of each verify run and reference.
#[must_use]
pub fn terminal(checks: &[VerifyCheck], verify: &BTreeMap<String, VerifyRun>) -> String {
    let mut s = String::new();
    for c in checks {
        match &c.result {
            Ok(sc) => {
                let _ = writeln!(
                    s,
                    "  verify {:<5} covered {} of {}{}; verify {:.1} s ({:.1} s of runs), \
                     reference `{}` {:.1} s",
                    c.subject.scene,
                    sc.covered(),
                    sc.rows.len(),
                    if sc.all_covered() {
                        String::new()
                    } else {
                        format!(", NOT COVERED: {}", sc.uncovered().join(", "))
                    },
                    verify.get(c.subject.scene).map_or(f64::NAN, |r| r.wall_s),
                    sc.levels.iter().map(|l| l.wall_s).sum::<f64>(),
                    c.subject.reference(),
                    sc.reference_wall_s
                );
            }
            Err(e) => {
                let _ = writeln!(s, "  verify {:<5} FAILED: {e}", c.subject.scene);
            }
        }
    }
    s
}
