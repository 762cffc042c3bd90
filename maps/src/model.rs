//! Film thickness × substrate modulus for the radial (MDR) and the homogeneous one-node model.
//!
//! What separates them is how much of the stamp's advance the substrate takes up. For the
//! homogeneous flat punch u3D = π·a0·τ/(2G*) and τ = a·φ²·(u0 − u3D)/h0, so the substrate's
//! share is set by ρ = π·a0·a·φ0²/(2·G*·h0) (the one-node lagged-sweep factor, 0.47 for fig2).
//! For ρ ≪ 1 the substrate hardly moves, the stress is nearly uniform and both models give the
//! same run; for ρ ≳ 1 the radial model concentrates the stress at the edge, which melts first.

use crate::{Check, Map, Section};
use stickslip_report::fmt::sig;
use stickslip_report::map::panels;
use stickslip_report::palette::GREY;
use stickslip_report::plot::Series;
use stickslip_studies::sweep::map::MapRow;

const H: &str = stickslip_run::keys::contact::FILM_THICKNESS.path;
const G: &str = stickslip_run::keys::contact::G_EFF.path;
const MODEL: &str = stickslip_run::keys::contact::MODEL.path;

/// Relative agreement asked of the two models where ρ ≤ 1.
pub const TOLERANCE: f64 = 0.01;

/// The map's cells: (h0, G*, the radial point, the homogeneous point).
#[must_use]
pub fn cells(map: &Map) -> Vec<(f64, f64, &MapRow, &MapRow)> {
    let rows = &map.json.table.rows;
    let mut cells = Vec::new();
    for r in rows.iter().filter(|r| map.word(r, MODEL) == "radial") {
        let (h, g) = (map.axis(r, H), map.axis(r, G));
        if let Some(hom) = rows.iter().find(|x| {
            map.word(x, MODEL) == "homogeneous" && map.axis(x, H) == h && map.axis(x, G) == g
        }) {
            cells.push((h, g, r, hom));
        }
    }
    cells
}

/// The substrate's share ρ = π·a0·a·φ²/(2·G*·h0) at film thickness `h0` and modulus `g` for
/// the base scene's film at φ² = `phi_sq`.
#[must_use]
pub fn substrate_share(scene: &stickslip_run::ResolvedScene, phi_sq: f64, h0: f64, g: f64) -> f64 {
    let c = &scene.config;
    std::f64::consts::PI * c.contact.radius_m * c.lubricant.a_pa * phi_sq / (2.0 * g * h0)
}

/// The model map's section.
///
/// # Errors
/// If the base scene does not resolve.
pub fn section(map: &Map) -> Result<Section, String> {
    let scene = map.base_scene()?;
    let c = &scene.config;
    let phi0_sq = c.temperature.a_coeff_pa(0.0) / c.lubricant.a_pa;
    let rho = |h0: f64, g: f64| substrate_share(&scene, phi0_sq, h0, g);
    let cells = cells(map);
    let diff = |x: Option<f64>, y: Option<f64>| match (x, y) {
        (Some(x), Some(y)) => Some((y / x - 1.0).abs()),
        _ => None,
    };
    // The first onset always; the last period only when both runs fit the same number of
    // events into time.end (else it compares different cycles).
    let worst = |r: &MapRow, h: &MapRow| {
        let period = if r.summary.n_events == h.summary.n_events {
            diff(r.summary.period_last, h.summary.period_last)
        } else {
            None
        };
        [
            diff(r.summary.t_first_onset, h.summary.t_first_onset),
            period,
        ]
        .into_iter()
        .flatten()
        .fold(0.0_f64, f64::max)
    };
    let stiff: Vec<_> = cells
        .iter()
        .filter(|(h, g, ..)| rho(*h, *g) <= 1.0)
        .collect();
    let stiff_worst = stiff
        .iter()
        .map(|(_, _, r, hm)| worst(r, hm))
        .fold(0.0_f64, f64::max);
    let stiff_regimes = stiff
        .iter()
        .filter(|(_, _, r, hm)| r.summary.regime == hm.summary.regime)
        .count();
    let mut checks = vec![Check {
        claim: format!(
            "C6, the inhomogeneity matters little: where the substrate's share ρ ≤ 1, radial and \
             homogeneous agree in regime and within {TOLERANCE} in t_first_onset and period_last (the latter where both fit \
             as many events into time.end)"
        ),
        measured: format!(
            "{stiff_regimes} of {} cells with ρ ≤ 1 agree in regime; largest relative \
             difference {}",
            stiff.len(),
            sig(stiff_worst, 2)
        ),
        pass: !stiff.is_empty() && stiff_regimes == stiff.len() && stiff_worst <= TOLERANCE,
    }];
    let differing: Vec<_> = cells
        .iter()
        .filter(|(_, _, r, hm)| r.summary.regime != hm.summary.regime || worst(r, hm) > TOLERANCE)
        .collect();
    let rho_min_diff = differing
        .iter()
        .map(|(h, g, ..)| rho(*h, *g))
        .fold(f64::INFINITY, f64::min);
    let regime_diffs: Vec<String> = cells
        .iter()
        .filter(|(_, _, r, hm)| r.summary.regime != hm.summary.regime)
        .map(|(h, g, r, hm)| {
            format!(
                "h0 = {} m, G* = {} Pa (ρ = {}): radial {}, homogeneous {}",
                sig(*h, 2),
                sig(*g, 2),
                sig(rho(*h, *g), 2),
                r.summary.regime.name(),
                hm.summary.regime.name()
            )
        })
        .collect();
    checks.push(Check {
        claim:
            "where they differ is a finding: only where the substrate takes a large share (ρ > 1)"
                .into(),
        measured: format!(
            "{} of {} cells differ (regime, or > {TOLERANCE} in onset or period), all at ρ ≥ {}; \
             {} regime differences",
            differing.len(),
            cells.len(),
            sig(rho_min_diff, 2),
            regime_diffs.len()
        ),
        pass: rho_min_diff > 1.0,
    });
    // Figure: the first onset per model, with the lines ρ = 1 and ρ = 10.
    let mut figure = panels(&map.json, "t_first_onset")?;
    let hs = map.values(H);
    let (h_lo, h_hi) = (hs[0], hs[hs.len() - 1]);
    let gs = map.values(G);
    let (g_lo, g_hi) = (gs[0], gs[gs.len() - 1]);
    for p in &mut figure {
        for (level, label) in [(1.0, "ρ = 1"), (10.0, "ρ = 10")] {
            let line: Vec<(f64, f64)> = (0..=40)
                .map(|i| h_lo * (h_hi / h_lo).powf(f64::from(i) / 40.0))
                .map(|h| (h, rho(h, 1.0) / level))
                .filter(|(_, g)| *g >= g_lo && *g <= g_hi)
                .collect();
            p.series.push(Series::new(label, line, GREY).dashed());
        }
    }
    let own = map.unswept_scene()?;
    let fig2_rho = rho(
        own.config.contact.film_thickness_m,
        own.config.contact.g_eff_pa,
    );
    let largest = cells
        .iter()
        .map(|(h, g, r, hm)| (worst(r, hm), rho(*h, *g)))
        .fold(
            (0.0_f64, 0.0_f64),
            |acc, x| if x.0 > acc.0 { x } else { acc },
        );
    let text = format!(
        "The base scene is `fig2.toml` (spring drive) at N = {} nodes, stopped after {} \
         events. Axes: h0 = {} … {} m and G* = {} … {} Pa (log), each point run with the radial \
         MDR contact and with the homogeneous one-node model (a flat punch of compliance \
         π·a0/(2G*)). The dashed lines mark the substrate's share ρ = π·a0·a·φ0²/(2·G*·h0) = 1 \
         and 10 (fig2: ρ = {}).\n\nWhat to see: above the ρ = 1 line the two rows of panels are \
         the same map (largest relative difference {} in onset and period); below it the radial \
         model melts first at the edge and its onsets come earlier, up to {} apart at ρ = {}. \
         Regime differences (a finding): {}.",
        c.contact.nodes,
        scene.max_events.unwrap_or(0),
        sig(h_lo, 2),
        sig(h_hi, 2),
        sig(g_lo, 2),
        sig(g_hi, 2),
        sig(fig2_rho, 2),
        sig(stiff_worst, 2),
        sig(largest.0, 2),
        sig(largest.1, 2),
        if regime_diffs.is_empty() {
            "none".to_string()
        } else {
            regime_diffs.join("; ")
        }
    );
    Ok(Section {
        title: "Radial against homogeneous: film thickness × modulus".into(),
        text,
        figure: ("maps_model.svg".into(), figure),
        checks,
    })
}
