//! Criterion bench: build and apply the MDR operators (literal and product) over a sweep of N.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use stickslip_core::grid::Grid;
use stickslip_core::mdr::{MdrOperators, Quadrature};

const SIZES: [usize; 5] = [125, 250, 500, 1000, 2000];

fn build(c: &mut Criterion) {
    let mut group = c.benchmark_group("mdr_build");
    group.sample_size(10);
    for quadrature in [Quadrature::Literal, Quadrature::Product] {
        for n in SIZES {
            group.throughput(Throughput::Elements(n as u64));
            group.bench_with_input(
                BenchmarkId::new(format!("{quadrature:?}"), n),
                &n,
                |b, &n| {
                    let grid = Grid::new(2e-5, n).expect("valid grid");
                    b.iter(|| MdrOperators::new(black_box(grid), quadrature));
                },
            );
        }
    }
    group.finish();
}

fn apply(c: &mut Criterion) {
    let mut group = c.benchmark_group("mdr_apply");
    for n in SIZES {
        let grid = Grid::new(2e-5, n).expect("valid grid");
        let ops = MdrOperators::new(grid, Quadrature::Product);
        let tau: Vec<f64> = grid.radii_m().iter().map(|r| 1.0 + r / 2e-5).collect();
        let mut q = vec![0.0; n];
        let mut u = vec![0.0; n];
        group.throughput(Throughput::Elements(n as u64));
        group.bench_with_input(BenchmarkId::new("forward", n), &n, |b, _| {
            b.iter(|| ops.forward(black_box(&tau), &mut q));
        });
        group.bench_with_input(BenchmarkId::new("back", n), &n, |b, _| {
            b.iter(|| ops.back(black_box(&tau), &mut u));
        });
        group.bench_with_input(BenchmarkId::new("compliance", n), &n, |b, _| {
            b.iter(|| ops.compliance(black_box(&tau), &mut q, &mut u));
        });
        group.bench_with_input(BenchmarkId::new("forces", n), &n, |b, _| {
            b.iter(|| ops.force_3d_n(black_box(&tau)) + ops.force_1d_n(black_box(&q)));
        });
    }
    group.finish();
}

criterion_group!(benches, build, apply);
criterion_main!(benches);
