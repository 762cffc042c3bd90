//! The pre-flight's estimates on fig2: the first onset's cubic law, the warning of a run too
//! short for anything to melt, and the literal scheme's refusal past its Euler limit.

use std::f64::consts::PI;
use stickslip_core::config::Scheme;
use stickslip_core::preflight::{Preflight, Severity};

#[test]
fn fig2_first_onset_estimate_is_the_cubic_law() {
    let config = crate::scenes::fig2(Scheme::Accurate);
    let p = Preflight::of(&config, 0.5);
    // X ≈ V0·ω²t³/6 = εc·h0 → t = (6·εc·h0/(V0·ω²))^(1/3) ≈ 0.59 ms.
    let omega_sq: f64 = 500.0 / 0.1;
    let expected = (6.0 * 3f64.sqrt() * 1e-7 / omega_sq).cbrt();
    let t = p.first_onset_estimate_s.unwrap();
    assert!((t / expected - 1.0).abs() < 1e-3, "{t} vs {expected}");
    assert!((p.melting_force_n - 1e6 * PI * 4e-10).abs() < 1e-15);
    assert!(p.refusal().is_none());
    assert!(p.euler_number.is_none());
}

#[test]
fn short_runs_warn_that_nothing_melts_and_literal_divergence_is_refused() {
    let mut config = crate::scenes::fig2(Scheme::Literal);
    config.time.end_s = 1e-4;
    let p = Preflight::of(&config, 1.5);
    // The estimate does not depend on time.end; the warning gives it.
    let full = Preflight::of(&crate::scenes::fig2(Scheme::Literal), 1.5);
    let t = p.first_onset_estimate_s.unwrap();
    assert!((t / full.first_onset_estimate_s.unwrap() - 1.0).abs() < 1e-9);
    assert!(p.at_least(Severity::Warning).any(|f| f.key == "time.end"
        && f.message.contains("nothing melts within time.end")
        && f.message.contains(&format!("{t:.3e}"))));
    let refusal = p.refusal().unwrap();
    assert_eq!(refusal.value, 1.5);
    let euler = p.euler_number.unwrap();
    assert!((euler - 1e-8 * 2.0 * 10.0 * 1.5e6 * 2e6 / 1e6).abs() < 1e-12);
}
