//! `cargo xtask validate [--check | --hard-only]`: build the binary, run the scenes, check the
//! claims, write (or, with `--check`, compare against) the reports, then run the hard cases and
//! write `reports/hard-cases.md` (not with `--check`; `--hard-only` does only that).

use crate::claims::{Runs, evaluate};
use crate::hard::HardSummary;
use crate::report::{Outcome, Resolution, claims_table_text, compare, index_md, summary_json};
use crate::runner::{Runner, run_all_with, specs as specs_list};
use std::path::{Path, PathBuf};
use std::time::Instant;
use stickslip_report::binary;
use stickslip_report::files::ReportFiles;

/// What `validate` should do.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// Workspace root.
    pub root: PathBuf,
    /// Compare with the committed `reports/summary.json` instead of writing reports.
    pub check: bool,
    /// Runs in parallel.
    pub jobs: usize,
    /// Only run the hard cases and write `reports/hard-cases.md` (`--hard-only`).
    pub hard_only: bool,
    /// The Python interpreter (with NumPy and SciPy) for the independent implementation; none
    /// skips the comparison and says so in the report.
    pub python: Option<PathBuf>,
    /// Only run the comparison with the independent implementation and write
    /// `reports/independent.json` and its figure (`--independent-only`).
    pub independent_only: bool,
    /// Only run the energy books' checks and write `reports/energy.json` and its figure
    /// (`--energy-only`).
    pub energy_only: bool,
}

/// Runs the validation. `Ok(true)` when every claim passes and verify covers every known error
/// (and, with `--check`, the fresh verdicts, event counts, reduced block and verify coverage
/// equal the committed ones). Unmet hard-case
/// expectations are printed and shown in reports/hard-cases.md.
///
/// # Errors
/// When the binary cannot be built or the reports cannot be read or written.
pub fn validate(opts: &Options) -> Result<bool, String> {
    let start = Instant::now();
    let root = &opts.root;
    println!("validate: building the stickslip binary (cargo build --release -p stickslip)");
    let bin = binary::build(root)?;
    if opts.hard_only {
        return hard_cases(&bin, root).map(|h| h.passed == h.total);
    }
    let scenes = root.join("validation").join("scenes");
    let out_root = root.join("target").join("validation");
    std::fs::create_dir_all(&out_root).map_err(|e| format!("{}: {e}", out_root.display()))?;
    if opts.independent_only {
        let runner = Runner::new(bin.clone(), root.clone(), out_root);
        let comparison =
            independent(&runner, opts).ok_or("--independent-only needs a Python interpreter")??;
        let mut files = ReportFiles::create(&root.join("reports"))?;
        write_independent(&mut files, &comparison)?;
        print!("{}", crate::independent::report::markdown(&comparison));
        return Ok(comparison.all_agree());
    }
    if opts.energy_only {
        let runner = Runner::new(bin.clone(), root.clone(), out_root);
        let results = run_all_with(
            &runner,
            &scenes,
            crate::energy::specs(),
            Vec::new(),
            opts.jobs,
        );
        let mut runs = Runs::default();
        for (name, r) in &results {
            runs.map.insert(name.clone(), r.output());
        }
        let energy = crate::energy::evaluate(&runs);
        let mut files = ReportFiles::create(&root.join("reports"))?;
        write_energy(&mut files, &energy)?;
        print!("{}", crate::energy::markdown(&energy));
        return Ok(energy.passes());
    }
    // The verify check's references first: the sfa one is the longest run.
    let mut specs = crate::verify_check::reference_specs();
    let base = specs_list();
    specs.extend(crate::uncertainty::specs(&base, &scenes));
    specs.extend(base);
    specs.extend(crate::sensitivity::specs());
    specs.extend(crate::energy::specs());
    println!(
        "validate: {} runs and {} verify runs, {} at a time, outputs in {}",
        specs.len(),
        crate::verify_check::SUBJECTS.len(),
        opts.jobs,
        out_root.display()
    );
    let runner = Runner::new(bin.clone(), root.clone(), out_root);
    let verify_runs = std::sync::Mutex::new(std::collections::BTreeMap::new());
    let tasks = crate::verify_check::tasks(&runner, &scenes, &verify_runs);
    let results = run_all_with(&runner, &scenes, specs, tasks, opts.jobs);
    let verify_runs = verify_runs.into_inner().map_err(|e| e.to_string())?;
    let mut runs = Runs::default();
    for (name, r) in &results {
        runs.map.insert(name.clone(), r.output());
    }
    let reduced = runs.get("fig2_reduced_cli").map(crate::reduced::features);
    let resolution = Resolution::of(&runs);
    let mut claims = evaluate(&runs);
    claims.extend(crate::claims_first_order::evaluate(&runs));
    let sensitivity = crate::sensitivity::evaluate(&runs);
    crate::sensitivity::annotate(&mut claims, &sensitivity);
    let margin_errors = crate::uncertainty::evaluate(&runs, &claims);
    let energy = crate::energy::evaluate(&runs);
    let advance = crate::advance::evaluate(&runs);
    let (event_rule, event_rule_missing) = crate::events_rule::compare(&runs);
    let verify_check = crate::verify_check::evaluate(&verify_runs, &runs);
    // Not under --check: summary.json does not hold it, and it takes minutes.
    let independent = if opts.check {
        None
    } else {
        independent(&runner, opts)
    };
    let outcome = Outcome {
        claims: &claims,
        runs: &runs,
        results: &results,
        reduced: reduced.as_ref().map_err(Clone::clone),
        resolution: resolution.as_ref(),
        event_rule: &event_rule,
        event_rule_missing: &event_rule_missing,
        verify_check: &verify_check,
        independent: independent.as_ref(),
        sensitivity: &sensitivity,
        energy: &energy,
        advance: &advance,
        margin_errors: &margin_errors,
    };
    let summary = summary_json(&outcome);
    println!("\nclaims:\n{}", claims_table_text(&claims));
    println!("{}", crate::events_rule::sentence(&event_rule));
    print!(
        "verify against known errors:\n{}",
        crate::verify_check::terminal(&verify_check, &verify_runs)
    );
    // Every claim passes and verify's uncertainty covers every known error (or says not
    // converged).
    let all_pass = claims.iter().all(|c| c.pass)
        && crate::verify_check::all_covered(&verify_check)
        && energy.passes()
        && advance.passes()
        && independent.as_ref().is_none_or(|c| {
            c.as_ref()
                .is_ok_and(crate::independent::Comparison::all_agree)
        });
    let reports = root.join("reports");
    if opts.check {
        let path = reports.join("summary.json");
        let text =
            std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let committed: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        let diffs = compare(&summary, &committed);
        if diffs.is_empty() {
            println!(
                "check: verdicts, event counts, the reduced block and verify's coverage match \
                 reports/summary.json"
            );
        } else {
            println!("check: reports/summary.json is stale (run `cargo xtask validate`):");
            for d in &diffs {
                println!("  - {d}");
            }
        }
        println!("check: the reports' age against their sources:");
        for line in crate::staleness::lines(&crate::staleness::ages(root)) {
            println!("  - {line}");
        }
        println!(
            "validate --check took {:.0} s",
            start.elapsed().as_secs_f64()
        );
        return Ok(all_pass && diffs.is_empty());
    }
    let mut files = ReportFiles::create(&reports)?;
    let mut figures = crate::figures::all(&runs);
    figures.extend(crate::figures_first_order::all(&runs));
    for fig in &figures {
        match &fig.svg {
            Ok(svg) => files.put(fig.file, svg)?,
            Err(e) => println!("figure {} not drawn: {e}", fig.file),
        }
    }
    if let Some(Ok(c)) = &independent {
        write_independent(&mut files, c)?;
    }
    write_energy(&mut files, &energy)?;
    match crate::figures::margins_svg(&claims) {
        Ok(svg) => files.put(crate::figures::MARGINS_SVG, svg)?,
        Err(e) => println!("figure {} not drawn: {e}", crate::figures::MARGINS_SVG),
    }
    match crate::advance::figure(&advance) {
        Ok(svg) => files.put(crate::advance::FIGURE, svg)?,
        Err(e) => println!("figure {} not drawn: {e}", crate::advance::FIGURE),
    }
    files.put("index.md", index_md(&outcome, &figures))?;
    files.put_json("summary.json", &summary)?;
    hard_cases(&bin, root)?;
    println!(
        "validate: wrote reports/index.md, reports/summary.json, reports/hard-cases.md and {} \
         figures in {:.0} s",
        figures.iter().filter(|f| f.svg.is_ok()).count(),
        start.elapsed().as_secs_f64()
    );
    Ok(all_pass)
}

/// The comparison with the independent implementation, when a Python interpreter was given.
fn independent(
    runner: &Runner,
    opts: &Options,
) -> Option<Result<crate::independent::Comparison, String>> {
    let python = opts.python.as_ref()?;
    println!(
        "validate: the independent implementation ({})",
        python.display()
    );
    let started = Instant::now();
    let c = crate::independent::compare(runner, python, opts.jobs);
    if let Ok(c) = &c {
        println!(
            "validate: independent comparison: {} in {:.0} s",
            if c.all_agree() {
                "every quantity agrees"
            } else {
                "a quantity DISAGREES"
            },
            started.elapsed().as_secs_f64()
        );
    }
    Some(c)
}

/// `reports/independent.json` and its figure.
fn write_independent(
    files: &mut ReportFiles,
    c: &crate::independent::Comparison,
) -> Result<(), String> {
    files.put_json("independent.json", c)?;
    match crate::independent::report::figure(c) {
        Ok(svg) => files.put(crate::independent::report::FIGURE, svg),
        Err(e) => {
            println!(
                "figure {} not drawn: {e}",
                crate::independent::report::FIGURE
            );
            Ok(())
        }
    }
}

/// reports/energy.json and the energy books' figure.
fn write_energy(
    files: &mut ReportFiles,
    energy: &crate::energy::EnergyCheck,
) -> Result<(), String> {
    files.put_json(
        "energy.json",
        &serde_json::json!({
            "generated_by": "cargo xtask validate",
            "commit": stickslip_report::provenance::Commit::of_workspace(),
            "energy_books": energy,
        }),
    )?;
    match crate::energy::figure(energy) {
        Ok(svg) => files.put(crate::energy::FIGURE, svg),
        Err(e) => {
            println!("figure {} not drawn: {e}", crate::energy::FIGURE);
            Ok(())
        }
    }
}

/// Runs the hard cases of `validation/hard/` and writes `reports/hard-cases.md`.
fn hard_cases(bin: &Path, root: &Path) -> Result<HardSummary, String> {
    println!("validate: hard cases (validation/hard/, outputs in target/hard/)");
    let started = Instant::now();
    let h = crate::hard::generate(bin, root)?;
    println!(
        "validate: hard cases: {} of {} expected outcomes met, {} findings, {:.0} s; wrote \
         reports/hard-cases.md",
        h.passed,
        h.total,
        h.findings,
        started.elapsed().as_secs_f64()
    );
    Ok(h)
}
