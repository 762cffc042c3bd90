//! The events misfit's onset σ against the scatter it stands for. A sawtooth F(t) whose drops
//! are faster than the sampling (as fig2's and the SFA contact's are), its period no multiple
//! of the sample spacing (each drop at its own phase between samples), sampled with gaussian
//! noise over many seeds and compared with the same curve: at the truth the first onset's and
//! the intervals' residuals scatter as the noise's share of their σ says. The onsets' sampling
//! error (a drop's place between the samples) is common to data and model, which are sampled
//! at the same times; counted in their σ it shrank this scatter to a root mean square of about
//! 0.17 here. Without it the root mean square is 0.68: the noise's share, σF/√5 over the
//! smoothed slope, still overstates the crossing's scatter by about 1.5 on these sharp drops
//! (the smoothed samples share their noise, which the formula does not credit), so the band
//! below is [0.5, 1.25]: an onset σ neither inflated by the sampling error nor below the
//! scatter it stands for.

use stickslip_studies::fit::misfit::{ModelCurve, Target};
use stickslip_studies::fit::{MisfitKind, Trace};

/// The sawtooth's period, s (not a multiple of the sample spacing).
const PERIOD_S: f64 = 97.3e-6;
/// Its drop's duration, s: shorter than the sample spacing.
const DROP_S: f64 = 0.7e-6;
/// Its rise and drop, N.
const RISE_N: f64 = 4e-4;
/// The force it starts each period from, N.
const BASE_N: f64 = 1e-4;
/// The data's sample spacing, s.
const SPACING_S: f64 = 2e-6;
/// The noise's standard deviation, N.
const SIGMA_N: f64 = 1e-5;
/// Periods in the trace.
const PERIODS: usize = 10;
/// Noise seeds.
const SEEDS: u64 = 100;

fn force_n(t: f64) -> f64 {
    let tau = t - (t / PERIOD_S).floor() * PERIOD_S;
    let rise_s = PERIOD_S - DROP_S;
    if tau < rise_s {
        BASE_N + RISE_N * tau / rise_s
    } else {
        BASE_N + RISE_N * (1.0 - (tau - rise_s) / DROP_S)
    }
}

/// Standard normal deviates from a splitmix64 stream (Box–Muller).
fn gaussians(seed: u64, n: usize) -> Vec<f64> {
    let mut state = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ 0x2545_f491_4f6c_dd1d;
    let mut uniform = move || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n)
        .map(|_| {
            let (u1, u2) = (uniform().max(1e-300), uniform());
            (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
        })
        .collect()
}

#[test]
fn at_the_truth_the_onsets_residuals_scatter_as_the_noise_does() {
    let end_s = PERIODS as f64 * PERIOD_S + 0.4 * PERIOD_S;
    // The model: the sawtooth itself, finely resolved (10 ns).
    let fine = (end_s / 1e-8) as usize;
    let model_t: Vec<f64> = (0..=fine).map(|k| k as f64 * 1e-8).collect();
    let model = ModelCurve {
        f_n: model_t.iter().map(|&t| force_n(t)).collect(),
        t_s: model_t,
        x_m: Vec::new(),
    };
    let samples = (end_s / SPACING_S) as usize;
    let t: Vec<f64> = (0..samples).map(|k| k as f64 * SPACING_S).collect();
    let (mut sum_sq, mut count) = (0.0, 0usize);
    for seed in 1..=SEEDS {
        let noise = gaussians(seed, samples);
        let f: Vec<f64> = t
            .iter()
            .zip(&noise)
            .map(|(&ti, e)| force_n(ti) + SIGMA_N * e)
            .collect();
        let trace = Trace::new(t.clone(), f, None).expect("a valid trace");
        let target = Target::new(trace, MisfitKind::Events, Some(SIGMA_N)).expect("events found");
        let events = target.events.len();
        assert_eq!(events, PERIODS, "seed {seed}: the data's drops");
        let residuals = target.compare(&model, 0.0).residuals;
        // The first onset and the n − 1 intervals come first.
        for r in &residuals[..events] {
            sum_sq += r * r;
            count += 1;
        }
    }
    let rms = (sum_sq / count as f64).sqrt();
    assert!(
        (0.5..=1.25).contains(&rms),
        "the onsets' and intervals' residuals at the truth: root mean square {rms:.3} over \
         {count}, where their σ claims 1"
    );
}
