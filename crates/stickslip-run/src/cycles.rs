//! Cycle statistics of meltings and of slips over the settled part of a run, and the
//! stamp-scale regime (docs/model.md#two-scales-meltings-and-slips).
//!
//! **The transient rule.** The first stick loads the contact from rest and the first slip
//! (or, without slips, the first melting) is not a cycle of the settled motion. The settled
//! part is the second half of what follows: from t_s = t_a + (t_final − t_a)/2, where t_a is
//! the end of the first slip, else the first melting's onset, else 0. A cycle belongs to it
//! when it starts at or after t_s.
//!
//! **Statistics** (per scale, over the cycles of the settled part): the count of cycles
//! starting there; the interval between consecutive starts; the peak force (a melting's
//! f_peak, a slip's drive force at its start); the drop (a melting's f_peak less the least F
//! before the next onset; a slip's drop of the drive force); the stamp's advance between
//! consecutive starts; each as median, mean, least, largest and coefficient of variation
//! (standard deviation over mean). f_mean is the time-mean force over the settled part: F for
//! meltings, the drive force for slips.
//!
//! **The stamp-scale regime**, decided in this order:
//! - `stick_slip`: two or more slips with meltings inside start in the settled part (slips
//!   recur; a slip without a melting is the stamp ringing on its spring, a drop the film did
//!   not cause);
//! - `steady_sliding`: over the last half of the settled part (from t_s + (t_final − t_s)/2:
//!   a contact that slid into steady motion after its last slip reloads for a while first)
//!   no slip starts, the drive force stays within a band of the slip hysteresis, and the
//!   stamp moves at the drive's speed (its mean speed there within 10 % of V0): the film may
//!   be liquid, or melting and re-freezing (its melting frequency is the melting statistics'
//!   interval);
//! - `creep`: no slip in the whole run (the stamp is still loading, or barely moves);
//! - `transient`: slips happened but neither recur in the settled part nor give way to steady
//!   sliding within the run (a longer run decides).

use crate::slips::{Envelope, Slip, SlipTracker};
use serde::{Deserialize, Serialize};
use stickslip_core::sim::events::MeltingEvent;

/// The stamp-scale regime (see the module's docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StampRegime {
    /// Slips recur in the settled part.
    StickSlip,
    /// The drive force stays within the slip hysteresis and the stamp moves at V0.
    SteadySliding,
    /// No slip within the run.
    Creep,
    /// Slips, but neither recurring nor settled into steady sliding.
    Transient,
}

impl StampRegime {
    /// All stamp regimes, in the order of the rules.
    pub const ALL: [Self; 4] = [
        Self::StickSlip,
        Self::SteadySliding,
        Self::Creep,
        Self::Transient,
    ];

    /// The name as written in files.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::StickSlip => "stick_slip",
            Self::SteadySliding => "steady_sliding",
            Self::Creep => "creep",
            Self::Transient => "transient",
        }
    }

    /// The regime called `name`.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|r| r.name() == name)
    }
}

/// Median, mean, least, largest and coefficient of variation of a sample.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Spread {
    /// Values in the sample.
    pub n: usize,
    /// Median.
    pub median: f64,
    /// Mean.
    pub mean: f64,
    /// Least value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
    /// Standard deviation (n − 1) over the mean's magnitude (0 for one value; none when the
    /// mean is 0).
    pub cv: Option<f64>,
}

impl Spread {
    /// The spread of `values` (none when empty or not all finite).
    #[must_use]
    pub fn of(values: &[f64]) -> Option<Self> {
        if values.is_empty() || values.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let n = values.len();
        let mut sorted = values.to_vec();
        sorted.sort_by(f64::total_cmp);
        let median = crate::stats::median_of_sorted(&sorted);
        let mean = values.iter().sum::<f64>() / n as f64;
        let var = if n > 1 {
            values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64
        } else {
            0.0
        };
        Some(Self {
            n,
            median,
            mean,
            min: sorted[0],
            max: sorted[n - 1],
            cv: (mean != 0.0).then(|| var.sqrt() / mean.abs()),
        })
    }
}

/// Statistics of one scale's cycles over the settled part (see the module's docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct CycleStats {
    /// Cycles (meltings or slips) starting in the settled part.
    pub count: usize,
    /// Interval between consecutive starts, s.
    #[serde(rename = "interval")]
    pub interval_s: Option<Spread>,
    /// Peak force, N.
    #[serde(rename = "peak")]
    pub peak_n: Option<Spread>,
    /// Force drop, N.
    #[serde(rename = "drop")]
    pub drop_n: Option<Spread>,
    /// The stamp's advance between consecutive starts, m.
    #[serde(rename = "advance")]
    pub advance_m: Option<Spread>,
    /// Time-mean force over the settled part, N.
    #[serde(rename = "f_mean")]
    pub f_mean_n: Option<f64>,
}

/// The stamp's scale of a run: its slips and regime, and both scales' statistics.
#[derive(Debug, Clone, PartialEq)]
pub struct StampScale {
    /// Slips within the run (one still open at the end included).
    pub n_slips: usize,
    /// The stamp-scale regime.
    pub stamp_regime: StampRegime,
    /// Both scales' statistics over the settled part.
    pub cycles: Cycles,
}

/// Cycle statistics of meltings and of slips over the settled part of a run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Cycles {
    /// Start of the settled part, s.
    #[serde(rename = "settled_from")]
    pub settled_from_s: f64,
    /// The slips' hysteresis, N (`output.slip_drop` × τmax·πa0²).
    #[serde(rename = "slip_drop")]
    pub slip_drop_n: f64,
    /// Meltings over the settled part.
    pub meltings: CycleStats,
    /// Slips over the settled part.
    pub slips: CycleStats,
}

/// Time-mean of a force over the envelope's bins at or after `t_s` (drive force, or F).
fn mean_over(env: &Envelope, t_s: f64, friction: bool) -> Option<f64> {
    let (mut area, mut span) = (0.0, 0.0);
    for b in env.from_time(t_s) {
        area += if friction {
            b.friction_integral_n_s
        } else {
            b.f_integral_n_s
        };
        span += b.t1_s - b.t0_s;
    }
    (span > 0.0).then(|| area / span)
}

/// Intervals and advances between consecutive starts `(t, x)`.
fn steps_between(starts: &[(f64, f64)]) -> (Vec<f64>, Vec<f64>) {
    starts
        .windows(2)
        .map(|w| (w[1].0 - w[0].0, w[1].1 - w[0].1))
        .unzip()
}

/// The stamp's scale of a run that reached `t_final_s` with these meltings and this tracker;
/// `v0` is the drive's speed, m/s.
#[must_use]
pub fn summarize_stamp(
    tracker: &SlipTracker,
    events: &[MeltingEvent],
    t_final_s: f64,
    v0_m_per_s: f64,
) -> StampScale {
    let all = tracker.all_slips(events);
    let slips: &[Slip] = &all;
    let env = &tracker.envelope;
    let t_a = match slips.first() {
        // The first slip is still open and its force still falling at the run's end, by less
        // and less (a stamp sliding into steady motion: its least force comes at the very
        // end). It is over, for this rule, once the force has come within the hysteresis of
        // its least: smaller changes are below the tracker's resolution.
        Some(first) if tracker.slips.is_empty() && first.t_end_s >= t_final_s * (1.0 - 1e-12) => {
            env.from_time(first.t_start_s)
                .find(|b| b.f_min_n <= first.f_end_n + tracker.drop_n)
                .map_or(first.t_end_s, |b| {
                    b.t0_s.max(first.t_start_s).min(first.t_end_s)
                })
        }
        Some(first) => first.t_end_s,
        None => events.first().map_or(0.0, |e| e.t_onset_s),
    };
    let settled = t_a + 0.5 * (t_final_s - t_a).max(0.0);

    let settled_slips: Vec<&Slip> = slips.iter().filter(|s| s.t_start_s >= settled).collect();
    let starts: Vec<(f64, f64)> = settled_slips
        .iter()
        .map(|s| (s.t_start_s, s.x_start_m))
        .collect();
    let (intervals, advances) = steps_between(&starts);
    let slip_stats = CycleStats {
        count: settled_slips.len(),
        interval_s: Spread::of(&intervals),
        peak_n: Spread::of(
            &settled_slips
                .iter()
                .map(|s| s.f_start_n)
                .collect::<Vec<_>>(),
        ),
        drop_n: Spread::of(&settled_slips.iter().map(|s| s.drop_n()).collect::<Vec<_>>()),
        advance_m: Spread::of(&advances),
        f_mean_n: mean_over(env, settled, false),
    };

    let settled_meltings: Vec<(usize, &MeltingEvent)> = events
        .iter()
        .enumerate()
        .filter(|(_, e)| e.t_onset_s >= settled)
        .collect();
    let starts: Vec<(f64, f64)> = settled_meltings
        .iter()
        .map(|(_, e)| (e.t_onset_s, e.x_onset_m))
        .collect();
    let (intervals, advances) = steps_between(&starts);
    let drops: Vec<f64> = settled_meltings
        .iter()
        .filter_map(|&(i, e)| tracker.melting_f_min_n.get(i).map(|m| e.f_peak_n - m))
        .collect();
    let melting_stats = CycleStats {
        count: settled_meltings.len(),
        interval_s: Spread::of(&intervals),
        peak_n: Spread::of(
            &settled_meltings
                .iter()
                .map(|(_, e)| e.f_peak_n)
                .collect::<Vec<_>>(),
        ),
        drop_n: Spread::of(&drops),
        advance_m: Spread::of(&advances),
        f_mean_n: mean_over(env, settled, true),
    };

    let tail = settled + 0.5 * (t_final_s - settled).max(0.0);
    let film_slips = settled_slips.iter().filter(|s| s.meltings > 0).count();
    let stamp_regime = if film_slips >= 2 {
        StampRegime::StickSlip
    } else if slips.iter().all(|s| s.t_start_s < tail)
        && steady_sliding(env, tail, tracker.drop_n, v0_m_per_s)
    {
        StampRegime::SteadySliding
    } else if slips.is_empty() {
        StampRegime::Creep
    } else {
        StampRegime::Transient
    };
    StampScale {
        n_slips: slips.len(),
        stamp_regime,
        cycles: Cycles {
            settled_from_s: settled,
            slip_drop_n: tracker.drop_n,
            meltings: melting_stats,
            slips: slip_stats,
        },
    }
}

/// Whether over the settled part the drive force stays within `band_n` and the stamp's mean
/// speed is within 10 % of `v0` (see the module's docs).
fn steady_sliding(env: &Envelope, settled_s: f64, band_n: f64, v0: f64) -> bool {
    let bins: Vec<_> = env.from_time(settled_s).collect();
    let (Some(first), Some(last)) = (bins.first(), bins.last()) else {
        return false;
    };
    let span = last.t1_s - first.t0_s;
    if span <= 0.0 {
        return false;
    }
    let lo = bins.iter().map(|b| b.f_min_n).fold(f64::INFINITY, f64::min);
    let hi = bins
        .iter()
        .map(|b| b.f_max_n)
        .fold(f64::NEG_INFINITY, f64::max);
    let speed = (last.x1_m - first.x0_m) / span;
    hi - lo <= band_n && (speed - v0).abs() <= 0.1 * v0.abs()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::slips::Moment;

    #[test]
    fn spreads_are_exact_on_small_samples() {
        let s = Spread::of(&[3.0, 1.0, 2.0, 6.0]).unwrap();
        assert_eq!(
            (s.n, s.median, s.mean, s.min, s.max),
            (4, 2.5, 3.0, 1.0, 6.0)
        );
        let sd = (14.0_f64 / 3.0).sqrt();
        assert!((s.cv.unwrap() - sd / 3.0).abs() < 1e-15);
        assert_eq!(Spread::of(&[5.0]).unwrap().cv, Some(0.0));
        assert!(Spread::of(&[]).is_none());
        assert!(Spread::of(&[1.0, f64::NAN]).is_none());
    }

    /// A tracker fed `f(t)` with the stamp at `x(t)`, 10 000 steps over [0, end].
    fn fed(end: f64, f: impl Fn(f64) -> f64, x: impl Fn(f64) -> f64, drop: f64) -> SlipTracker {
        fed_melting(end, f, x, drop, &[]).0
    }

    /// As [`fed`], with meltings at `onsets`; also returns them as events.
    fn fed_melting(
        end: f64,
        f: impl Fn(f64) -> f64,
        x: impl Fn(f64) -> f64,
        drop: f64,
        onsets: &[f64],
    ) -> (SlipTracker, Vec<MeltingEvent>) {
        let event = |k: usize, t: f64| MeltingEvent {
            k,
            t_onset_s: t,
            r_first_m: 0.0,
            x_onset_m: x(t),
            f_peak_n: f(t),
            r_min_m: 0.0,
            t_center_s: None,
            max_melted_fraction: 1.0,
            t_end_s: Some(t),
            recovery: 1.0,
            f_mean_n: 0.0,
            melted_area: 1.0,
            energy: None,
        };
        let mut tr = SlipTracker::new(drop, end);
        let mut events = Vec::new();
        for i in 0..=10_000 {
            let t = end * f64::from(i) / 10_000.0;
            while let Some(&o) = onsets.get(events.len()) {
                if o > t {
                    break;
                }
                events.push(event(events.len() + 1, o));
            }
            tr.observe(
                Moment {
                    t_s: t,
                    f_n: f(t),
                    x_m: x(t),
                    dissipated_j: f64::NAN,
                },
                f(t),
                &events,
            );
        }
        (tr, events)
    }

    #[test]
    fn the_stamp_regimes_on_constructed_traces() {
        // A sawtooth of period 1 and height 1 over 10 s (V0 = 1): stick–slip, 9 slips ended
        // and the tenth open at the end.
        // A melting sets off each slip, just before the peak.
        let onsets: Vec<f64> = (1..=10).map(|k| f64::from(k) - 2e-3).collect();
        let (saw, events) = fed_melting(10.0, |t| t.fract(), |t| t - t.fract(), 0.5, &onsets);
        let s = summarize_stamp(&saw, &events, 10.0, 1.0);
        assert_eq!(s.stamp_regime, StampRegime::StickSlip);
        assert!(saw.slips.iter().all(|s| s.meltings == 1), "{:?}", saw.slips);
        // The same drops without meltings are the stamp ringing on its spring: no stick–slip.
        let rings = fed(10.0, |t| t.fract(), |t| t - t.fract(), 0.5);
        let ringing = summarize_stamp(&rings, &[], 10.0, 1.0);
        assert_eq!(ringing.stamp_regime, StampRegime::Transient);
        assert_eq!((saw.slips.len(), s.n_slips), (9, 10));
        // The first slip ends at ≈ 1: settled from ≈ 5.5, slips at 5.999, …, 9.999.
        assert_eq!(s.cycles.slips.count, 5);
        let iv = s.cycles.slips.interval_s.unwrap();
        assert!(
            (iv.median - 1.0).abs() < 1e-9 && iv.cv.unwrap() < 1e-6,
            "{iv:?}"
        );
        assert!((s.cycles.slips.drop_n.unwrap().median - 1.0).abs() < 2e-3);
        assert!((s.cycles.slips.advance_m.unwrap().median - 1.0).abs() < 1e-9);
        // f_mean: ∫ frac(t) dt over the settled bins (from the first bin at or after t_s).
        let t0 = saw
            .envelope
            .from_time(s.cycles.settled_from_s)
            .next()
            .unwrap()
            .t0_s;
        let primitive = |t: f64| 0.5 * t.floor() + 0.5 * t.fract() * t.fract();
        let exact = (primitive(10.0) - primitive(t0)) / (10.0 - t0);
        let f_mean = s.cycles.slips.f_mean_n.unwrap();
        assert!((f_mean - exact).abs() < 2e-3, "{f_mean} vs {exact}");
        assert_eq!(s.cycles.meltings.f_mean_n, Some(f_mean));
        // One slip at t = 1, then a constant force with the stamp at V0: steady sliding.
        let settle = fed(
            10.0,
            |t| if t < 1.0 { t } else { 0.2 },
            |t| if t < 1.0 { 0.0 } else { t - 1.0 },
            0.5,
        );
        let s = summarize_stamp(&settle, &[], 10.0, 1.0);
        assert_eq!((s.n_slips, s.stamp_regime), (1, StampRegime::SteadySliding));
        // One slip into steady sliding whose force falls ever more slowly to its level, so
        // that the slip is still open at the end: over once within the hysteresis (0.5) of
        // its least force, at t ≈ 1.1, so the settled part starts at ≈ 5.6.
        let glide = fed(
            10.0,
            |t| {
                if t < 1.0 {
                    t
                } else {
                    0.2 + 0.8 * (-(t - 1.0) / 0.5).exp()
                }
            },
            |t| if t < 1.0 { 0.0 } else { t - 1.0 },
            0.5,
        );
        let s = summarize_stamp(&glide, &[], 10.0, 1.0);
        assert!(
            glide.slips.is_empty() && glide.falling,
            "the slip is still open"
        );
        assert_eq!((s.n_slips, s.stamp_regime), (1, StampRegime::SteadySliding));
        assert!(
            (s.cycles.settled_from_s - 5.57).abs() < 0.05,
            "{}",
            s.cycles.settled_from_s
        );
        let f_mean = s.cycles.slips.f_mean_n.unwrap();
        assert!((f_mean - 0.2).abs() < 1e-3, "{f_mean}");
        // The same with the stamp at rest after the slip (the force still constant): no V0.
        let stuck = fed(10.0, |t| if t < 1.0 { t } else { 0.2 }, |_| 0.0, 0.5);
        assert_eq!(
            summarize_stamp(&stuck, &[], 10.0, 1.0).stamp_regime,
            StampRegime::Transient
        );
        // Loading without a slip: creep.
        let load = fed(10.0, |t| 0.1 * t, |_| 0.0, 0.5);
        let s = summarize_stamp(&load, &[], 10.0, 1.0);
        assert_eq!((s.n_slips, s.stamp_regime), (0, StampRegime::Creep));
        assert_eq!(s.cycles.settled_from_s, 5.0);
        // A liquid film: no force, the stamp at V0 from the start: steady sliding.
        let liquid = fed(10.0, |_| 0.0, |t| t, 0.5);
        assert_eq!(
            summarize_stamp(&liquid, &[], 10.0, 1.0).stamp_regime,
            StampRegime::SteadySliding
        );
    }

    #[test]
    fn regime_names_round_trip() {
        for r in StampRegime::ALL {
            assert_eq!(StampRegime::from_name(r.name()), Some(r));
        }
    }
}
