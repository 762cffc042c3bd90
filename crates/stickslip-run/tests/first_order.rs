//! The first-order film (docs/model.md#the-first-order-film) through the run library:
//! `lubricant.cubic = 0` is the second-order film byte for byte, `eps_melt` and `cubic` name
//! the same film, one event per melt–recover cycle with the stamp advancing about ε₊·h0 per
//! cycle (derived here independently of the core), the metastable solid above the melting
//! temperature, and the recovery measured against the solid branch.

use crate::common;

use std::path::Path;
use stickslip_run::{Control, DirOptions, ResolvedScene, Scene, run_in_memory, run_to_dir};

const GAMMA: f64 = 10.0;
const A_PA: f64 = 1e6;
const B_PA: f64 = 2e6;
const A_COEFF_PA: f64 = 1.5e6;
const H0_M: f64 = 1e-7;
const THRESHOLD: f64 = 0.01;
/// ε₊ = 1.3·εc, fig2_first_order's melting strain.
const EPS_MELT: f64 = 2.251_666_049_839_5;

fn scene(name: &str, sets: &[&str]) -> ResolvedScene {
    Scene::from_path(&common::scene(name), sets).unwrap()
}

fn run_dir(scene: &ResolvedScene, dir: &Path) {
    let options = DirOptions {
        force: false,
        checkpoint_every_s: 0.0,
    };
    run_to_dir(scene, dir, &options, &mut Control::default()).unwrap();
}

#[test]
fn cubic_zero_is_the_second_order_film_byte_for_byte() {
    // Through the first event and into the second stick phase.
    let base = [
        "contact.nodes=40",
        "time.end=7e-4",
        "output.profile_times=[6.5e-4, 7e-4]",
    ];
    let tmp = tempfile::tempdir().unwrap();
    let mut runs = Vec::new();
    for extra in [
        None,
        Some("lubricant.cubic=0"),
        Some("lubricant.cubic=-0.0"),
    ] {
        let mut sets: Vec<&str> = base.to_vec();
        sets.extend(extra);
        let s = scene("fig2", &sets);
        let dir = tmp.path().join(format!("run{}", runs.len()));
        run_dir(&s, &dir);
        runs.push((s, common::outputs(&dir)));
    }
    let (plain, files) = &runs[0];
    assert!(files.iter().any(|(n, _)| n == "events.csv"));
    for (s, other) in &runs[1..] {
        assert_eq!(s.config, plain.config);
        assert_eq!(s.resolved, plain.resolved);
        assert_eq!(other.len(), files.len());
        for ((name, a), (_, b)) in files.iter().zip(other) {
            assert!(a == b, "{name} differs with lubricant.cubic = 0");
        }
    }
}

#[test]
fn eps_melt_and_the_cubic_it_gives_are_one_film_converted_at_the_initial_temperature() {
    let by_strain = scene("fig2_first_order", &["contact.nodes=20"]);
    let b3 = by_strain.config.lubricant.cubic_pa;
    // b₃ = 2·√(a·b·(ε₊² − εc²)), εc² = A·b/a².
    let expected =
        2.0 * (A_PA * B_PA * (EPS_MELT * EPS_MELT - A_COEFF_PA * B_PA / (A_PA * A_PA))).sqrt();
    assert!((b3 / expected - 1.0).abs() < 1e-12, "{b3} vs {expected}");
    // The resolved scene gives b₃, not ε₊, and reads back as the same film.
    let lub = by_strain.resolved.lubricant.as_ref().unwrap();
    assert_eq!((lub.cubic, lub.eps_melt), (Some(b3), None));
    let text = by_strain.resolved.to_toml_string();
    let again = Scene::resolve_table(Scene::parse_table(&text).unwrap(), &[] as &[&str]).unwrap();
    assert_eq!(again.config, by_strain.config);
    let by_cubic = scene(
        "fig2",
        &["contact.nodes=20", &format!("lubricant.cubic={b3}")],
    );
    let by_eps = scene(
        "fig2",
        &[
            "contact.nodes=20",
            &format!("lubricant.eps_melt={EPS_MELT}"),
        ],
    );
    assert_eq!(by_cubic.config, by_eps.config);
    assert_eq!(by_cubic.config, by_strain.config);
    // With a temperature law, b₃ is converted once, at A(0) = A0: the melting strain then
    // follows A(t) with the width ε₊² − εc² fixed.
    let heating = scene(
        "fig4",
        &[
            "contact.nodes=20",
            &format!("lubricant.eps_melt={EPS_MELT}"),
        ],
    );
    assert_eq!(heating.config.lubricant.cubic_pa, b3);
    let l = heating.config.lubricant;
    let t = 1e-3;
    let a_t = heating.config.temperature.a_coeff_pa(t);
    let width = l.melting_strain(a_t).powi(2) - l.critical_strain(a_t).powi(2);
    assert!(
        (width / (EPS_MELT.powi(2) - 3.0) - 1.0).abs() < 1e-9,
        "{width}"
    );
    assert!(l.melting_strain(a_t) < EPS_MELT);
}

/// dφ/dt of the one-node first-order film at strain ε: −γφ(aε² + bφ² − b₃φ − A·b/a).
fn rate(phi: f64, eps: f64, b3: f64) -> f64 {
    -GAMMA * phi * (A_PA * eps * eps + B_PA * phi * phi - b3 * phi - A_COEFF_PA * B_PA / A_PA)
}

/// Time from a reset at φ = `phi0` until φ falls below the threshold again under the rigid
/// drive at `v0` (ε = V0·t/h0), by classical RK4 with step `dt` (not the core's stepper).
fn time_to_melt(v0: f64, phi0: f64, b3: f64, dt: f64) -> f64 {
    let (mut t, mut phi) = (0.0_f64, phi0);
    let mut above = phi0 > THRESHOLD * 1.0001;
    loop {
        let f = |t: f64, phi: f64| rate(phi, v0 * t / H0_M, b3);
        let k1 = f(t, phi);
        let k2 = f(t + 0.5 * dt, phi + 0.5 * dt * k1);
        let k3 = f(t + 0.5 * dt, phi + 0.5 * dt * k2);
        let k4 = f(t + dt, phi + dt * k3);
        let next = phi + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        if above && next < THRESHOLD {
            return t + dt * (phi - THRESHOLD) / (phi - next);
        }
        above |= next > THRESHOLD * 1.0001;
        phi = next;
        t += dt;
        assert!(t < 1.0, "no melting");
    }
}

#[test]
fn rigid_drive_one_event_per_cycle_advancing_eps_plus_times_h0() {
    // One node, rigid substrate, rigid drive at a slow V0: the film follows its solid branch
    // up to ε₊ (not εc), melts, u0 resets and it regrows from the threshold. The derivation:
    // φ₊(0) by hand, the two times by RK4 of the one-node equation.
    let v0 = 1e-3;
    let b3 = 2.0 * (A_PA * B_PA * (EPS_MELT * EPS_MELT - 3.0)).sqrt();
    let ap = A_COEFF_PA * B_PA / A_PA;
    let phi_plus0 = (b3 + (b3 * b3 + 4.0 * B_PA * ap).sqrt()) / (2.0 * B_PA);
    let dt = 2e-9;
    let first = time_to_melt(v0, phi_plus0, b3, dt);
    let period = time_to_melt(v0, THRESHOLD, b3, dt);
    let advance = v0 * period;
    let eps_c_h0 = 3f64.sqrt() * H0_M;
    eprintln!(
        "derived: first onset {first:e} s, period {period:e} s, advance per cycle {:.4} µm \
         (eps+·h0 = {:.4} µm, eps_c·h0 = {:.4} µm)",
        advance * 1e6,
        EPS_MELT * H0_M * 1e6,
        eps_c_h0 * 1e6
    );
    // The advance is ε₊·h0 plus the film's lag, far from εc·h0.
    assert!(advance > EPS_MELT * H0_M && advance < 1.02 * EPS_MELT * H0_M);
    let end = first + 4.5 * period;
    let s = scene(
        "rigid",
        &[
            "contact.model=homogeneous",
            "contact.substrate=rigid",
            &format!("lubricant.eps_melt={EPS_MELT}"),
            &format!("drive.velocity={v0}"),
            &format!("time.end={end:e}"),
            &format!("output.profile_times=[{end:e}]"),
        ],
    );
    let (outcome, _) = run_in_memory(&s, &mut Control::default()).unwrap();
    let t: Vec<f64> = outcome.events.iter().map(|e| e.t_onset_s).collect();
    let x: Vec<f64> = outcome.events.iter().map(|e| e.x_onset_m).collect();
    eprintln!("simulated onsets {t:?}");
    assert_eq!(t.len(), 5);
    assert!((t[0] / first - 1.0).abs() < 1e-3, "first onset {}", t[0]);
    for (w, xw) in t.windows(2).zip(x.windows(2)) {
        assert!(
            ((w[1] - w[0]) / period - 1.0).abs() < 2e-3,
            "interval {:e} vs {period:e}",
            w[1] - w[0]
        );
        assert!(((xw[1] - xw[0]) / advance - 1.0).abs() < 2e-3);
    }
    // Each event ends: the film re-solidifies fully between them.
    assert!(outcome.events[..4].iter().all(|e| e.t_end_s.is_some()));
    assert!(
        outcome.events[..4]
            .iter()
            .all(|e| (e.recovery - 1.0).abs() < 1e-3)
    );
}

#[test]
fn radial_contact_has_one_event_per_cycle_and_recovers_against_the_solid_branch() {
    // fig2_first_order at N = 40 through three events: the front crosses the contact within
    // each event (melted area 1) and the film re-solidifies fully between them. The recovery
    // is measured against φ₊(0) ≈ 2.61 (against √(A/a) ≈ 1.22 it would be about 2.1).
    let s = scene(
        "fig2_first_order",
        &[
            "contact.nodes=40",
            "time.end=1.15e-3",
            "output.profile_times=[1.15e-3]",
        ],
    );
    let (outcome, _) = run_in_memory(&s, &mut Control::default()).unwrap();
    let ev = &outcome.events;
    eprintln!(
        "onsets {:?}, recoveries {:?}",
        ev.iter().map(|e| e.t_onset_s).collect::<Vec<_>>(),
        ev.iter().map(|e| e.recovery).collect::<Vec<_>>()
    );
    assert_eq!(ev.len(), 3);
    for e in ev {
        assert!(e.t_end_s.is_some() && e.melted_area > 0.99);
        assert!(e.r_first_m > 0.9 * 2e-5, "melting starts at the edge");
    }
    let r = outcome.summary.recovery.unwrap();
    assert!((0.99..=1.0001).contains(&r), "recovery {r}");
    assert_eq!(outcome.summary.regime.name(), "stick_slip");
    // Consecutive intervals shrink as the spring speeds the stamp up, as in fig2.
    assert!(ev[2].t_onset_s - ev[1].t_onset_s < ev[1].t_onset_s - ev[0].t_onset_s);
}

#[test]
fn above_the_melting_temperature_a_metastable_solid_melts_once_and_stays_liquid() {
    // A = −1e5 Pa: the second-order film is liquid from the start. The first-order film with
    // b₃ = 4.07e6 Pa (b₃² ≥ −4b·A·b/a) starts as a metastable solid at φ₊(0) ≈ 1.99, carries
    // a force until the strain reaches ε₊ ≈ 1.37, melts, and with the liquid stable at every
    // strain never re-solidifies.
    let b3 = 2.0 * (A_PA * B_PA * (EPS_MELT * EPS_MELT - 3.0)).sqrt();
    let sets = [
        "contact.nodes=30",
        "temperature.A0=-1e5",
        "time.end=9e-4",
        "output.profile_times=[9e-4]",
    ];
    let metastable = scene(
        "fig2",
        &[&sets[..], &[&format!("lubricant.cubic={b3}")]].concat(),
    );
    let (outcome, out) = run_in_memory(&metastable, &mut Control::default()).unwrap();
    let d = &out.info.derived;
    assert_eq!(d.metastable_solid, Some(true));
    assert!(d.phi0 > 1.9 && d.phi0 < 2.0, "{}", d.phi0);
    assert!(d.first_onset_estimate.unwrap() > 0.0);
    assert_eq!(outcome.events.len(), 1);
    assert!(outcome.events[0].t_onset_s > 1e-4 && outcome.events[0].t_end_s.is_none());
    let f_max = out.series.f_n.iter().copied().fold(0.0, f64::max);
    assert!(
        f_max > 1e-4,
        "the metastable solid carries a force: {f_max:e} N"
    );
    assert_eq!(out.series.f_n.last().copied(), Some(0.0));
    assert!(out.series.melted_fraction.last().copied().unwrap() == 1.0);
    // Below the limit (A < −a·b₃²/(4b²) ≈ −2.07e6 Pa) no solid exists: liquid from the start.
    let liquid = scene(
        "fig2",
        &[
            "contact.nodes=30",
            "temperature.A0=-3e6",
            "time.end=1e-4",
            "output.profile_times=[1e-4]",
            &format!("lubricant.cubic={b3}"),
        ],
    );
    let (outcome, out) = run_in_memory(&liquid, &mut Control::default()).unwrap();
    assert_eq!(out.info.derived.metastable_solid, Some(false));
    assert_eq!(out.info.derived.phi0, 0.0);
    assert_eq!(outcome.summary.regime.name(), "sliding");
    assert!(out.series.f_n.iter().all(|&f| f == 0.0));
}

#[test]
fn a_vanishing_cubic_term_gives_the_second_order_films_run() {
    // b₃ = 1e-9·b·φ0 against b₃ = 0 through the first event: the first-order film's step,
    // thresholds and error estimate tend to the second-order film's frozen-strain step (the
    // one the first-order film takes; the second-order film's default ramp correction has no
    // first-order counterpart).
    let base = [
        "numerics.film_step=frozen",
        "contact.nodes=40",
        "time.end=7e-4",
        "output.profile_times=[7e-4]",
    ];
    let b3 = 1e-9 * B_PA * (A_COEFF_PA / A_PA).sqrt();
    let cubic = format!("lubricant.cubic={b3}");
    let (second, out2) = run_in_memory(&scene("fig2", &base), &mut Control::default()).unwrap();
    let (first, out1) = run_in_memory(
        &scene("fig2", &[&base[..], &[cubic.as_str()]].concat()),
        &mut Control::default(),
    )
    .unwrap();
    assert_eq!(first.events.len(), second.events.len());
    for (a, b) in first.events.iter().zip(&second.events) {
        let (da, df) = (
            (a.t_onset_s - b.t_onset_s).abs() / b.t_onset_s,
            (a.f_peak_n - b.f_peak_n).abs() / b.f_peak_n,
        );
        eprintln!(
            "onset {:e} s: relative differences {da:.1e} (onset), {df:.1e} (f_peak)",
            b.t_onset_s
        );
        assert!(da < 1e-6 && df < 1e-6);
    }
    let (f1, f2) = (
        out1.series.f_n.last().unwrap(),
        out2.series.f_n.last().unwrap(),
    );
    assert!((f1 - f2).abs() <= 1e-6 * f2.abs(), "{f1} vs {f2}");
    assert!((out1.info.derived.phi0 / out2.info.derived.phi0 - 1.0).abs() < 1e-8);
}
