//! Criterion bench: cost of one time step per effect switched on or off, and per N.
//!
//! Shows that what a scene leaves off costs nothing: a rigid substrate applies no operator,
//! floor/off noise draws no random numbers, the homogeneous model steps a single node. Each
//! step is one iteration of the driver with nothing recorded.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use stickslip_benches::{Setting, scene};
use stickslip_run::driver::{Control, Driver, Limit, NullSink};
use stickslip_run::keys::words::{ContactModel, NoiseKindName, Scheme, Stepping, Substrate};
use stickslip_run::keys::{contact, noise, output, time};

/// fig2 with fixed steps of 20 ns over a long interval (so the bench never reaches the end),
/// no rows recorded, advanced into its first stick phase (t = 0.3 ms) so the step measured is
/// a typical one rather than the trivial first.
fn warmed(extra: &[Setting]) -> Driver {
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

fn step(driver: &mut Driver) {
    let stop = driver
        .advance(&mut NullSink, &mut Control::default(), Limit::Steps(1))
        .expect("no I/O");
    assert!(stop.is_none(), "the run stopped: {stop:?}");
}

fn effects(c: &mut Criterion) {
    let mut group = c.benchmark_group("step_effects_n200");
    let literal = time::SCHEME.set(Scheme::Literal);
    let rigid = contact::SUBSTRATE.set(Substrate::Rigid);
    let variants: [(&str, Vec<Setting>); 7] = [
        ("accurate_elastic_floor", vec![]),
        ("accurate_rigid_substrate", vec![rigid.clone()]),
        (
            "accurate_noise_off",
            vec![noise::KIND.set(NoiseKindName::Off)],
        ),
        (
            "accurate_noise_gaussian",
            vec![noise::KIND.set(NoiseKindName::Gaussian)],
        ),
        (
            "accurate_homogeneous",
            vec![contact::MODEL.set(ContactModel::Homogeneous)],
        ),
        ("literal_elastic_floor", vec![literal.clone()]),
        ("literal_rigid_substrate", vec![literal, rigid]),
    ];
    for (name, sets) in variants {
        let mut all = vec![contact::NODES.set(200)];
        all.extend(sets);
        let mut driver = warmed(&all);
        group.bench_function(name, |b| b.iter(|| step(&mut driver)));
    }
    group.finish();
}

fn per_n(c: &mut Criterion) {
    let mut group = c.benchmark_group("step_per_n");
    group.sample_size(20);
    for scheme in [Scheme::Literal, Scheme::Accurate] {
        for n in [125usize, 250, 500, 1000, 2000] {
            let mut driver = warmed(&[contact::NODES.set(n as i64), time::SCHEME.set(scheme)]);
            group.throughput(Throughput::Elements(n as u64));
            let label = if scheme == Scheme::Literal {
                "literal"
            } else {
                "accurate"
            };
            group.bench_with_input(BenchmarkId::new(label, n), &n, |b, _| {
                b.iter(|| step(&mut driver))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, effects, per_n);
criterion_main!(benches);
