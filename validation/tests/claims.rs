//! The claims logic on small synthetic outputs built from the run library's schema types: each
//! criterion passes on data that has the property and fails on data that lacks it; missing
//! runs fail claims instead of panicking.

use std::path::Path;
use std::sync::OnceLock;
use stickslip_core::sim::events::MeltingEvent;
use stickslip_report::stats::{cv, diffs};
use stickslip_run::schema::Table;
use stickslip_run::schema::events::Events;
use stickslip_run::schema::probes::Probes;
use stickslip_run::schema::profiles::Profiles;
use stickslip_run::schema::run_info::RunInfo;
use stickslip_run::schema::series::Series;
use stickslip_run::{RunOutput, RunStatus, Scene};
use stickslip_validation::claims::{
    Runs, c2_part, c4_events_part, c4_probes_part, c5_part, c8_part, c9_periodic_part, c10_part,
    evaluate, probe_melts,
};

/// run.json of fig2 at N = 200, end = 1 ms (a0 = 20 µm, spring K = 500 N/m, m = 0.1 kg,
/// V0 = 1 m/s, τmax = 1e6 Pa), as a finished run.
fn info() -> RunInfo {
    static INFO: OnceLock<RunInfo> = OnceLock::new();
    INFO.get_or_init(|| {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/fig2.toml");
        let scene = Scene::from_path(
            &path,
            &[
                "contact.nodes=200",
                "time.end=1e-3",
                "output.profile_times=[1e-3]",
            ],
        )
        .expect("fig2 resolves");
        let preflight = stickslip_run::check::check(&scene)
            .expect("fig2 checks")
            .preflight;
        let mut info = RunInfo::starting(&scene, &preflight, Vec::new());
        info.status = RunStatus::Ok;
        info
    })
    .clone()
}

fn event(k: usize, t: f64, x: f64) -> MeltingEvent {
    MeltingEvent {
        k,
        t_onset_s: t,
        r_first_m: 1.99e-5,
        x_onset_m: x,
        f_peak_n: 1e-3,
        r_min_m: 0.0,
        t_center_s: Some(t + 2e-7),
        max_melted_fraction: 0.07,
        t_end_s: Some(t + 3e-7),
        recovery: 1.0,
        f_mean_n: 5e-4,
        melted_area: 1.0,
        energy: None,
    }
}

/// A run with events at `onsets` (s) and stamp positions `xs` (m); series sampled every µs.
fn run(onsets: &[f64], xs: &[f64]) -> RunOutput {
    let n = 1001;
    let t: Vec<f64> = (0..n).map(|i| i as f64 * 1e-6).collect();
    let series = Series {
        x_m: t.clone(),
        v_m_per_s: vec![1.0; n],
        f_n: vec![0.0; n],
        f_1d_n: vec![0.0; n],
        phi_mean: vec![1.0; n],
        eps_mean: vec![0.0; n],
        melted_fraction: vec![0.0; n],
        t_s: t,
    };
    RunOutput {
        series,
        events: Events(
            onsets
                .iter()
                .zip(xs)
                .enumerate()
                .map(|(k, (&t, &x))| event(k + 1, t, x))
                .collect(),
        ),
        slips: stickslip_run::schema::slips::Slips::default(),
        profiles: Profiles::default(),
        probes: Probes::new(&[]),
        info: info(),
    }
}

/// Probes at `radii_m` sampled every µs: φ and t_melt columns as given.
fn probes(radii_m: &[f64], phi: Vec<Vec<f64>>, t_melt_s: Vec<Vec<f64>>) -> Probes {
    Probes {
        radii_m: radii_m.to_vec(),
        t_s: (0..1000).map(|i| i as f64 * 1e-6).collect(),
        phi,
        t_melt_s,
    }
}

#[test]
fn cv_and_diffs_of_the_kit_are_the_sample_ones() {
    assert_eq!(diffs(&[1.0, 3.0, 6.0]), vec![2.0, 3.0]);
    assert_eq!(cv(&[2.0, 2.0, 2.0]), 0.0);
    assert!((cv(&[1.0, 3.0]) - 2f64.sqrt() / 2.0).abs() < 1e-15);
    assert!(cv(&[1.0]).is_nan());
}

#[test]
fn c2_wants_every_interval_shorter_than_the_one_before() {
    let x = [0.0; 4];
    assert!(c2_part(&run(&[0.5e-3, 0.7e-3, 0.85e-3, 0.95e-3], &x)).pass);
    assert!(!c2_part(&run(&[0.5e-3, 0.7e-3, 0.85e-3, 1.0e-3], &x)).pass);
    assert!(
        !c2_part(&run(&[0.5e-3, 0.7e-3], &x[..2])).pass,
        "one interval shows nothing"
    );
}

#[test]
fn c9_and_c10_measure_spread() {
    let even_x = run(&[1e-4, 2e-4, 3e-4, 4e-4], &[1e-7, 2e-7, 3e-7, 4e-7]);
    assert!(c9_periodic_part(&even_x).pass);
    assert!(c10_part(&even_x).pass);
    let uneven = run(&[1e-4, 2e-4, 3.5e-4, 4e-4], &[1e-7, 2e-7, 3.5e-7, 4e-7]);
    assert!(!c9_periodic_part(&uneven).pass);
    assert!(!c10_part(&uneven).pass);
}

#[test]
fn c8_flags_any_friction_or_departure_from_the_free_spring() {
    let mut r = run(&[0.0], &[0.0]);
    let omega = (500.0_f64 / 0.1).sqrt();
    r.series.x_m = r
        .series
        .t_s
        .iter()
        .map(|&t| t - (omega * t).sin() / omega)
        .collect();
    r.series.melted_fraction = vec![1.0; r.series.len()];
    assert!(c8_part(&r).pass, "{}", c8_part(&r).text);
    let mut rubbing = r.clone();
    rubbing.series.f_n[10] = 1e-6;
    assert!(!c8_part(&rubbing).pass);
    let mut dragged = r.clone();
    dragged.series.x_m[500] *= 1.0 - 1e-4;
    assert!(!c8_part(&dragged).pass);
    // A first-order film above the melting temperature that starts as a metastable solid is
    // not C8's liquid start, whatever its series.
    let mut metastable = r.clone();
    metastable.info.derived.metastable_solid = Some(true);
    let part = c8_part(&metastable);
    assert!(
        !part.pass && part.text.contains("metastable"),
        "{}",
        part.text
    );
}

#[test]
fn sampled_meltings_are_grouped_by_event_and_timed() {
    // No located melting (t_melt = −1 throughout): the meltings are the samples below the
    // threshold.
    let mut r = run(&[99.5e-6, 499.5e-6], &[1e-7, 2e-7]);
    let mut phi = vec![1.0; 1000];
    phi[100] = 0.005; // event 1: one sample below the threshold
    phi[500] = 0.005; // event 2: three samples, flickering
    phi[501] = 0.02;
    phi[502] = 0.005;
    r.probes = probes(&[1e-5], vec![phi], vec![vec![-1.0; 1000]]);
    let m = probe_melts(&r);
    assert_eq!(m.len(), 2);
    assert_eq!(m[0].event, 0);
    assert!((m[1].t_solid_s.unwrap() - m[1].t_melt_s - 3e-6).abs() < 1e-12);
    let c5 = c5_part(&r);
    assert!(c5.pass, "{}", c5.text);
}

#[test]
fn located_meltings_count_although_sampled_phi_never_drops_below_the_threshold() {
    // Instantaneous melting: φ touches the threshold between samples; the t_melt column
    // dates it. Probe 0 (outer) melts at 100.2 µs, probe 1 (inner) at 100.4 µs.
    let mut r = run(&[100.1e-6], &[1e-7]);
    let mut outer = vec![-1.0; 1000];
    let mut inner = vec![-1.0; 1000];
    for i in 101..1000 {
        outer[i] = 100.2e-6;
        inner[i] = 100.4e-6;
    }
    let mut phi_inner = vec![1.0; 1000];
    phi_inner[101] = 0.5;
    r.probes = probes(
        &[1.8e-5, 2e-6],
        vec![vec![1.0; 1000], phi_inner],
        vec![outer, inner.clone()],
    );
    let m = probe_melts(&r);
    assert_eq!(m.len(), 2);
    assert!((m[0].t_melt_s - 100.2e-6).abs() < 1e-15);
    assert_eq!(
        m[1].t_solid_s,
        Some(101e-6),
        "first sample at or above the threshold"
    );
    assert!(c4_probes_part(&r).pass);
    // Swapped: the inner probe first is an order violation.
    r.probes.t_melt_s[0] = inner
        .iter()
        .map(|&v| if v > 0.0 { 100.6e-6 } else { v })
        .collect();
    assert!(!c4_probes_part(&r).pass);
}

#[test]
fn c4_wants_the_edge_first_and_the_front_at_the_axis_later() {
    let mut r = run(&[99.5e-6], &[1e-7]);
    let part = c4_events_part(&r);
    assert!(part.pass, "{}", part.text);
    // events.csv with an empty t_center: the front never reached the axis.
    let text = r.events.to_csv().replace(
        &format!(",{:e},", r.events.events()[0].t_center_s.unwrap()),
        ",,",
    );
    r.events = Events::parse(&text).expect("events.csv parses");
    assert_eq!(r.events.events()[0].t_center_s, None);
    assert!(!c4_events_part(&r).pass, "no arrival at the axis");
    let mut near_axis = run(&[99.5e-6], &[1e-7]);
    near_axis.events.0[0].r_first_m = 1e-6;
    assert!(
        !c4_events_part(&near_axis).pass,
        "first melting near the axis"
    );
    assert!(!c4_probes_part(&near_axis).pass, "no probes");
}

#[test]
fn missing_runs_fail_every_claim_without_panicking() {
    let claims = evaluate(&Runs::default());
    assert_eq!(claims.len(), 10);
    assert!(claims.iter().all(|c| !c.pass));
    assert!(claims[0].value_text.contains("missing"));
}
