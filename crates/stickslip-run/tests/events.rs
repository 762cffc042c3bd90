//! One event per melt–recover cycle, whatever the period, with the default settings.
//!
//! The reference is derived independently of the core: the one-node film under a rigid drive
//! and a rigid substrate obeys dφ/dt = −γφ(aε² + bφ² − Ab/a) with ε = V0·(t − t_reset)/h0;
//! it melts when φ falls below the threshold, u0 resets (ε = 0) and φ regrows from the
//! threshold. A classical RK4 integration here (not the core's stepper) gives the first onset
//! and the period; the stamp advance per cycle is V0 times the period.

use crate::common;

use stickslip_run::{Control, ResolvedScene, Scene, run_in_memory};

const GAMMA: f64 = 10.0;
const A_PA: f64 = 1e6;
const B_PA: f64 = 2e6;
const A_COEFF_PA: f64 = 1.5e6;
const H0_M: f64 = 1e-7;
const THRESHOLD: f64 = 0.01;

/// Time from a reset at φ = `phi0` until φ falls below the threshold again, for the one-node
/// film at drive speed `v0`, by RK4 with step `dt`.
fn time_to_melt(v0: f64, phi0: f64, dt: f64) -> f64 {
    let rate = |t: f64, phi: f64| {
        let eps = v0 * t / H0_M;
        -GAMMA * phi * (A_PA * eps * eps + B_PA * phi * phi - A_COEFF_PA * B_PA / A_PA)
    };
    let (mut t, mut phi) = (0.0_f64, phi0);
    let mut above = phi0 > THRESHOLD * 1.0001;
    loop {
        let k1 = rate(t, phi);
        let k2 = rate(t + 0.5 * dt, phi + 0.5 * dt * k1);
        let k3 = rate(t + 0.5 * dt, phi + 0.5 * dt * k2);
        let k4 = rate(t + dt, phi + dt * k3);
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

/// First onset (from the solid equilibrium at rest) and period of the one-node film, s.
fn one_node_cycle(v0: f64) -> (f64, f64) {
    let dt = 1e-4 * H0_M / v0;
    let phi_eq = (A_COEFF_PA / A_PA).sqrt();
    (
        time_to_melt(v0, phi_eq, dt),
        time_to_melt(v0, THRESHOLD, dt),
    )
}

fn rigid(v0: f64, end_s: f64, extra: &[&str]) -> ResolvedScene {
    let mut sets = vec![
        format!("drive.velocity={v0}"),
        format!("time.end={end_s:e}"),
        format!("output.profile_times=[{end_s:e}]"),
    ];
    sets.extend(extra.iter().map(|s| (*s).to_string()));
    Scene::from_path(&common::scene("rigid"), &sets).unwrap()
}

fn onsets(scene: &ResolvedScene) -> Vec<f64> {
    let (outcome, _) = run_in_memory(scene, &mut Control::default()).unwrap();
    outcome.events.iter().map(|e| e.t_onset_s).collect()
}

#[test]
fn one_node_film_has_one_event_per_cycle_at_the_derived_period() {
    for v0 in [0.1, 0.3, 1.0] {
        let (first, period) = one_node_cycle(v0);
        let end = first + 8.5 * period;
        let expected = 9;
        let scene = rigid(
            v0,
            end,
            &["contact.model=homogeneous", "contact.substrate=rigid"],
        );
        let t = onsets(&scene);
        eprintln!(
            "V0 = {v0} m/s: derived first onset {first:e} s, period {period:e} s (advance {:.4} µm); \
             simulated {} events, onsets {t:?}",
            v0 * period * 1e6,
            t.len()
        );
        assert_eq!(t.len(), expected, "V0 = {v0}: events");
        assert!(
            (t[0] / first - 1.0).abs() < 1e-3,
            "V0 = {v0}: first onset {}",
            t[0]
        );
        for w in t.windows(2) {
            let p = w[1] - w[0];
            assert!(
                (p / period - 1.0).abs() < 2e-3,
                "V0 = {v0}: interval {p:e} vs {period:e}"
            );
        }
    }
}

#[test]
fn radial_elastic_contact_has_one_event_per_cycle_at_short_periods() {
    // The front crosses the contact within each event; the film recovers between events.
    // Split events would show intervals far below the period; merged ones intervals of a
    // multiple of it.
    for v0 in [0.1, 0.3, 1.0] {
        let (first, period) = one_node_cycle(v0);
        let end = first + 8.5 * period;
        let t = onsets(&rigid(v0, end, &["contact.nodes=50"]));
        let intervals: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
        eprintln!(
            "V0 = {v0} m/s: {} events, intervals / derived one-node period: {:?}",
            t.len(),
            intervals.iter().map(|p| p / period).collect::<Vec<_>>()
        );
        assert!((8..=9).contains(&t.len()), "V0 = {v0}: {} events", t.len());
        for p in &intervals {
            assert!(
                (p / period - 1.0).abs() < 0.05,
                "V0 = {v0}: interval {p:e} s against the period {period:e} s"
            );
        }
    }
}

#[test]
fn gaussian_noise_flicker_does_not_split_fig2_events() {
    for seed in [1, 2] {
        let scene = Scene::from_path(
            &common::scene("fig2"),
            &[
                "contact.nodes=50",
                "lubricant.noise.kind=gaussian",
                &format!("lubricant.noise.seed={seed}"),
            ],
        )
        .unwrap();
        assert_eq!(onsets(&scene).len(), 10, "seed {seed}");
    }
}

#[test]
fn max_events_stops_once_that_many_events_have_ended() {
    let (first, period) = one_node_cycle(1.0);
    let scene = rigid(
        1.0,
        first + 20.0 * period,
        &["contact.nodes=50", "time.max_events=3"],
    );
    let (outcome, output) = run_in_memory(&scene, &mut Control::default()).unwrap();
    assert_eq!(outcome.stop, stickslip_run::StopReason::MaxEvents);
    assert_eq!(outcome.events.len(), 3);
    let last_end = outcome.events[2]
        .t_end_s
        .expect("the third event has ended");
    // The run stops at the end of the step in which the film recovered; t_end is located
    // inside that step.
    assert!(
        last_end <= outcome.t_final_s && outcome.t_final_s - last_end < 0.05 * period,
        "t_end {last_end:e}, stopped at {:e}, period {period:e}",
        outcome.t_final_s
    );
    assert!(outcome.t_final_s < first + 3.0 * period);
    assert_eq!(output.info.stop.as_deref(), Some("max_events"));
}

/// Event times located inside the step converge at second order with fixed steps, and the
/// swept area does not depend on Δt; the instantaneous melted fraction of the accurate scheme
/// (instantaneous melting) shrinks with Δt.
#[test]
fn located_event_times_converge_at_second_order_and_melted_area_does_not_depend_on_dt() {
    let (first, period) = one_node_cycle(1.0);
    let end = first + 1.5 * period;
    let runs: Vec<Vec<stickslip_core::sim::events::MeltingEvent>> = [4e-9, 2e-9, 1e-9]
        .iter()
        .map(|dt| {
            let dt_set = format!("time.dt={dt:e}");
            let scene = rigid(
                1.0,
                end,
                &[
                    "contact.nodes=40",
                    "contact.substrate=elastic",
                    "time.stepping=fixed",
                    &dt_set,
                ],
            );
            run_in_memory(&scene, &mut Control::default())
                .unwrap()
                .0
                .events
        })
        .collect();
    let e: Vec<_> = runs.iter().map(|r| r[0].clone()).collect();
    let order = |f: &dyn Fn(&stickslip_core::sim::events::MeltingEvent) -> f64| {
        ((f(&e[0]) - f(&e[1])) / (f(&e[1]) - f(&e[2]))).abs().log2()
    };
    let o_end = order(&|x| x.t_end_s.unwrap());
    let o_center = order(&|x| x.t_center_s.unwrap());
    let o_onset = order(&|x| x.t_onset_s);
    println!("observed orders: t_onset {o_onset:.2}, t_center {o_center:.2}, t_end {o_end:.2}");
    assert!(o_end > 1.6, "t_end order {o_end}");
    assert!(o_center > 1.6, "t_center order {o_center}");
    for r in &runs {
        assert_eq!(r[0].melted_area, runs[2][0].melted_area);
    }
    assert!(e[2].max_melted_fraction <= e[0].max_melted_fraction);
}
