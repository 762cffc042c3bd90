//! The first-order film's claims C11–C13 (`stickslip_validation::claims_first_order`) where
//! their computation can fail: C11's thresholds extracted from a one-node `hysteresis` run made
//! in-process with the run library (and refused on a run where X/h0 is not the strain), the
//! imposed-strain loop against the closed forms, C12's comparison on synthetic contrasts, and
//! C13's front speeds on synthetic events.

use std::path::Path;
use stickslip_core::sim::events::MeltingEvent;
use stickslip_run::schema::events::Events;
use stickslip_run::{Control, RunOutput, RunStatus, Scene, run_in_memory};
use stickslip_validation::claims_first_order::{
    C11_REL_TOL, C12_MIN_FACTOR, Contrast, c11_part, c12_part, c13_speed_part, front_speeds,
    hysteresis,
};
use stickslip_validation::hysteresis::{Film, imposed_loop};

fn run(scene: &str, sets: &[&str]) -> RunOutput {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenes/{scene}.toml"));
    let scene = Scene::from_path(&path, sets).expect("the scene resolves");
    let (outcome, output) = run_in_memory(&scene, &mut Control::default()).expect("it starts");
    assert_eq!(outcome.status(), RunStatus::Ok, "{:?}", outcome.failure);
    output
}

#[test]
fn c11_finds_the_thresholds_of_a_one_node_run_and_its_loop() {
    let out = run("hysteresis", &["temperature.A0=2e6"]);
    let h = hysteresis(&out).expect("a first-order film on one node, rigid substrate and drive");
    let (ep, em, w) = h.theory();
    // The closed forms at A = 2e6 Pa with fig2's a, b and b3 ≈ 4.07e6 Pa.
    assert!((em - 2.0).abs() < 1e-12, "εc = {em}");
    assert!((w - 2.07).abs() < 1e-6, "width {w}");
    assert!((ep * ep - em * em - w).abs() < 1e-12);
    let d = h.deviations();
    eprintln!(
        "melt (run) {}, melt (loop) {:?}, solid (loop) {:?}, deviations {d:?}",
        h.melt_binary, h.imposed.melt_eps, h.imposed.solid_eps
    );
    assert!(d.iter().all(|&x| x <= C11_REL_TOL), "{d:?}");
    assert!(c11_part(&h).pass);
    // The jumps: φ falls from about b3/(2b) and rises to about b3/b.
    let f = &h.imposed.film;
    let b3_over_b = f.params.cubic_pa / f.b_pa();
    assert!((h.imposed.phi_before_fall / (0.5 * b3_over_b) - 1.0).abs() < 0.1);
    assert!((h.imposed.phi_after_jump / b3_over_b - 1.0).abs() < 0.1);
}

#[test]
fn c11_refuses_a_run_where_x_over_h0_is_not_the_strain() {
    // Elastic substrate: u3D ≠ 0, so X_onset/h0 is not the strain at melting.
    let out = run(
        "hysteresis",
        &[
            "contact.substrate=elastic",
            "time.end=0.1",
            "output.profile_times=[0.1]",
        ],
    );
    let e = hysteresis(&out).expect_err("refused");
    assert!(e.contains("rigid substrate"), "{e}");
    // The second-order film has no hysteresis to measure.
    let out = run(
        "hysteresis",
        &[
            "lubricant.cubic=0",
            "time.end=0.1",
            "output.profile_times=[0.1]",
        ],
    );
    assert!(hysteresis(&out).is_err());
}

#[test]
fn the_imposed_loop_shows_no_hysteresis_for_the_second_order_film_and_fails_a_fast_ramp() {
    let out = run("hysteresis", &[]);
    let film = Film::of(&out).expect("the scene resolves");
    // b3 = 0: melting and re-solidification both at εc (no width).
    let mut second = film;
    second.params.cubic_pa = 0.0;
    let l = imposed_loop(&second, 0.05, 1e-3);
    let (m, s) = (l.melt_eps.unwrap(), l.solid_eps.unwrap());
    assert!((m / film.eps_minus() - 1.0).abs() < 1e-3, "{m}");
    assert!((s / film.eps_minus() - 1.0).abs() < 1e-3, "{s}");
    // A ramp 1000 times faster re-solidifies measurably late: the criterion can fail.
    let l = imposed_loop(&film, 50.0, 1e-6);
    let s = l.solid_eps.unwrap();
    assert!((s / film.eps_minus() - 1.0).abs() > C11_REL_TOL, "{s}");
}

fn contrast(scale: f64) -> Contrast {
    Contrast {
        events: (10, 10),
        rel_l2_f: 0.05 * scale,
        onset_shift: 0.01 * scale,
        f_peak: 0.002 * scale,
        x_period_last: 0.003 * scale,
    }
}

#[test]
fn c12_wants_every_measure_larger_by_the_factor() {
    let second = contrast(1.0);
    assert!(c12_part(&second, &contrast(C12_MIN_FACTOR)).pass);
    assert!(!c12_part(&second, &contrast(0.99 * C12_MIN_FACTOR)).pass);
    let mut one_short = contrast(10.0);
    one_short.x_period_last = second.x_period_last;
    let p = c12_part(&second, &one_short);
    assert!(!p.pass, "{}", p.text);
    let mut nan = contrast(10.0);
    nan.rel_l2_f = f64::NAN;
    assert!(!c12_part(&second, &nan).pass);
}

fn with_fronts(fronts: &[(f64, f64, Option<f64>)]) -> RunOutput {
    let mut out = run(
        "hysteresis",
        &[
            "time.end=1e-3",
            "time.dt_max=1e-3",
            "output.profile_times=[1e-3]",
        ],
    );
    out.events = Events(
        fronts
            .iter()
            .enumerate()
            .map(|(k, &(t, r, tc))| MeltingEvent {
                k: k + 1,
                t_onset_s: t,
                r_first_m: r,
                x_onset_m: 0.0,
                f_peak_n: 1e-3,
                r_min_m: 0.0,
                t_center_s: tc,
                max_melted_fraction: 0.0,
                t_end_s: None,
                recovery: 1.0,
                f_mean_n: 0.0,
                melted_area: 1.0,
                energy: None,
            })
            .collect(),
    );
    out
}

#[test]
fn c13_front_speed_is_radius_over_travel_time() {
    let fast = with_fronts(&[(1e-4, 2e-5, Some(1e-4 + 2e-7)), (2e-4, 2e-5, None)]);
    let v = front_speeds(&fast);
    assert_eq!(v.len(), 1, "only the event that reached the axis");
    assert!((v[0] / 100.0 - 1.0).abs() < 1e-9, "{v:?}");
    let slow = with_fronts(&[(1e-4, 1e-5, Some(1e-4 + 1e-6))]);
    let p = c13_speed_part(&fast, &slow);
    assert!(p.pass);
    assert!((p.value["ratio"].as_f64().unwrap() - 10.0).abs() < 1e-6);
    let none = with_fronts(&[(1e-4, 1e-5, None)]);
    assert!(!c13_speed_part(&none, &slow).pass);
}
