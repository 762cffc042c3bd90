//! `time.until = "periodic"`: a rigid drive's stick–slip settles into repeating cycles and the
//! run stops there, with the regime of the steady state; a longer window changes nothing; a
//! spring-driven fig2, whose cycles keep shortening, runs to its end and is not steady.

use crate::common;
use stickslip_run::scene::Scene;
use stickslip_run::{Control, StopReason, run_in_memory};

fn rigid(extra: &[&str]) -> stickslip_run::scene::ResolvedScene {
    let mut sets = vec![
        "contact.nodes=30",
        "temperature.A0=1e6",
        "drive.velocity=0.05",
    ];
    sets.extend(extra);
    Scene::from_path(&common::scene("rigid"), &sets).unwrap()
}

#[test]
fn a_periodic_run_stops_once_its_cycles_repeat_and_a_longer_window_agrees() {
    let (to_end, _) = run_in_memory(&rigid(&[]), &mut Control::default()).unwrap();
    assert_eq!(to_end.stop, StopReason::End);
    let (periodic, _) = run_in_memory(
        &rigid(&["time.until=\"periodic\""]),
        &mut Control::default(),
    )
    .unwrap();
    assert_eq!(
        periodic.stop,
        StopReason::Periodic,
        "{:?}",
        periodic.summary
    );
    assert!(periodic.summary.steady);
    assert!(periodic.t_final_s < to_end.t_final_s);
    assert_eq!(periodic.summary.regime, to_end.summary.regime);
    // The last steady_cycles (3) cycles agree within steady_rtol (1e-3), checked here directly.
    let ev = &periodic.events;
    let n = ev.len();
    assert!(n >= 4, "{n} events");
    let period = |k: usize| ev[k].t_onset_s - ev[k - 1].t_onset_s;
    for k in n - 3..n {
        assert!((period(k) / period(n - 1) - 1.0).abs() <= 1e-3);
        assert!((ev[k].f_peak_n / ev[n - 1].f_peak_n - 1.0).abs() <= 1e-3);
    }
    // Doubling the window: the same stop, time and regime (the stop does not depend on end).
    let end = rigid(&[]).config.time.end_s;
    let longer = format!("time.end={:e}", 2.0 * end);
    let profile = format!("output.profile_times=[{:e}]", 2.0 * end);
    let (doubled, _) = run_in_memory(
        &rigid(&["time.until=\"periodic\"", &longer, &profile]),
        &mut Control::default(),
    )
    .unwrap();
    assert_eq!(doubled.stop, StopReason::Periodic);
    assert_eq!(doubled.summary.regime, periodic.summary.regime);
    assert_eq!(doubled.events.len(), periodic.events.len());
}

#[test]
fn fig2s_shortening_cycles_are_not_steady() {
    let scene = Scene::from_path(
        &common::scene("fig2"),
        &["contact.nodes=50", "time.until=\"periodic\""],
    )
    .unwrap();
    let (out, _) = run_in_memory(&scene, &mut Control::default()).unwrap();
    assert_eq!(out.stop, StopReason::End);
    assert!(!out.summary.steady);
    assert_eq!(out.events.len(), 10);
}

#[test]
fn bad_steady_keys_name_the_key() {
    for (set, key) in [
        ("time.until=\"forever\"", "time.until"),
        ("time.steady_cycles=0", "time.steady_cycles"),
        ("time.steady_rtol=0", "time.steady_rtol"),
        ("time.steady_rtol=2", "time.steady_rtol"),
    ] {
        let e = Scene::from_path(&common::scene("rigid"), &[set]).unwrap_err();
        assert!(e.to_string().contains(key), "{set}: {e}");
    }
}
