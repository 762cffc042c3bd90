//! Section 8 of the report, spatial convergence at the user's scale: the first onset and its
//! peak force of three contacts on the uniform and the edge-graded grids (tables with
//! observed orders and extrapolations), the references, the targets' verdicts, and Figure 8
//! (`convergence_grid.svg`: the total error of every (grid, N, tolerance) against its cost,
//! with the cheapest setting per error named in the text).

use super::{header, row};
use crate::grid_study::{
    DEFAULT_POWER, GridKind, GridRun, GridScene, GridStudy, OBSERVABLES, reference, sequence_run,
};
use std::fmt::Write as _;
use stickslip_report::fmt::sig;
use stickslip_report::palette::PALETTE;
use stickslip_report::plot::{Marker, Panel, Series, render_svg};

/// The graded grid with the default exponent.
const DEFAULT: GridKind = GridKind::Graded {
    power: DEFAULT_POWER,
};

/// The observable in the unit the tables print: onsets in s (ns for fig2), forces in N.
fn shown(scene: &GridScene, observable: &str, v: f64) -> String {
    match (scene.name.as_str(), observable) {
        ("fig2", "t_onset") => sig(v * 1e9, 12),
        (_, "t_onset") => sig(v, 9),
        _ => sig(v, 8),
    }
}

fn unit(scene: &GridScene, observable: &str) -> &'static str {
    match (scene.name.as_str(), observable) {
        ("fig2", "t_onset") => "ns",
        (_, "t_onset") => "s",
        _ => "N",
    }
}

/// An error in the table's unit.
fn shown_error(scene: &GridScene, observable: &str, e: f64) -> String {
    match (scene.name.as_str(), observable) {
        ("fig2", "t_onset") => sig(e * 1e9, 2),
        _ => sig(e, 2),
    }
}

/// Writes "## 8. Spatial convergence at the user's scale".
pub(super) fn section(md: &mut String, g: &GridStudy) {
    let s = &g.settings;
    let _ = writeln!(md, "## 8. Spatial convergence at the user's scale\n");
    let _ = writeln!(
        md,
        "The first onset and the peak force before it, on the paper's uniform grid \
         r_i = i·a0/N and on the edge-graded one r_i = a0·(1 − (1 − i/N)^p) (`contact.grid = \
         \"graded\"`, docs/model.md \"The radial grid\"), for {} contacts: {}. Each run stops \
         at its first event. The spatial sequences double N ({:?} uniform, {:?} graded with p \
         = {:?}) at a tolerance small enough that the time error is far below the spatial one; \
         the reference is the graded grid's (p = {DEFAULT_POWER}) Celik extrapolation from its \
         finest three N, corrected by the tolerance extrapolation at that N (tolerance ×100, \
         ×10, ×1). Its uncertainty adds the two GCIs and the distance to the uniform grid's own \
         extrapolation, an independent sequence. The study took {} s. The graded grid meets the \
         accuracy targets below and is the accurate scheme's default grid (p = 3 from N = 10 nodes \
         on): the whole-simulation runs of sections 2–7 use it, while section 1 studies the \
         operators on the uniform grid, as the literal scheme uses it.\n",
        s.scenes.len(),
        s.scenes
            .iter()
            .map(|c| format!("`{}` ({}, tolerance {:e})", c.name, c.file, c.tolerance))
            .collect::<Vec<_>>()
            .join(", "),
        s.uniform_nodes,
        s.graded_nodes,
        s.powers,
        sig(g.wall_s, 3)
    );
    targets(md, g);
    for scene in &s.scenes {
        scene_tables(md, g, scene);
    }
    cheapest(md, g);
}

fn targets(md: &mut String, g: &GridStudy) {
    if g.targets.is_empty() {
        return;
    }
    let met = g.targets.iter().filter(|t| t.met).count();
    let _ = writeln!(
        md,
        "**Targets at N = 200 on the graded grid: {met} of {} met.**\n",
        g.targets.len()
    );
    header(md, &["target", "asks", "measured", "bound", "verdict"]);
    for t in &g.targets {
        row(
            md,
            &[
                t.name.clone(),
                t.asks.clone(),
                sig(t.measured, 3),
                sig(t.bound, 3),
                if t.met { "met" } else { "**not met**" }.to_string(),
            ],
        );
    }
    let _ = writeln!(md);
}

fn scene_tables(md: &mut String, g: &GridStudy, scene: &GridScene) {
    let _ = writeln!(md, "### `{}`\n", scene.name);
    for (observable, _) in OBSERVABLES {
        let Some(rf) = reference(&g.references, &scene.name, observable) else {
            continue;
        };
        let u = unit(scene, observable);
        let _ = writeln!(
            md,
            "**{}**: reference {} ± {} {u} (the uniform grid's own extrapolation: {} {u}; \
             tolerance correction {} {u}).\n",
            if observable == "t_onset" {
                "First onset"
            } else {
                "Peak force"
            },
            shown(scene, observable, rf.value),
            shown_error(scene, observable, rf.uncertainty),
            rf.uniform_extrapolated
                .map_or("–".into(), |v| shown(scene, observable, v)),
            shown_error(scene, observable, rf.tolerance_correction),
        );
        let grids: Vec<GridKind> = std::iter::once(GridKind::Uniform)
            .chain(
                g.settings
                    .powers
                    .iter()
                    .map(|&power| GridKind::Graded { power }),
            )
            .collect();
        let mut columns = vec!["N".to_string()];
        for grid in &grids {
            columns.push(format!("{} ({u})", grid.label()));
            columns.push(format!("{} error ({u})", grid.label()));
            columns.push(format!("{} order", grid.label()));
        }
        header(md, &columns);
        let mut all_nodes: Vec<usize> = g
            .settings
            .uniform_nodes
            .iter()
            .chain(&g.settings.graded_nodes)
            .copied()
            .collect();
        all_nodes.sort_unstable();
        all_nodes.dedup();
        for &n in &all_nodes {
            let mut cells = vec![n.to_string()];
            for &grid in &grids {
                let seq = g.sequences.iter().find(|q| {
                    q.scene == scene.name && q.grid == grid && q.observable == observable
                });
                let value = seq.and_then(|q| {
                    q.nodes
                        .iter()
                        .position(|&m| m == n)
                        .map(|i| (i, q.values[i]))
                });
                match value {
                    Some((i, v)) => {
                        cells.push(shown(scene, observable, v));
                        cells.push(shown_error(scene, observable, (v - rf.value).abs()));
                        // The order of the triple centred on this level.
                        let order = i
                            .checked_sub(1)
                            .and_then(|j| seq.and_then(|q| q.orders.get(j).copied().flatten()));
                        cells.push(order.map_or("–".into(), |p| sig(p, 3)));
                    }
                    None => cells.extend(["".to_string(), String::new(), String::new()]),
                }
            }
            row(md, &cells);
        }
        let _ = writeln!(md);
    }
    // Where the first melting starts on each grid at N = 200.
    let r_first = |grid: GridKind| {
        sequence_run(&g.runs, scene, grid, 200)
            .and_then(|r| r.r_first_m)
            .map_or("–".into(), |r| sig(r * 1e6, 8))
    };
    let _ = writeln!(
        md,
        "The first melting starts at the outermost node: at N = 200, r_first = {} µm on the \
         uniform grid and {} µm on the graded one (p = {DEFAULT_POWER}).\n",
        r_first(GridKind::Uniform),
        r_first(DEFAULT)
    );
}

/// The total error of a cost point: |onset − reference| (s) and relative |f_peak − reference|.
fn total_errors(g: &GridStudy, r: &GridRun) -> Option<(f64, f64)> {
    let on = reference(&g.references, &r.scene, "t_onset")?;
    let fp = reference(&g.references, &r.scene, "f_peak")?;
    Some((
        (r.t_onset_s? - on.value).abs(),
        (r.f_peak_n? - fp.value).abs() / fp.value.abs(),
    ))
}

/// The cheapest cost point of `scene` whose onset error is within `rel` of the onset and whose
/// peak force is within `rel` relative.
fn cheapest_within<'a>(g: &'a GridStudy, scene: &GridScene, rel: f64) -> Option<&'a GridRun> {
    let on = reference(&g.references, &scene.name, "t_onset")?;
    g.runs
        .iter()
        .filter(|r| r.cost_point && r.scene == scene.name)
        .filter(|r| {
            total_errors(g, r)
                .is_some_and(|(e_on, e_fp)| e_on <= rel * on.value.abs() && e_fp <= rel)
        })
        .min_by(|a, b| a.wall_s.total_cmp(&b.wall_s))
}

fn cheapest(md: &mut String, g: &GridStudy) {
    let _ = writeln!(md, "### Total error against cost\n");
    let _ = writeln!(
        md,
        "Figure 8 (`convergence_grid.svg`): every (grid, N, tolerance) of N = {:?} × tolerance \
         = {:?} on the uniform grid and the graded one (p = {DEFAULT_POWER}), its first onset's \
         and peak force's distance to the reference (space and time together) against its wall \
         time (median of {} runs to the first event, in-process). The cheapest setting whose \
         first onset and peak force are both within a relative error:\n",
        g.settings.cost_nodes, g.settings.cost_tolerances, g.settings.repeats
    );
    header(
        md,
        &[
            "scene",
            "relative error",
            "cheapest: grid, N, tolerance",
            "wall (s)",
            "cheapest uniform",
            "wall (s)",
        ],
    );
    for scene in &g.settings.scenes {
        for rel in [1e-2, 1e-3, 1e-4, 1e-5] {
            let best = cheapest_within(g, scene, rel);
            let best_uniform = g
                .runs
                .iter()
                .filter(|r| r.cost_point && r.scene == scene.name && r.grid == GridKind::Uniform)
                .filter(|r| {
                    let on = reference(&g.references, &scene.name, "t_onset");
                    total_errors(g, r).is_some_and(|(e_on, e_fp)| {
                        on.is_some_and(|on| e_on <= rel * on.value.abs()) && e_fp <= rel
                    })
                })
                .min_by(|a, b| a.wall_s.total_cmp(&b.wall_s));
            let describe = |r: Option<&GridRun>| match r {
                Some(r) => (
                    format!("{}, {}, {:e}", r.grid.label(), r.nodes, r.tolerance),
                    sig(r.wall_s, 2),
                ),
                None => ("none in the grid".into(), "–".into()),
            };
            let (b, bw) = describe(best);
            let (u, uw) = describe(best_uniform);
            row(md, &[scene.name.clone(), format!("{rel:e}"), b, bw, u, uw]);
        }
    }
    let _ = writeln!(md);
}

/// Figure 8: total error against cost, one panel per scene and observable.
pub(super) fn figure(g: &GridStudy) -> Result<String, String> {
    let mut panels = Vec::new();
    for scene in &g.settings.scenes {
        for (observable, ylabel) in [
            ("t_onset", "|first onset − reference| / reference"),
            ("f_peak", "|f_peak − reference| / reference"),
        ] {
            let Some(rf) = reference(&g.references, &scene.name, observable) else {
                continue;
            };
            let mut p = Panel::new(
                &format!("{}: {observable}", scene.name),
                "wall time to the first event (s)",
                ylabel,
            )
            .log_log()
            .legend_outside();
            let grids = [GridKind::Uniform, DEFAULT];
            let mut colour = 0;
            for (gi, grid) in grids.iter().enumerate() {
                for &tol in &g.settings.cost_tolerances {
                    let (pts, labels): (Vec<(f64, f64)>, Vec<String>) = g
                        .runs
                        .iter()
                        .filter(|r| {
                            r.cost_point
                                && r.scene == scene.name
                                && r.grid == *grid
                                && (r.tolerance / tol - 1.0).abs() < 1e-9
                        })
                        .filter_map(|r| {
                            let v = if observable == "t_onset" {
                                r.t_onset_s
                            } else {
                                r.f_peak_n
                            }?;
                            let e = ((v - rf.value) / rf.value).abs().max(1e-13);
                            Some(((r.wall_s, e), r.nodes.to_string()))
                        })
                        .unzip();
                    if pts.is_empty() {
                        continue;
                    }
                    let s = Series::new(
                        format!("{}, tol {tol:e}", grid.label()),
                        pts,
                        PALETTE[colour % PALETTE.len()],
                    )
                    .labels(labels);
                    colour += 1;
                    p.series.push(if gi == 0 {
                        s.dashed().marker(Marker::Square)
                    } else {
                        s.marker(Marker::Circle)
                    });
                }
            }
            panels.push(p);
        }
    }
    render_svg(&panels, 2, 720, 430)
}
