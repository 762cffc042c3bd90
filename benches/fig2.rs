//! Criterion bench: the whole fig2 run (1.3 ms) in-process through the driver, per scheme, at
//! N = 200.
//!
//! accurate: the scene's defaults (adaptive steps at tolerance 1e-4, fast operators); literal:
//! the paper's scheme at Δt = 1e-8 s with direct sums. Nothing is recorded (a null sink); the
//! end-to-end process timings of `cargo xtask bench` (reports/performance.md) add start-up and
//! output.

use criterion::{Criterion, criterion_group, criterion_main};
use stickslip_benches::{Setting, scene};
use stickslip_run::keys::words::Scheme;
use stickslip_run::keys::{contact, time};
use stickslip_run::{Control, NullSink};

fn run(sets: &[Setting]) -> usize {
    let scene = scene("fig2", sets);
    stickslip_run::run(&scene, &mut NullSink, &mut Control::default())
        .expect("valid scene")
        .events
        .len()
}

fn fig2(c: &mut Criterion) {
    let mut group = c.benchmark_group("fig2_n200");
    group.sample_size(10);
    group.bench_function("accurate_adaptive", |b| {
        b.iter(|| run(&[contact::NODES.set(200)]))
    });
    group.bench_function("literal_dt1e-8", |b| {
        b.iter(|| run(&[contact::NODES.set(200), time::SCHEME.set(Scheme::Literal)]))
    });
    group.finish();
}

criterion_group!(benches, fig2);
criterion_main!(benches);
