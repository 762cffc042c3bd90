//! Shared helpers of the criterion benches (the benches themselves are the `[[bench]]` targets).

pub mod evaluation_floor;

use std::path::Path;
use stickslip_run::driver::{Control, Driver, Limit, NullSink};
pub use stickslip_run::keys::Setting;
use stickslip_run::keys::words::Stepping;
use stickslip_run::keys::{output, time};
use stickslip_run::{ResolvedScene, Scene};

/// The shipped scene `name` of `validation/scenes` with `sets` applied.
///
/// # Panics
/// If the scene does not resolve (the benches use fixed, valid overrides).
#[must_use]
pub fn scene(name: &str, sets: &[Setting]) -> ResolvedScene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../validation/scenes")
        .join(format!("{name}.toml"));
    Scene::from_path(&path, &[] as &[&str])
        .and_then(|s| s.with_settings(sets))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// fig2 with fixed steps of 20 ns over a long interval (so the bench never reaches the end),
/// no rows recorded, advanced into its first stick phase (t = 0.3 ms) so the step measured is
/// a typical one rather than the trivial first.
///
/// # Panics
/// If the scene does not start (the benches use fixed, valid overrides).
#[must_use]
pub fn warmed(extra: &[Setting]) -> Driver {
    let mut sets = vec![
        time::DT.set(2e-8),
        time::END.set(1.0),
        time::STEPPING.set(Stepping::Fixed),
        output::SERIES_INTERVAL.set(1.0),
        output::PROFILE_TIMES.set(vec![1.0]),
    ];
    sets.extend_from_slice(extra);
    let scene = scene("fig2", &sets);
    let mut driver = Driver::start(&scene, &mut NullSink).expect("valid scene");
    driver
        .advance(&mut NullSink, &mut Control::default(), Limit::Time(3e-4))
        .expect("no I/O");
    driver
}

/// One step of `driver`, nothing recorded.
///
/// # Panics
/// If the run stops (the warmed scene ends at 1 s, far beyond any bench).
pub fn step(driver: &mut Driver) {
    let stop = driver
        .advance(&mut NullSink, &mut Control::default(), Limit::Steps(1))
        .expect("no I/O");
    assert!(stop.is_none(), "the run stopped: {stop:?}");
}
