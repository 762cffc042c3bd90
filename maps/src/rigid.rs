//! The rigid-drive map, speed × temperature (A0), and the critical speed on paper.
//!
//! **On paper.** After an event the node's strain is reset and φ regrows from the threshold
//! towards φ_eq = √(A/a): y = φ² grows logistically, dy/dt = 2λ·y·(1 − y/y_eq) with
//! λ = γ·A·b/a, so it reaches f²·y_eq after t_r = ln(f²(1 − y0)/((1 − f²)·y0))/(2λ),
//! y0 = (threshold/φ_eq)². Meanwhile the stamp loads the film again; the equilibrium
//! φ_eq(ε)² = (A/a)(1 − ε²/εc²) stays above f²·A/a only while ε ≤ √(1 − f²)·εc. A recovery
//! R ≥ f therefore needs t_r shorter than the time the stamp takes to advance that strain:
//! V_c = √(1 − f²)·εc·(h0 + C·a·f²·φ_eq²)/t_r, with f the stick–slip threshold (0.9). The
//! second term is the substrate's share of the advance: a film at φ under strain ε carries
//! τ = a·φ²·ε, and a flat punch under a mean stress τ sinks by C·τ, C = π·a0/(2G*), so the stamp
//! advances ε·(h0 + C·a·φ²) (the radial contact's stress is not uniform, its mean compliance is
//! the punch's). Without it (h0 alone) the estimate misses a drift with A0: the share grows
//! with φ_eq² ∝ A0 (0.04 to 0.4 on this map).

use crate::{Check, Map, Section};
use stickslip_report::fmt::sig;
use stickslip_report::map::panels;
use stickslip_report::palette::DARK;
use stickslip_report::plot::{Marker, Series};
use stickslip_run::ResolvedScene;
use stickslip_run::summary::Regime;
use stickslip_studies::boundary;
use stickslip_studies::sweep::refine::agreement;

const V: &str = stickslip_run::keys::drive::VELOCITY.path;
const A: &str = "temperature.A0";

/// Relative tolerance of the critical speeds found by bisection.
pub const BOUNDARY_RTOL: f64 = 1e-3;

/// The critical speed on paper for A0 = `a0` Pa with the scene's film and substrate (see the
/// module docs), m/s; `f` the recovery asked for; `substrate` false leaves the substrate's
/// share out (a rigid substrate).
#[must_use]
pub fn critical_speed(scene: &ResolvedScene, a0: f64, f: f64, substrate: bool) -> f64 {
    let l = &scene.config.lubricant;
    let b = l.b_pa();
    let lambda = l.gamma_per_pa_s * a0 * b / l.a_pa;
    let phi_eq_sq = a0 / l.a_pa;
    let thr = scene.config.melt_threshold;
    let y0 = thr * thr / phi_eq_sq;
    let t_r = (f * f * (1.0 - y0) / ((1.0 - f * f) * y0)).ln() / (2.0 * lambda);
    let c = &scene.config.contact;
    let share = if substrate && c.substrate == stickslip_core::config::Substrate::Elastic {
        std::f64::consts::PI * c.radius_m / (2.0 * c.g_eff_pa) * l.a_pa * f * f * phi_eq_sq
    } else {
        0.0
    };
    (1.0 - f * f).sqrt() * l.critical_strain(a0) * (c.film_thickness_m + share) / t_r
}

/// The speed at which a row's recovery falls through `f` (log-interpolated between the
/// bracketing points), if it does.
fn crossing(points: &[(f64, f64)], f: f64) -> Option<f64> {
    points.windows(2).find_map(|w| {
        let ((v1, r1), (v2, r2)) = (w[0], w[1]);
        (r1 >= f && r2 < f).then(|| (v1.ln() + (v2.ln() - v1.ln()) * (r1 - f) / (r1 - r2)).exp())
    })
}

/// The window of the finest grid that [`uniform_window`] runs: fine indices per axis (V0, A0),
/// where the map's boundaries cross its upper temperatures.
pub const UNIFORM_WINDOW: [(usize, usize); 2] = [(160, 224), (128, 192)];

/// The uniform sweep over [`UNIFORM_WINDOW`] of the refined map's finest grid, as a sweep file
/// (the refined file's base scene and `[set]`, no `[refine]`, the window's values listed exactly).
///
/// # Errors
/// If the refined map is not refined or its sweep file does not read.
pub fn uniform_window(map: &Map, file: &std::path::Path) -> Result<String, String> {
    let sweep = &map.json.sweep;
    if sweep.refine.is_none() {
        return Err("the rigid map is not refined".into());
    }
    let text = std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
    let mut table: toml::Table =
        toml::from_str(&text).map_err(|e| format!("{}: {e}", file.display()))?;
    table.remove("refine");
    // The window checks the refinement point by point; it needs no spot checks of its own.
    table.remove("verify");
    table.insert(
        "name".into(),
        "rigid-speed-temperature-uniform-window".into(),
    );
    table.insert(
        "scene".into(),
        sweep.scene_path.display().to_string().into(),
    );
    let window: Vec<Option<(usize, usize)>> = UNIFORM_WINDOW.iter().map(|w| Some(*w)).collect();
    let axes: Vec<toml::Value> = agreement::subgrid_axes(sweep, 1, &window)
        .into_iter()
        .map(toml::Value::Table)
        .collect();
    table.insert("axis".into(), toml::Value::Array(axes));
    toml::to_string(&table).map_err(|e| e.to_string())
}

/// The rigid map's section; `uniform` the sweep of [`uniform_window`].
///
/// # Errors
/// If the base scene does not resolve or the map has no numeric axis.
pub fn section(map: &Map, uniform: &Map) -> Result<Section, String> {
    let scene = map.base_scene()?;
    let rows = &map.json.table.rows;
    let th = map.json.thresholds;
    let f = th.stick_slip_recovery;
    let speeds = map.values(V);
    // The base grid's temperatures: their rows are complete (refinement adds points between
    // them and, near each boundary, along them).
    let mut temps: Vec<f64> = rows
        .iter()
        .filter(|r| r.level == 0)
        .map(|r| map.axis(r, A))
        .collect();
    temps.sort_by(f64::total_cmp);
    temps.dedup();
    let (v_lo, v_hi) = (speeds[0], speeds[speeds.len() - 1]);
    let mut checks = Vec::new();

    // A0 ≤ 0: sliding with F = 0.
    let cold: Vec<_> = rows.iter().filter(|r| map.axis(r, A) <= 0.0).collect();
    let sliding = cold
        .iter()
        .filter(|r| r.summary.regime == Regime::Sliding && r.summary.f_peak_first == Some(0.0))
        .count();
    checks.push(Check {
        claim: "A0 ≤ 0: the film is melted, `sliding`, F = 0".into(),
        measured: format!(
            "{sliding} of {} points with A0 ≤ 0 sliding with F = 0",
            cold.len()
        ),
        pass: sliding == cold.len() && !cold.is_empty(),
    });

    // Slow drive: stick–slip; fast drive: no recovery; the regimes follow in order.
    let warm: Vec<f64> = temps.iter().copied().filter(|&a| a > 0.0).collect();
    let row_of = |a0: f64| {
        let mut pts: Vec<_> = rows.iter().filter(|r| map.axis(r, A) == a0).collect();
        pts.sort_by(|x, y| map.axis(x, V).total_cmp(&map.axis(y, V)));
        pts
    };
    let slow_ss = warm
        .iter()
        .filter(|&&a| {
            row_of(a)
                .first()
                .is_some_and(|r| r.summary.regime == Regime::StickSlip)
        })
        .count();
    checks.push(Check {
        claim: format!(
            "slow drive (V0 = {} m/s): `stick_slip` for every A0 > 0",
            sig(v_lo, 2)
        ),
        measured: format!("{slow_ss} of {} rows", warm.len()),
        pass: slow_ss == warm.len(),
    });
    let fast_smooth = warm
        .iter()
        .filter(|&&a| {
            row_of(a)
                .last()
                .is_some_and(|r| r.summary.recovery.is_some_and(|x| x < th.smooth_recovery))
        })
        .count();
    let rank = |r: Regime| match r {
        Regime::StickSlip => 0,
        Regime::Partial => 1,
        Regime::Smooth => 2,
        _ => 3,
    };
    let out_of_order: usize = warm
        .iter()
        .map(|&a| {
            row_of(a)
                .windows(2)
                .filter(|w| rank(w[1].summary.regime) < rank(w[0].summary.regime))
                .count()
        })
        .sum();
    checks.push(Check {
        claim: format!(
            "fast drive (V0 = {} m/s): the film stops recovering (R < {}), regimes go \
             stick_slip → partial → smooth with speed",
            sig(v_hi, 2),
            th.smooth_recovery
        ),
        measured: format!(
            "R < {} in {fast_smooth} of {} rows; {out_of_order} steps against that order",
            th.smooth_recovery,
            warm.len()
        ),
        pass: fast_smooth == warm.len() && out_of_order == 0,
    });

    // Critical speed: on paper against the map.
    let mut ratios = Vec::new();
    let mut measured_pts = Vec::new();
    for &a0 in &warm {
        let pts: Vec<(f64, f64)> = row_of(a0)
            .iter()
            .map(|r| (map.axis(r, V), r.summary.recovery.unwrap_or(0.0)))
            .collect();
        if let Some(v) = crossing(&pts, f) {
            ratios.push((
                a0,
                v,
                critical_speed(&scene, a0, f, true),
                critical_speed(&scene, a0, f, false),
            ));
            measured_pts.push((v, a0));
        }
    }
    let span = |v: &[f64]| {
        v.iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                (a.min(x), b.max(x))
            })
    };
    let r: Vec<f64> = ratios.iter().map(|(_, m, p, _)| m / p).collect();
    let (rmin, rmax) = span(&r);
    let rigid_r: Vec<f64> = ratios.iter().map(|(_, m, _, q)| m / q).collect();
    let paper_ok = !r.is_empty() && rmin >= 1.0 / 1.5 && rmax <= 1.5 && rmax / rmin < 1.3;
    checks.push(Check {
        claim: format!(
            "critical speed: R falls through {f} near V_c = √(1 − f²)·εc·(h0 + C·a·f²·φ_eq²)/t_r \
             on paper (within a factor 1.5, same scaling with A0: ratio varying by < 30 %)"
        ),
        measured: format!(
            "map/paper = {} … {} over {} rows (A0 = {} … {} Pa)",
            sig(rmin, 3),
            sig(rmax, 3),
            r.len(),
            sig(warm[0], 3),
            sig(warm[warm.len() - 1], 3)
        ),
        pass: paper_ok,
    });

    // The same critical speed by bisection (`stickslip boundary`): inside the map's bracket.
    let mut bisected = Vec::new();
    for &a0 in &warm {
        let row = row_of(a0);
        let Some(k) = row.windows(2).position(|w| {
            w[0].summary.recovery.unwrap_or(0.0) >= f && w[1].summary.recovery.unwrap_or(0.0) < f
        }) else {
            continue;
        };
        let (lo, hi) = (map.axis(row[k], V), map.axis(row[k + 1], V));
        let scene = map
            .json
            .sweep
            .scene(row[0].point)
            .map_err(|e| e.to_string())?;
        let b = boundary::find(
            &scene,
            V,
            (v_lo, v_hi),
            BOUNDARY_RTOL,
            th,
            None,
            &mut |_| {},
        )
        .map_err(|e| e.to_string())?;
        let interpolated = crossing(
            &row.iter()
                .map(|r| (map.axis(r, V), r.summary.recovery.unwrap_or(0.0)))
                .collect::<Vec<_>>(),
            f,
        )
        .unwrap_or(f64::NAN);
        bisected.push((a0, b, (lo, hi), interpolated));
    }
    // Inside the map's bracket to the bisection's own resolution: its final bracket
    // [below, above] (relative width ≤ BOUNDARY_RTOL) meets the map's. Where the map's
    // recovery at a grid speed lies within numerical noise of the threshold, the midpoint
    // alone may fall a hair outside (1 of 10 rows, 0.0015 from the crossing, once).
    let inside = bisected
        .iter()
        .filter(|(_, b, (lo, hi), _)| b.below.value <= *hi && b.above.value >= *lo)
        .count();
    let worst_rel = bisected
        .iter()
        .map(|(_, b, _, x)| (b.value / x - 1.0).abs())
        .fold(0.0_f64, f64::max);
    let runs_max = bisected.iter().map(|(_, b, ..)| b.runs).max().unwrap_or(0);
    checks.push(Check {
        claim: format!(
            "`stickslip boundary` (bisection to {BOUNDARY_RTOL}) finds the end of stick–slip \
             between the two speeds where the map's recovery crosses {f} (its final bracket \
             meets theirs), in every row"
        ),
        measured: format!(
            "{inside} of {} rows; at most {} from the log-interpolated crossing; at most \
             {runs_max} runs each",
            bisected.len(),
            sig(worst_rel, 2)
        ),
        pass: !bisected.is_empty() && inside == bisected.len(),
    });

    // The refinement against the uniform grid at its finest spacing, on a window.
    let refine = map
        .json
        .sweep
        .refine
        .as_ref()
        .ok_or("the rigid map is not refined")?;
    let agree = agreement::agreement(
        &map.json.sweep,
        refine,
        rows,
        &uniform.json.sweep,
        &uniform.json.table.rows,
    );
    checks.push(Check {
        claim: "refinement finds the boundaries a uniform grid shows: on a window of the uniform \
                grid at the finest spacing, every point the refined map ran has the same regime, \
                and the points it did not run lie in cells of their own regime"
            .into(),
        measured: format!(
            "{} uniform points: {} shared ({} differ), {} inside refined cells ({} differ), {} \
             off the grid",
            agree.compared,
            agree.shared,
            agree.shared_differ.len(),
            agree.inferred,
            agree.inferred_differ.len(),
            agree.off_grid
        ),
        pass: agree.compared > 0
            && agree.off_grid == 0
            && agree.shared_differ.is_empty()
            && agree.inferred_differ.is_empty(),
    });

    // Figure: regimes and recovery, the paper's curve and the map's crossings on both.
    let mut figure = panels(&map.json, "recovery")?;
    let a_hi = temps[temps.len() - 1];
    let curve: Vec<(f64, f64)> = (0..=60)
        .map(|i| warm[0] + (a_hi - warm[0]) * f64::from(i) / 60.0)
        .map(|a| (critical_speed(&scene, a, f, true), a))
        .filter(|(v, _)| *v >= v_lo && *v <= v_hi)
        .collect();
    for p in &mut figure {
        p.series
            .push(Series::new("V_c on paper", curve.clone(), DARK).dashed());
        p.series.push(
            Series::new(format!("R = {f} on the map"), measured_pts.clone(), DARK)
                .points()
                .marker(Marker::Triangle),
        );
    }
    let (uv, ua) = (uniform.values(V), uniform.values(A));
    let counts = map.json.table.regime_counts();
    let count = |r: Regime| counts.get(&r).copied().unwrap_or(0);
    let table: String = ratios
        .iter()
        .map(|(a0, m, p, q)| {
            format!(
                "| {} | {} | {} | {} | {} |\n",
                sig(*a0, 3),
                sig(*p, 3),
                sig(*m, 3),
                sig(m / p, 3),
                sig(m / q, 3)
            )
        })
        .collect();
    let text = format!(
        "The base scene is `{}` with a rigid coupler X = V0·t, N = {} nodes, stopped after {} \
         events have ended or when an event stays open for {} s (the film has not recovered). \
         Axes: V0 = {} … {} m/s ({} values, log) and A0 = {} … {} Pa ({} values), refined {} \
         times where neighbouring points differ in regime: {} points of the {} × {} uniform grid \
         of the finest spacing ({} %), each drawn as its level's cell. Regimes over the {} \
         points: {} sliding, {} stick_slip, {} partial, {} smooth, {} transient. A window of \
         that uniform grid ({} × {} points: V0 = {} … {} m/s, A0 = {} … {} Pa) checks the \
         refinement point by point.\n\n\
         What to see: below A0 = 0 the film is molten and slides (F = 0). Above, slow drives \
         stick and slip with the film fully re-solidified between events (R ≈ 1); as V0 grows \
         the cycle, about εc·h0/V0 long, becomes shorter than the film's regrowth, R falls, \
         and the regime turns `partial`, then `smooth`. Colder films (smaller A0: smaller εc, \
         slower kinetics λ = γAb/a) lose recovery at lower speed. The dashed line is the \
         critical speed on paper (the module docs of `maps/src/rigid.rs`: the film must \
         regrow to f·φ_eq, f = {f}, before the reloading strain pushes φ_eq(ε) below it, while \
         the substrate takes its share of the stamp's advance), the triangles where the map's \
         recovery crosses f (log-interpolated between points, which the refinement puts a \
         finest step apart):\n\n\
         | A0 [Pa] | V_c on paper [m/s] | on the map [m/s] | map/paper | map/paper without the \
         substrate's share |\n|---|---|---|---|---|\n{table}\n\
         The estimate follows the map's A0 dependence (V_c ∝ A0^(3/2)/ln A0, with the \
         substrate's share growing ∝ A0) with ratios {} … {}. Without the substrate's share the \
         ratios drift from {} to {} with A0: the coarse map (before its refinement) hid that \
         drift within its interpolation between speeds a factor 1.7 apart.",
        map.scene_file(),
        scene.config.contact.nodes,
        scene.max_events.unwrap_or(0),
        scene.max_open_event_s.map_or("–".into(), |t| sig(t, 2)),
        sig(v_lo, 2),
        sig(v_hi, 2),
        refine.base[0],
        sig(temps[0], 3),
        sig(a_hi, 3),
        refine.base[1],
        refine.levels,
        rows.len(),
        speeds.len(),
        map.values(A).len(),
        sig(
            100.0 * rows.len() as f64 / (speeds.len() * map.values(A).len()) as f64,
            2
        ),
        rows.len(),
        count(Regime::Sliding),
        count(Regime::StickSlip),
        count(Regime::Partial),
        count(Regime::Smooth),
        count(Regime::Transient),
        uv.len(),
        ua.len(),
        sig(uv[0], 3),
        sig(uv[uv.len() - 1], 3),
        sig(ua[0], 3),
        sig(ua[ua.len() - 1], 3),
        sig(rmin, 3),
        sig(rmax, 3),
        sig(rigid_r.first().copied().unwrap_or(f64::NAN), 3),
        sig(rigid_r.last().copied().unwrap_or(f64::NAN), 3),
    );
    Ok(Section {
        title: "Rigid drive: speed × temperature".into(),
        text,
        figure: ("maps_rigid.svg".into(), figure),
        checks,
    })
}
