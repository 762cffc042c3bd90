//! Criterion bench: build and apply the MDR operators (literal and product) over a sweep of N,
//! and the hierarchical form of the product operators (built from entries on demand) beside
//! the dense ones.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use stickslip_core::grid::Grid;
use stickslip_core::mdr::hodlr::HodlrOperator;
use stickslip_core::mdr::{MdrOperators, OperatorEntries, OperatorForm, Quadrature, product};

const SIZES: [usize; 5] = [125, 250, 500, 1000, 2000];

/// Sizes of the hierarchical sweep (the cost-vs-N slope is fitted over 125..8000).
const HODLR_SIZES: [usize; 7] = [125, 250, 500, 1000, 2000, 4000, 8000];

/// Tolerances benched: 1e-10 (the simulations' `FAST_REL_TOL`) and 1e-8.
const HODLR_REL_TOLS: [f64; 2] = [1e-10, 1e-8];

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

/// The product forward and back operators built from their entries at `HODLR_REL_TOLS[0]`
/// (one operator at a time), and the start-up of a simulation's operators
/// (`MdrOperators::with_form(…, Fast)`: both, side by side where threads are free).
fn hodlr_build(c: &mut Criterion) {
    let mut group = c.benchmark_group("hodlr_build");
    group.sample_size(10);
    for n in HODLR_SIZES {
        let grid = Grid::new(2e-5, n).expect("valid grid");
        let forward = product::ForwardEntries::new(grid);
        let back = product::BackEntries::new(grid);
        group.throughput(Throughput::Elements(n as u64));
        group.bench_with_input(BenchmarkId::new("forward", n), &n, |b, _| {
            b.iter(|| HodlrOperator::build(black_box(&forward), HODLR_REL_TOLS[0]));
        });
        group.bench_with_input(BenchmarkId::new("back", n), &n, |b, _| {
            b.iter(|| HodlrOperator::build(black_box(&back), HODLR_REL_TOLS[0]));
        });
        group.bench_with_input(BenchmarkId::new("with_form_fast", n), &n, |b, _| {
            b.iter(|| {
                MdrOperators::with_form(black_box(grid), Quadrature::Product, OperatorForm::Fast)
            });
        });
    }
    group.finish();
}

/// Apply of the compressed product operators, and of the dense packed ones single-threaded
/// (`TriangularOperator::apply`, the like-for-like baseline; `mdr_apply` above shares rows
/// among threads from N = 512 on).
fn hodlr_apply(c: &mut Criterion) {
    let mut group = c.benchmark_group("hodlr_apply");
    for n in HODLR_SIZES {
        let grid = Grid::new(2e-5, n).expect("valid grid");
        let x: Vec<f64> = grid.radii_m().iter().map(|r| 1.0 + r / 2e-5).collect();
        let mut y = vec![0.0; n];
        group.throughput(Throughput::Elements(n as u64));
        let forward = product::ForwardEntries::new(grid);
        let back = product::BackEntries::new(grid);
        for (name, dense, entries) in [
            (
                "forward",
                product::forward(&grid),
                &forward as &(dyn OperatorEntries + Sync),
            ),
            ("back", product::back(&grid), &back),
        ] {
            for rel_tol in HODLR_REL_TOLS {
                let fast = HodlrOperator::build(entries, rel_tol);
                let mut scratch = fast.scratch();
                group.bench_with_input(
                    BenchmarkId::new(format!("{name}_{rel_tol:e}"), n),
                    &n,
                    |b, _| {
                        b.iter(|| fast.apply(black_box(&x), &mut y, &mut scratch));
                    },
                );
            }
            group.bench_with_input(BenchmarkId::new(format!("{name}_dense"), n), &n, |b, _| {
                b.iter(|| dense.apply(black_box(&x), &mut y));
            });
        }
    }
    group.finish();
}

criterion_group!(benches, build, apply, hodlr_build, hodlr_apply);
criterion_main!(benches);
