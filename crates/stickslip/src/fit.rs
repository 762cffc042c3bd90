//! `stickslip fit`: the studies crate's fit (`stickslip_studies::fit`) of a scene's parameters to a
//! measured trace; a line on stderr per stage (and every few seconds), the table of fitted
//! values at the end, and `DIR/fit.json`, `DIR/fit.svg` and `DIR/fitted.toml`, written by the
//! reporting kit's `fit::write_outputs` (each through the atomic writer). Exit 0, 2 for bad input, 3 when no run
//! of the optimiser succeeded, 130 when interrupted (the best fit so far written, status
//! `interrupted`).

use std::path::Path;
use std::process::ExitCode;
use std::time::{Duration, Instant};
use stickslip_run::exit::Exit;
use stickslip_run::scene::Scene;
use stickslip_studies::fit::report::FitReport;
use stickslip_studies::fit::{Columns, FitOptions, JacobianKind, MisfitKind, Progress, Trace};

/// Seconds between progress lines within a stage.
const PROGRESS_EVERY: Duration = Duration::from_secs(5);

/// The command's arguments.
pub struct Args<'a> {
    /// Scene file.
    pub scene: &'a Path,
    /// `--set` overrides.
    pub set: &'a [String],
    /// `--unset` keys.
    pub unset: &'a [String],
    /// The trace file.
    pub data: &'a Path,
    /// `KEY[=LO:HI]` per free parameter.
    pub params: &'a [String],
    /// `events` or `trace`.
    pub misfit: &'a str,
    /// `t=NAME,F=NAME,X=NAME`.
    pub columns: Option<&'a str>,
    /// σF, N.
    pub noise: Option<f64>,
    /// Runs at a time.
    pub jobs: usize,
    /// The parameter to profile.
    pub profile: Option<&'a str>,
    /// `differences` or `replay`.
    pub jacobian: &'a str,
    /// Output directory (default: a fresh `fit-NAME[-k]`).
    pub out: Option<&'a Path>,
    /// Write over an earlier result in `out`.
    pub force: bool,
    /// No progress lines.
    pub quiet: bool,
}

/// A number with its interval, or a dash.
fn num(x: Option<f64>) -> String {
    x.map_or_else(|| "–".to_string(), |v| format!("{v:.4e}"))
}

/// The table of fitted values, the misfit and what the data cannot determine.
fn table(r: &FitReport) -> String {
    let mut out = format!(
        "{:<28} {:>12} {:>11} {:>25} {:>11} {:<9}\n",
        "parameter", "value", "± (1σ)", "95 % interval", "± (discr.)", "unit"
    );
    for p in &r.parameters {
        out.push_str(&format!(
            "{:<28} {:>12.5e} {:>11} {:>25} {:>11} {:<9}\n",
            p.key,
            p.value,
            num(p.stderr),
            format!("[{}, {}]", num(p.lo95), num(p.hi95)),
            num(p.discretisation),
            p.unit
        ));
    }
    if !r.discretisation_settings.is_empty() {
        out.push_str(&format!(
            "discretisation error: each value's move when the model at the optimum is refined \
             ({})\n",
            r.discretisation_settings.join(", ")
        ));
    }
    for w in &r.warnings {
        out.push_str(&format!("WARNING: {w}\n"));
    }
    if r.provisional_intervals {
        out.push_str(
            "PROVISIONAL intervals: the fit was interrupted before its final Jacobian at the \
             optimum; these are the last local step's (fit.json: provisional_intervals)\n",
        );
    }
    if r.parameters.len() > 1 && !r.correlation.is_empty() {
        out.push_str("correlations:");
        for (a, row) in r.correlation.iter().enumerate() {
            for (b, c) in row.iter().enumerate().skip(a + 1) {
                out.push_str(&format!(
                    " {}~{} {}",
                    short(&r.parameters[a].key),
                    short(&r.parameters[b].key),
                    c.map_or_else(|| "–".to_string(), |c| format!("{c:+.3}"))
                ));
            }
        }
        out.push('\n');
    }
    out.push_str(&format!(
        "misfit χ² = {:.4} over {} residuals (s = {}), {} events in the data, {} in the model; \
         {} runs ({} failed), {} local iterations{}, {:.1} s\n",
        r.misfit,
        r.residuals,
        r.residual_sigma
            .map_or_else(|| "–".to_string(), |s| format!("{s:.3}")),
        r.data_events.len(),
        r.model_events.len(),
        r.evaluations,
        r.failed_runs,
        r.iterations,
        if r.converged { "" } else { " (not converged)" },
        r.wall_s
    ));
    for u in &r.unidentified {
        out.push_str(&format!("not determined: {u}\n"));
    }
    if let Some(p) = &r.profile {
        out.push_str(&format!(
            "profile of {}: 95 % interval [{}, {}] from Δχ²/s² ≤ 3.84 over {} values\n",
            p.key,
            num(p.lo95),
            num(p.hi95),
            p.values.len()
        ));
    }
    out
}

/// The last part of a key, for the correlation line.
fn short(key: &str) -> &str {
    key.rsplit('.').next().unwrap_or(key)
}

/// Runs `stickslip fit`.
pub fn main(a: &Args<'_>) -> ExitCode {
    let scene = match Scene::from_path_unsetting(a.scene, a.unset, a.set) {
        Ok(s) => s,
        Err(e) => return crate::fail(e, Exit::BadInput),
    };
    if a.jobs == 0 {
        return crate::fail(
            "--jobs = 0 is invalid; allowed: an integer >= 1",
            Exit::BadInput,
        );
    }
    let prepared = MisfitKind::from_name(a.misfit).and_then(|kind| {
        let jacobian = JacobianKind::from_name(a.jacobian)?;
        let columns = a
            .columns
            .map_or_else(|| Ok(Columns::default()), Columns::parse)?;
        Ok(((kind, jacobian), Trace::read(a.data, &columns)?))
    });
    let ((kind, jacobian), trace) = match prepared {
        Ok(x) => x,
        Err(e) => return crate::fail(&e, e.exit()),
    };
    // A trace that starts long after the drive: every forward run simulates from t = 0, so
    // its cost is set by the trace's end, not its span. Said before the runs.
    let (t0, t1) = (trace.t_s[0], trace.t_s[trace.t_s.len() - 1]);
    if t0 > t1 - t0 {
        eprintln!(
            "fit: note: the trace starts at t = {} s, {:.0}× its span of {} s after the drive \
             started: every forward run simulates from t = 0 to {} s (the model's drive starts \
             at t = 0; shift the trace's times if it does not)",
            stickslip_run::keys::human(t0),
            t0 / (t1 - t0),
            stickslip_run::keys::human(t1 - t0),
            stickslip_run::keys::human(t1)
        );
    }
    // An interrupted fit of the same inputs in --out is resumed from its best point (its
    // global sample was made): the same command finishes it.
    let inputs =
        stickslip_studies::fit::inputs_fingerprint(&scene, a.params, kind, a.noise, &trace);
    let resume = a
        .out
        .and_then(|d| stickslip_studies::fit::report::FitReport::read(d).ok())
        .filter(|r| r.status == "interrupted" && r.inputs == inputs);
    if let (Some(r), Some(d)) = (&resume, a.out) {
        eprintln!(
            "fit: resuming the interrupted fit in {} from its best point (χ² {:.4} after {} \
             runs; the global sample is not made again)",
            d.display(),
            r.misfit,
            r.evaluations
        );
    }
    // The output directory before any run: nothing computed is lost to it.
    let out = match crate::out_dir::prepare(a.out, "fit", &scene.name, a.force || resume.is_some())
    {
        Ok(d) => d,
        Err((msg, exit)) => return crate::fail(msg, exit),
    };
    let dir = out.path.clone();
    let flag = match crate::interrupt_flag() {
        Ok(f) => f,
        Err(e) => return crate::fail(format!("cannot install signal handlers: {e}"), Exit::Io),
    };
    let quiet = a.quiet;
    let (mut stage, mut last) = ("", Instant::now());
    let mut progress = |p: &Progress| {
        if !quiet && (p.stage != stage || last.elapsed() >= PROGRESS_EVERY) {
            eprintln!(
                "fit: {} stage, {} runs so far ({} failed), best χ² {}{}{}",
                p.stage,
                p.evaluations,
                p.failed_runs,
                if p.best_chi2.is_finite() {
                    format!("{:.4}", p.best_chi2)
                } else {
                    "–".to_string()
                },
                // The runs' tolerance: a fit that tightens it has its runs grow costlier.
                p.tolerance
                    .map(|t| format!(", runs at time.tolerance {t:e}"))
                    .unwrap_or_default(),
                // What is left of the present batch of runs, and how long it should take.
                match (p.batch_left, p.batch_eta_s) {
                    (0, _) => String::new(),
                    (n, Some(eta)) => format!(
                        "; {n} runs left in this batch, about {}",
                        crate::progress::duration_text(eta)
                    ),
                    (n, None) => format!("; {n} runs left in this batch"),
                }
            );
            stage = p.stage;
            last = Instant::now();
        }
        false
    };
    let options = FitOptions {
        misfit: kind,
        noise_n: a.noise,
        jobs: a.jobs,
        profile: a.profile.map(str::to_string),
        interrupt: Some(&flag),
        progress: Some(&mut progress),
        start: resume.map(|r| r.parameters.iter().map(|p| p.value).collect()),
        jacobian,
        ..FitOptions::default()
    };
    let outcome = match stickslip_studies::fit::fit(&scene, trace, a.params, options) {
        Ok(o) => o,
        Err(e) => {
            out.discard_if_unused();
            return crate::fail(&e, e.exit());
        }
    };
    let r = &outcome.report;
    say_raw!("{}", table(r));
    if let Err(e) = stickslip_report::fit::write_outputs(&dir, &outcome) {
        return crate::fail(e, Exit::Io);
    }
    say!(
        "wrote {}, fit.svg and fitted.toml (stickslip run {} reproduces the fitted model)",
        dir.join("fit.json").display(),
        dir.join("fitted.toml").display()
    );
    if r.status == "interrupted" {
        eprintln!(
            "interrupted: the best fit so far is in {} (status \"interrupted\", {}); the same \
             command with --out {} resumes it from there",
            dir.display(),
            if r.provisional_intervals {
                "provisional intervals from the last local step's Jacobian"
            } else {
                "no uncertainty: no Jacobian was made before the interrupt"
            },
            dir.display()
        );
        return crate::code(Exit::Interrupted);
    }
    ExitCode::SUCCESS
}
