//! `stickslip verify`: the error of every summary number of a scene, from the run library's
//! refinements (`stickslip_studies::verify`); states the cost first, prints a table, writes
//! `DIR/verify.json` and a figure per quantity (the reporting kit's `verify`). Exit 0 when every quantity is within --rtol, 4 when one is not, 2 for
//! bad input.

use std::path::Path;
use std::process::ExitCode;
use stickslip_run::exit::Exit;
use stickslip_run::scene::Scene;
use stickslip_studies::verify::{self, Quantity, Verdict, VerifyReport};

/// The command's arguments.
pub struct Args<'a> {
    /// Scene file.
    pub scene: &'a Path,
    /// `--set` overrides.
    pub set: &'a [String],
    /// `--unset` keys.
    pub unset: &'a [String],
    /// Requested relative accuracy.
    pub rtol: f64,
    /// `--target`: search the cheapest resolution within this relative error instead.
    pub target: Option<f64>,
    /// Output directory (default: a fresh `verify-NAME[-k]`).
    pub out: Option<&'a Path>,
    /// Write over an earlier result in `out`.
    pub force: bool,
    /// Runs at a time.
    pub jobs: usize,
}

fn verdict_word(v: Verdict) -> &'static str {
    match v {
        Verdict::Within => "within",
        Verdict::Outside => "OUTSIDE",
        Verdict::NotConverged => "NOT CONVERGED",
        Verdict::Changed => "CHANGED",
    }
}

fn order(e: Option<&verify::estimate::Estimate>) -> String {
    match e {
        None => "–".to_string(),
        Some(e) => format!(
            "{} ({:.2})",
            e.order_observed
                .map_or("–".to_string(), |p| format!("{p:.2}")),
            e.order_theoretical
        ),
    }
}

fn row(q: &Quantity) -> String {
    let value = q
        .text
        .clone()
        .unwrap_or_else(|| format!("{:.6e} {}", q.value, q.unit));
    let unc = if q.text.is_some() {
        "–".to_string()
    } else {
        format!("{:.2e}", q.uncertainty)
    };
    let ext = q
        .extrapolated
        .map_or("–".to_string(), |x| format!("{x:.6e}"));
    format!(
        "{:<14} {:>22} {:>10} {:>14} {:>12} {:>12} {:>4} {}",
        q.name,
        value,
        unc,
        ext,
        order(q.space.as_ref()),
        order(q.time.as_ref()),
        if q.asymptotic { "yes" } else { "no" },
        verdict_word(q.verdict)
    )
}

/// The table of `report`.
fn table(report: &VerifyReport) -> String {
    let mut out = format!(
        "{:<14} {:>22} {:>10} {:>14} {:>12} {:>12} {:>4} verdict (rtol {})\n",
        "quantity",
        "value",
        "± (abs)",
        "extrapolated",
        "p space",
        "p time",
        "asym",
        stickslip_run::keys::human(report.rtol)
    );
    for q in &report.quantities {
        out.push_str(&row(q));
        out.push('\n');
    }
    out
}

/// Runs `stickslip verify`.
pub fn main(a: &Args<'_>) -> ExitCode {
    let scene = match Scene::from_path_unsetting(a.scene, a.unset, a.set) {
        Ok(s) => s,
        Err(e) => return crate::fail(e, Exit::BadInput),
    };
    if !(a.rtol.is_finite() && a.rtol > 0.0 && a.rtol < 1.0) {
        return crate::fail(
            format!(
                "--rtol {} is invalid; allowed: finite, > 0 and < 1 (a relative accuracy)",
                stickslip_run::keys::human(a.rtol)
            ),
            Exit::BadInput,
        );
    }
    if a.jobs == 0 {
        return crate::fail(
            "--jobs 0 is invalid; allowed: an integer >= 1",
            Exit::BadInput,
        );
    }
    // The output directory before any run: nothing computed is lost to it.
    // A directory holding only an interrupted verify's kept levels is this verify's to finish.
    let out = match crate::out_dir::prepare_resumable(
        a.out,
        "verify",
        &scene.name,
        a.force,
        &[verify::levels::DIR],
    ) {
        Ok(d) => d,
        Err((msg, exit)) => return crate::fail(msg, exit),
    };
    let dir = out.path.clone();
    if let Some(target) = a.target {
        return search(&scene, target, &out);
    }
    let levels = match verify::level_scenes(&scene) {
        Ok(l) => l,
        Err(e) => {
            out.discard_if_unused();
            return crate::fail(e, Exit::BadInput);
        }
    };
    // The cost, from check's estimate of each level's run.
    let seconds: Option<f64> = levels
        .iter()
        .map(|(_, s)| {
            stickslip_run::check::cost_estimate(s)
                .ok()
                .and_then(|c| c.seconds)
        })
        .sum();
    match seconds {
        Some(s) => eprintln!(
            "verify: {} runs ({} at a time), about {} of runs by check's estimates",
            levels.len(),
            a.jobs,
            crate::progress::duration_text(s)
        ),
        None => eprintln!(
            "verify: {} runs ({} at a time); their cost is unknown (check cannot back an \
             estimate for every level)",
            levels.len(),
            a.jobs
        ),
    }
    let flag = match crate::interrupt_flag() {
        Ok(f) => f,
        Err(e) => return crate::fail(format!("cannot install the signal handler: {e}"), Exit::Io),
    };
    let kept_before = verify::levels::count(&dir);
    let on_level = |k: usize, reused: bool| {
        if reused {
            eprintln!("verify: level {k} reused from an interrupted verify (kept in levels/)");
        }
    };
    let keep = verify::Keep {
        dir: Some(&dir),
        interrupt: Some(&flag),
        on_level: Some(&on_level),
    };
    let report = match verify::verify_kept(&scene, &levels, a.rtol, a.jobs, keep) {
        Ok(r) => r,
        Err(e) => {
            if kept_before == 0 && verify::levels::count(&dir) == 0 {
                out.discard_if_unused();
            }
            let exit = match e {
                verify::VerifyError::Failed { .. } => Exit::Numerical,
                verify::VerifyError::Interrupted { .. } => Exit::Interrupted,
                _ => Exit::BadInput,
            };
            return crate::fail(e, exit);
        }
    };
    for (level, (axis, s)) in report.levels.iter().zip(&levels).skip(1) {
        if level.status != "ok" {
            eprintln!(
                "verify: the {} level N = {}{} {}: its quantities are missing (changed)",
                match axis {
                    verify::Axis::Space => "space",
                    verify::Axis::Time => "time",
                },
                s.config.contact.nodes,
                level.tolerance.map_or_else(
                    || level
                        .dt_s
                        .map_or(String::new(), |dt| format!(", time.dt = {dt:e}")),
                    |t| format!(", time.tolerance = {t:e}")
                ),
                level.status
            );
        }
    }
    say_raw!("{}", table(&report));
    let json = match serde_json::to_vec_pretty(&report) {
        Ok(j) => j,
        Err(e) => return crate::fail(format!("cannot encode verify.json: {e}"), Exit::Io),
    };
    if let Err(e) = std::fs::create_dir_all(&dir)
        .and_then(|()| stickslip_run::atomic::write_atomic(&dir, "verify.json", &json))
    {
        return crate::fail(
            format!("cannot write {}: {e}", dir.join("verify.json").display()),
            Exit::Io,
        );
    }
    let mut figures = 0;
    for q in &report.quantities {
        let svg = match stickslip_report::verify::svg(&report, q) {
            Ok(Some(svg)) => svg,
            Ok(None) => continue,
            Err(e) => return crate::fail(format!("cannot draw {}: {e}", q.name), Exit::Io),
        };
        let path = dir.join(format!("verify_{}.svg", q.name));
        if let Err(e) = stickslip_report::write_atomic(&path, svg.as_bytes()) {
            return crate::fail(format!("cannot write {}: {e}", path.display()), Exit::Io);
        }
        figures += 1;
    }
    say!(
        "wrote {} and {figures} figures (verify_QUANTITY.svg: each quantity against N and \
         against the time stepping)",
        dir.join("verify.json").display()
    );
    if report.all_within() {
        ExitCode::SUCCESS
    } else {
        let bad = report
            .quantities
            .iter()
            .filter(|q| q.verdict != Verdict::Within)
            .count();
        eprintln!(
            "verify: {bad} of {} quantities are not within rtol {} (exit {})",
            report.quantities.len(),
            stickslip_run::keys::human(report.rtol),
            Exit::FailedPoints.code()
        );
        crate::code(Exit::FailedPoints)
    }
}

/// `verify --target`: the cheapest N and tolerance within `target`.
fn search(
    scene: &stickslip_run::ResolvedScene,
    target: f64,
    out: &crate::out_dir::OutDir,
) -> ExitCode {
    let dir = &out.path;
    // The plan is said with the first run, once the options are known to be good.
    let mut started = false;
    let mut line = |p: &verify::target::Probe| {
        if !std::mem::replace(&mut started, true) {
            eprintln!(
                "verify --target {}: runs to the first event, N doubling from {} at \
                 time.tolerance / 100, then the tolerance falling tenfold at the N found",
                stickslip_run::keys::human(target),
                verify::target::FIRST_NODES
            );
        }
        eprintln!(
            "  {:<6} N = {:>5}  tolerance = {:<8}  first onset {}  peak force {}  ({} steps, \
             {:.2} s)",
            p.ladder,
            p.nodes,
            stickslip_run::keys::human(p.tolerance),
            p.t_first_onset
                .map_or("none".to_string(), |t| format!("{t:.9e} s")),
            p.f_peak_first
                .map_or("none".to_string(), |f| format!("{f:.6e} N")),
            p.steps,
            p.wall_s
        );
    };
    let report = match verify::target::search(scene, target, &mut line) {
        Ok(r) => r,
        Err(e) => {
            out.discard_if_unused();
            return crate::fail(e, Exit::BadInput);
        }
    };
    let json = match serde_json::to_vec_pretty(&report) {
        Ok(j) => j,
        Err(e) => return crate::fail(format!("cannot encode target.json: {e}"), Exit::Io),
    };
    let mut files = vec![("target.json", json)];
    if let Some(c) = &report.choice {
        files.push((
            "resolution.toml",
            c.overrides_toml(&scene.name, target).into_bytes(),
        ));
    }
    for (name, bytes) in &files {
        if let Err(e) = std::fs::create_dir_all(dir)
            .and_then(|()| stickslip_run::atomic::write_atomic(dir, name, bytes))
        {
            return crate::fail(
                format!("cannot write {}: {e}", dir.join(name).display()),
                Exit::Io,
            );
        }
    }
    let spent: f64 = report.probes.iter().map(|p| p.wall_s).sum();
    match &report.choice {
        Some(c) => {
            let [onset, force] = c.total_error();
            say!(
                "cheapest within {}: contact.nodes = {}, time.tolerance = {} (first onset ±{:.2e}, \
                 peak force ±{:.2e} relative: space {:.2e} and {:.2e}, time {:.2e} and {:.2e}); \
                 {:.3} s to the first event (estimated {:.3} s); the search ran {} runs in {:.1} s",
                stickslip_run::keys::human(target),
                c.nodes,
                stickslip_run::keys::human(c.tolerance),
                onset,
                force,
                c.space_error[0],
                c.space_error[1],
                c.time_error[0],
                c.time_error[1],
                c.wall_s,
                c.estimated_wall_s,
                report.probes.len(),
                spent
            );
            say!(
                "wrote {} (stickslip run SCENE --set {})",
                dir.join("resolution.toml").display(),
                c.overrides().join(" --set ")
            );
            ExitCode::SUCCESS
        }
        None => {
            eprintln!(
                "verify --target {}: no resolution found: {} (exit {}); wrote {}",
                stickslip_run::keys::human(target),
                report.note.as_deref().unwrap_or("unknown"),
                Exit::FailedPoints.code(),
                dir.join("target.json").display()
            );
            crate::code(Exit::FailedPoints)
        }
    }
}
