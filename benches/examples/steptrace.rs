//! The adaptive steps of a run over a time window: per accepted step its end time, length, the
//! parts of its estimated error (film, strain, stamp position and velocity, each in units of
//! the tolerance's scale), the melted nodes, the smallest φ, F, X, V and the attempts rejected
//! before it — to see which part of the error limits the steps through a melting.
//!
//! `cargo run --release -p stickslip-benches --example steptrace -- SCENE T_FROM T_TO [KEY=VALUE ...]`

use stickslip_core::sim::Simulation;
use stickslip_run::Scene;
use stickslip_run::driver::{Control, Driver, Limit, NullSink};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    assert!(
        args.len() >= 3,
        "usage: steptrace SCENE T_FROM T_TO [KEY=VALUE ...]"
    );
    let path = std::path::Path::new(&args[0]);
    let t_from: f64 = args[1].parse().expect("T_FROM in s");
    let t_to: f64 = args[2].parse().expect("T_TO in s");
    let text = Scene::read_text(path).expect("readable scene");
    let scene = Scene::from_toml_str(&text, &args[3..]).expect("valid scene");
    let mut sink = NullSink;
    let mut driver = Driver::start(&scene, &mut sink).expect("a run that starts");
    let started = std::time::Instant::now();
    driver
        .advance(&mut sink, &mut Control::default(), Limit::Time(t_from))
        .expect("null sink");
    let before = driver.simulation().state().counters;
    eprintln!(
        "to t = {:.6e} s: {:?}, {:.2} s",
        driver.simulation().time_s(),
        before,
        started.elapsed().as_secs_f64()
    );
    println!("t h err_phi err_eps err_x err_v melted min_phi F X V rejected");
    let thr = scene.config.melt_threshold;
    let mut rejected = before.rejected_steps;
    let (mut t_prev, mut rows) = (driver.simulation().time_s(), 0_u64);
    let mut observe = |sim: &Simulation| {
        let s = sim.state();
        let e = sim.last_step_error();
        let p = &s.physical;
        let melted = p.phi.iter().filter(|&&phi| phi < thr).count();
        let min_phi = p.phi.iter().copied().fold(f64::INFINITY, f64::min);
        println!(
            "{:.9e} {:.3e} {:.3e} {:.3e} {:.3e} {:.3e} {melted} {min_phi:.3e} {:.6e} {:.6e} {:.6e} {}",
            sim.time_s(),
            sim.time_s() - t_prev,
            e.phi,
            e.eps,
            e.x,
            e.v,
            p.force_n,
            p.drive.x_m,
            p.drive.v_m_per_s,
            s.counters.rejected_steps - rejected
        );
        rejected = s.counters.rejected_steps;
        t_prev = sim.time_s();
        rows += 1;
    };
    let mut control = Control {
        observer: Some(&mut observe),
        ..Control::default()
    };
    driver
        .advance(&mut sink, &mut control, Limit::Time(t_to))
        .expect("null sink");
    eprintln!("window: {:?}", driver.simulation().state().counters);
}
