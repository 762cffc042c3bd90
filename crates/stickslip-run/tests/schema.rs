//! The output schema: every file written and read back keeps every bit, and a run kept in
//! memory equals the same run written to a directory and read back through the schema.

use crate::common;
use stickslip_run::schema::Table;

use stickslip_run::schema::events::Events;
use stickslip_run::schema::probes::Probes;
use stickslip_run::schema::profiles::Profiles;
use stickslip_run::schema::run_info::RunInfo;
use stickslip_run::schema::series::Series;
use stickslip_run::{Control, DirOptions, RunOutput, Scene, run_in_memory, run_to_dir};

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn small_run(extra: &[&str]) -> RunOutput {
    let mut sets = vec![
        "contact.nodes=20",
        "time.end=7e-4",
        "output.profile_times=[0, 6.5e-4, 7e-4]",
        "output.probe_radii=[2e-6, 1.5e-5]",
    ];
    sets.extend_from_slice(extra);
    let scene = Scene::from_path(&common::scene("fig2"), &sets).unwrap();
    run_in_memory(&scene, &mut Control::default()).unwrap().1
}

#[test]
fn every_table_round_trips_bit_for_bit() {
    let out = small_run(&["lubricant.noise.kind=gaussian"]);
    assert!(out.series.len() > 100 && !out.events.is_empty() && out.profiles.len() == 60);
    let series = Series::parse(&out.series.to_csv()).unwrap();
    for ((name, a), (_, b)) in out.series.columns().iter().zip(series.columns()) {
        assert_eq!(bits(a), bits(b), "series.csv {name}");
    }
    let events = Events::parse(&out.events.to_csv()).unwrap();
    for ((name, a), (_, b)) in out.events.columns().iter().zip(events.columns()) {
        assert_eq!(bits(a), bits(&b), "events.csv {name}");
    }
    let profiles = Profiles::parse(&out.profiles.to_csv()).unwrap();
    for ((name, a), (_, b)) in out.profiles.columns().iter().zip(profiles.columns()) {
        assert_eq!(bits(a), bits(b), "profiles.csv {name}");
    }
    assert_eq!(bits(&profiles.times_s()), bits(&out.profiles.times_s()));
    assert_eq!(profiles.times_s().len(), 3);
    let probes = Probes::parse(&out.probes.to_csv()).unwrap();
    assert_eq!(probes.radii_m, vec![2e-6, 1.5e-5]);
    for ((name, a), (_, b)) in out.probes.columns().iter().zip(probes.columns()) {
        assert_eq!(bits(a), bits(b), "probes.csv {name}");
    }
    let info = RunInfo::parse(&out.info.to_json()).unwrap();
    assert_eq!(info, out.info);
}

#[test]
fn special_values_keep_their_bits() {
    let mut s = Series::default();
    let mut o = stickslip_core::sim::Observables {
        t_s: 0.1 + 0.2,
        x_m: -0.0,
        v_m_per_s: f64::MIN_POSITIVE / 3.0,
        f_n: 1e300,
        f_1d_n: f64::NAN,
        phi_mean: f64::INFINITY,
        eps_mean: f64::NEG_INFINITY,
        melted_fraction: 5e-324,
    };
    s.push(&o);
    o.t_s = 1.0;
    s.push(&o);
    let back = Series::parse(&s.to_csv()).unwrap();
    for ((name, a), (_, b)) in s.columns().iter().zip(back.columns()) {
        assert_eq!(bits(a), bits(b), "{name}");
    }
}

#[test]
fn memory_and_directory_sinks_give_the_same_output() {
    let sets = [
        "contact.nodes=20",
        "time.end=7e-4",
        "output.profile_times=[6.5e-4, 7e-4]",
        "output.probe_radii=[1e-5]",
    ];
    let scene = Scene::from_path(&common::scene("fig2"), &sets).unwrap();
    let (_, mut memory) = run_in_memory(&scene, &mut Control::default()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    run_to_dir(
        &scene,
        dir.path(),
        &DirOptions::default(),
        &mut Control::default(),
    )
    .unwrap();
    let mut read = RunOutput::read(dir.path()).unwrap();
    assert!(read.info.wall_seconds >= 0.0);
    memory.info.wall_seconds = 0.0;
    read.info.wall_seconds = 0.0;
    assert_eq!(read.series.to_csv(), memory.series.to_csv());
    assert_eq!(read.events.to_csv(), memory.events.to_csv());
    assert_eq!(read.profiles.to_csv(), memory.profiles.to_csv());
    assert_eq!(read.probes.to_csv(), memory.probes.to_csv());
    assert_eq!(read.info, memory.info);
}

#[test]
fn run_json_names_every_column_with_its_unit_and_carries_the_summary() {
    let out = small_run(&[]);
    let series = &out.info.columns["series.csv"];
    assert_eq!(series["F"], "N");
    assert_eq!(series["t"], "s");
    assert_eq!(out.info.columns["events.csv"]["x_onset"], "m");
    assert_eq!(out.info.columns["probes.csv"]["phi@2e-6"], "–");
    assert_eq!(out.info.columns["probes.csv"]["t_melt@1.5e-5"], "s");
    let summary = out.info.summary.as_ref().expect("a summary");
    assert_eq!(summary.n_events, out.events.len());
    assert_eq!(out.info.status.name(), "ok");
    assert!(out.info.derived.melting_force > 1e-3);
}
