//! Scratch probe: runs fig2 at a given N and scheme and prints events.
use stickslip_core::config::{Scheme, SimConfig};
use stickslip_core::sim::Simulation;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).map(|s| s.parse().unwrap()).unwrap_or(200);
    let scheme = if args.get(2).map(String::as_str) == Some("literal") { Scheme::Literal } else { Scheme::Accurate };
    let dt: f64 = args.get(3).map(|s| s.parse().unwrap()).unwrap_or(1e-8);
    let mut c = SimConfig::fig2(scheme);
    c.contact.nodes = n;
    c.time.dt_s = dt;
    let mut sim = Simulation::new(c, 1e-5).unwrap();
    let steps = (1.3e-3 / dt).round() as u64;
    let t0 = std::time::Instant::now();
    let mut fmax: f64 = 0.0;
    for s in 0..steps {
        if let Err(e) = sim.step(dt) { println!("{e}"); break; }
        fmax = fmax.max(sim.state().force_n);
        if s % 10000 == 0 { let o = sim.observables(); eprintln!("t={:.3e} X={:.3e} F={:.3e} F1d={:.3e} phi={:.3} eps={:.3} melt={:.3}", o.t_s, o.x_m, o.f_n, o.f_1d_n, o.phi_mean, o.eps_mean, o.melted_fraction); }
    }
    let wall = t0.elapsed().as_secs_f64();
    for e in sim.events() { println!("k={} t={:.4e} r_first={:.3e} x={:.4e} fpeak={:.4e} rmin={:.2e} tc={:?} end={:?} maxfrac={:.2}", e.k, e.t_onset_s, e.r_first_m, e.x_onset_m, e.f_peak_n, e.r_min_m, e.t_center_s, e.t_end_s, e.max_melted_fraction); }
    println!("wall {wall:.2}s fmax {fmax:.4e} coupling iters {}", sim.state().coupling_iterations);
}
