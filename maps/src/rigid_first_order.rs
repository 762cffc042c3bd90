//! The first-order film under the rigid drive: melting strain ε₊ × drive speed, on the
//! homogeneous one-node contact (docs/model.md#the-first-order-film).
//!
//! **On paper: the advance per cycle.** With the stamp X = V0·t and a one-node film whose
//! substrate takes u3D = C·τ (C = π·a0/(2G*), τ = a·φ²·ε), the film's strain is
//! ε = u0/(h0 + C·a·φ²), u0 the stamp's advance since the film last re-solidified. Loaded
//! slowly, the film follows its solid branch, a·ε(φ)² = A' + b₃·φ − b·φ² (A' = A·b/a), from
//! φ₊(0) down; u0(φ) = ε(φ)·(h0 + C·a·φ²) first grows and then, near the fold at
//! φ = b₃/(2b), falls. The branch can be followed only up to the largest u0: beyond it no
//! solid state carries the stamp's advance and the film melts. So the quasi-static advance per
//! cycle is X* = max over the branch of ε(φ)·(h0 + C·a·φ²) ≥ ε₊·h0 — a stiff substrate
//! (C → 0) gives ε₊·h0, a soft one melts the film below ε₊ but after a longer advance. At a
//! finite speed the film lags behind the branch near its end: the delayed passage through a
//! fold, whose overshoot grows as the loading rate to the power 2/3.
//!
//! **The loss of recovery.** After a melting the first-order film's liquid is stable as soon
//! as the strain passes ε₋ = εc, which does not depend on b₃: the film must regrow before the
//! stamp has moved about εc·h0 again, or it stays liquid. Unlike the second-order film, whose
//! φ regrows towards a lowered equilibrium as far as the reloading allows (a range of
//! `partial` speeds), the first-order film either escapes the liquid or does not: recovery
//! collapses at one speed.

use crate::{Check, Map, Section};
use stickslip_report::fmt::sig;
use stickslip_report::map::panels;
use stickslip_report::palette::DARK;
use stickslip_report::plot::{Marker, Series};
use stickslip_report::stats::log_log_slope;
use stickslip_run::ResolvedScene;
use stickslip_run::summary::Regime;
use stickslip_studies::boundary::{self, Boundary};

const E: &str = stickslip_run::keys::lubricant::EPS_MELT.path;
const V: &str = stickslip_run::keys::drive::VELOCITY.path;

/// Relative tolerance of the critical speeds found by bisection.
pub const BOUNDARY_RTOL: f64 = 1e-3;
/// Largest lag asked of the slowest speed's advance over X* (relative). Reason: the delayed
/// passage through the fold overshoots by ∝ (V0/h0 / (γ·A'))^(2/3) ≈ (1e4/3e7)^(2/3) ≈ 5e-3
/// at V0 = 1e-3 m/s; 2 % leaves room for the prefactor, while the substrate's share that X*
/// accounts for is 14–300 % of ε₊·h0 on this map.
pub const MAX_SLOW_LAG: f64 = 0.02;
/// The fold's delay law: the lag's exponent in V0, 2/3, to within this.
pub const LAG_EXPONENT_TOL: f64 = 0.1;

/// The quasi-static advance per cycle X* (m) of the module docs, and the φ where it is taken.
#[must_use]
pub fn quasi_static_advance(scene: &ResolvedScene) -> (f64, f64) {
    let c = &scene.config;
    let l = &c.lubricant;
    let a0 = c.temperature.a_coeff_pa(0.0);
    let (a, b, b3) = (l.a_pa, l.b_pa(), l.cubic_pa);
    let ap = a0 * b / a;
    let h0 = c.contact.film_thickness_m;
    let compliance = if c.contact.substrate == stickslip_core::config::Substrate::Rigid {
        0.0
    } else {
        std::f64::consts::PI * c.contact.radius_m / (2.0 * c.contact.g_eff_pa)
    };
    let u0 = |phi: f64| {
        let e2 = (ap + b3 * phi - b * phi * phi) / a;
        e2.max(0.0).sqrt() * (h0 + compliance * a * phi * phi)
    };
    let lo = b3 / (2.0 * b);
    let hi = l.solid_phi(0.0, a0);
    // The branch's u0 has one maximum: a fine scan, then golden sections around the best.
    let n = 4000;
    let best = (0..=n)
        .map(|i| lo + (hi - lo) * f64::from(i) / f64::from(n))
        .max_by(|x, y| u0(*x).total_cmp(&u0(*y)))
        .unwrap_or(lo);
    let step = (hi - lo) / f64::from(n);
    let (mut x0, mut x1) = ((best - step).max(lo), (best + step).min(hi));
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..80 {
        let (p, q) = (x1 - g * (x1 - x0), x0 + g * (x1 - x0));
        if u0(p) > u0(q) {
            x1 = q;
        } else {
            x0 = p;
        }
    }
    let phi = 0.5 * (x0 + x1);
    (u0(phi), phi)
}

/// The critical speed of `scene` between `lo` and `hi` by bisection.
fn critical_speed(scene: &ResolvedScene, lo: f64, hi: f64) -> Result<Boundary, String> {
    boundary::find(
        scene,
        V,
        (lo, hi),
        BOUNDARY_RTOL,
        stickslip_run::summary::RegimeThresholds::default(),
        None,
        &mut |_| {},
    )
    .map_err(|e| e.to_string())
}

/// The first-order rigid map's section.
///
/// # Errors
/// If a scene does not resolve or a critical speed cannot be bracketed.
#[allow(clippy::too_many_lines)]
pub fn section(map: &Map) -> Result<Section, String> {
    let rows = &map.json.table.rows;
    let strains = map.values(E);
    let speeds = map.values(V);
    let (v_lo, v_hi) = (speeds[0], speeds[speeds.len() - 1]);
    let row_of = |e: f64| {
        let mut pts: Vec<_> = rows.iter().filter(|r| map.axis(r, E) == e).collect();
        pts.sort_by(|x, y| map.axis(x, V).total_cmp(&map.axis(y, V)));
        pts
    };
    // The resolved scene of a row's first point.
    let scene_of_row = |e: f64| -> Result<ResolvedScene, String> {
        let first = rows
            .iter()
            .find(|r| map.axis(r, E) == e)
            .ok_or("an ε₊ row without points")?;
        map.json.sweep.scene(first.point).map_err(|x| x.to_string())
    };
    let mut checks = Vec::new();

    // Slow drive: stick–slip in every row.
    let slow_ss = strains
        .iter()
        .filter(|&&e| {
            row_of(e)
                .first()
                .is_some_and(|r| r.summary.regime == Regime::StickSlip)
        })
        .count();
    checks.push(Check {
        claim: format!(
            "slow drive (V0 = {} m/s): `stick_slip` for every ε₊",
            sig(v_lo, 2)
        ),
        measured: format!("{slow_ss} of {} rows", strains.len()),
        pass: slow_ss == strains.len(),
    });

    // The advance per cycle at the slowest speeds against X*, and the fold's 2/3 law.
    let mut advance = Vec::new();
    for &e in &strains {
        let scene = scene_of_row(e)?;
        let (x_star, phi_star) = quasi_static_advance(&scene);
        let h0 = scene.config.contact.film_thickness_m;
        let lags: Vec<(f64, f64)> = row_of(e)
            .iter()
            .take(3)
            .filter_map(|r| Some((map.axis(r, V), r.summary.x_period_last? / x_star - 1.0)))
            .collect();
        advance.push((e, x_star, phi_star, x_star / (e * h0), lags));
    }
    let slow_lag: Vec<f64> = advance
        .iter()
        .filter_map(|(.., lags)| lags.first().map(|l| l.1))
        .collect();
    let (lag_min, lag_max) = slow_lag
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    let exponents: Vec<f64> = advance
        .iter()
        .filter(|(.., lags)| lags.len() == 3 && lags.iter().all(|l| l.1 > 0.0))
        .map(|(.., lags)| log_log_slope(lags))
        .collect();
    let (exp_min, exp_max) = exponents
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    checks.push(Check {
        claim: format!(
            "slow drive: the stamp advances X* = max over the solid branch of ε(φ)·(h0 + C·a·φ²) \
             per cycle (the largest advance a solid film carries), plus a lag ≥ 0 of at most \
             {MAX_SLOW_LAG} at V0 = {} m/s",
            sig(v_lo, 2)
        ),
        measured: format!(
            "x_period_last/X* − 1 = {} … {} over {} rows (X*/(ε₊·h0) = {} … {})",
            sig(lag_min, 2),
            sig(lag_max, 2),
            slow_lag.len(),
            sig(advance.first().map_or(f64::NAN, |a| a.3), 3),
            sig(advance.last().map_or(f64::NAN, |a| a.3), 3),
        ),
        pass: slow_lag.len() == strains.len() && lag_min >= 0.0 && lag_max <= MAX_SLOW_LAG,
    });
    checks.push(Check {
        claim: format!(
            "the lag is a fold's delay: it grows as V0^(2/3) (exponent within \
             {LAG_EXPONENT_TOL}, fitted over the three slowest speeds)"
        ),
        measured: format!(
            "exponent {} … {} over {} rows",
            sig(exp_min, 3),
            sig(exp_max, 3),
            exponents.len()
        ),
        pass: exponents.len() == strains.len()
            && (exp_min - 2.0 / 3.0).abs() <= LAG_EXPONENT_TOL
            && (exp_max - 2.0 / 3.0).abs() <= LAG_EXPONENT_TOL,
    });

    // Fast drive and an abrupt loss of recovery.
    let rank = |r: Regime| match r {
        Regime::StickSlip => 0,
        Regime::Partial => 1,
        Regime::Smooth => 2,
        _ => 3,
    };
    let fast_not_ss = strains
        .iter()
        .filter(|&&e| {
            row_of(e)
                .last()
                .is_some_and(|r| r.summary.regime != Regime::StickSlip)
        })
        .count();
    let out_of_order: usize = strains
        .iter()
        .map(|&e| {
            row_of(e)
                .windows(2)
                .filter(|w| rank(w[1].summary.regime) < rank(w[0].summary.regime))
                .count()
        })
        .sum();
    let partial_max = strains
        .iter()
        .map(|&e| {
            row_of(e)
                .iter()
                .filter(|r| r.summary.regime == Regime::Partial)
                .count()
        })
        .max()
        .unwrap_or(0);
    checks.push(Check {
        claim: format!(
            "fast drive (V0 = {} m/s): no stick–slip; regimes go stick_slip → partial → smooth \
             with speed, and the loss of recovery is abrupt (at most one `partial` speed per row)",
            sig(v_hi, 2)
        ),
        measured: format!(
            "not stick_slip in {fast_not_ss} of {} rows; {out_of_order} steps against the \
             order; at most {partial_max} partial speed(s) in a row",
            strains.len()
        ),
        pass: fast_not_ss == strains.len() && out_of_order == 0 && partial_max <= 1,
    });

    // Critical speeds by bisection, against the map's rows and the second-order film.
    let mut crit = Vec::new();
    for &e in &strains {
        let row = row_of(e);
        let scene = scene_of_row(e)?;
        let found = critical_speed(&scene, v_lo, v_hi)?;
        // The map's bracket: the last stick_slip speed and the speed after it.
        let last_ss = row
            .iter()
            .rposition(|r| r.summary.regime == Regime::StickSlip)
            .unwrap_or(0);
        let bracket = (
            map.axis(row[last_ss], V),
            row.get(last_ss + 1)
                .map_or(f64::INFINITY, |r| map.axis(r, V)),
        );
        crit.push((e, found, bracket));
    }
    let second = critical_speed(&map.unswept_scene()?, v_lo, v_hi)?;
    let inside = crit
        .iter()
        .filter(|(_, b, (lo, hi))| {
            b.below.regime == stickslip_studies::boundary::Label::Film(Regime::StickSlip)
                && b.value >= *lo
                && b.value <= *hi
        })
        .count();
    let runs_max = crit.iter().map(|(_, b, _)| b.runs).max().unwrap_or(0);
    checks.push(Check {
        claim: format!(
            "`stickslip boundary` (bisection to {BOUNDARY_RTOL}) puts the end of stick–slip \
             between the map's last stick_slip speed and the next, in every row"
        ),
        measured: format!(
            "{inside} of {} rows; at most {runs_max} runs each",
            crit.len()
        ),
        pass: inside == crit.len(),
    });

    // Figure: regimes and recovery, the critical speeds found by bisection on both.
    let mut figure = panels(&map.json, "recovery")?;
    let pts: Vec<(f64, f64)> = crit.iter().map(|(e, b, _)| (*e, b.value)).collect();
    for p in &mut figure {
        p.series.push(
            Series::new("end of stick–slip (bisection)", pts.clone(), DARK)
                .points()
                .marker(Marker::Triangle),
        );
    }
    let scene = map.unswept_scene()?;
    let table: String = advance
        .iter()
        .zip(&crit)
        .map(|((e, x_star, phi_star, ratio, lags), (_, b, _))| {
            format!(
                "| {} | {} | {} | {} | {} | {} | {} |\n",
                sig(*e, 3),
                sig(*phi_star, 3),
                sig(x_star * 1e6, 4),
                sig(*ratio, 3),
                lags.first().map_or("–".into(), |l| sig(l.1, 2)),
                sig(b.value, 4),
                b.runs
            )
        })
        .collect();
    let v_c: Vec<f64> = crit.iter().map(|(_, b, _)| b.value).collect();
    let (vc_min, vc_max) = v_c
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    let x_growth =
        advance.last().map_or(f64::NAN, |a| a.1) / advance.first().map_or(f64::NAN, |a| a.1);
    let text = format!(
        "The base scene is `{}` (rigid coupler X = V0·t) with the homogeneous one-node contact \
         (one node for the whole contact), stopped after {} events or when an event stays open for {} s. Axes: \
         the melting strain ε₊ = {} … {} ({} values; εc = {} at this temperature) and V0 = {} … \
         {} m/s ({} values, log). The module docs of `maps/src/rigid_first_order.rs` derive the \
         advance per cycle X* on paper.\n\n\
         What to see: at slow speed every row sticks and slips, and the stamp advances X* per \
         cycle, more than ε₊·h0: the elastic substrate makes the film melt before its strain \
         reaches ε₊ (at φ* above the fold's b₃/(2b)), after a longer advance. As V0 grows the \
         film lags behind its branch (a fold's delay, ∝ V0^(2/3)); then, at a critical speed \
         ({} … {} m/s; the second-order film of the same scene: {} m/s), the film stays liquid \
         after a slip: its liquid is stable beyond ε₋ = εc, which b₃ does not move, and the \
         recovery collapses instead of fading through `partial` speeds. Over the ε₊ range the \
         critical speed grows {}× while the advance per cycle X* grows {}×: the race is won or \
         lost in the regrowth from the liquid, before the strain passes εc, not at ε₊. Triangles: the end of stick–slip found by `stickslip boundary` (bisection to \
         {BOUNDARY_RTOL}).\n\n\
         | ε₊ | φ* | X* [µm] | X*/(ε₊·h0) | lag at V0 = {} m/s | end of stick–slip [m/s] | runs |\n\
         |---|---|---|---|---|---|---|\n{table}",
        map.scene_file(),
        scene.max_events.unwrap_or(0),
        scene.max_open_event_s.map_or("–".into(), |t| sig(t, 2)),
        sig(strains[0], 3),
        sig(strains[strains.len() - 1], 3),
        strains.len(),
        sig(
            scene
                .config
                .lubricant
                .critical_strain(scene.config.temperature.a_coeff_pa(0.0)),
            4
        ),
        sig(v_lo, 2),
        sig(v_hi, 2),
        speeds.len(),
        sig(vc_min, 3),
        sig(vc_max, 3),
        sig(second.value, 3),
        sig(vc_max / vc_min, 3),
        sig(x_growth, 3),
        sig(v_lo, 2),
    );
    Ok(Section {
        title: "First-order film, rigid drive: melting strain × speed".into(),
        text,
        figure: ("maps_rigid_first_order.svg".into(), figure),
        checks,
    })
}
