//! Criterion bench: cost of one time step per effect switched on or off, and per N.
//!
//! Shows that what a scene leaves off costs nothing: a rigid substrate applies no operator,
//! floor/off noise draws no random numbers, the homogeneous model steps a single node.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use stickslip_core::config::{ContactModel, Scheme, SimConfig, Substrate};
use stickslip_core::noise::NoiseKind;
use stickslip_core::sim::Simulation;

/// A fig2 simulation advanced into its first stick phase (t = 0.3 ms), so the step measured is
/// a typical one rather than the trivial first.
fn warmed(config: SimConfig) -> Simulation {
    let dt = config.time.dt_s;
    let mut sim = Simulation::new(config, 1e-5).expect("valid scene");
    while sim.time_s() < 3e-4 {
        sim.step(dt).expect("stable");
    }
    sim
}

fn base(scheme: Scheme, nodes: usize) -> SimConfig {
    let mut c = SimConfig::fig2(scheme);
    c.contact.nodes = nodes;
    c.time.dt_s = 2e-8;
    c
}

fn effects(c: &mut Criterion) {
    let mut group = c.benchmark_group("step_effects_n200");
    let variants: Vec<(&str, SimConfig)> = vec![
        ("accurate_elastic_floor", base(Scheme::Accurate, 200)),
        ("accurate_rigid_substrate", {
            let mut c = base(Scheme::Accurate, 200);
            c.contact.substrate = Substrate::Rigid;
            c
        }),
        ("accurate_noise_off", {
            let mut c = base(Scheme::Accurate, 200);
            c.noise = NoiseKind::Off;
            c
        }),
        ("accurate_noise_gaussian", {
            let mut c = base(Scheme::Accurate, 200);
            c.noise = NoiseKind::Gaussian {
                sigma_per_sqrt_s: 1.0,
                seed: 1,
            };
            c
        }),
        ("accurate_homogeneous", {
            let mut c = base(Scheme::Accurate, 200);
            c.contact.model = ContactModel::Homogeneous;
            c
        }),
        ("literal_elastic_floor", base(Scheme::Literal, 200)),
        ("literal_rigid_substrate", {
            let mut c = base(Scheme::Literal, 200);
            c.contact.substrate = Substrate::Rigid;
            c
        }),
    ];
    for (name, config) in variants {
        let dt = config.time.dt_s;
        let mut sim = warmed(config);
        group.bench_function(name, |b| b.iter(|| sim.step(dt).expect("stable")));
    }
    group.finish();
}

fn per_n(c: &mut Criterion) {
    let mut group = c.benchmark_group("step_per_n");
    group.sample_size(20);
    for scheme in [Scheme::Literal, Scheme::Accurate] {
        for n in [125usize, 250, 500, 1000, 2000] {
            let config = base(scheme, n);
            let dt = config.time.dt_s;
            let mut sim = warmed(config);
            group.throughput(Throughput::Elements(n as u64));
            group.bench_with_input(BenchmarkId::new(format!("{scheme:?}"), n), &n, |b, _| {
                b.iter(|| sim.step(dt).expect("stable"))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, effects, per_n);
criterion_main!(benches);
