//! Hard cases: the scenes of `validation/hard/` run through the `stickslip` binary on a
//! [`Bench`] (the validation's own [`Runner`]), what each run did (exit status, run.json's
//! typed failure record, bounds, events, convergence), and `reports/hard-cases.md`.
//!
//! Each case lives in its own module: a function runs its scenes and returns a measured struct
//! implementing [`Case`], whose [`Case::checks`] are the expected outcomes (asserted by
//! `validation/tests/hard_cases.rs`, shown as ✅/❌ in the report), whose [`Case::findings`] say
//! what the engine does that it should not, or that a user should know (reported, never
//! asserted), and whose literal/accurate/numbers columns fill the report's table. The report
//! and the tests share this measurement code, so the report shows exactly what the tests
//! assert.
//!
//! The paper's literal scheme may fail, but must fail loudly (exit 3, run.json's failure record
//! naming time, step and node); the accurate scheme must survive every case. Failures are read
//! from run.json, never from stderr; stability numbers (Euler number, lagged-sweep contraction
//! factor) come from the preflight in-process (`stickslip_run::check::check`); a rejected scene
//! is the typed `SceneError` of the same resolution the binary does.

mod complete_melting;
mod critical_strain;
mod extreme_sizes;
pub mod figures;
mod first_order_fold;
mod large_dt;
mod noise_extremes;
mod rigid_fast;
mod soft_substrate;
mod stiff_kinetics;

pub use complete_melting::{Melting, melting};
pub use critical_strain::{
    CRITICAL_FACTORS, CriticalNumbers, CriticalVariant, NEAR_CRITICAL_A0_PA,
    NEAR_CRITICAL_PROFILE_S, NearCritical, near_critical,
};
pub use extreme_sizes::{EdgeScaling, SCALINGS, Scaled, edge_scaling, scaling_sets};
pub use first_order_fold::{
    FOLD_ADAPTIVE_REL_TOL, FOLD_DT_S, FOLD_LITERAL_SMALL_DT_S, FOLD_REFERENCE_DT_S, FirstOrderFold,
    first_order_fold, melting_strains,
};
pub use large_dt::{LARGE_DT_S, LargeDt, large_dt};
pub use noise_extremes::{LARGE_SIGMAS, NoiseExtremes, noise_extremes, stuck_melted};
pub use rigid_fast::{RigidFast, rigid_fast, spacing};
pub use soft_substrate::{SOFT_F_TIME_S, SOFT_NODES, SoftSubstrate, soft_substrate};
pub use stiff_kinetics::{STIFF_GAMMAS, StiffKinetics, StiffRun, stiff_kinetics};

use crate::facts::Facts;
pub use crate::runner::Attempt;
use crate::runner::Runner;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use stickslip_core::preflight::Preflight;
use stickslip_report::binary::invoke;
use stickslip_report::fmt::{self, first_line, sig};
use stickslip_run::keys::Setting;
use stickslip_run::{ResolvedScene, Scene, SceneError};

/// Runs hard-case scenes with one `stickslip` binary, writing outputs under one directory.
#[derive(Debug, Clone)]
pub struct Bench {
    runner: Runner,
}

/// A scene value the validation must reject.
#[derive(Debug, Clone)]
pub struct Rejection {
    /// The key.
    pub key: String,
    /// The value as given.
    pub value: String,
    /// Exit status of `stickslip check` with it.
    pub exit_code: Option<i32>,
    /// The same resolution in-process: the typed error (or, wrongly, a scene).
    pub resolved: Result<ResolvedScene, SceneError>,
}

impl Rejection {
    /// Exit 2, and the typed error names the key, the value and the allowed range.
    pub fn named(&self) -> bool {
        self.exit_code == Some(2)
            && self.resolved.as_ref().err().is_some_and(|e| {
                let text = e.to_string();
                e.key() == Some(self.key.as_str())
                    && text.contains(&self.value)
                    && text.contains("allowed")
            })
    }

    /// What happened, in a line.
    pub fn text(&self) -> String {
        format!(
            "exit {}: {}",
            self.exit_code
                .map_or_else(|| "none".to_string(), |c| c.to_string()),
            match &self.resolved {
                Err(e) => first_line(&e.to_string()),
                Ok(_) => "accepted".to_string(),
            }
        )
    }
}

impl Bench {
    /// A bench running `bin` on the scenes of `<root>/validation/hard/`, outputs in `out_root`.
    pub fn new(bin: PathBuf, root: PathBuf, out_root: PathBuf) -> Self {
        Self {
            runner: Runner::new(bin, root, out_root),
        }
    }

    /// Path of hard-case scene `scene` (file stem).
    pub fn scene_path(&self, scene: &str) -> PathBuf {
        self.runner
            .root()
            .join("validation")
            .join("hard")
            .join(format!("{scene}.toml"))
    }

    /// `stickslip run <scene> --out <out_root>/<label> --set …`, then reads the outputs.
    pub fn run(&self, label: &str, scene: &str, sets: &[String]) -> Attempt {
        self.runner.run(label, &self.scene_path(scene), sets)
    }

    /// The preflight of `scene` with `sets`, in-process (`stickslip_run::check::check`).
    ///
    /// # Errors
    /// The scene error or the engine's rejection, as text.
    pub fn preflight(&self, scene: &str, sets: &[String]) -> Result<Preflight, String> {
        let resolved =
            Scene::from_path(&self.scene_path(scene), sets).map_err(|e| e.to_string())?;
        stickslip_run::check::check(&resolved)
            .map(|c| c.preflight)
            .map_err(|e| e.to_string())
    }

    /// `stickslip check <scene> --set <key>=<value>` and the same resolution in-process.
    pub fn reject(&self, scene: &str, key: &str, value: &str) -> Rejection {
        let path = self.scene_path(scene);
        let set = vec![format!("{key}={value}")];
        let args = vec![
            "check".to_string(),
            path.display().to_string(),
            "--set".into(),
            set[0].clone(),
        ];
        Rejection {
            key: key.to_string(),
            value: value.to_string(),
            exit_code: invoke(self.runner.bin(), &args, &[])
                .ok()
                .and_then(|p| p.code),
            resolved: Scene::from_path(&path, &set),
        }
    }
}

/// A failure record's value as a number (NaN and infinities are written as strings).
pub fn failure_value(a: &Attempt) -> Option<f64> {
    let v = &a.failure()?.value;
    v.as_f64()
        .or_else(|| v.as_str().and_then(|s| s.parse().ok()))
}

/// A number from run.json's `derived` block.
pub fn derived(a: &Attempt) -> Option<&stickslip_run::schema::run_info::DerivedReport> {
    a.out().map(|o| &o.info.derived)
}

/// Exit 3 with run.json status `failed` and a failure record (time, step and node named).
pub fn failed_loudly(a: &Attempt) -> bool {
    a.exit_code() == Some(3) && a.failure().is_some()
}

/// One line: what happened.
pub fn outcome(a: &Attempt) -> String {
    match (a.exit_code(), a.failure(), a.out()) {
        (Some(0), _, Some(o)) => format!(
            "exit 0, {} event{}, {} steps",
            o.events.len(),
            if o.events.len() == 1 { "" } else { "s" },
            o.info.steps
        ),
        (Some(3), Some(f), _) => format!(
            "exit 3 at step {}, node {}, t = {}: {} = {}",
            f.step,
            f.node,
            fmt::time(f.time_s, 6),
            f.quantity,
            failure_value(a).map_or_else(|| f.value.to_string(), |v| sig(v, 4))
        ),
        _ => first_line(&a.error()),
    }
}

/// Bounds and finiteness of one run's outputs.
#[derive(Debug, Clone, PartialEq)]
pub struct Health {
    /// Every recorded number (series, profiles, probes, events) is finite.
    pub finite: bool,
    /// Smallest φ anywhere in the outputs (⟨φ⟩, probes, profiles).
    pub phi_min: f64,
    /// Largest φ anywhere in the outputs.
    pub phi_max: f64,
    /// Largest |F| (series F and F_1d, events f_peak), N.
    pub f_max_n: f64,
    /// τmax·π·a0², N (run.json's derived melting_force): the stationary maximum of F for the
    /// scene's default A.
    pub f_bound_n: f64,
}

impl Health {
    /// Measures `out`.
    pub fn of(out: &stickslip_run::RunOutput) -> Self {
        let s = &out.series;
        let mut finite = true;
        let mut all = |v: &[f64]| finite &= v.iter().all(|x| x.is_finite());
        for (_, col) in s.columns() {
            all(col);
        }
        let p = &out.profiles;
        for col in [&p.phi, &p.eps, &p.tau_pa, &p.u0_m, &p.u3d_m] {
            all(col);
        }
        for col in &out.probes.phi {
            all(col);
        }
        for e in out.events.events() {
            all(&[e.t_onset_s, e.x_onset_m, e.f_peak_n]);
        }
        let phis = s
            .phi_mean
            .iter()
            .chain(&out.profiles.phi)
            .chain(out.probes.phi.iter().flatten());
        let (phi_min, phi_max) = phis.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
        let f_max_n = s
            .f_n
            .iter()
            .chain(&s.f_1d_n)
            .chain(out.events.events().iter().map(|e| &e.f_peak_n))
            .fold(0.0_f64, |m, f| m.max(f.abs()));
        Self {
            finite,
            phi_min,
            phi_max,
            f_max_n,
            f_bound_n: out.info.derived.melting_force,
        }
    }

    /// max |F| / (τmax·π·a0²).
    pub fn f_ratio(&self) -> f64 {
        self.f_max_n / self.f_bound_n
    }

    /// Finite, φ ≥ 0 and |F| ≤ `factor`·τmax·π·a0².
    pub fn bounded(&self, factor: f64) -> bool {
        self.finite && self.phi_min >= 0.0 && self.f_max_n <= factor * self.f_bound_n
    }

    /// `finite, φ ∈ [min, max], max|F| = r·τmax·πa0²`.
    pub fn text(&self) -> String {
        format!(
            "{}, φ ∈ [{}, {}], max |F| = {}·τmax·πa0²",
            if self.finite { "finite" } else { "NON-FINITE" },
            sig(self.phi_min, 3),
            sig(self.phi_max, 3),
            sig(self.f_ratio(), 4)
        )
    }
}

/// One expected outcome and whether it was met.
#[derive(Debug, Clone, PartialEq)]
pub struct Check {
    /// What is expected.
    pub what: String,
    /// Whether the measurement meets it.
    pub pass: bool,
    /// What was measured.
    pub measured: String,
}

/// A [`Check`].
pub fn check(what: impl Into<String>, pass: bool, measured: impl Into<String>) -> Check {
    Check {
        what: what.into(),
        pass,
        measured: measured.into(),
    }
}

/// One measured hard case.
pub trait Case: Send {
    /// Number and short name, e.g. `1 soft substrate`.
    fn title(&self) -> String;
    /// Scene files used.
    fn scenes(&self) -> String;
    /// What the paper's literal scheme did.
    fn literal(&self) -> String;
    /// What the accurate scheme did.
    fn accurate(&self) -> String;
    /// The numbers behind both.
    fn numbers(&self) -> String;
    /// Expected outcomes (asserted by the tests).
    fn checks(&self) -> Vec<Check>;
    /// What the engine does that it should not, or that users should know; never asserted.
    fn findings(&self) -> Vec<String> {
        Vec::new()
    }
    /// Every run made, for the report's command list.
    fn attempts(&self) -> Vec<&Attempt>;
    /// The case's own figure, if it has one.
    fn figure(&self) -> Option<figures::HardFigure> {
        None
    }
}

/// The page's figures: the stability chart, then each case's own.
#[must_use]
pub fn all_figures(cases: &[Box<dyn Case>]) -> Vec<figures::HardFigure> {
    let runs: Vec<(usize, Vec<&Attempt>)> = cases
        .iter()
        .enumerate()
        .map(|(i, c)| (i + 1, c.attempts()))
        .collect();
    let mut v = vec![figures::HardFigure {
        file: "hard_stability.svg",
        title: "Stability: every run by case, scheme and outcome",
        caption: "Each marker is one run of the case (the runs listed under it below), the \
                  paper's literal scheme above, the accurate scheme below. What to see: the \
                  literal scheme fails, loudly, where the cases push it past its limits; the \
                  accurate scheme runs every case (exit 2 marks scenes refused up front by \
                  design, such as N = 1)."
            .into(),
        svg: figures::stability(&runs),
    }];
    v.extend(cases.iter().filter_map(|c| c.figure()));
    v
}

/// Panics listing every failed check of `case` (for the tests).
///
/// # Panics
/// If any check fails.
pub fn assert_checks(case: &dyn Case) {
    let failed: Vec<String> = case
        .checks()
        .into_iter()
        .filter(|c| !c.pass)
        .map(|c| format!("  - {}: measured {}", c.what, c.measured))
        .collect();
    assert!(
        failed.is_empty(),
        "hard case {}: {} check(s) failed:\n{}\nruns:\n{}",
        case.title(),
        failed.len(),
        failed.join("\n"),
        case.attempts()
            .iter()
            .map(|a| format!("  {} → {}", a.command, outcome(a)))
            .collect::<Vec<_>>()
            .join("\n")
    );
}

/// `--set` list from string slices.
pub fn sets(v: &[Setting]) -> Vec<String> {
    v.iter().map(ToString::to_string).collect()
}

/// `base` followed by `extra`.
pub fn with(base: &[String], extra: &[String]) -> Vec<String> {
    base.iter().chain(extra).cloned().collect()
}

/// Onset times of a run (empty without outputs), s.
pub fn onsets(a: &Attempt) -> Vec<f64> {
    a.out().map(|o| o.events.onsets_s()).unwrap_or_default()
}

/// Number of events (0 without outputs).
pub fn event_count(a: &Attempt) -> usize {
    a.out().map_or(0, |o| o.events.len())
}

/// Bounds and finiteness, if the run left outputs.
pub fn health(a: &Attempt) -> Option<Health> {
    a.out().map(Health::of)
}

/// Exit 0 and bounded by `factor`·τmax·π·a0².
pub fn bounded(a: &Attempt, factor: f64) -> bool {
    a.ok() && health(a).is_some_and(|h| h.bounded(factor))
}

/// [`Health::text`], or the outcome without outputs.
pub fn health_text(a: &Attempt) -> String {
    health(a).map_or_else(|| outcome(a), |h| h.text())
}

/// Times in s as µs, six significant digits.
pub fn us_list(v: &[f64]) -> String {
    fmt::us_list(v, 6)
}

/// What a literal run did, stating the failure record when it failed loudly.
pub fn literal_loud_text(a: &Attempt) -> String {
    match a.failure() {
        Some(f) if a.exit_code() == Some(3) => format!(
            "exit 3 at step {}, node {} (t = {}): {} = {}",
            f.step,
            f.node,
            fmt::time(f.time_s, 6),
            f.quantity,
            failure_value(a).map_or_else(|| f.value.to_string(), |v| sig(v, 4))
        ),
        _ => outcome(a),
    }
}

/// The run's contact radius a0, m (NaN without outputs).
pub fn radius_m(a: &Attempt) -> f64 {
    a.out().map_or(f64::NAN, |o| o.info.radius_m())
}

// ---------------------------------------------------------------------------------------------
// All cases and the report.

/// Runs every case (two at a time); `with_big_n` includes case 6's N = 8000 run.
pub fn measure_all(b: &Bench, with_big_n: bool) -> Vec<Box<dyn Case>> {
    type Job<'a> = Box<dyn Fn() -> Box<dyn Case> + Send + Sync + 'a>;
    let jobs: Vec<Job<'_>> = vec![
        Box::new(|| Box::new(soft_substrate(b))),
        Box::new(|| Box::new(stiff_kinetics(b))),
        Box::new(|| Box::new(large_dt(b))),
        Box::new(|| Box::new(melting(b))),
        Box::new(|| Box::new(near_critical(b))),
        Box::new(move || Box::new(edge_scaling(b, with_big_n))),
        Box::new(|| Box::new(noise_extremes(b))),
        Box::new(|| Box::new(rigid_fast(b))),
        Box::new(|| Box::new(first_order_fold(b))),
    ];
    let next = std::sync::atomic::AtomicUsize::new(0);
    let results: std::sync::Mutex<Vec<(usize, Box<dyn Case>)>> = std::sync::Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for _ in 0..2 {
            scope.spawn(|| {
                loop {
                    let i = next.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
                    let Some(job) = jobs.get(i) else { break };
                    let case = job();
                    results.lock().expect("results lock").push((i, case));
                }
            });
        }
    });
    let mut v = results.into_inner().expect("results lock");
    v.sort_by_key(|(i, _)| *i);
    v.into_iter().map(|(_, c)| c).collect()
}

fn md(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

/// reports/hard-cases.md from measured cases (no wall-clock times: the page must not change
/// when nothing changed).
pub fn report_md(cases: &[Box<dyn Case>], figs: &[figures::HardFigure]) -> String {
    let mut s = String::new();
    let checks: Vec<Check> = cases.iter().flat_map(|c| c.checks()).collect();
    let passed = checks.iter().filter(|c| c.pass).count();
    let _ = writeln!(s, "# Hard cases: does the numerics stay stable?\n");
    let _ = writeln!(
        s,
        "{}\n",
        stickslip_report::provenance::sentence(
            stickslip_report::provenance::Commit::of_workspace().as_ref()
        )
    );
    let _ = writeln!(
        s,
        "Generated by `cargo xtask validate` (or `cargo xtask validate --hard-only`) from the \
         runs it made with the `stickslip` binary; do not edit by hand. Scenes: \
         `validation/hard/*.toml` (each file's header says what it tests and what to expect); \
         measurement code: `validation/src/hard/` (one file per case); the same checks are \
         asserted by `validation/tests/hard_cases.rs`. The paper's literal scheme may fail, but \
         must fail loudly (exit 3, run.json's failure record naming time, step and node); the \
         accurate scheme must survive. Failures are read from run.json, stability numbers from \
         the preflight (`stickslip_run::check`), rejections from the typed scene error; \
         coefficients of variation are sample ones (n − 1). **{passed} of {} expected outcomes \
         met.**\n",
        checks.len()
    );
    let _ = writeln!(
        s,
        "| Case | Literal (the paper's scheme) | Accurate | The numbers | Expected outcomes |\n\
         |---|---|---|---|---|"
    );
    for c in cases {
        let ch = c.checks();
        let ok = ch.iter().filter(|x| x.pass).count();
        let _ = writeln!(
            s,
            "| **{}** ({}) | {} | {} | {} | {} {ok}/{} |",
            md(&c.title()),
            md(&c.scenes()),
            md(&c.literal()),
            md(&c.accurate()),
            md(&c.numbers()),
            if ok == ch.len() { "✅" } else { "❌" },
            ch.len()
        );
    }
    let findings: Vec<String> = cases.iter().flat_map(|c| c.findings()).collect();
    let _ = writeln!(s, "\n## Findings\n");
    if findings.is_empty() {
        let _ = writeln!(s, "None.");
    }
    for f in &findings {
        let _ = writeln!(s, "- {f}");
    }
    let _ = writeln!(s, "\n## Figures\n");
    for f in figs {
        let _ = writeln!(s, "### {}\n", f.title);
        match &f.svg {
            Ok(_) => {
                let _ = writeln!(s, "![{}]({})\n", f.title, f.file);
            }
            Err(e) => {
                let _ = writeln!(s, "*Not drawn: {}*\n", md(e));
            }
        }
        let _ = writeln!(s, "{}\n", f.caption);
    }
    let _ = writeln!(s, "## Expected outcomes, case by case\n");
    for c in cases {
        let _ = writeln!(s, "### {}\n", c.title());
        let _ = writeln!(s, "| Expected | Measured | |\n|---|---|---|");
        for x in c.checks() {
            let _ = writeln!(
                s,
                "| {} | {} | {} |",
                md(&x.what),
                md(&x.measured),
                if x.pass { "✅" } else { "❌" }
            );
        }
        let _ = writeln!(
            s,
            "\nRuns (from the workspace root; the binary is `target/release/stickslip`):\n"
        );
        for a in c.attempts() {
            let _ = writeln!(s, "- `{}` → {}", a.command, md(&outcome(a)));
        }
        let _ = writeln!(s);
    }
    let _ = writeln!(
        s,
        "Case 6 is also checked below the command line: `edge_singularity_operators` in \
         `validation/tests/hard_cases.rs` feeds the flat-punch stress τ = 1/(π√(a0² − r²)) to \
         the MDR operators (both quadratures) at N = 1, 2, 3 and 8000 and at a0 = 1e-9, 2e-5 \
         and 1e12 m (finite results, q = 1 and u3D·G* = 1 approached, the same numbers at every \
         a0 after scaling); this report does not repeat it."
    );
    s
}

/// What [`generate`] did.
#[derive(Debug, Clone, PartialEq)]
pub struct HardSummary {
    /// Expected outcomes met.
    pub passed: usize,
    /// Expected outcomes in all.
    pub total: usize,
    /// Findings reported.
    pub findings: usize,
}

/// Runs every hard case with `bin` (outputs in `<root>/target/hard/`) and writes
/// `<root>/reports/hard-cases.md`.
///
/// # Errors
/// If the report cannot be written.
pub fn generate(bin: &Path, root: &Path) -> Result<HardSummary, String> {
    let out_root = root.join("target").join("hard");
    std::fs::create_dir_all(&out_root).map_err(|e| format!("{}: {e}", out_root.display()))?;
    let bench = Bench::new(bin.to_path_buf(), root.to_path_buf(), out_root);
    let cases = measure_all(&bench, true);
    let checks: Vec<Check> = cases.iter().flat_map(|c| c.checks()).collect();
    let figs = all_figures(&cases);
    let text = report_md(&cases, &figs);
    let reports = root.join("reports");
    let mut files = stickslip_report::files::ReportFiles::create(&reports)?;
    for f in &figs {
        if let Ok(svg) = &f.svg {
            files.put(f.file, svg)?;
        }
    }
    files.put("hard-cases.md", text)?;
    for c in &cases {
        for x in c.checks().iter().filter(|x| !x.pass) {
            println!(
                "  hard case {}: NOT MET: {} ({})",
                c.title(),
                x.what,
                x.measured
            );
        }
    }
    Ok(HardSummary {
        passed: checks.iter().filter(|c| c.pass).count(),
        total: checks.len(),
        findings: cases.iter().map(|c| c.findings().len()).sum(),
    })
}
