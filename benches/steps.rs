//! Criterion bench: cost of one time step per effect switched on or off, and per N.
//!
//! Shows that what a scene leaves off costs nothing: a rigid substrate applies no operator,
//! floor/off noise draws no random numbers, the homogeneous model steps a single node. Each
//! step is one iteration of the driver with nothing recorded.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use stickslip_benches::{Setting, step, warmed};
use stickslip_run::keys::words::{ContactModel, NoiseKindName, Scheme, Substrate};
use stickslip_run::keys::{contact, noise, time};

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
