//! The study's sections: a case prepared once ([`crate::prepared`]), then one fit per noisy
//! trace. Each section — the coverage of a set, the widths against samples, the single fits —
//! is a function here returning its part of the record, with the Jacobian checks of its fits,
//! each fit's CPU time and the χ² of the true model on its data.

use crate::cases::{Case, Sizes};
use crate::jacobian;
use crate::prepared::{Prepared, prepare};
use crate::record::{CoverageRun, Curves, FitSummary, JacobianCheck, SingleFit, WidthRun};
use std::path::Path;
use stickslip_studies::fit::{FitOutcome, JacobianKind, MisfitKind, Strategy};

/// The CPU time of this process so far (user and system, all threads), s: from
/// `/proc/self/stat` in clock ticks of 1/100 s; none where unreadable.
#[must_use]
pub fn cpu_time_s() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/self/stat").ok()?;
    // The fields after the command's closing parenthesis: utime and stime are the 12th and
    // 13th of them (fields 14 and 15 of the line).
    let rest = text.rsplit_once(')')?.1;
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// The summary of `out`, a fit of `p`'s trace of `seed` with `samples`, begun at CPU time
/// `cpu0`, with the χ² of the true model on the same data.
fn summary(
    p: &Prepared,
    out: &FitOutcome,
    (seed, samples): (u64, usize),
    cpu0: Option<f64>,
    jobs: usize,
) -> Result<FitSummary, String> {
    let mut s = FitSummary::new(&p.case, seed, samples, &out.report);
    s.cpu_s = cpu0.zip(cpu_time_s()).map(|(a, b)| b - a);
    s.chi2_truth = Some(jacobian::chi2_at_truth(p, out, jobs)?);
    Ok(s)
}

/// A progress line.
pub type Log<'a> = dyn FnMut(&str) + 'a;

/// One line on a fit: its values and intervals against the truth, χ², runs and time.
fn line(what: &str, s: &FitSummary) -> String {
    let parts: Vec<String> = s
        .params
        .iter()
        .filter(|p| p.key != "time_shift")
        .map(|p| {
            let short = p.key.rsplit('.').next().unwrap_or(&p.key);
            let mark = match p.covers() {
                Some(true) => "",
                Some(false) => " MISSES",
                None => " (not determined)",
            };
            format!(
                "{short} {:.6e} [{}, {}]{mark}",
                p.value,
                p.lo95.map_or("–".into(), |v| format!("{v:.5e}")),
                p.hi95.map_or("–".into(), |v| format!("{v:.5e}")),
            )
        })
        .collect();
    format!(
        "{what}: {}; χ² {:.2} (truth {}) over {}, {} runs, {:.1} s{}",
        parts.join("; "),
        s.chi2,
        s.chi2_truth.map_or("–".into(), |c| format!("{c:.2}")),
        s.residuals,
        s.evaluations,
        s.wall_s,
        s.cpu_s
            .map_or_else(String::new, |c| format!(" ({:.2} cores)", c / s.wall_s))
    )
}

/// Item 1: the coverage of `case` over the seeds 1…`sizes.seeds`, and the Jacobian check at
/// the first seed's optimum.
///
/// # Errors
/// A case that cannot be prepared, or a fit without any successful run.
///
/// With `keep`, each seed's fit (and the first seed's Jacobian check) is kept as
/// `keep/seed-K.json` when it finishes, and a seed whose record is there is not fitted again:
/// a coverage set of 20 fits takes hours, and an interrupted one resumes at its next seed.
pub fn coverage(
    root: &Path,
    case: Case,
    sizes: &Sizes,
    jobs: usize,
    keep: Option<&Path>,
    log: &mut Log<'_>,
) -> Result<(CoverageRun, JacobianCheck), String> {
    let p = prepare(root, case)?;
    log(&format!(
        "{}: {} samples over {} s",
        p.case.id, p.case.samples, p.case.end_s
    ));
    let mut fits = Vec::new();
    let mut check = None;
    for seed in 1..=sizes.seeds as u64 {
        let record = keep.map(|dir| dir.join(format!("seed-{seed}.json")));
        let kept = record
            .as_ref()
            .and_then(|path| std::fs::read_to_string(path).ok())
            .and_then(|text| {
                serde_json::from_str::<(FitSummary, Option<JacobianCheck>)>(&text).ok()
            })
            .filter(|(s, c)| s.seed == seed && (seed > 1 || c.is_some()));
        let (s, c) = if let Some(kept) = kept {
            log(&format!("{} seed {seed}: kept", p.case.id));
            kept
        } else {
            let trace = p.trace(p.case.samples, seed)?;
            let cpu0 = cpu_time_s();
            let out = p.fit(trace, MisfitKind::Events, jobs, false)?;
            let s = summary(&p, &out, (seed, p.case.samples), cpu0, jobs)?;
            let c = if seed == 1 {
                Some(jacobian::check(&p, &out, seed, jobs)?)
            } else {
                None
            };
            if let (Some(path), Some(dir)) = (&record, keep) {
                std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
                let text = serde_json::to_string(&(&s, &c)).map_err(|e| e.to_string())?;
                stickslip_report::write_atomic(path, text.as_bytes())
                    .map_err(|e| format!("{}: {e}", path.display()))?;
            }
            (s, c)
        };
        log(&line(&format!("{} seed {seed}", p.case.id), &s));
        if check.is_none() {
            check = c;
        }
        fits.push(s);
    }
    let check = check.ok_or("no seeds")?;
    Ok((CoverageRun { case: p.case, fits }, check))
}

/// The cost target's fits: `case` fitted on each of the seeds `seeds` with `strategy`, each
/// fit's summary (time, runs, χ² against the truth's, intervals) logged as it ends. With
/// `from_truth` the local stage starts at the true values and the global search is skipped:
/// what a fit costs once its search has found the truth's basin.
///
/// # Errors
/// As [`coverage`].
pub fn per_seed(
    root: &Path,
    case: Case,
    seeds: std::ops::RangeInclusive<u64>,
    (jobs, strategy, jacobian): (usize, Strategy, JacobianKind),
    from_truth: bool,
    log: &mut Log<'_>,
) -> Result<Vec<(FitSummary, FitOutcome)>, String> {
    let p = prepare(root, case)?;
    // The case's parameters are in the order of its truth.
    let truth: Vec<f64> = p.case.truth.iter().map(|(_, v)| *v).collect();
    log(&format!(
        "{}: {} samples over {} s",
        p.case.id, p.case.samples, p.case.end_s
    ));
    let mut out = Vec::new();
    for seed in seeds {
        let trace = p.trace(p.case.samples, seed)?;
        let cpu0 = cpu_time_s();
        let fit = p.fit_with(
            trace,
            MisfitKind::Events,
            (jobs, false),
            (strategy, jacobian),
            from_truth.then(|| truth.clone()),
        )?;
        let s = summary(&p, &fit, (seed, p.case.samples), cpu0, jobs)?;
        log(&line(&format!("{} seed {seed}", p.case.id), &s));
        out.push((s, fit));
    }
    Ok(out)
}

/// Item 2: `case` (set A) sampled at 1, 2, 4, … times its samples, `sizes.width_seeds` seeds
/// per level, fitted with the events and the trace misfit given the known σF (so that the
/// widths change with the samples alone); the Jacobian check of the trace misfit at its first
/// fit.
///
/// # Errors
/// As [`coverage`].
pub fn width(
    root: &Path,
    case: Case,
    sizes: &Sizes,
    jobs: usize,
    log: &mut Log<'_>,
) -> Result<(WidthRun, JacobianCheck), String> {
    let p = prepare(root, case)?;
    let levels: Vec<usize> = (0..sizes.width_levels)
        .map(|k| p.case.samples << k)
        .collect();
    let (mut events, mut trace_fits) = (Vec::new(), Vec::new());
    let mut check = None;
    for (k, &n) in levels.iter().enumerate() {
        for s in 1..=sizes.width_seeds as u64 {
            let seed = 1000 * (k as u64 + 1) + s;
            for (kind, into) in [
                (MisfitKind::Events, &mut events),
                (MisfitKind::Trace, &mut trace_fits),
            ] {
                let cpu0 = cpu_time_s();
                let out = p.fit(p.trace(n, seed)?, kind, jobs, true)?;
                let sum = summary(&p, &out, (seed, n), cpu0, jobs)?;
                log(&line(
                    &format!("width, {} misfit, {n} samples, seed {seed}", kind.name()),
                    &sum,
                ));
                if kind == MisfitKind::Trace && check.is_none() {
                    check = Some(jacobian::check(&p, &out, seed, jobs)?);
                }
                into.push(sum);
            }
        }
    }
    let check = check.ok_or("no width fits")?;
    Ok((
        WidthRun {
            case: p.case,
            levels,
            events,
            trace: trace_fits,
        },
        check,
    ))
}

/// Items 4 and 5: one fit of `case` (seed 1), its curves and its Jacobian check. With
/// `stage = Some(k)` the fit is staged, as a user would stage it: first the case's first `k`
/// parameters alone from the scene's own values (the others held there), then every parameter
/// from the values the first stage found.
///
/// # Errors
/// As [`coverage`].
pub fn single(
    root: &Path,
    case: Case,
    stage: Option<usize>,
    jobs: usize,
    log: &mut Log<'_>,
) -> Result<(SingleFit, JacobianCheck), String> {
    let mut p = prepare(root, case)?;
    log(&format!(
        "{}: {} samples over {} s",
        p.case.id, p.case.samples, p.case.end_s
    ));
    let seed = 1;
    let trace = p.trace(p.case.samples, seed)?;
    let mut first_stage = None;
    if let Some(k) = stage {
        let mut case = p.case.clone();
        case.params.truncate(k);
        case.truth.truncate(k);
        let first = Prepared {
            case,
            scene: p.scene.clone(),
            curve: p.curve.clone(),
        };
        let cpu0 = cpu_time_s();
        let out = first.fit(trace.clone(), MisfitKind::Events, jobs, false)?;
        let s = summary(&first, &out, (seed, p.case.samples), cpu0, jobs)?;
        log(&line(&format!("{} first stage", p.case.id), &s));
        let found: Vec<String> = s
            .params
            .iter()
            .map(|q| format!("{}={:e}", q.key, q.value))
            .collect();
        p.scene = p
            .scene
            .with_overrides(&found)
            .map_err(|e| format!("{}: {e}", p.case.id))?;
        first_stage = Some(s);
    }
    let cpu0 = cpu_time_s();
    let out = p.fit(trace, MisfitKind::Events, jobs, false)?;
    let summary = summary(&p, &out, (seed, p.case.samples), cpu0, jobs)?;
    log(&line(&p.case.id, &summary));
    let check = jacobian::check(&p, &out, seed, jobs)?;
    Ok((
        SingleFit {
            case: p.case,
            summary,
            first_stage,
            report: out.report.clone(),
            curves: thin(&out, CURVE_BUCKETS),
        },
        check,
    ))
}

/// Buckets of a figure's thinned curves (with the least and largest of data and model in
/// each, at most four points a bucket: enough for a panel a few hundred pixels wide).
pub const CURVE_BUCKETS: usize = 300;

/// The data and the model of `out` thinned to [`CURVE_BUCKETS`] buckets ([`thin_curves`]).
#[must_use]
pub fn thin(out: &FitOutcome, buckets: usize) -> Curves {
    thin_curves(&out.trace.t_s, &out.trace.f_n, &out.model_f_n, buckets)
}

/// The samples of `(t, data, model)` that keep each of `buckets` runs of samples' least and
/// largest values of either (so drops survive), in order.
#[must_use]
pub fn thin_curves(t: &[f64], d: &[f64], m: &[f64], buckets: usize) -> Curves {
    let n = t.len().min(d.len()).min(m.len());
    let per = n.div_ceil(buckets.max(1)).max(1);
    let mut keep = Vec::new();
    for start in (0..n).step_by(per) {
        let end = (start + per).min(n);
        let arg = |f: &[f64], max: bool| {
            (start..end)
                .max_by(|&a, &b| {
                    let o = f[a].total_cmp(&f[b]);
                    if max { o } else { o.reverse() }
                })
                .unwrap_or(start)
        };
        keep.extend([arg(d, true), arg(d, false), arg(m, true), arg(m, false)]);
    }
    keep.sort_unstable();
    keep.dedup();
    Curves {
        t_s: keep.iter().map(|&i| t[i]).collect(),
        data_f_n: keep.iter().map(|&i| d[i]).collect(),
        model_f_n: keep.iter().map(|&i| m[i]).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thinning_keeps_each_buckets_extremes_in_order() {
        let t: Vec<f64> = (0..1000).map(f64::from).collect();
        let d: Vec<f64> = t.iter().map(|x| (x / 37.0).sin()).collect();
        let m: Vec<f64> = t
            .iter()
            .map(|x| if *x == 500.0 { 9.0 } else { 0.0 })
            .collect();
        let c = thin_curves(&t, &d, &m, 10);
        assert!(c.t_s.len() <= 40 && c.t_s.len() >= 20, "{}", c.t_s.len());
        assert!(c.t_s.windows(2).all(|w| w[0] < w[1]));
        // The model's lone spike and the data's extremes survive.
        assert!(c.model_f_n.contains(&9.0));
        let top = d.iter().copied().fold(f64::MIN, f64::max);
        assert!(c.data_f_n.contains(&top));
        // Thinning again to as many buckets keeps what is there.
        let again = thin_curves(&c.t_s, &c.data_f_n, &c.model_f_n, 10);
        assert!(again.model_f_n.contains(&9.0));
    }
}
