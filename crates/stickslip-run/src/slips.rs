//! Slips of the stamp: the stamp's scale beside the film's meltings
//! (docs/model.md#two-scales-meltings-and-slips).
//!
//! A friction trace has two scales. A **melting** is the film's event (the core's
//! [`MeltingEvent`]). A **slip** is a drop of the drive's force — the spring's K·(V0·t − X),
//! or F itself under the rigid drive — by more than `drop_n` = `output.slip_drop` × τmax·πa0²
//! (the force at which the whole contact would melt at once). It starts at the force's peak and
//! ends at its lowest value before the force has risen by `drop_n` again: a zigzag of the
//! force with hysteresis `drop_n`, followed on every step (not on sampled rows), so the
//! extremes are those of the steps. A slip counts the meltings inside it: the melting that set
//! it off (the last onset at or before its start, after the previous slip's end) and those up
//! to its end. A slip whose force is still at or near its lowest when the run stops (it fell
//! by more than `drop_n`, and has not risen by as much since: the stamp may slide on steadily
//! at a lower force) is a slip too; its end is its lowest force so far
//! ([`SlipTracker::all_slips`]).
//!
//! The tracker also keeps a bounded envelope of the force over time (at most [`ENVELOPE_BINS`]
//! bins, each with the drive force's least and largest value, the time integrals of the drive
//! force and of F, and the stamp's position at its ends; bins merge in pairs as time goes on),
//! from which the settled part's force band, mean forces and speed are read
//! ([`crate::cycles`]), and the least F between consecutive onsets (a melting's drop).

use serde::{Deserialize, Serialize};
use stickslip_core::sim::events::MeltingEvent;

/// Bins of the force envelope at most (merged in pairs when full).
pub const ENVELOPE_BINS: usize = 256;

/// One slip of the stamp.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Slip {
    /// Slip number, from 1.
    pub k: usize,
    /// When the drive force peaked, s.
    pub t_start_s: f64,
    /// When it reached its lowest value, s.
    pub t_end_s: f64,
    /// Drive force at the start, N.
    pub f_start_n: f64,
    /// Drive force at the end, N.
    pub f_end_n: f64,
    /// Stamp position at the start, m.
    pub x_start_m: f64,
    /// Stamp position at the end, m.
    pub x_end_m: f64,
    /// Meltings inside the slip (the one that set it off included).
    pub meltings: usize,
    /// Energy dissipated from the start to the end (every sink of the energy books), J; NaN
    /// for a slip whose start was seen before the books existed (an old checkpoint).
    #[serde(default = "no_energy")]
    pub dissipated_energy_j: f64,
}

/// The books' value where none was kept.
fn no_energy() -> f64 {
    f64::NAN
}

impl Slip {
    /// The force's drop, N.
    #[must_use]
    pub fn drop_n(&self) -> f64 {
        self.f_start_n - self.f_end_n
    }

    /// The stamp's jump, m.
    #[must_use]
    pub fn jump_m(&self) -> f64 {
        self.x_end_m - self.x_start_m
    }

    /// The slip's duration, s.
    #[must_use]
    pub fn duration_s(&self) -> f64 {
        self.t_end_s - self.t_start_s
    }
}

/// One moment of the trace: time, drive force, stamp position.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Moment {
    /// Time, s.
    pub t_s: f64,
    /// Drive force, N.
    pub f_n: f64,
    /// Stamp position, m.
    pub x_m: f64,
    /// Energy dissipated since t = 0 (the energy books), J; NaN where the books are not kept.
    #[serde(default = "no_energy")]
    pub dissipated_j: f64,
}

/// One bin of the envelope.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Bin {
    /// Start of the bin, s.
    pub t0_s: f64,
    /// Last time in the bin, s.
    pub t1_s: f64,
    /// Least drive force in the bin, N.
    pub f_min_n: f64,
    /// Largest drive force in the bin, N.
    pub f_max_n: f64,
    /// ∫ drive force dt over the bin, N·s.
    pub f_integral_n_s: f64,
    /// ∫ F dt over the bin, N·s.
    pub friction_integral_n_s: f64,
    /// Stamp position at the bin's start, m.
    pub x0_m: f64,
    /// Stamp position at its last time, m.
    pub x1_m: f64,
}

impl Bin {
    fn merge(a: &Self, b: &Self) -> Self {
        Self {
            t0_s: a.t0_s,
            t1_s: b.t1_s,
            f_min_n: a.f_min_n.min(b.f_min_n),
            f_max_n: a.f_max_n.max(b.f_max_n),
            f_integral_n_s: a.f_integral_n_s + b.f_integral_n_s,
            friction_integral_n_s: a.friction_integral_n_s + b.friction_integral_n_s,
            x0_m: a.x0_m,
            x1_m: b.x1_m,
        }
    }
}

/// The drive force's envelope over time, in at most [`ENVELOPE_BINS`] bins of equal width.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Envelope {
    /// Width of a bin, s.
    pub width_s: f64,
    /// The bins, in time order; the last one is being filled.
    pub bins: Vec<Bin>,
}

impl Envelope {
    /// An empty envelope whose first bins are `width_s` wide.
    #[must_use]
    pub fn new(width_s: f64) -> Self {
        Self {
            width_s,
            bins: Vec::new(),
        }
    }

    /// Adds the step from `from` to `to` (drive force and F at both ends, trapezoidal
    /// integrals).
    fn add(&mut self, from: (&Moment, f64), to: (&Moment, f64)) {
        let (a, fa) = from;
        let (b, fb) = to;
        let h = b.t_s - a.t_s;
        let index = |t: f64, w: f64| (t / w).floor();
        let new_bin = self
            .bins
            .last()
            .is_none_or(|last| index(b.t_s, self.width_s) > index(last.t0_s, self.width_s));
        if new_bin {
            if self.bins.len() == ENVELOPE_BINS {
                self.width_s *= 2.0;
                let merged: Vec<Bin> = self
                    .bins
                    .chunks(2)
                    .map(|p| p.iter().skip(1).fold(p[0], |acc, x| Bin::merge(&acc, x)))
                    .collect();
                self.bins = merged;
            }
            let fits = self
                .bins
                .last()
                .is_some_and(|last| index(b.t_s, self.width_s) <= index(last.t0_s, self.width_s));
            if !fits {
                self.bins.push(Bin {
                    t0_s: a.t_s,
                    t1_s: a.t_s,
                    f_min_n: a.f_n,
                    f_max_n: a.f_n,
                    f_integral_n_s: 0.0,
                    friction_integral_n_s: 0.0,
                    x0_m: a.x_m,
                    x1_m: a.x_m,
                });
            }
        }
        if let Some(bin) = self.bins.last_mut() {
            bin.t1_s = b.t_s;
            bin.f_min_n = bin.f_min_n.min(b.f_n);
            bin.f_max_n = bin.f_max_n.max(b.f_n);
            bin.f_integral_n_s += 0.5 * h * (a.f_n + b.f_n);
            bin.friction_integral_n_s += 0.5 * h * (fa + fb);
            bin.x1_m = b.x_m;
        }
    }

    /// The bins that end after `t_s`: the part of the run from `t_s` on, widened to whole
    /// bins (by less than one bin, so a run of a few long steps still has its last bin).
    pub fn from_time(&self, t_s: f64) -> impl Iterator<Item = &Bin> {
        self.bins.iter().filter(move |b| b.t1_s > t_s)
    }
}

/// Follows the drive force step by step and records the slips (see the module's docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SlipTracker {
    /// Hysteresis of the zigzag: the drop that makes a slip, N.
    pub drop_n: f64,
    /// The last moment seen and F then (none before the first).
    pub last: Option<(Moment, f64)>,
    /// Whether the force is falling (a slip is open).
    pub falling: bool,
    /// The running extreme of the phase: the largest force while rising, the least while
    /// falling.
    pub extreme: Option<Moment>,
    /// The opposite extreme since `extreme` was last reached.
    pub rebound: Option<Moment>,
    /// The peak that began the open slip.
    pub peak: Option<Moment>,
    /// The slips that have ended.
    pub slips: Vec<Slip>,
    /// The least F between onset k and onset k + 1 (index k − 1), N.
    pub melting_f_min_n: Vec<f64>,
    /// The force's envelope.
    pub envelope: Envelope,
}

impl SlipTracker {
    /// A tracker with hysteresis `drop_n` for a run of `end_s`.
    #[must_use]
    pub fn new(drop_n: f64, end_s: f64) -> Self {
        Self {
            drop_n,
            last: None,
            falling: false,
            extreme: None,
            rebound: None,
            peak: None,
            slips: Vec::new(),
            melting_f_min_n: Vec::new(),
            envelope: Envelope::new((end_s / ENVELOPE_BINS as f64).max(f64::MIN_POSITIVE)),
        }
    }

    /// Takes in the state after a step (or at t = 0): the moment `now`, F, and the meltings so
    /// far.
    pub fn observe(&mut self, now: Moment, friction_n: f64, events: &[MeltingEvent]) {
        // The least F of each melting's cycle.
        while self.melting_f_min_n.len() < events.len() {
            self.melting_f_min_n.push(friction_n);
        }
        if let Some(m) = self.melting_f_min_n.last_mut() {
            *m = m.min(friction_n);
        }
        if let Some((before, f_before)) = self.last {
            self.envelope.add((&before, f_before), (&now, friction_n));
        } else {
            // The first bin starts at the first moment.
            self.envelope.add((&now, friction_n), (&now, friction_n));
        }
        self.last = Some((now, friction_n));
        let (Some(extreme), Some(rebound)) = (self.extreme, self.rebound) else {
            self.extreme = Some(now);
            self.rebound = Some(now);
            return;
        };
        // A plateau keeps its first moment: a slip ends where the force first reached its
        // lowest value, not where the stamp went on sliding at it.
        let further = if self.falling {
            now.f_n < extreme.f_n
        } else {
            now.f_n > extreme.f_n
        };
        if further {
            self.extreme = Some(now);
            self.rebound = Some(now);
            return;
        }
        let back = if self.falling {
            now.f_n > rebound.f_n
        } else {
            now.f_n < rebound.f_n
        };
        let rebound = if back { now } else { rebound };
        self.rebound = Some(rebound);
        if (now.f_n - extreme.f_n).abs() <= self.drop_n {
            return;
        }
        // The force has turned by more than the hysteresis: the extreme is a turning point.
        if self.falling {
            if let Some(peak) = self.peak.take() {
                let meltings = self.meltings_between(&peak, &extreme, events);
                self.slips.push(Slip {
                    k: self.slips.len() + 1,
                    t_start_s: peak.t_s,
                    t_end_s: extreme.t_s,
                    f_start_n: peak.f_n,
                    f_end_n: extreme.f_n,
                    x_start_m: peak.x_m,
                    x_end_m: extreme.x_m,
                    meltings,
                    dissipated_energy_j: extreme.dissipated_j - peak.dissipated_j,
                });
            }
        } else {
            self.peak = Some(extreme);
        }
        self.falling = !self.falling;
        // Since the last extreme the force has only moved towards `rebound`, which is `now`
        // (it would have turned earlier otherwise): the new phase starts from here.
        self.extreme = Some(rebound);
        self.rebound = Some(now);
    }

    /// The meltings of a slip from `peak` to `end`: the last onset at or before the peak after
    /// the previous slip's end (the one that set it off), and every onset after it up to the
    /// end.
    fn meltings_between(&self, peak: &Moment, end: &Moment, events: &[MeltingEvent]) -> usize {
        let after = self.slips.last().map_or(f64::NEG_INFINITY, |s| s.t_end_s);
        let trigger = events
            .iter()
            .rev()
            .map(|e| e.t_onset_s)
            .find(|&t| t <= peak.t_s && t > after)
            .unwrap_or(peak.t_s);
        events
            .iter()
            .filter(|e| e.t_onset_s >= trigger && e.t_onset_s <= end.t_s)
            .count()
    }

    /// Every slip: those that ended, then the one still open (see the module's docs).
    #[must_use]
    pub fn all_slips(&self, events: &[MeltingEvent]) -> Vec<Slip> {
        let mut all = self.slips.clone();
        all.extend(self.open_slip(events));
        all
    }

    /// The slip open now (its force still falling), from its peak to the least force so far;
    /// none when the force is rising.
    #[must_use]
    pub fn open_slip(&self, events: &[MeltingEvent]) -> Option<Slip> {
        let (peak, low) = (self.peak?, self.extreme?);
        self.falling.then(|| Slip {
            k: self.slips.len() + 1,
            t_start_s: peak.t_s,
            t_end_s: low.t_s,
            f_start_n: peak.f_n,
            f_end_n: low.f_n,
            x_start_m: peak.x_m,
            x_end_m: low.x_m,
            meltings: self.meltings_between(&peak, &low, events),
            dissipated_energy_j: low.dissipated_j - peak.dissipated_j,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn onset(k: usize, t: f64) -> MeltingEvent {
        MeltingEvent {
            k,
            t_onset_s: t,
            r_first_m: 0.0,
            x_onset_m: 0.0,
            f_peak_n: 1.0,
            r_min_m: 0.0,
            t_center_s: None,
            max_melted_fraction: 0.0,
            t_end_s: Some(t),
            recovery: 1.0,
            f_mean_n: 0.0,
            melted_area: 1.0,
            energy: None,
        }
    }

    /// Feeds a sampled trace f(t) (x = t) with meltings at `onsets`.
    fn track(drop: f64, samples: &[(f64, f64)], onsets: &[f64]) -> SlipTracker {
        let mut tr = SlipTracker::new(drop, samples.last().map_or(1.0, |s| s.0));
        for &(t, f) in samples {
            let events: Vec<MeltingEvent> = onsets
                .iter()
                .filter(|&&o| o <= t)
                .enumerate()
                .map(|(i, &o)| onset(i + 1, o))
                .collect();
            tr.observe(
                Moment {
                    t_s: t,
                    f_n: f,
                    x_m: t,
                    dissipated_j: 0.5 * t,
                },
                f,
                &events,
            );
        }
        tr
    }

    /// A sawtooth: rises by 1 over 9 samples, drops by `drop` in one, `cycles` times.
    fn sawtooth(cycles: usize, drop: f64) -> Vec<(f64, f64)> {
        let mut out = vec![(0.0, 0.0)];
        let mut f = 0.0;
        let mut t = 0.0;
        for _ in 0..cycles {
            for _ in 0..9 {
                t += 1.0;
                f += drop / 9.0;
                out.push((t, f));
            }
            t += 1.0;
            f -= drop;
            out.push((t, f));
        }
        out
    }

    #[test]
    fn a_sawtooth_gives_one_slip_per_tooth_and_small_wiggles_none() {
        let tr = track(0.5, &sawtooth(4, 1.0), &[]);
        // The last tooth's drop is not yet confirmed by a rise: three slips ended, one open.
        assert_eq!(tr.slips.len(), 3);
        for (i, s) in tr.slips.iter().enumerate() {
            assert_eq!(s.k, i + 1);
            assert!((s.drop_n() - 1.0).abs() < 1e-12, "{s:?}");
            assert_eq!(s.t_start_s, 9.0 + 10.0 * i as f64);
            assert_eq!(s.duration_s(), 1.0);
            assert_eq!(s.jump_m(), 1.0);
        }
        assert!(tr.open_slip(&[]).is_some());
        // The same teeth below the hysteresis: no slip.
        let small = track(1.5, &sawtooth(4, 1.0), &[]);
        assert!(small.slips.is_empty());
        assert!(small.open_slip(&[]).is_none());
    }

    #[test]
    fn a_slip_with_wiggles_smaller_than_the_hysteresis_is_one_slip_with_its_meltings() {
        // Peak 10 at t = 1, then a staircase down to 0 with rebounds of 0.3, then a rise.
        let mut s = vec![(0.0, 0.0), (1.0, 10.0)];
        let mut t = 1.0;
        let mut f = 10.0;
        for _ in 0..10 {
            t += 1.0;
            f -= 1.3;
            s.push((t, f));
            t += 1.0;
            f += 0.3;
            s.push((t, f));
        }
        let low_t = t - 1.0;
        for _ in 0..5 {
            t += 1.0;
            f += 2.0;
            s.push((t, f));
        }
        // Meltings: one before the peak (sets it off), one per stair, one well after.
        let mut onsets = vec![0.9];
        onsets.extend((0..10).map(|i| 1.5 + 2.0 * f64::from(i)));
        onsets.push(t - 0.5);
        let tr = track(1.0, &s, &onsets);
        assert_eq!(tr.slips.len(), 1, "{:?}", tr.slips);
        let slip = tr.slips[0];
        assert_eq!((slip.t_start_s, slip.f_start_n), (1.0, 10.0));
        assert_eq!(slip.t_end_s, low_t);
        assert!((slip.f_end_n - (10.0 - 1.3 * 10.0 + 0.3 * 9.0)).abs() < 1e-9);
        assert_eq!(slip.meltings, 11);
        // The least F of each melting's cycle.
        assert_eq!(tr.melting_f_min_n.len(), onsets.len());
    }

    #[test]
    fn the_envelope_stays_bounded_and_keeps_the_extremes() {
        let samples: Vec<(f64, f64)> = (0..=10_000)
            .map(|i| {
                let t = f64::from(i) * 1e-3;
                (t, (t * 37.0).sin())
            })
            .collect();
        let mut tr = SlipTracker::new(0.1, 1.0);
        for &(t, f) in &samples {
            tr.observe(
                Moment {
                    t_s: t,
                    f_n: f,
                    x_m: 2.0 * t,
                    dissipated_j: f64::NAN,
                },
                3.0,
                &[],
            );
        }
        let env = &tr.envelope;
        assert!(env.bins.len() <= ENVELOPE_BINS);
        let lo = env
            .bins
            .iter()
            .map(|b| b.f_min_n)
            .fold(f64::INFINITY, f64::min);
        let hi = env
            .bins
            .iter()
            .map(|b| b.f_max_n)
            .fold(f64::NEG_INFINITY, f64::max);
        assert!(lo < -0.9999 && hi > 0.9999);
        let total: f64 = env.bins.iter().map(|b| b.friction_integral_n_s).sum();
        assert!((total - 30.0).abs() < 1e-9, "∫3 dt over 10 s = {total}");
        // Bins tile the time: each starts where the one before ended.
        for w in env.bins.windows(2) {
            assert_eq!(w[0].t1_s, w[1].t0_s);
            assert_eq!(w[0].x1_m, w[1].x0_m);
        }
        let f_int: f64 = env.bins.iter().map(|b| b.f_integral_n_s).sum();
        let exact = (1.0 - (370.0_f64).cos()) / 37.0;
        assert!((f_int - exact).abs() < 1e-3, "{f_int} vs {exact}");
    }
}
