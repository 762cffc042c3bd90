//! Synthetic traces from known parameters: the scene with the true values run once by the
//! fit's own forward model (the fit's settings) at a tenth of the tightest tolerance a fit may
//! tighten to (the scene's tolerance / 10⁶), so that the data stand for a measurement — the
//! model's exact answer plus noise — and a fit at the truth differs from them by the noise
//! and its own solver's error alone; its F sampled at evenly spaced times (linearly
//! interpolated between the model's steps, as the fit compares), and gaussian noise of a known
//! standard deviation added from a seeded ChaCha stream.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use stickslip_run::scene::ResolvedScene;
use stickslip_studies::fit::Trace;
use stickslip_studies::fit::forward::{Forward, MAX_LEVEL, Run};
use stickslip_studies::fit::misfit::ModelCurve;

/// The clean model curve of `scene` with `truth` (`KEY=VALUE` overrides) up to `end_s`, run
/// as a fit's forward runs are, at a tenth of their tightest tolerance.
///
/// # Errors
/// The scene refuses a value, or the run fails.
pub fn clean_curve(
    scene: &ResolvedScene,
    truth: &[String],
    end_s: f64,
) -> Result<ModelCurve, String> {
    let base = scene.with_overrides(truth).map_err(|e| e.to_string())?;
    let forward = Forward::new(&base, end_s).map_err(|e| e.to_string())?;
    match forward.noise_run(&[], &[], MAX_LEVEL, None) {
        Run::Done(curve) => Ok(curve),
        Run::Failed(why) => Err(format!("the true model failed: {why}")),
        Run::Interrupted => Err("the true model was interrupted".into()),
    }
}

/// `n` sample times evenly spaced over (0, `end_s`]: the i-th at (i + 1)·end/n.
#[must_use]
pub fn sample_times(end_s: f64, n: usize) -> Vec<f64> {
    (1..=n).map(|i| end_s * i as f64 / n as f64).collect()
}

/// The curve at `t_s` with gaussian noise of standard deviation `sigma_n` from the ChaCha8
/// stream of `seed`.
///
/// # Errors
/// A trace the fit would refuse (too few samples).
pub fn noisy(curve: &ModelCurve, t_s: &[f64], sigma_n: f64, seed: u64) -> Result<Trace, String> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let normal = Normal::new(0.0, sigma_n).map_err(|e| e.to_string())?;
    let f = t_s
        .iter()
        .map(|&t| curve.at(t) + normal.sample(&mut rng))
        .collect();
    Trace::new(t_s.to_vec(), f, None).map_err(|e| e.to_string())
}

/// The melting onsets of `curve` up to `end_s` as the fit's event rule finds them on the
/// clean curve sampled every `spacing_s` (hysteresis 5 % of F's span), s.
#[must_use]
pub fn onsets(curve: &ModelCurve, end_s: f64, spacing_s: f64) -> Vec<f64> {
    let t = sample_times(end_s, (end_s / spacing_s).round() as usize);
    let f: Vec<f64> = t.iter().map(|&x| curve.at(x)).collect();
    let (lo, hi) = f
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let h = stickslip_studies::fit::misfit::HYSTERESIS_OF_RANGE * (hi - lo);
    stickslip_studies::fit::events::find(&t, &f, h)
        .iter()
        .map(|(e, _)| e.t_onset_s)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_noise_has_the_asked_deviation_and_a_seed_repeats_it() {
        let curve = ModelCurve {
            t_s: vec![0.0, 1.0],
            f_n: vec![0.0, 1.0],
            x_m: Vec::new(),
        };
        let t = sample_times(1.0, 4000);
        assert_eq!(t.len(), 4000);
        assert!((t[3999] - 1.0).abs() < 1e-15 && t[0] > 0.0);
        let a = noisy(&curve, &t, 0.01, 7).unwrap();
        let residual: Vec<f64> = a.f_n.iter().zip(&t).map(|(f, t)| f - t).collect();
        let rms = (residual.iter().map(|r| r * r).sum::<f64>() / 4000.0).sqrt();
        assert!((rms / 0.01 - 1.0).abs() < 0.05, "{rms}");
        assert_eq!(a, noisy(&curve, &t, 0.01, 7).unwrap());
        assert_ne!(a, noisy(&curve, &t, 0.01, 8).unwrap());
    }
}
