//! The step loop allocates nothing: allocations counted per thread (the allocation-counter
//! crate's global allocator) over fixed and adaptive accurate steps of fig2 after warm-up.

use stickslip_core::config::{AdaptiveConfig, Scheme};
use stickslip_core::sim::Simulation;

fn fig2(nodes: usize, adaptive: bool) -> Simulation {
    let mut c = crate::scenes::fig2(Scheme::Accurate);
    c.contact.nodes = nodes;
    if adaptive {
        c.time.adaptive = Some(AdaptiveConfig {
            tolerance: 5e-5,
            dt_max_s: c.time.end_s,
            dt_min_s: 1e-14,
        });
        c.numerics.coupling_tol = 5e-7;
    }
    Simulation::new(c).unwrap()
}

#[test]
fn fixed_accurate_steps_allocate_nothing_after_warm_up() {
    let mut sim = fig2(200, false);
    for _ in 0..50 {
        sim.step(1e-8).unwrap();
    }
    let info = allocation_counter::measure(|| {
        for _ in 0..500 {
            sim.step(1e-8).unwrap();
        }
    });
    assert_eq!(info.count_total, 0, "allocations in 500 fixed steps");
}

#[test]
fn adaptive_accurate_steps_allocate_nothing_after_warm_up() {
    let mut sim = fig2(200, true);
    for _ in 0..10 {
        sim.step_adaptive(1.3e-3).unwrap();
    }
    let mut steps = 0;
    // The stick phase before the first onset (≈ 0.6 ms): no event is pushed.
    let info = allocation_counter::measure(|| {
        while sim.time_s() < 5.5e-4 {
            sim.step_adaptive(1.3e-3).unwrap();
            steps += 1;
        }
    });
    assert!(steps > 20, "{steps} steps");
    assert_eq!(info.count_total, 0, "allocations in {steps} adaptive steps");
}
