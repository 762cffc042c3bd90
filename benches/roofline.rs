//! Criterion bench: the roofline of one evaluation at N = 2000 on this machine — what one
//! coupled evaluation of the accurate step cannot be cheaper than (`evaluation_floor`, shared
//! with `cargo xtask bench`'s roofline target).
//!
//! - `node_pass`: the fused node pass with one vectorised exponential per node;
//! - `two_applies`: the forward and back MDR transforms of fig2's default operators;
//! - `roofline`: both, in sequence, as one evaluation would run them.
//!
//! The stepper's evaluation is `step_per_n/accurate/2000` of the `steps` bench (one fixed
//! step of fig2); the target is an evaluation within 2× of `roofline`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use stickslip_benches::evaluation_floor::Floor;

const N: usize = 2000;

fn roofline(c: &mut Criterion) {
    let mut floor = Floor::fig2(N);
    let mut group = c.benchmark_group("evaluation_roofline_n2000");
    group.throughput(Throughput::Elements(N as u64));
    group.bench_function("node_pass", |b| {
        b.iter(|| floor.node_pass(black_box(1.5e6)))
    });
    group.bench_function("two_applies", |b| b.iter(|| floor.two_applies()));
    group.bench_function("roofline", |b| {
        b.iter(|| floor.evaluation(black_box(1.5e6)))
    });
    group.finish();
}

criterion_group!(benches, roofline);
criterion_main!(benches);
