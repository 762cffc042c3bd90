//! Criterion bench: the whole fig2 run (1.3 ms) in-process, per scheme, at N = 200.
//!
//! accurate: adaptive steps at the default tolerance 1e-4 and the fast operators (the CLI's
//! defaults); literal: the paper's scheme at Δt = 1e-8 s with direct sums. The end-to-end
//! process timings of `cargo xtask bench` (reports/performance.md) add start-up and output.

use criterion::{Criterion, criterion_group, criterion_main};
use stickslip_core::config::{AdaptiveConfig, Scheme, SimConfig};
use stickslip_core::sim::Simulation;

const END_S: f64 = 1.3e-3;

fn fig2_accurate() -> usize {
    let mut c = SimConfig::fig2(Scheme::Accurate);
    c.contact.nodes = 200;
    c.time.adaptive = Some(AdaptiveConfig {
        tolerance: 1e-4,
        dt_max_s: END_S / 1000.0,
        dt_min_s: 1e-14,
    });
    let mut sim = Simulation::new(c, 1e-5).expect("valid scene");
    while sim.time_s() < END_S {
        sim.step_adaptive(END_S).expect("stable");
    }
    sim.events().len()
}

fn fig2_literal() -> usize {
    let mut c = SimConfig::fig2(Scheme::Literal);
    c.contact.nodes = 200;
    let mut sim = Simulation::new(c, 1e-5).expect("valid scene");
    while sim.time_s() < END_S - 0.5e-8 {
        sim.step(1e-8).expect("stable");
    }
    sim.events().len()
}

fn fig2(c: &mut Criterion) {
    let mut group = c.benchmark_group("fig2_n200");
    group.sample_size(10);
    group.bench_function("accurate_adaptive", |b| b.iter(fig2_accurate));
    group.bench_function("literal_dt1e-8", |b| b.iter(fig2_literal));
    group.finish();
}

criterion_group!(benches, fig2);
criterion_main!(benches);
