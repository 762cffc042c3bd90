//! stickslip-fit-study: the verification study of the fit (`cargo xtask fit-study`): synthetic
//! traces from known parameters with noise, fitted through the studies crate's typed fit API,
//! and `reports/fit.md`, `reports/fit.json` and `reports/fit_*.svg` from what they give.
//!
//! - [`cases`]: the fits' scenes, truths, bounds, windows, sampling and noise, at the full and
//!   the `--quick` size;
//! - [`synth`]: the true model's clean curve (the fit's own forward run), sample times, noise
//!   from a seeded ChaCha8 stream, the true model's melting onsets;
//! - [`prepared`]: a case prepared once (scene, window, the true model's curve), its noisy
//!   traces and their fits through the run library's typed API;
//! - [`fits`]: the sections of fits: the coverage over seeds (item 1), the widths against
//!   samples (item 2), the single fits (items 4 and 5);
//! - [`jacobian`]: the fit's Jacobian at its optimum against central differences at two
//!   steps (item 3);
//! - [`sigmas`]: the events misfit's σ against the residuals' scatter at the truth (item 1's
//!   explanation);
//! - [`record`]: `fit.json`, the record every number of the report comes from;
//! - [`measures`]: coverage, slopes, agreement, costs and identifiability from the record, with
//!   targets and verdicts (item 6 among them);
//! - [`report`] and [`figures`]: the page and its SVGs (the reporting kit's plotting layer).
//!
//! Invariant: every number of the page is computed from the record it describes; the fits go
//! through `stickslip_studies::fit` as `stickslip fit`'s do, never through the command line.

pub mod cases;
pub mod figures;
pub mod fits;
pub mod jacobian;
pub mod measures;
pub mod prepared;
pub mod record;
pub mod report;
pub mod sigmas;
pub mod synth;

use record::{CoverageRun, Host, JacobianCheck, SectionTime, SingleFit, Study, WidthRun};
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// How the study runs.
#[derive(Debug, Clone)]
pub struct Options {
    /// The workspace (scenes under `validation/scenes`).
    pub root: PathBuf,
    /// Where the report goes.
    pub out: PathBuf,
    /// The smoke size.
    pub quick: bool,
    /// Forward runs at a time per fit.
    pub jobs: usize,
    /// Only redraw the page and figures from `out/fit.json`.
    pub render_only: bool,
    /// Keep the sections an earlier (interrupted) study finished, from `work`.
    pub resume: bool,
    /// Each finished section's record, for `--resume`.
    pub work: PathBuf,
}

/// `cargo xtask fit-study`'s options.
#[derive(Debug, clap::Parser)]
#[command(
    name = "cargo xtask fit-study",
    about = "Fits synthetic traces (known parameters, seeded noise) through the studies crate's fit",
    long_about = "Fits synthetic traces (known parameters, seeded noise) through the run library's \
                  fit and writes reports/fit.md, reports/fit.json and reports/fit_*.svg: coverage \
                  of the 95 % intervals over 20 seeds for fig2 and the SFA contact, interval \
                  width against samples, Jacobians against central differences, the cost of each \
                  fit (the fig2 and SFA first-slip targets), the damped viscous SFA contact, and \
                  what the fits find identifiable. The full study takes hours on two cores; \
                  every section's result is kept under target/fit-study/ (in CARGO_TARGET_DIR \
                  when set) as it finishes, and each coverage fit as it finishes.",
    after_help = "Exit status: 0 when every verdict passes, 1 when one fails (the report is \
                  written; the events misfit's width slope, which is not expected to follow \
                  n^-1/2, aside) or on an error, 2 for bad arguments."
)]
struct Args {
    /// A smoke study of about ten minutes (N = 30, two seeds, the SFA fits with tau_max and
    /// gamma free), written to target/fit-study/quick/report unless --out is given.
    #[arg(long)]
    quick: bool,
    /// Output directory [default: the workspace's reports/].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Forward runs at a time per fit.
    #[arg(long, value_name = "J", default_value_t = stickslip_studies::options::JOBS,
          value_parser = stickslip_report::options::at_least_one)]
    jobs: usize,
    /// Keep the sections (and the coverage fits) a previous run of the same size finished.
    #[arg(long)]
    resume: bool,
    /// Where each finished section and coverage fit is kept for --resume [default:
    /// target/fit-study/full, or .../quick]: a directory that outlives the machine (shared
    /// storage, or one committed) lets a study of several hours go on elsewhere.
    #[arg(long, value_name = "DIR")]
    work: Option<PathBuf>,
    /// Redraw the page and figures from DIR/fit.json.
    #[arg(long)]
    render_only: bool,
}

/// The 1-minute load average, when readable.
fn load_average() -> Option<f64> {
    std::fs::read_to_string("/proc/loadavg")
        .ok()?
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

/// A section's record, kept under `work` as it finishes (and read back with `--resume`).
fn section<T: Serialize + DeserializeOwned>(
    opts: &Options,
    name: &str,
    times: &mut Vec<SectionTime>,
    log: &mut fits::Log<'_>,
    make: &mut dyn FnMut(&mut fits::Log<'_>) -> Result<T, String>,
) -> Result<T, String> {
    let path = opts.work.join(format!("{name}.json"));
    if opts.resume
        && let Ok(text) = std::fs::read_to_string(&path)
        && let Ok((value, wall_s)) = serde_json::from_str::<(T, f64)>(&text)
    {
        log(&format!("{name}: kept from {}", path.display()));
        times.push(SectionTime {
            name: name.into(),
            wall_s,
        });
        return Ok(value);
    }
    log(&format!("{name}: running"));
    let started = Instant::now();
    let value = make(log)?;
    let wall_s = started.elapsed().as_secs_f64();
    log(&format!("{name}: done in {wall_s:.0} s"));
    let text = serde_json::to_string(&(&value, wall_s)).map_err(|e| e.to_string())?;
    std::fs::create_dir_all(&opts.work).map_err(|e| e.to_string())?;
    stickslip_report::write_atomic(&path, text.as_bytes()).map_err(|e| e.to_string())?;
    times.push(SectionTime {
        name: name.into(),
        wall_s,
    });
    Ok(value)
}

/// Runs the study.
///
/// # Errors
/// A case that cannot be prepared or fitted, or a section's record that cannot be kept.
pub fn run(opts: &Options, log: &mut fits::Log<'_>) -> Result<Study, String> {
    let sizes = if opts.quick {
        cases::Sizes::quick()
    } else {
        cases::Sizes::full()
    };
    let load_start = load_average();
    let (root, jobs) = (opts.root.as_path(), opts.jobs);
    let mut times = Vec::new();
    let mut jacobians: Vec<JacobianCheck> = Vec::new();
    // Each coverage fit's record, for --resume within a section; a fresh study starts afresh.
    let seeds_dir = |name: &str| opts.work.join(format!("{name}-seeds"));
    if !opts.resume {
        for name in ["coverage-A", "coverage-B"] {
            let _ = std::fs::remove_dir_all(seeds_dir(name));
        }
    }
    let seed_dirs = [seeds_dir("coverage-A"), seeds_dir("coverage-B")];
    let keep = |name: &str| Some(seed_dirs[usize::from(name == "coverage-B")].as_path());
    let (a, ja): (CoverageRun, JacobianCheck) =
        section(opts, "coverage-A", &mut times, log, &mut |l| {
            fits::coverage(
                root,
                cases::set_a(&sizes),
                &sizes,
                jobs,
                keep("coverage-A"),
                l,
            )
        })?;
    jacobians.push(ja);
    let (width, jw): (WidthRun, JacobianCheck) =
        section(opts, "width", &mut times, log, &mut |l| {
            fits::width(root, cases::set_a(&sizes), &sizes, jobs, l)
        })?;
    jacobians.push(jw);
    let (mut first_slip, jf): (SingleFit, JacobianCheck) =
        section(opts, "first-slip", &mut times, log, &mut |l| {
            fits::single(root, cases::first_slip(&sizes), None, jobs, l)
        })?;
    let (b, jb): (CoverageRun, JacobianCheck) =
        section(opts, "coverage-B", &mut times, log, &mut |l| {
            fits::coverage(
                root,
                cases::set_b(&sizes),
                &sizes,
                jobs,
                keep("coverage-B"),
                l,
            )
        })?;
    jacobians.push(jb);
    jacobians.push(jf);
    // The viscous fit is staged as a user would stage it (τmax and γ first, from the scene's
    // values, then all four). The first slip's fit is
    // the direct one alone, the target's measure: its twelve meltings make a needle that
    // staging does not remove (docs/fit.md, "What is not there yet").
    // (The smoke size frees τmax and γ alone: nothing to stage.)
    let staged = (!sizes.quick).then_some(2);
    let mut first_slip_staged: Option<SingleFit> = None;
    let (mut viscous, jv): (SingleFit, JacobianCheck) =
        section(opts, "viscous-staged", &mut times, log, &mut |l| {
            fits::single(root, cases::viscous(&sizes), staged, jobs, l)
        })?;
    jacobians.push(jv);
    let sigmas: Vec<sigmas::SigmaCheck> = section(opts, "sigmas", &mut times, log, &mut |_| {
        [cases::set_a(&sizes), cases::set_b(&sizes)]
            .into_iter()
            .map(|c| sigmas::check(root, c, &sizes))
            .collect()
    })?;
    // The figures' curves as thin as the record keeps them (a section kept from an earlier
    // run may hold more).
    let mut singles: Vec<&mut SingleFit> = vec![&mut first_slip, &mut viscous];
    if let Some(f) = first_slip_staged.as_mut() {
        singles.push(f);
    }
    for f in singles {
        let c = &f.curves;
        f.curves = fits::thin_curves(&c.t_s, &c.data_f_n, &c.model_f_n, fits::CURVE_BUCKETS);
    }
    Ok(Study {
        commit: stickslip_report::provenance::Commit::of_workspace(),
        sizes,
        host: Host {
            cores: std::thread::available_parallelism().map_or(1, std::num::NonZero::get),
            jobs,
            load_start,
            load_end: load_average(),
        },
        wall_s: times.iter().map(|t| t.wall_s).sum(),
        sections: times,
        coverage: vec![a, b],
        width,
        jacobians,
        sigmas,
        first_slip,
        first_slip_staged,
        viscous,
    })
}

/// Writes fit.json, fit.md and the figures of `study` into `out`; the paths written.
///
/// # Errors
/// A drawing or writing error, in words.
pub fn write(study: &Study, out: &Path, with_json: bool) -> Result<Vec<PathBuf>, String> {
    let mut files: Vec<(&str, String)> = vec![
        (
            report::COVERAGE_SVG,
            figures::coverage_svg(&study.coverage)?,
        ),
        (report::PULLS_SVG, figures::pulls_svg(&study.coverage)?),
        (report::WIDTH_SVG, figures::width_svg(&study.width)?),
        (
            report::FIRST_SLIP_SVG,
            figures::single_svg(&study.first_slip)?,
        ),
        (report::VISCOUS_SVG, figures::single_svg(&study.viscous)?),
        ("fit.md", report::markdown(study)),
    ];
    if let Some(f) = &study.first_slip_staged {
        files.push((report::FIRST_SLIP_STAGED_SVG, figures::single_svg(f)?));
    }
    if with_json {
        files.push((record::FILE, study.to_json()));
    }
    let mut written = stickslip_report::files::ReportFiles::create(out)?;
    for (name, text) in files {
        written.put(name, text)?;
    }
    Ok(written.into_written())
}

/// `cargo xtask fit-study` with `args` (the words after `fit-study`), the workspace at `root`.
///
/// Exit status: 0 every verdict passes, 1 a verdict fails (the report is written) or an
/// error, 2 bad arguments.
#[must_use]
pub fn cli(args: &[String], root: PathBuf) -> ExitCode {
    let args = match stickslip_report::options::parse::<Args>(
        "cargo xtask fit-study",
        args.iter().cloned(),
    ) {
        Ok((a, _)) => a,
        Err(code) => return code,
    };
    let Args {
        quick,
        out,
        jobs,
        resume,
        work,
        render_only,
    } = args;
    let size = if quick { "quick" } else { "full" };
    let target =
        std::env::var_os("CARGO_TARGET_DIR").map_or_else(|| root.join("target"), PathBuf::from);
    let default_work = target.join("fit-study").join(size);
    let work = work.unwrap_or_else(|| default_work.clone());
    let out = out.unwrap_or_else(|| {
        if quick {
            default_work.join("report")
        } else {
            root.join("reports")
        }
    });
    let opts = Options {
        root,
        out,
        quick,
        jobs,
        render_only,
        resume,
        work,
    };
    let study = if opts.render_only {
        let path = opts.out.join(record::FILE);
        match std::fs::read_to_string(&path)
            .map_err(|e| e.to_string())
            .and_then(|t| Study::parse(&t))
        {
            Ok(s) => s,
            Err(e) => {
                eprintln!("fit-study: {}: {e}", path.display());
                return ExitCode::FAILURE;
            }
        }
    } else {
        let mut log = |line: &str| eprintln!("fit-study: {line}");
        match run(&opts, &mut log) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("fit-study: {e}");
                return ExitCode::FAILURE;
            }
        }
    };
    match write(&study, &opts.out, !opts.render_only) {
        Ok(files) => {
            for f in files {
                println!("wrote {}", f.display());
            }
        }
        Err(e) => {
            eprintln!("fit-study: {e}");
            return ExitCode::FAILURE;
        }
    }
    let failed: Vec<String> = report::verdicts(&study)
        .into_iter()
        .filter(|(_, v)| v.starts_with("fail") && v != report::EXPECTED_FAIL)
        .map(|(item, v)| format!("{item}: {v}"))
        .collect();
    eprintln!(
        "fit-study: {} s in all; {} verdict(s) fail{}",
        study.wall_s.round(),
        failed.len(),
        if failed.is_empty() {
            String::new()
        } else {
            format!(": {}", failed.join("; "))
        }
    );
    if failed.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

#[cfg(test)]
mod cli_tests {
    use super::Args;
    use clap::Parser;

    #[test]
    fn options_parse_with_their_defaults_and_bad_ones_are_refused() {
        let a = Args::try_parse_from(["fit-study"]).unwrap();
        assert_eq!(a.jobs, stickslip_studies::options::JOBS);
        assert!(!a.quick && !a.resume && !a.render_only && a.out.is_none());
        let a = Args::try_parse_from(["fit-study", "--quick", "--jobs", "3", "--resume"]).unwrap();
        assert!(a.quick && a.resume && a.jobs == 3 && a.work.is_none());
        let a = Args::try_parse_from(["fit-study", "--resume", "--work", "kept"]).unwrap();
        assert_eq!(a.work, Some(std::path::PathBuf::from("kept")));
        for bad in [
            &["--jobs", "0"][..],
            &["--jobs", "x"],
            &["--bogus"],
            &["--out"],
        ] {
            let e = Args::try_parse_from(std::iter::once("fit-study").chain(bad.iter().copied()))
                .unwrap_err();
            assert!(e.use_stderr(), "{bad:?}");
        }
    }
}
