//! The stamp's scale on the h0 = 1 nm contact (validation/scenes/sfa.toml): under a soft
//! spring (K = 500 N/m, V0 = 1 µm/s) the first slip of the stamp is made of many meltings of
//! the film; slips.csv, the summary and Python read the same slips; a checkpoint carries the
//! tracker, so a resumed run finds the same slips.

use crate::common;

use stickslip_run::cycles::StampRegime;
use stickslip_run::driver::{Control, Driver, Limit, NullSink};
use stickslip_run::{DirOptions, RunOutput, Scene, run_to_dir};

#[test]
fn the_first_slip_of_a_soft_spring_holds_about_78_meltings() {
    // Through the first slip (0.944 → 0.989 s) and a little of the reloading after it.
    let scene = Scene::from_path(
        &common::scene("sfa"),
        &[
            "drive.stiffness=500",
            "time.end=1.0",
            "output.series_interval=1e-2",
            "output.profile_times=[1.0]",
        ],
    )
    .unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("run");
    let options = DirOptions {
        force: false,
        checkpoint_every_s: 0.0,
    };
    let outcome = run_to_dir(&scene, &dir, &options, &mut Control::default()).unwrap();
    assert_eq!(outcome.slips.len(), 1, "{:?}", outcome.slips);
    let slip = outcome.slips[0];
    println!("first slip: {slip:?}");
    // About 76 meltings (76 at N = 200 … 800 on the default graded grid, docs/model.md; the
    // count is the film's, so a few more or fewer would still be the same physics).
    assert!(
        (74..=82).contains(&slip.meltings),
        "{} meltings",
        slip.meltings
    );
    // It starts at the first melting and drops nearly the whole spring force: the stamp jumps
    // about 1 µm.
    let first_onset = outcome.summary.t_first_onset.unwrap();
    assert!(slip.t_start_s >= first_onset && slip.t_start_s - first_onset < 1e-3);
    assert!(slip.drop_n() > 0.9 * slip.f_start_n, "{slip:?}");
    assert!((0.8e-6..1.2e-6).contains(&slip.jump_m()), "{slip:?}");
    // Every melting in it is one of the run's: the slip holds every onset up to its end.
    let inside = outcome
        .events
        .iter()
        .filter(|e| e.t_onset_s <= slip.t_end_s)
        .count();
    assert_eq!(slip.meltings, inside);
    assert_eq!(outcome.summary.n_slips, 1);
    // One slip, and the run ends while the stamp reloads: neither recurring nor steady yet.
    assert_eq!(outcome.summary.stamp_regime, Some(StampRegime::Transient));
    // slips.csv holds it bit for bit, and run.json's summary its statistics.
    let read = RunOutput::read(&dir).unwrap();
    assert_eq!(read.slips.slips(), &outcome.slips[..]);
    assert_eq!(read.info.summary.as_ref(), Some(&outcome.summary));
    let cycles = outcome.summary.cycles.as_ref().unwrap();
    assert!((cycles.settled_from_s - (slip.t_end_s + 0.5 * (1.0 - slip.t_end_s))).abs() < 1e-12);
    assert_eq!(cycles.slips.count, 0);
}

#[test]
fn a_resumed_run_finds_the_same_slips() {
    // fig2's film under the rigid drive, whose force is F: a slip at every melting; paused
    // mid-run, the tracker travels through the driver's state, and the slips are those of a
    // run without a pause.
    let scene = Scene::from_path_unsetting(
        &common::scene("fig2"),
        &["drive.stiffness", "drive.mass", "drive.integrator"],
        &[
            "contact.nodes=40",
            "time.end=2e-5",
            "drive.kind=rigid",
            "output.profile_times=[2e-5]",
        ],
    )
    .unwrap();
    let whole = stickslip_run::run(&scene, &mut NullSink, &mut Control::default()).unwrap();
    assert!(whole.slips.len() >= 20, "{:?}", whole.slips);
    let mut driver = Driver::start(&scene, &mut NullSink).unwrap();
    assert!(
        driver
            .advance(&mut NullSink, &mut Control::default(), Limit::Time(1e-5))
            .unwrap()
            .is_none()
    );
    let snapshot = driver.snapshot();
    let (sim, state) = (snapshot.sim.clone(), snapshot.driver.clone());
    let preflight = driver.preflight().clone();
    let resumed = Driver::restore(&scene, preflight, sim, state)
        .unwrap()
        .run_to_end(&mut NullSink, &mut Control::default())
        .unwrap();
    assert_eq!(resumed.slips, whole.slips);
    assert_eq!(resumed.summary, whole.summary);
}

#[test]
fn before_its_first_slip_the_stamp_creeps() {
    // K = 5000 N/m loads the contact quasi-statically: the first melting comes at ≈ 0.107 s,
    // so in 0.05 s the spring force only grows.
    let scene = Scene::from_path(
        &common::scene("sfa"),
        &[
            "contact.nodes=50",
            "time.end=0.05",
            "output.profile_times=[0.05]",
        ],
    )
    .unwrap();
    let outcome = stickslip_run::run(&scene, &mut NullSink, &mut Control::default()).unwrap();
    assert!(outcome.slips.is_empty() && outcome.events.is_empty());
    assert_eq!(outcome.summary.stamp_regime, Some(StampRegime::Creep));
    let cycles = outcome.summary.cycles.unwrap();
    assert_eq!((cycles.meltings.count, cycles.slips.count), (0, 0));
    assert_eq!(cycles.settled_from_s, 0.025);
}
