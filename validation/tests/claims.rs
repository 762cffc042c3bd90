//! The claims logic on small synthetic outputs: each criterion passes on data that has the
//! property and fails on data that lacks it; missing runs fail claims instead of panicking.

use stickslip_validation::claims::{
    Runs, c2_part, c4_events_part, c4_probes_part, c5_part, c8_part, c9_periodic_part, c10_part,
    cv, diffs, evaluate, probe_melts,
};
use stickslip_validation::data::{Event, Events, Probes, RunInfo, RunOutput, Series, Table};
use stickslip_validation::plot::decimate;

fn info() -> RunInfo {
    RunInfo {
        radius_m: 2e-5,
        melt_threshold: 0.01,
        velocity_m_per_s: 1.0,
        stiffness_n_per_m: Some(500.0),
        mass_kg: Some(0.1),
        tau_max_pa: 1e6,
        nodes: 200,
        scheme: "accurate".into(),
        dt_s: 1e-8,
        end_s: 1e-3,
        steps: 100_000,
        wall_seconds: 1.0,
        status: "ok".into(),
    }
}

fn event(k: usize, t: f64, x: f64) -> Event {
    Event {
        k,
        t_onset_s: t,
        r_first_m: 1.99e-5,
        x_onset_m: x,
        f_peak_n: 1e-3,
        r_min_m: Some(0.0),
        t_center_s: Some(t + 2e-7),
        t_end_s: Some(t + 3e-7),
        max_melted_fraction: Some(0.07),
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
        name: "synthetic".into(),
        series,
        events: Events {
            events: onsets
                .iter()
                .zip(xs)
                .enumerate()
                .map(|(k, (&t, &x))| event(k + 1, t, x))
                .collect(),
            has_front_columns: true,
        },
        probes: None,
        profiles: Vec::new(),
        info: info(),
    }
}

#[test]
fn cv_and_diffs() {
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
}

#[test]
fn probe_meltings_are_grouped_by_event_and_timed() {
    let mut r = run(&[99.5e-6, 499.5e-6], &[1e-7, 2e-7]);
    let t: Vec<f64> = (0..1000).map(|i| i as f64 * 1e-6).collect();
    let mut phi = vec![1.0; t.len()];
    phi[100] = 0.005; // event 1: one sample below the threshold
    phi[500] = 0.005; // event 2: three samples, flickering
    phi[501] = 0.02;
    phi[502] = 0.005;
    r.probes = Some(Probes {
        radii_m: vec![1e-5],
        t_s: t,
        phi: vec![phi],
        t_melt_s: vec![],
    });
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
    let t: Vec<f64> = (0..1000).map(|i| i as f64 * 1e-6).collect();
    let mut outer = vec![-1.0; t.len()];
    let mut inner = vec![-1.0; t.len()];
    for i in 101..t.len() {
        outer[i] = 100.2e-6;
        inner[i] = 100.4e-6;
    }
    let mut phi_inner = vec![1.0; t.len()];
    phi_inner[101] = 0.5;
    r.probes = Some(Probes {
        radii_m: vec![1.8e-5, 2e-6],
        t_s: t.clone(),
        phi: vec![vec![1.0; t.len()], phi_inner],
        t_melt_s: vec![outer, inner.clone()],
    });
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
    if let Some(p) = r.probes.as_mut() {
        p.t_melt_s[0] = inner
            .iter()
            .map(|&v| if v > 0.0 { 100.6e-6 } else { v })
            .collect();
    }
    assert!(!c4_probes_part(&r).pass);
}

#[test]
fn c4_uses_the_innermost_probe_when_events_csv_has_no_front_columns() {
    let mut r = run(&[99.5e-6], &[1e-7]);
    assert!(
        c4_events_part(&r).pass,
        "t_center after the onset, r_first at the edge"
    );
    r.events.has_front_columns = false;
    for e in &mut r.events.events {
        e.t_center_s = None;
    }
    assert!(!c4_events_part(&r).pass, "no front columns and no probes");
    let t: Vec<f64> = (0..1000).map(|i| i as f64 * 1e-6).collect();
    let mut inner = vec![1.0; t.len()];
    inner[101] = 0.0;
    r.probes = Some(Probes {
        radii_m: vec![1.8e-5, 2e-6],
        t_s: t.clone(),
        phi: vec![vec![1.0; t.len()], inner],
        t_melt_s: vec![],
    });
    let part = c4_events_part(&r);
    assert!(part.pass, "{}", part.text);
    r.events.events[0].r_first_m = 1e-6;
    assert!(!c4_events_part(&r).pass, "first melting near the axis");
}

#[test]
fn missing_runs_fail_every_claim_without_panicking() {
    let claims = evaluate(&Runs::default());
    assert_eq!(claims.len(), 10);
    assert!(claims.iter().all(|c| !c.pass));
    assert!(claims[0].value_text.contains("missing"));
}

#[test]
fn tables_parse_empty_cells_and_events_keep_optional_columns() {
    let t = Table::parse("a,b\n1,\n2,3e-1\n", "t.csv").unwrap();
    assert!(t.get("b").unwrap()[0].is_nan());
    assert_eq!(t.get("b").unwrap()[1], 0.3);
    let e = Events::parse(
        "k,t_onset,r_first,x_onset,f_peak,r_min,t_center,t_end,max_melted_fraction\n\
         1,1e-4,2e-5,1e-7,1e-3,0e0,,,5e-2\n",
    )
    .unwrap();
    assert!(e.has_front_columns);
    assert_eq!(e.events[0].t_center_s, None);
    assert_eq!(e.events[0].r_min_m, Some(0.0));
    let minimal =
        Events::parse("k,t_onset,r_first,x_onset,f_peak\n1,1e-4,2e-5,1e-7,1e-3\n").unwrap();
    assert!(!minimal.has_front_columns);
    assert!(Table::parse("a,b\n1\n", "t.csv").is_err());
}

#[test]
fn decimation_keeps_the_extremes() {
    let pts: Vec<(f64, f64)> = (0..100_000)
        .map(|i| {
            (
                i as f64,
                if i == 54_321 {
                    -5.0
                } else {
                    (i as f64 * 0.01).sin()
                },
            )
        })
        .collect();
    let d = decimate(&pts, 500);
    assert!(d.len() <= 1002);
    assert!(d.iter().any(|&(x, y)| x == 54_321.0 && y == -5.0));
    assert!(d.windows(2).all(|w| w[0].0 <= w[1].0));
}
