//! The page's sections on single fits: the cost of each fit (§4, with the fig2 and SFA
//! first-slip targets) and the damped, viscous SFA contact (§5), with their tables.

use super::*;

fn cost_rows(name: &str, fits: &[FitSummary], out: &mut String) {
    let runs: Vec<f64> = fits.iter().map(|f| f.evaluations as f64).collect();
    let walls: Vec<f64> = fits.iter().map(|f| f.wall_s).collect();
    let max = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
    let p = fits.first().map_or(0, |f| {
        f.params.iter().filter(|q| q.key != "time_shift").count()
    });
    let cores: Vec<f64> = fits
        .iter()
        .filter_map(|f| f.cpu_s.map(|c| c / f.wall_s))
        .collect();
    let _ = writeln!(
        out,
        "| {name} | {p}{} | {} | {} / {} | {} / {} | {} |",
        if fits.first().is_some_and(|f| f.misfit_kind == "trace") {
            " + time shift"
        } else {
            ""
        },
        fits.len(),
        sig(median(&runs), 3),
        sig(max(&runs), 3),
        secs(median(&walls)),
        secs(max(&walls)),
        if cores.is_empty() {
            "–".to_string()
        } else {
            sig(median(&cores), 2)
        }
    );
}

pub(super) fn cost_section(st: &Study, rows: &mut Vec<Row>, out: &mut String) {
    out.push_str("## 4. The cost of each fit\n\n");
    out.push_str(
        "| fits | parameters | fits | runs: median / largest | wall: median / largest | cores \
         used (median CPU / wall) |\n|---|---|---|---|---|---|\n",
    );
    for run in &st.coverage {
        cost_rows(
            &format!("set {} ({})", run.case.id, run.case.title),
            &run.fits,
            out,
        );
    }
    cost_rows("widths, events misfit", &st.width.events, out);
    cost_rows("widths, trace misfit", &st.width.trace, out);
    let mut singles = vec![("", &st.first_slip)];
    if let Some(f) = &st.first_slip_staged {
        singles.push((", staged", f));
    }
    singles.push(("", &st.viscous));
    for (how, f) in singles {
        if let Some(first) = &f.first_stage {
            cost_rows(
                &format!("{}{how}: first stage", f.case.title),
                std::slice::from_ref(first),
                out,
            );
        }
        cost_rows(
            &format!(
                "{}{how}{}",
                f.case.title,
                if f.first_stage.is_some() {
                    ": second stage"
                } else {
                    ""
                }
            ),
            std::slice::from_ref(&f.summary),
            out,
        );
    }
    out.push('\n');
    if let Some(a) = st.coverage.iter().find(|c| c.case.id == "A") {
        let (med, max, over) = measures::wall_times(&a.fits, FIG2_FIT_TARGET_S);
        let pass = med <= FIG2_FIT_TARGET_S;
        let nodes = a.case.nodes();
        let _ = writeln!(
            out,
            "**Target: a {}-parameter event fit of fig2 at N = {nodes} ({} of trace) within {} \
             on {} cores.** Over set A's {} fits: median {}, largest {}, {} over the target: \
             **{}** (the verdict is the median's; the largest is the busiest moment of a shared \
             host).\n",
            a.case.truth.len(),
            stickslip_report::fmt::time(a.case.end_s, 2),
            secs(FIG2_FIT_TARGET_S),
            st.host.jobs,
            a.fits.len(),
            secs(med),
            secs(max),
            over,
            verdict(pass)
        );
        rows.push(Row {
            item: format!(
                "4. fig2 event fit, {} parameters, N = {nodes}",
                a.case.truth.len()
            ),
            target: format!("≤ {}", secs(FIG2_FIT_TARGET_S)),
            measured: format!("median {}, largest {}", secs(med), secs(max)),
            verdict: verdict(pass).into(),
        });
    }
    let f = &st.first_slip;
    let pass = f.summary.wall_s <= FIRST_SLIP_TARGET_S;
    let nodes = f.case.nodes();
    let _ = writeln!(
        out,
        "**Target: a {}-parameter fit of the SFA contact's first slip at N = {nodes} within \
         {}.** The fit of {} ({} events in the data, {} samples): {} runs, {}: **{}**.\n",
        f.case.truth.len(),
        secs(FIRST_SLIP_TARGET_S),
        f.case
            .truth
            .iter()
            .map(|(k, _)| format!("`{k}`"))
            .collect::<Vec<_>>()
            .join(", "),
        f.summary.data_events,
        f.case.samples,
        f.summary.evaluations,
        secs(f.summary.wall_s),
        verdict(pass)
    );
    rows.push(Row {
        item: format!(
            "4. SFA first slip, {} parameters, N = {nodes}",
            f.case.truth.len()
        ),
        target: format!("≤ {}", secs(FIRST_SLIP_TARGET_S)),
        measured: secs(f.summary.wall_s),
        verdict: verdict(pass).into(),
    });
    truth_row(rows, "4. SFA first slip, direct fit", f);
    single_table(f, out);
    let _ = writeln!(
        out,
        "![the first slip's direct fit: data, model and residual]({})\n\nWhat to see: the \
         data and the fitted model over the meltings (from a quarter of their span before the \
         first onset) with the events' onsets and peaks, and the residual against ±2σF (the \
         curves thinned to each time bucket's extremes for the record).\n",
        crate::report::FIRST_SLIP_SVG
    );
    if let Some(g) = &st.first_slip_staged {
        out.push_str("### The first slip, staged\n\n");
        let _ = writeln!(
            out,
            "The same trace fitted as a user would stage it: first {} alone from the scene's \
             own values (the other parameters held at the scene's), then all {} from the values \
             the first stage found.\n",
            g.first_stage
                .as_ref()
                .map(|s| {
                    s.params
                        .iter()
                        .map(|p| format!("`{}`", p.key))
                        .collect::<Vec<_>>()
                        .join(" and ")
                })
                .unwrap_or_default(),
            g.case.truth.len()
        );
        let pass = g.summary.wall_s <= FIRST_SLIP_TARGET_S;
        rows.push(Row {
            item: format!(
                "4. SFA first slip, staged: its {}-parameter stage",
                g.case.truth.len()
            ),
            target: format!("≤ {}", secs(FIRST_SLIP_TARGET_S)),
            measured: format!(
                "{} (both stages {})",
                secs(g.summary.wall_s),
                secs(g.summary.wall_s + g.first_stage.as_ref().map_or(0.0, |s| s.wall_s))
            ),
            verdict: verdict(pass).into(),
        });
        truth_row(rows, "4. SFA first slip, staged fit", g);
        single_table(g, out);
        let _ = writeln!(
            out,
            "![the first slip's staged fit]({})\n\nWhat to see: as for the direct fit.\n",
            crate::report::FIRST_SLIP_STAGED_SVG
        );
    }
}

/// A summary row: whether every 95 % interval of a single fit holds the truth.
fn truth_row(rows: &mut Vec<Row>, item: &str, f: &SingleFit) {
    // A parameter at a bound of the box, or one the fit leaves unidentified, is reported apart:
    // a Gaussian interval there proves nothing, so it neither passes nor fails the target.
    let judged: Vec<_> = f
        .summary
        .params
        .iter()
        .filter(|p| crate::measures::excluded(&f.summary, &p.key).is_none())
        .collect();
    let left_out: Vec<String> = f
        .summary
        .params
        .iter()
        .filter_map(|p| {
            crate::measures::excluded(&f.summary, &p.key).map(|e| {
                format!(
                    "{} {}",
                    short(&p.key),
                    match e {
                        crate::measures::Excluded::AtBound => "at a bound",
                        crate::measures::Excluded::Unidentified => "unidentified",
                    }
                )
            })
        })
        .collect();
    let held = judged.iter().filter(|p| p.covers() == Some(true)).count();
    let n = judged.len();
    rows.push(Row {
        item: format!("{item}: truth within the 95 % intervals"),
        target: format!("{n} of {n} judged"),
        measured: format!(
            "{held} of {n} (χ² {} against the truth's {}){}",
            sig(f.summary.chi2, 3),
            f.summary.chi2_truth.map_or("–".into(), |c| sig(c, 3)),
            if left_out.is_empty() {
                String::new()
            } else {
                format!("; left out: {}", left_out.join(", "))
            }
        ),
        verdict: verdict(n > 0 && held == n).into(),
    });
}

/// A single fit's parameters against the truth (and its first stage's, when staged).
fn single_table(f: &SingleFit, out: &mut String) {
    if let Some(first) = &f.first_stage {
        let _ = writeln!(
            out,
            "First stage: {}; χ² = {} (the true model's on the same data: {}), {} runs, {}.\n\n\
             Second stage:\n",
            first
                .params
                .iter()
                .map(|p| format!(
                    "`{}` = {} from {}",
                    p.key,
                    val(p.value, &p.unit),
                    p.initial.map_or("–".into(), |v| sig(v, 4))
                ))
                .collect::<Vec<_>>()
                .join(", "),
            sig(first.chi2, 4),
            first.chi2_truth.map_or("–".into(), |x| sig(x, 4)),
            first.evaluations,
            secs(first.wall_s)
        );
    }
    out.push_str(
        "| parameter | true | fitted | 95 % interval | holds the truth |\n|---|---|---|---|---|\n",
    );
    for p in &f.summary.params {
        let _ = writeln!(
            out,
            "| `{}` | {} | {} {} | [{}, {}] | {} |",
            p.key,
            val(p.truth, &p.unit),
            sig(p.value, 7),
            p.unit,
            p.lo95.map_or("–".into(), |v| sig(v, 7)),
            p.hi95.map_or("–".into(), |v| sig(v, 7)),
            match (crate::measures::excluded(&f.summary, &p.key), p.covers()) {
                (Some(crate::measures::Excluded::AtBound), _) => "at a bound: left out",
                (Some(crate::measures::Excluded::Unidentified), _) => "unidentified: left out",
                (None, Some(true)) => "yes",
                (None, Some(false)) => "no",
                (None, None) => "undetermined",
            }
        );
    }
    let s = &f.summary;
    let _ = writeln!(
        out,
        "\nχ² = {} over {} residuals (s = {}; the true model's χ² on the same data: {}), {} \
         events in the data and {} in the model, {} local iterations ({}), {} runs ({} \
         failed); the solver's noise at the optimum {} residual units.{}\n",
        sig(s.chi2, 4),
        s.residuals,
        s.residual_sigma.map_or("–".into(), |x| sig(x, 3)),
        s.chi2_truth.map_or("–".into(), |x| sig(x, 4)),
        s.data_events,
        s.model_events,
        s.iterations,
        if s.converged {
            "converged"
        } else {
            "not converged"
        },
        s.evaluations,
        s.failed_runs,
        s.solver_noise.map_or("–".into(), |x| sig(x, 3)),
        if s.unidentified.is_empty() {
            " The fit names no undetermined combination.".to_string()
        } else {
            format!(
                " The fit names as undetermined: {}.",
                s.unidentified
                    .iter()
                    .map(|u| format!("\"{u}\""))
                    .collect::<Vec<_>>()
                    .join("; ")
            )
        }
    );
}

pub(super) fn viscous_section(st: &Study, rows: &mut Vec<Row>, out: &mut String) {
    let f = &st.viscous;
    out.push_str("## 5. The damped, viscous SFA contact\n\n");
    let _ = writeln!(
        out,
        "The SFA contact with a dashpot on the drive (`drive.damping` = {} N·s/m, known) and \
         a viscous film, fitted for {}; the target: each 95 % interval holds the truth.\n",
        stickslip_run::scene::overrides::value_in(
            stickslip_run::keys::drive::DAMPING.path,
            &f.case.settings,
        )
        .and_then(|v| v.as_float())
        .map_or("–".into(), |v| sig(v, 4)),
        f.case
            .truth
            .iter()
            .map(|(k, _)| format!("`{k}`"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    if f.first_stage.is_some() {
        let d = &st.first_slip.summary;
        let _ = writeln!(
            out,
            "Staged as the first slip's staged fit is (the direct fit of the first slip ends at \
             χ² = {} against the true model's {}).\n",
            sig(d.chi2, 3),
            d.chi2_truth.map_or("–".into(), |c| sig(c, 3))
        );
    }
    single_table(f, out);
    truth_row(rows, "5. damped, viscous SFA", f);
    let _ = writeln!(
        out,
        "![the damped, viscous contact's fit]({})\n\nWhat to see: as for the first slip.\n",
        crate::report::VISCOUS_SVG
    );
}
