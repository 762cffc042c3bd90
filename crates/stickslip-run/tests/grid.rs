//! The edge-graded radial grid through the run library: its keys and their errors, outputs that
//! follow the grid's nodes (profiles, r_first, probes, melted area), and the accuracy the
//! grading buys at a fixed N.

use crate::common::scene;
use stickslip_core::grid::{Grading, Grid};
use stickslip_run::driver::Control;
use stickslip_run::scene::Scene;

fn resolve(name: &str, sets: &[&str]) -> Result<stickslip_run::ResolvedScene, String> {
    Scene::from_path(&scene(name), sets).map_err(|e| e.to_string())
}

/// The first event's onset (s), peak force (N) and r_first (m) of `name` with `sets`.
fn first_event(name: &str, sets: &[&str]) -> (f64, f64, f64) {
    let mut all = vec!["time.max_events=1"];
    all.extend_from_slice(sets);
    let s = resolve(name, &all).unwrap();
    let (_, out) = stickslip_run::run_in_memory(&s, &mut Control::default()).unwrap();
    let e = out.events.events().first().expect("a first event");
    (e.t_onset_s, e.f_peak_n, e.r_first_m)
}

#[test]
fn grid_keys_refuse_what_does_not_fit_naming_the_key() {
    // The paper's sums are the uniform grid's.
    let e = resolve("fig2", &["time.scheme=literal", "contact.grid=graded"]).unwrap_err();
    assert!(e.contains("contact.grid") && e.contains("literal"), "{e}");
    // A grading without the graded grid (the literal scheme's default is the uniform one).
    let e = resolve("fig2", &["contact.grid=uniform", "contact.grading=3"]).unwrap_err();
    assert!(e.contains("contact.grading") && e.contains("graded"), "{e}");
    let e = resolve("fig2", &["time.scheme=literal", "contact.grading=3"]).unwrap_err();
    assert!(e.contains("contact.grading") && e.contains("graded"), "{e}");
    // Outside the exponent's range.
    for bad in ["0.5", "4.5", "nan"] {
        let e = resolve(
            "fig2",
            &["contact.grid=graded", &format!("contact.grading={bad}")],
        )
        .unwrap_err();
        assert!(e.contains("contact.grading"), "{bad}: {e}");
    }
    // Edge cells below the rounding guard: 2000^-4 ≈ 6e-14.
    let e = resolve("fig2", &["contact.grid=graded", "contact.grading=4"]).unwrap_err();
    assert!(
        e.contains("contact.grading") && e.contains("N^(-grading)"),
        "{e}"
    );
    // A word that is no grid.
    let e = resolve("fig2", &["contact.grid=chebyshev"]).unwrap_err();
    assert!(e.contains("contact.grid") && e.contains("uniform"), "{e}");
}

#[test]
fn the_resolved_scene_states_the_grid_and_reads_back() {
    let s = resolve("fig2", &["contact.grid=graded", "contact.nodes=100"]).unwrap();
    assert_eq!(s.config.contact.grid, Grading::Edge { power: 3.0 });
    let text = toml::to_string(&s.to_table()).unwrap();
    assert!(
        text.contains("grid = \"graded\"") && text.contains("grading = 3"),
        "{text}"
    );
    let back = Scene::from_toml_str(&text, &[] as &[&str]).unwrap();
    assert_eq!(back.config, s.config);
    // The accurate scheme's default is the graded grid with p = 3; the literal scheme's and
    // the homogeneous model's, the uniform grid, which states no grading.
    let d = resolve("fig2", &["contact.nodes=100"]).unwrap();
    assert_eq!(d.config, s.config);
    let ten = resolve("fig2", &["contact.nodes=10"]).unwrap();
    assert_eq!(ten.config.contact.grid, Grading::Edge { power: 3.0 });
    for sets in [
        &["time.scheme=literal"][..],
        &["contact.nodes=9"][..],
        &["contact.model=homogeneous", "contact.nodes=1"][..],
    ] {
        let u = resolve("fig2", sets).unwrap();
        assert_eq!(u.config.contact.grid, Grading::Uniform, "{sets:?}");
        let text = toml::to_string(&u.to_table()).unwrap();
        assert!(
            text.contains("grid = \"uniform\"") && !text.contains("grading"),
            "{text}"
        );
    }
}

#[test]
fn the_default_grading_stays_clear_of_the_rounding_guard_at_every_n() {
    // 3 up to N ≈ 6800, then lower: every N the key registry allows gets a valid grid.
    for n in [2, 100, 2000, 6000, 10_000, 20_000] {
        let s = resolve(
            "fig2",
            &["contact.grid=graded", &format!("contact.nodes={n}")],
        )
        .unwrap_or_else(|e| panic!("N = {n}: {e}"));
        let Grading::Edge { power } = s.config.contact.grid else {
            panic!("not graded")
        };
        assert!((2.5..=3.0).contains(&power), "N = {n}: p = {power}");
        assert_eq!(power == 3.0, n <= 6000, "N = {n}: p = {power}");
    }
}

#[test]
fn outputs_follow_the_graded_nodes() {
    let n = 60;
    let s = resolve(
        "fig2",
        &[
            "contact.grid=graded",
            "contact.grading=3",
            &format!("contact.nodes={n}"),
            "time.max_events=1",
            "output.profile_times=[5e-4]",
        ],
    )
    .unwrap();
    let (_, out) = stickslip_run::run_in_memory(&s, &mut Control::default()).unwrap();
    let grid = Grid::graded(2e-5, n, Grading::Edge { power: 3.0 }).unwrap();
    let radii = grid.radii_m();
    // The profile's radii are the grid's nodes.
    let p = &out.profiles;
    assert_eq!(p.r_m.len() % n, 0);
    assert_eq!(&p.r_m[..n], &radii[..]);
    // The first melting is at the outermost node, a0·(1 − N^−3) here.
    let e = &out.events.events()[0];
    assert_eq!(e.r_first_m, radii[n - 1]);
    assert!(2e-5 - e.r_first_m < 2e-5 / (n as f64).powi(3) * 1.0001);
    // The melted area is an area fraction (weights, not node counts), at most the whole
    // contact.
    assert!(
        e.melted_area > 0.0 && e.melted_area <= 1.0 + 1e-12,
        "{}",
        e.melted_area
    );
    // Probes interpolate between the graded nodes.
    assert_eq!(out.probes.radii_m.len(), 9);
    for phi in &out.probes.phi {
        assert!(phi.iter().all(|v| v.is_finite() && *v >= 0.0));
    }
}

#[test]
fn at_fixed_n_the_graded_grid_is_far_closer_to_the_converged_onset() {
    // The SFA contact (h0 = 1 nm): the uniform grid's first onset at N = 200 is 5 % late
    // (its outermost node a0 − a0/N moves with N); graded, N = 200 and N = 800 agree within
    // 1e-4 s, which the uniform grid misses by fifty times. Each run stops at its first event.
    let graded = |n: usize| {
        first_event(
            "sfa",
            &["contact.grid=graded", &format!("contact.nodes={n}")],
        )
    };
    let (g200, f200, _) = graded(200);
    let (g800, f800, _) = graded(800);
    let (u200, _, _) = first_event("sfa", &["contact.grid=uniform"]);
    // The default grid is the graded one.
    assert_eq!(first_event("sfa", &[]).0, g200);
    assert!((g200 - g800).abs() < 1e-4, "graded {g200} vs {g800}");
    assert!(
        (f200 - f800).abs() < 2e-3 * f800,
        "graded peak {f200} vs {f800}"
    );
    assert!(
        (u200 - g800).abs() > 50.0 * (g200 - g800).abs(),
        "uniform {u200}"
    );
}
