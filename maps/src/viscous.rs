//! The viscous map, spring stiffness × film viscosity on the h0 = 1 nm contact at a fixed
//! drive speed (maps/viscous.toml), and the critical speed of the spring drive at two
//! stiffnesses found by `boundary` on the stamp's scale.
//!
//! Physics: the molten film's viscous stress loads the substrate, u3D ≈ C·η·V/h0 with C the
//! flat punch's compliance π·a0/(2G*); a molten node's strain is −u3D/h0, and once its size
//! passes εc the film cannot re-solidify. Slips then stop recurring: the stamp slides steadily
//! with the Couette force η·V0·πa0²/h0. The threshold is a critical η·V, of the film and the
//! substrate, not of the spring: V_c ≈ εc·h0²/(C·η) on paper.

use crate::{Check, Map, Section};
use std::f64::consts::PI;
use stickslip_report::fmt::sig;
use stickslip_report::map::panels;
use stickslip_run::cycles::StampRegime;
use stickslip_run::summary::{Regime, RegimeThresholds};
use stickslip_studies::boundary::Scale;
use stickslip_studies::boundary::scan::{Scan, ScanOptions, scan};
use stickslip_studies::sweep::map::MapRow;

const K: &str = stickslip_run::keys::drive::STIFFNESS.path;
const ETA: &str = stickslip_run::keys::lubricant::VISCOSITY.path;
/// Kinetic friction in steady sliding against the Couette force, where the film is liquid
/// (film regime `sliding`): relative agreement required.
pub const COUETTE_TOLERANCE: f64 = 0.02;
/// The critical speeds found must lie within this factor of the estimate on paper (a
/// compliance from the flat punch's mean, a threshold from the rim's strain).
pub const PAPER_FACTOR: f64 = 2.5;
/// The viscosity of the critical-speed scans, Pa·s.
pub const SCAN_ETA: f64 = 10.0;
/// The drive speeds the critical-speed scans cover, m/s.
pub const SCAN_RANGE: (f64, f64) = (3e-6, 1e-4);
/// The stiffnesses of the critical-speed scans, N/m.
pub const SCAN_K: [f64; 2] = [5e3, 5e4];

/// The damping ratio, viscosity and stiffness of the dashpot's check: a point where the film
/// stays liquid and the drag's approach is over well inside the settled part (c_v/K ≈ 8 ms,
/// the drag's own damping ratio ≈ 0.8: no ringing), so both runs are in steady sliding.
pub const DAMPING_RATIO: f64 = 0.5;
/// Pa·s.
pub const DAMPED_ETA: f64 = 30.0;
/// N/m.
pub const DAMPED_K: f64 = 5e3;

/// The spring's mean force over the settled part at [`DAMPED_ETA`] and [`DAMPED_K`], without
/// and with a dashpot of [`DAMPING_RATIO`] (two runs through the driver).
fn damped_pair(map: &Map) -> Result<(f64, f64), String> {
    let base = map.unswept_scene()?;
    let stickslip_core::drive::Drive::Spring(spring) = base.config.drive else {
        return Err("the viscous map needs a spring drive".into());
    };
    let c_d = DAMPING_RATIO * 2.0 * (DAMPED_K * spring.mass_kg).sqrt();
    let mut means = Vec::new();
    for damping in [0.0, c_d] {
        let scene = base
            .with_overrides(&[
                format!("{K}={DAMPED_K:e}"),
                format!("{ETA}={DAMPED_ETA:e}"),
                stickslip_run::keys::drive::DAMPING.set(damping).to_string(),
            ])
            .map_err(|e| e.to_string())?;
        let outcome = stickslip_run::run(
            &scene,
            &mut stickslip_run::NullSink,
            &mut stickslip_run::Control::default(),
        )
        .map_err(|e| e.to_string())?;
        means.push(
            outcome
                .summary
                .cycles
                .and_then(|c| c.slips.f_mean_n)
                .ok_or("no settled part")?,
        );
    }
    Ok((means[0], means[1]))
}

/// The critical speed at one stiffness: the scan and its stick–slip → steady-sliding change.
struct Critical {
    k: f64,
    scan: Scan,
}

impl Critical {
    /// The change from `stick_slip` below to `steady_sliding` above, if found.
    fn change(&self) -> Option<&stickslip_studies::boundary::scan::Change> {
        self.scan.changes.iter().find(|c| {
            c.below.regime.name() == StampRegime::StickSlip.name()
                && c.above.regime.name() == StampRegime::SteadySliding.name()
        })
    }
}

/// `boundary`'s scan of `scene` along `key` over `range` (7 points, bisected to `rtol`, each
/// change rerun at 2N and a tenth of the tolerance), following the regime of `scale`.
fn scan_along(
    scene: &stickslip_run::ResolvedScene,
    key: &str,
    range: (f64, f64),
    rtol: f64,
    scale: Scale,
    jobs: usize,
) -> Result<Scan, stickslip_studies::boundary::BoundaryError> {
    scan(
        scene,
        key,
        range,
        rtol,
        ScanOptions {
            points: 7,
            jobs,
            scale,
            cache: None,
        },
        RegimeThresholds::default(),
        None,
        &|_| {},
        &mut || {},
    )
}

/// Runs `boundary` on the stamp's scale along the drive speed for each of [`SCAN_K`].
fn critical_speeds(map: &Map, jobs: usize) -> Result<Vec<Critical>, String> {
    let base = map.unswept_scene()?;
    let mut out = Vec::new();
    for k in SCAN_K {
        // Long enough for five sticks at the slowest speed: a stick lasts about
        // F_peak/(K·V0), F_peak ≈ 0.47 mN on this contact.
        let end = (5.0 * 0.47e-3 / (k * SCAN_RANGE.0)).max(0.3);
        let scene = base
            .with_overrides(&[
                format!("{K}={k:e}"),
                format!("{ETA}={SCAN_ETA:e}"),
                stickslip_run::keys::time::END.set(end).to_string(),
            ])
            .map_err(|e| e.to_string())?;
        let found = scan_along(
            &scene,
            "drive.velocity",
            SCAN_RANGE,
            0.05,
            Scale::Stamp,
            jobs,
        )
        .map_err(|e| format!("critical speed at K = {k}: {e}"))?;
        out.push(Critical { k, scan: found });
    }
    Ok(out)
}

/// The critical viscosity at one stiffness, found by `boundary` along η on the film's scale:
/// the change to `sliding` (the film stays liquid), with its error.
struct CriticalEta {
    k: f64,
    scan: Scan,
}

impl CriticalEta {
    /// The lowest change into `sliding`, if found.
    fn change(&self) -> Option<&stickslip_studies::boundary::scan::Change> {
        self.scan
            .changes
            .iter()
            .find(|c| c.above.regime.name() == Regime::Sliding.name())
    }
}

/// Runs `boundary` along η over the map's range at each of the map's stiffnesses.
fn critical_viscosities(map: &Map, jobs: usize) -> Result<Vec<CriticalEta>, String> {
    let base = map.unswept_scene()?;
    let etas = map.values(ETA);
    let range = (etas[0], etas[etas.len() - 1]);
    let mut out = Vec::new();
    for k in map.values(K) {
        let scene = base
            .with_overrides(&[stickslip_run::keys::drive::STIFFNESS.set(k).to_string()])
            .map_err(|e| e.to_string())?;
        let found = scan_along(&scene, ETA, range, ETA_RTOL, Scale::Film, jobs)
            .map_err(|e| format!("critical viscosity at K = {k}: {e}"))?;
        out.push(CriticalEta { k, scan: found });
    }
    Ok(out)
}

/// The bisection's relative bracket for the critical viscosity.
pub const ETA_RTOL: f64 = 0.05;

/// The viscous map's section.
///
/// # Errors
/// If the base scene does not resolve, or a critical-speed scan fails.
pub fn section(map: &Map, jobs: usize) -> Result<Section, String> {
    let scene = map.base_scene()?;
    let c = &scene.config.contact;
    let (a0, h0, g) = (c.radius_m, c.film_thickness_m, c.g_eff_pa);
    let v0 = scene.config.drive.velocity_m_per_s();
    let lub = &scene.config.lubricant;
    let eps_c = lub.melting_strain(scene.derived.a_coeff_pa);
    let compliance = PI * a0 / (2.0 * g);
    let vc_eta_paper = eps_c * h0 * h0 / compliance;
    let couette = |eta: f64| eta * v0 * PI * a0 * a0 / h0;
    let rows: Vec<&MapRow> = map.json.table.rows.iter().collect();
    let ks = map.values(K);
    let etas = map.values(ETA);
    let stamp = |r: &MapRow| r.summary.stamp_regime;

    // Along η at each K: the lowest η at which the film stays liquid (film regime `sliding`),
    // and whether it stays so above.
    let liquid = |r: &MapRow| r.summary.regime == Regime::Sliding;
    let mut critical_eta = Vec::new();
    let mut monotone = true;
    for &k in &ks {
        let mut line: Vec<&&MapRow> = rows
            .iter()
            .filter(|r| (map.axis(r, K) / k - 1.0).abs() < 1e-9)
            .collect();
        line.sort_by(|a, b| map.axis(a, ETA).total_cmp(&map.axis(b, ETA)));
        if let Some(i) = line.iter().position(|r| liquid(r)) {
            monotone &= line[i..].iter().all(|r| liquid(r));
            if i > 0 {
                // The change lies between the last other point and the first liquid one.
                let (lo, hi) = (map.axis(line[i - 1], ETA), map.axis(line[i], ETA));
                critical_eta.push((k, (lo * hi).sqrt(), hi / lo));
            }
        }
    }
    let at_eta = |e: f64| {
        rows.iter()
            .filter(move |r| (map.axis(r, ETA) / e - 1.0).abs() < 1e-9)
    };
    let lowest_eta_stick =
        at_eta(etas[0]).all(|r| r.summary.regime == Regime::StickSlip && r.summary.n_slips >= 2);
    let highest_eta_liquid =
        at_eta(etas[etas.len() - 1]).all(|r| liquid(r) && stamp(r) != Some(StampRegime::StickSlip));
    let mut checks = vec![Check {
        claim: format!(
            "at the lowest viscosity ({} Pa·s) the film sticks and slips and the stamp slips \
             (two slips or more) at every stiffness; along η the film, once it stays liquid \
             (`sliding`), stays liquid, with one change inside the map at every stiffness; at \
             the highest ({} Pa·s) the film is liquid and the stamp's slips have stopped (no \
             slip with a melting recurs; what remains at stiff springs is the stamp ringing, \
             damped slowly by the drag)",
            sig(etas[0], 2),
            sig(etas[etas.len() - 1], 2)
        ),
        measured: format!(
            "lowest η: {lowest_eta_stick}; highest η: {highest_eta_liquid}; liquid once, \
             liquid above: {monotone}, a change at {} of {} stiffnesses",
            critical_eta.len(),
            ks.len()
        ),
        pass: lowest_eta_stick && highest_eta_liquid && monotone && critical_eta.len() == ks.len(),
    }];
    // The critical viscosity per stiffness: a finding (the spring moves it), in the prose.
    let per_k = critical_eta
        .iter()
        .map(|(k, e, _)| format!("{} Pa·s at K = {} N/m", sig(*e, 2), sig(*k, 3)))
        .collect::<Vec<_>>()
        .join(", ");
    // The same critical viscosity by bisection, with its error (the bracket plus its move at
    // 2N and a tenth of the tolerance): the map's cells are a factor √10 wide.
    let eta_scans = critical_viscosities(map, jobs)?;
    let eta_found: Vec<(f64, f64, f64)> = eta_scans
        .iter()
        .filter_map(|c| c.change().map(|ch| (c.k, ch.value, ch.error)))
        .collect();
    let inside_cells = eta_found.len() == ks.len()
        && eta_found.iter().all(|(k, v, _)| {
            critical_eta
                .iter()
                .find(|(kk, _, _)| (kk / k - 1.0).abs() < 1e-9)
                .is_some_and(|(_, mid, ratio)| {
                    let (lo, hi) = (mid / ratio.sqrt(), mid * ratio.sqrt());
                    *v >= lo && *v <= hi
                })
        });
    let eta_describe = eta_found
        .iter()
        .map(|(k, v, e)| {
            format!(
                "K = {} N/m: η_c = {} ± {} Pa·s",
                sig(*k, 3),
                sig(*v, 4),
                sig(*e, 2)
            )
        })
        .collect::<Vec<_>>()
        .join("; ");
    checks.push(Check {
        claim: format!(
            "`boundary` along η (7 scan points over the map's range, bisected to {}, errors \
             from 2N and a tenth of the tolerance) finds the change into `sliding` at every \
             stiffness, inside the map's cell where the film begins to stay liquid",
            sig(ETA_RTOL, 2)
        ),
        measured: if eta_describe.is_empty() {
            "no change into sliding found".into()
        } else {
            eta_describe.clone()
        },
        pass: inside_cells,
    });
    // Kinetic friction where the film is liquid throughout the settled sliding and the
    // spring has had time to take up the drag: its approach time c_v/K (overdamped) well
    // inside the settled part.
    let mut worst: f64 = 0.0;
    let mut compared = 0;
    let mut skipped = 0;
    for r in &rows {
        if stamp(r) != Some(StampRegime::SteadySliding) || r.summary.regime != Regime::Sliding {
            continue;
        }
        let Some(cycles) = r.summary.cycles.as_ref() else {
            continue;
        };
        let Some(f) = cycles.slips.f_mean_n else {
            continue;
        };
        let rise = map.axis(r, ETA) * PI * a0 * a0 / h0 / map.axis(r, K);
        if rise > 0.1 * (scene.config.time.end_s - cycles.settled_from_s) {
            skipped += 1;
            continue;
        }
        let expected = couette(map.axis(r, ETA));
        worst = worst.max((f / expected - 1.0).abs());
        compared += 1;
    }
    checks.push(Check {
        claim: format!(
            "kinetic friction in steady sliding with the film liquid: the spring's mean force \
             over the settled part is the Couette force η·V0·πa0²/h0 within {} (where the \
             drag's rise time c_v/K is under a tenth of the settled part)",
            sig(COUETTE_TOLERANCE, 2)
        ),
        measured: format!(
            "largest relative difference {} over {compared} points ({skipped} still rising)",
            sig(worst, 2)
        ),
        pass: compared > 0 && worst <= COUETTE_TOLERANCE,
    });
    // The critical speed of the spring drive at two stiffnesses.
    let crit = critical_speeds(map, jobs)?;
    let found: Vec<(f64, f64, f64)> = crit
        .iter()
        .filter_map(|c| c.change().map(|ch| (c.k, ch.value, ch.error)))
        .collect();
    let describe = found
        .iter()
        .map(|(k, v, e)| {
            format!(
                "K = {} N/m: V_c = {} ± {} m/s (η·V_c = {} Pa·m)",
                sig(*k, 3),
                sig(*v, 4),
                sig(*e, 2),
                sig(v * SCAN_ETA, 3)
            )
        })
        .collect::<Vec<_>>()
        .join("; ");
    let paper = vc_eta_paper / SCAN_ETA;
    let agree = found.len() == 2
        && found
            .iter()
            .all(|(_, v, _)| (v / paper).max(paper / v) <= PAPER_FACTOR);
    checks.push(Check {
        claim: format!(
            "with η = {} Pa·s slips stop recurring above a critical speed of the spring drive, \
             which `boundary --scale stamp` finds at K = {} and {} N/m, each within a factor \
             {} of the estimate on paper εc·h0²/(C·η) = {} m/s (which has no spring in it; the \
             spring decides how the film gets into steady sliding, so the two may differ)",
            sig(SCAN_ETA, 2),
            sig(SCAN_K[0], 3),
            sig(SCAN_K[1], 3),
            sig(PAPER_FACTOR, 2),
            sig(paper, 3)
        ),
        measured: if describe.is_empty() {
            "no stick_slip → steady_sliding change found".into()
        } else {
            describe.clone()
        },
        pass: agree,
    });
    // The dashpot leaves steady sliding untouched: c_d·(V0 − Ẋ) averages to 0 when the stamp
    // moves at V0 on average.
    let (plain, damped) = damped_pair(map)?;
    let same = (damped / plain - 1.0).abs();
    checks.push(Check {
        claim: format!(
            "a dashpot of damping ratio {DAMPING_RATIO} leaves steady sliding untouched: at η = \
             {} Pa·s, K = {} N/m the spring's mean force over the settled part is the same with \
             and without it (within 1e-3) and is the Couette force (within {})",
            sig(DAMPED_ETA, 2),
            sig(DAMPED_K, 2),
            sig(COUETTE_TOLERANCE, 2)
        ),
        measured: format!(
            "{} N without, {} N with (relative difference {}); Couette {} N",
            sig(plain, 6),
            sig(damped, 6),
            sig(same, 2),
            sig(couette(DAMPED_ETA), 6)
        ),
        pass: same <= 1e-3 && (plain / couette(DAMPED_ETA) - 1.0).abs() <= COUETTE_TOLERANCE,
    });
    let mut figure = panels(&map.json, "n_slips")?;
    for p in &mut figure {
        p.hlines.push((vc_eta_paper / v0, "η_c on paper".into()));
    }
    let text = format!(
        "The base scene is `{}` (a0 = {} m, h0 = {} m, G* = {} Pa) at N = {} nodes, V0 = {} m/s, \
         time.end = {} s, stopped after {} meltings. Axes: K = {} … {} N/m and η = {} … {} Pa·s. \
         Colours: the slips of the stamp in the run (the regime panel is the film's). What to \
         see: below a critical viscosity the stamp slips; above it the molten film's viscous \
         stress keeps the substrate strained past εc = {}, the film stays liquid and the stamp \
         slides steadily with the Couette force. The critical viscosity at this speed (the geometric \
         middle of the cell where the film begins to stay liquid, a factor {} wide): {}; found by \
         `stickslip boundary` along η with its error: {}; against {} Pa·s on paper (no \
         spring in it). The critical-speed scans (N = {}, η = {} \
         Pa·s, 7 scan points from 3e-6 to 1e-4 m/s, bisected to 5 %, errors from 2N and a \
         tenth of the tolerance): {}.",
        map.scene_file(),
        sig(a0, 3),
        sig(h0, 3),
        sig(g, 3),
        c.nodes,
        sig(v0, 3),
        sig(scene.config.time.end_s, 3),
        scene.max_events.unwrap_or(0),
        sig(ks[0], 3),
        sig(ks[ks.len() - 1], 3),
        sig(etas[0], 3),
        sig(etas[etas.len() - 1], 3),
        sig(eps_c, 3),
        sig(etas[1] / etas[0], 3),
        if per_k.is_empty() {
            "none found".to_string()
        } else {
            per_k
        },
        if eta_describe.is_empty() {
            "none found".to_string()
        } else {
            eta_describe
        },
        sig(vc_eta_paper / v0, 3),
        c.nodes,
        sig(SCAN_ETA, 2),
        describe
    );
    Ok(Section {
        title: "Viscous film: stiffness × viscosity, and the critical speed".into(),
        text,
        figure: ("maps_viscous.svg".into(), figure),
        checks,
    })
}
