//! Criterion bench: cost of one time step per effect switched on or off, and per N.
//!
//! Shows that what a scene leaves off costs nothing: a rigid substrate applies no operator,
//! floor/off noise draws no random numbers, the homogeneous model steps a single node. Each
//! step is one iteration of the driver with nothing recorded.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use stickslip_benches::scene;
use stickslip_run::driver::{Control, Driver, Limit, NullSink};

/// fig2 with fixed steps of 20 ns over a long interval (so the bench never reaches the end),
/// no rows recorded, advanced into its first stick phase (t = 0.3 ms) so the step measured is
/// a typical one rather than the trivial first.
fn warmed(extra: &[&str]) -> Driver {
    let mut sets = vec![
        "time.dt=2e-8",
        "time.end=1",
        "time.stepping=fixed",
        "output.series_interval=1",
        "output.profile_times=[1]",
    ];
    sets.extend_from_slice(extra);
    if extra.contains(&"time.scheme=literal") {
        sets.retain(|s| *s != "time.stepping=fixed");
    }
    let scene = scene("fig2", &sets);
    let mut driver = Driver::start(&scene, &mut NullSink).expect("valid scene");
    driver
        .advance(&mut NullSink, &mut Control::default(), Limit::Time(3e-4))
        .expect("no I/O");
    driver
}

fn step(driver: &mut Driver) {
    let stop = driver
        .advance(&mut NullSink, &mut Control::default(), Limit::Steps(1))
        .expect("no I/O");
    assert!(stop.is_none(), "the run stopped: {stop:?}");
}

fn effects(c: &mut Criterion) {
    let mut group = c.benchmark_group("step_effects_n200");
    let variants: [(&str, &[&str]); 7] = [
        ("accurate_elastic_floor", &[]),
        ("accurate_rigid_substrate", &["contact.substrate=rigid"]),
        ("accurate_noise_off", &["lubricant.noise.kind=off"]),
        (
            "accurate_noise_gaussian",
            &["lubricant.noise.kind=gaussian"],
        ),
        ("accurate_homogeneous", &["contact.model=homogeneous"]),
        ("literal_elastic_floor", &["time.scheme=literal"]),
        (
            "literal_rigid_substrate",
            &["time.scheme=literal", "contact.substrate=rigid"],
        ),
    ];
    for (name, sets) in variants {
        let mut all = vec!["contact.nodes=200"];
        all.extend_from_slice(sets);
        let mut driver = warmed(&all);
        group.bench_function(name, |b| b.iter(|| step(&mut driver)));
    }
    group.finish();
}

fn per_n(c: &mut Criterion) {
    let mut group = c.benchmark_group("step_per_n");
    group.sample_size(20);
    for scheme in ["literal", "accurate"] {
        for n in [125usize, 250, 500, 1000, 2000] {
            let nodes = format!("contact.nodes={n}");
            let scheme_set = format!("time.scheme={scheme}");
            let mut driver = warmed(&[&nodes, &scheme_set]);
            group.throughput(Throughput::Elements(n as u64));
            group.bench_with_input(BenchmarkId::new(scheme, n), &n, |b, _| {
                b.iter(|| step(&mut driver))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, effects, per_n);
criterion_main!(benches);
