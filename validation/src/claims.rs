//! The paper's claims C1–C10 (docs/model.md#the-papers-claims) as measured criteria on run outputs
//! read through the run library's schema ([`RunOutput`]); C11–C13, the first-order film's, are
//! in [`crate::claims_first_order`].
//!
//! Every claim states its criterion with the threshold, and the reason for the threshold sits
//! next to the constant. A claim whose runs are missing or failed is a failing claim: nothing
//! is skipped and no threshold bends to the data. Statistics come from `stickslip_report::stats`
//! (one coefficient of variation: the sample one, n − 1), numbers in prose from
//! `stickslip_report::fmt`.

use crate::facts::Facts;
use serde_json::{Value, json};
use std::collections::BTreeMap;
use stickslip_core::grid::Grading;
use stickslip_report::fmt;
use stickslip_report::stats::{cv, diffs, interp, max_ratio};
use stickslip_run::RunOutput;

/// C1: least number of melting events in fig2 that makes "rises and drops repeatedly".
/// Reason: two events could be a transient; three give two full stick–slip cycles.
pub const C1_MIN_EVENTS: usize = 3;
/// C1: least relative drop of F from its peak in the stick phase to its minimum before the
/// film has recovered (the event's `t_end`), 1 − F_min/f_peak. Reason: a slip must release most of the
/// stored force; a partial melt that leaves F above half its peak is not a slip in the sense
/// of the paper's Fig. 2a, where F falls to ≈ 0.
pub const C1_MIN_DROP: f64 = 0.5;
/// C4: the first melted node must lie in the outer part r ≥ (1 − C4_EDGE_BAND)·a0.
/// Reason: "melting starts at the contact edge"; 10 % of the radius is 20 grid cells at
/// N = 200, far wider than the grid, yet excludes the interior.
pub const C4_EDGE_BAND: f64 = 0.10;
/// C5: the longest melted spell at any probe radius must be shorter than this fraction of the
/// shortest interval between successive onsets. Reason: "followed at once by
/// re-solidification" means the film is solid for almost all of every cycle; 5 % is ≪ 1 and
/// still many probe samples at the shortest interval of fig2 (fig3 samples every 1e-8 s).
pub const C5_MAX_MELT_FRACTION: f64 = 0.05;
/// C6: each homogeneous onset must lie within this fraction of the radial interval ending
/// at the radial onset. Reason: a relative error on the onset *time* would be meaningless late
/// in the run when events come every ~45 µs at t ≈ 1.3 ms; relative to the local interval,
/// 10 % keeps events matched one to one and the phase error small ("similar F(t)").
pub const C6_ONSET_TOL: f64 = 0.10;
/// C8: |F| must stay below this fraction of the largest possible force τmax·πa0².
/// Reason: with u0 held at 0 on a melted film the model's force is exactly 0; 1e-9 of the
/// force scale leaves room only for rounding.
pub const C8_FORCE_TOL: f64 = 1e-9;
/// C8: max |X − X_free| relative to max X_free. Reason: velocity Verlet's global error is
/// ≈ Δt²·ω²V0·t/12 against X ≈ V0ω²t³/6, i.e. Δt²/(2t²) relative (5e-9 at Δt = 1e-8 s and
/// t = 0.1 ms; the adaptive steps of the melt scene are longer, and the measured error is
/// reported beside the verdict); 1e-6 still catches any friction: a force of 2e-8 N over
/// 0.1 ms shifts X by 1e-6 of its value.
pub const C8_X_TOL: f64 = 1e-6;
/// C8: least melted area fraction at every recorded time ("complete melting").
pub const C8_MIN_MELTED: f64 = 1.0 - 1e-9;
/// C9: largest coefficient of variation of the X-distance between successive fig2 onsets.
/// Reason: "F(X) periodic" means equal X spacing while the *time* spacing shrinks by a factor
/// ≈ 3 over the run (the CV of the time intervals is reported beside); 5 % is a small
/// fraction of that and orders of magnitude above the resolution of the located onsets.
pub const C9_MAX_CV_X: f64 = 0.05;
/// C9: largest ratio last f_peak / first f_peak in fig4 that counts as "damped".
/// Reason: a 20 % fall is far beyond the resolution of f_peak (< 1 % between N = 100 and 200),
/// so F(X) visibly decays rather than merely fluctuates.
pub const C9_MAX_DAMPING_RATIO: f64 = 0.8;
/// What C2, C3 and C9 (fig2's part) share, said beside their reasons: they follow from the
/// free stamp's kinematics. Under the spring drive the stamp accelerates (X ≈ V0·ω²·t³/6 early
/// on), so onsets a fixed stamp advance apart come at t_k ≈ t_1·k^(1/3): shrinking intervals
/// (C2), the first the longest (C3) and equal X spacing (C9). Any scheme that melts at a fixed
/// advance passes them; they do not discriminate between schemes that melt at different
/// strains.
pub const KINEMATIC: &str = "Kinematic: this follows from the free stamp's motion alone (onsets \
     a fixed stamp advance apart come at t_k ≈ t_1·k^(1/3)), so any scheme that melts at a fixed \
     advance passes it; it does not test the strain at which the film melts";

/// C10: largest coefficient of variation of the intervals between successive onsets with a
/// rigid drive at V0 = 1e-3 m/s. Reason: constant stamp speed and a film that re-solidifies
/// to the same state make every cycle alike; intervals are resolved to Δt/interval ~ 1e-4, so
/// 1 % allows only a short transient of the film state over the first cycles.
pub const C10_MAX_CV: f64 = 0.01;

/// One claim's verdict with the number behind it.
#[derive(Debug, Clone, PartialEq)]
pub struct Claim {
    /// `C1` … `C10`.
    pub id: &'static str,
    /// The paper's claim in a sentence.
    pub statement: &'static str,
    /// The measured criterion, with its threshold(s).
    pub criterion: String,
    /// Why the threshold is what it is.
    pub reason: String,
    /// The measured numbers (structured, for summary.json).
    pub value: Value,
    /// The measured numbers in a line (for the table).
    pub value_text: String,
    /// The verdict.
    pub pass: bool,
}

/// A part of a claim evaluated on one run.
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    /// Whether this part holds.
    pub pass: bool,
    /// The numbers.
    pub value: Value,
    /// The numbers in words.
    pub text: String,
}

impl Part {
    /// A failing part whose text says why.
    pub fn fail(text: impl Into<String>) -> Self {
        let text = text.into();
        Self {
            pass: false,
            value: json!({ "error": text }),
            text,
        }
    }
}

/// The runs the claims read, by name; a failed run carries its error message.
#[derive(Debug, Default)]
pub struct Runs {
    /// Run name → parsed outputs or the reason there are none.
    pub map: BTreeMap<String, Result<RunOutput, String>>,
}

impl Runs {
    /// The run called `name`, or why it is not available.
    ///
    /// # Errors
    /// The run's failure message, or "not run".
    pub fn get(&self, name: &str) -> Result<&RunOutput, String> {
        match self.map.get(name) {
            Some(Ok(r)) => Ok(r),
            Some(Err(e)) => Err(format!("run `{name}` failed: {e}")),
            None => Err(format!("run `{name}` missing")),
        }
    }
}

fn strictly_decreasing(xs: &[f64]) -> bool {
    xs.windows(2).all(|w| w[1] < w[0])
}

fn us(t_s: f64) -> f64 {
    (t_s * 1e7).round() / 10.0
}

fn us_list(ts: &[f64]) -> Vec<f64> {
    ts.iter().map(|&t| us(t)).collect()
}

/// Start of stick phase k (0-based): t = start of the record for the first, else the film's
/// recovery after the previous event (its `t_end`: every node back above the recovery level),
/// or, if that is missing or not before onset k, the start of the last all-solid stretch of
/// series.csv before the onset.
pub fn stick_start_s(run: &RunOutput, k: usize) -> f64 {
    let s = &run.series;
    let t0 = s.t_s.first().copied().unwrap_or(0.0);
    if k == 0 {
        return t0;
    }
    let ev = run.events.events();
    let onset = ev[k].t_onset_s;
    if let Some(t_end) = ev[k - 1].t_end_s
        && t_end < onset
    {
        return t_end;
    }
    let end = s.t_s.partition_point(|&t| t < onset);
    let mut i = end;
    while i > 0 && s.melted_fraction[i - 1] == 0.0 {
        i -= 1;
    }
    s.t_s.get(i).copied().unwrap_or(t0)
}

/// Mean growth rate of `y` over the stick phase [s, onset]: (max y − y(s)) / (t at max − s).
pub fn stick_rate(run: &RunOutput, y: &[f64], start_s: f64, onset_s: f64) -> f64 {
    let s = &run.series;
    let w = s.window(start_s, onset_s);
    let Some(i_max) = w.clone().max_by(|&a, &b| y[a].total_cmp(&y[b])) else {
        return f64::NAN;
    };
    let y0 = interp(&s.t_s, y, start_s);
    (y[i_max] - y0) / (s.t_s[i_max] - start_s)
}

/// Largest minus smallest of `y` over [t0, t1].
pub fn amplitude(run: &RunOutput, y: &[f64], t0: f64, t1: f64) -> f64 {
    let w = run.series.window(t0, t1);
    let (lo, hi) = y[w]
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    hi - lo
}

/// C1 on one run: enough events, and each completed event (one whose film recovered, `t_end`)
/// drops F by at least [`C1_MIN_DROP`] of its peak.
pub fn c1_part(run: &RunOutput) -> Part {
    let ev = run.events.events();
    let s = &run.series;
    let mut drops = Vec::new();
    for (k, e) in ev.iter().enumerate() {
        let Some(t_end) = e.t_end_s else { continue };
        let start = stick_start_s(run, k);
        let w = s.window(start, e.t_onset_s);
        let t_peak = w
            .clone()
            .max_by(|&a, &b| s.f_n[a].total_cmp(&s.f_n[b]))
            .map_or(start, |i| s.t_s[i]);
        let w = s.window(t_peak, t_end);
        let f_min = s.f_n[w].iter().copied().fold(f64::INFINITY, f64::min);
        drops.push(1.0 - f_min / e.f_peak_n);
    }
    let min_drop = drops.iter().copied().fold(f64::INFINITY, f64::min);
    let pass = ev.len() >= C1_MIN_EVENTS
        && drops.len() >= C1_MIN_EVENTS.min(ev.len())
        && min_drop >= C1_MIN_DROP;
    Part {
        pass,
        value: json!({ "events": ev.len(), "completed_events": drops.len(),
                       "min_drop": min_drop, "drops": drops }),
        text: format!(
            "{} events ({} completed); smallest F drop {} % of the peak",
            ev.len(),
            drops.len(),
            fmt::sig(100.0 * min_drop, 4)
        ),
    }
}

/// C2 on one run: every interval between successive onsets is shorter than the one before.
pub fn c2_part(run: &RunOutput) -> Part {
    let intervals = diffs(&run.events.onsets_s());
    let pass = intervals.len() >= 2 && strictly_decreasing(&intervals);
    let ratio = max_ratio(&intervals);
    Part {
        pass,
        value: json!({ "intervals_us": us_list(&intervals), "max_ratio": ratio }),
        text: format!(
            "{}: {} intervals {} µs, largest Δ(k+1)/Δk = {}",
            run.info.name,
            intervals.len(),
            fmt::list(&us_list(&intervals), 1),
            fmt::sig(ratio, 3)
        ),
    }
}

/// C3 on one run: the first interval is the longest, and the mean growth rates of F and ⟨ε⟩
/// over the first stick phase are below those of every later stick phase.
pub fn c3_part(run: &RunOutput) -> Part {
    let ev = run.events.events();
    if ev.len() < 2 {
        return Part::fail(format!("{}: {} events, need ≥ 2", run.info.name, ev.len()));
    }
    let onsets = run.events.onsets_s();
    let t0 = stick_start_s(run, 0);
    let first = onsets[0] - t0;
    let later = diffs(&onsets);
    let longest_later = later.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mut rate_f = Vec::new();
    let mut rate_eps = Vec::new();
    for (k, &onset) in onsets.iter().enumerate() {
        let start = stick_start_s(run, k);
        rate_f.push(stick_rate(run, &run.series.f_n, start, onset));
        rate_eps.push(stick_rate(run, &run.series.eps_mean, start, onset));
    }
    let min_later = |r: &[f64]| r[1..].iter().copied().fold(f64::INFINITY, f64::min);
    let (mf, me) = (min_later(&rate_f), min_later(&rate_eps));
    let pass = first > longest_later && rate_f[0] < mf && rate_eps[0] < me;
    Part {
        pass,
        value: json!({
            "first_interval_us": us(first), "longest_later_interval_us": us(longest_later),
            "rate_F_first_N_per_s": rate_f[0], "rate_F_min_later_N_per_s": mf,
            "rate_eps_first_per_s": rate_eps[0], "rate_eps_min_later_per_s": me,
            "rate_F_N_per_s": rate_f, "rate_eps_per_s": rate_eps,
        }),
        text: format!(
            "first interval {} vs longest later {}; dF/dt first {} N/s vs later ≥ {} N/s; \
             d⟨ε⟩/dt first {}/s vs later ≥ {}/s",
            fmt::time(first, 4),
            fmt::time(longest_later, 4),
            fmt::sig(rate_f[0], 3),
            fmt::sig(mf, 4),
            fmt::sig(rate_eps[0], 4),
            fmt::sig(me, 5)
        ),
    }
}

/// C4 from events.csv: every first melted node lies in the outer band, and the front reaches
/// the axis (`t_center`) strictly after the onset in every event.
pub fn c4_events_part(run: &RunOutput) -> Part {
    let ev = run.events.events();
    if ev.is_empty() {
        return Part::fail(format!("{}: no events", run.info.name));
    }
    let a0 = run.info.radius_m();
    let edge = (1.0 - C4_EDGE_BAND) * a0;
    let r_first: Vec<f64> = ev.iter().map(|e| e.r_first_m).collect();
    let min_r_first = r_first.iter().copied().fold(f64::INFINITY, f64::min);
    let travel: Vec<Option<f64>> = ev
        .iter()
        .map(|e| e.t_center_s.map(|tc| tc - e.t_onset_s))
        .collect();
    let reached = travel.iter().filter(|t| t.is_some_and(|d| d > 0.0)).count();
    let min_travel = travel
        .iter()
        .flatten()
        .copied()
        .fold(f64::INFINITY, f64::min);
    let pass = min_r_first >= edge && reached == ev.len();
    Part {
        pass,
        value: json!({
            "r_first_um": r_first.iter().map(|r| r * 1e6).collect::<Vec<_>>(),
            "min_r_first_over_a0": min_r_first / a0,
            "events_reaching_centre_later": reached, "events": ev.len(),
            "min_front_travel_us": if min_travel.is_finite() { json!(min_travel * 1e6) } else { Value::Null },
        }),
        text: format!(
            "{}: min r_first = {} µm = {}·a0; front reached r = 0 after the onset in {}/{} \
             events (shortest travel {} µs)",
            run.info.name,
            fmt::sig(min_r_first * 1e6, 4),
            fmt::sig(min_r_first / a0, 3),
            reached,
            ev.len(),
            fmt::sig(min_travel * 1e6, 2)
        ),
    }
}

/// Melting of one probe in one event window: first time below threshold, final recovery.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProbeMelt {
    /// Event index (0-based).
    pub event: usize,
    /// Probe index.
    pub probe: usize,
    /// First sample below the threshold, s.
    pub t_melt_s: f64,
    /// First sample back at or above the threshold after the last sub-threshold sample, s
    /// (None when the record or the window ends first).
    pub t_solid_s: Option<f64>,
    /// Whether the window ended because the record ended (not because of the next event).
    pub censored_by_end: bool,
}

/// All probe meltings of `run`, grouped by event window [onset_k, onset_{k+1}).
///
/// From the `t_melt@` columns (the located time each probe's node last melted), a melting is a
/// change of that time, dated exactly; its re-solidification is the first sample from then on
/// with φ ≥ threshold. Where they show none in a window, a melting is a run of samples with φ
/// below the threshold.
pub fn probe_melts(run: &RunOutput) -> Vec<ProbeMelt> {
    let p = &run.probes;
    let thr = run.info.melt_threshold();
    let onsets = run.events.onsets_s();
    let mut out = Vec::new();
    for (k, &t0) in onsets.iter().enumerate() {
        let t1 = onsets.get(k + 1).copied().unwrap_or(f64::INFINITY);
        let a = p.t_s.partition_point(|&t| t < t0);
        let b = p.t_s.partition_point(|&t| t < t1);
        for (j, phi) in p.phi.iter().enumerate() {
            let melt = p
                .t_melt_s
                .get(j)
                .and_then(|t_melt| located_melt(&p.t_s, phi, t_melt, thr, t0, t1))
                .or_else(|| sampled_melt(&p.t_s, phi, thr, a, b));
            if let Some((t_melt_s, t_solid_s)) = melt {
                out.push(ProbeMelt {
                    event: k,
                    probe: j,
                    t_melt_s,
                    t_solid_s,
                    censored_by_end: t_solid_s.is_none() && b == p.t_s.len(),
                });
            }
        }
    }
    out
}

/// First located melting in [t0, t1) and the first sample at or after the last one with φ at
/// or above the threshold.
fn located_melt(
    t_s: &[f64],
    phi: &[f64],
    t_melt: &[f64],
    thr: f64,
    t0: f64,
    t1: f64,
) -> Option<(f64, Option<f64>)> {
    // The onset and the first melting are located by the same formula, up to rounding.
    let slack = 1e-9 * t0.abs().max(1e-12);
    let inside: Vec<f64> = t_melt
        .iter()
        .copied()
        .filter(|&t| t >= 0.0 && t >= t0 - slack && t < t1 - slack)
        .collect();
    let first = inside.iter().copied().fold(f64::INFINITY, f64::min);
    let last = inside.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !first.is_finite() {
        return None;
    }
    let from = t_s.partition_point(|&t| t < last);
    let t_solid = (from..t_s.len())
        .find(|&i| phi[i] >= thr)
        .map(|i| t_s[i])
        .filter(|&t| t < t1);
    Some((first, t_solid))
}

/// First sample below the threshold in rows [a, b) and the sample after the last one.
fn sampled_melt(
    t_s: &[f64],
    phi: &[f64],
    thr: f64,
    a: usize,
    b: usize,
) -> Option<(f64, Option<f64>)> {
    let below: Vec<usize> = (a..b).filter(|&i| phi[i] < thr).collect();
    let (Some(&first), Some(&last)) = (below.first(), below.last()) else {
        return None;
    };
    Some((t_s[first], (last + 1 < b).then(|| t_s[last + 1])))
}

/// C4 from probes: in every event, the probes melt in order from the outermost to the
/// innermost radius (first-melt times non-decreasing inwards).
pub fn c4_probes_part(run: &RunOutput) -> Part {
    let p = &run.probes;
    if p.radii_m.is_empty() {
        return Part::fail(format!("{}: no probes in probes.csv", run.info.name));
    }
    let melts = probe_melts(run);
    let n_events = run.events.len();
    let mut order_violations = 0;
    let mut spans = Vec::new();
    for k in 0..n_events {
        let mut by_r: Vec<(f64, f64)> = melts
            .iter()
            .filter(|m| m.event == k)
            .map(|m| (p.radii_m[m.probe], m.t_melt_s))
            .collect();
        by_r.sort_by(|a, b| b.0.total_cmp(&a.0));
        order_violations += by_r.windows(2).filter(|w| w[1].1 < w[0].1).count();
        if let (Some(o), Some(i)) = (by_r.first(), by_r.last()) {
            spans.push(i.1 - o.1);
        }
    }
    let pass = n_events > 0 && !melts.is_empty() && order_violations == 0;
    Part {
        pass,
        value: json!({ "order_violations": order_violations,
                       "outer_to_inner_probe_delay_us": spans.iter().map(|s| s * 1e6).collect::<Vec<_>>() }),
        text: format!(
            "{}: probes melt outer → inner in every event ({} order violations; outer-to-inner \
             probe delay {} µs)",
            run.info.name,
            order_violations,
            fmt::list(&spans.iter().map(|s| s * 1e6).collect::<Vec<_>>(), 2)
        ),
    }
}

/// C5 on a run with probes: every probe melts at least once, every melting re-solidifies
/// before the next event, and the longest melted spell is < [`C5_MAX_MELT_FRACTION`] of the
/// shortest interval between successive onsets.
pub fn c5_part(run: &RunOutput) -> Part {
    let p = &run.probes;
    if p.radii_m.is_empty() {
        return Part::fail(format!("{}: no probes in probes.csv", run.info.name));
    }
    let melts = probe_melts(run);
    let intervals = diffs(&run.events.onsets_s());
    let shortest = intervals.iter().copied().fold(f64::INFINITY, f64::min);
    let never: Vec<f64> = (0..p.radii_m.len())
        .filter(|&j| !melts.iter().any(|m| m.probe == j))
        .map(|j| p.radii_m[j] * 1e6)
        .collect();
    let unrecovered = melts
        .iter()
        .filter(|m| m.t_solid_s.is_none() && !m.censored_by_end)
        .count();
    let longest = melts
        .iter()
        .filter_map(|m| m.t_solid_s.map(|t| t - m.t_melt_s))
        .fold(0.0, f64::max);
    let ratio = longest / shortest;
    let pass = !melts.is_empty()
        && never.is_empty()
        && unrecovered == 0
        && !intervals.is_empty()
        && ratio < C5_MAX_MELT_FRACTION;
    Part {
        pass,
        value: json!({
            "probe_radii_um": p.radii_m.iter().map(|r| r * 1e6).collect::<Vec<_>>(),
            "meltings": melts.len(), "probes_never_melted_um": never,
            "unrecovered_before_next_event": unrecovered,
            "longest_melted_us": longest * 1e6, "shortest_interval_us": shortest * 1e6,
            "ratio": ratio,
        }),
        text: format!(
            "{} meltings at {} radii; longest melted spell {} = {} × the shortest interval \
             ({}); {} not re-solidified before the next event; radii never melted: {}",
            melts.len(),
            p.radii_m.len(),
            fmt::time(longest, 3),
            fmt::sig(ratio, 2),
            fmt::time(shortest, 3),
            unrecovered,
            fmt::list(&never, 0)
        ),
    }
}

/// Relative L2 difference of F between two runs on the first run's times.
pub fn rel_l2_force(reference: &RunOutput, other: &RunOutput) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for (i, &t) in reference.series.t_s.iter().enumerate() {
        let fo = interp(&other.series.t_s, &other.series.f_n, t);
        num += (fo - reference.series.f_n[i]).powi(2);
        den += reference.series.f_n[i].powi(2);
    }
    (num / den).sqrt()
}

/// C6: homogeneous against radial: same number of events, every onset within
/// [`C6_ONSET_TOL`] of the preceding radial interval; relative L2 difference of F reported.
pub fn c6_part(radial: &RunOutput, hom: &RunOutput) -> Part {
    let (r, h) = (radial.events.onsets_s(), hom.events.onsets_s());
    let mut worst = 0.0_f64;
    let mut worst_abs = 0.0_f64;
    if r.len() == h.len() {
        let mut prev = radial.series.t_s.first().copied().unwrap_or(0.0);
        for (&tr, &th) in r.iter().zip(&h) {
            worst = worst.max((th - tr).abs() / (tr - prev));
            worst_abs = worst_abs.max((th - tr).abs());
            prev = tr;
        }
    }
    let l2 = rel_l2_force(radial, hom);
    let fp =
        |run: &RunOutput| -> Vec<f64> { run.events.events().iter().map(|e| e.f_peak_n).collect() };
    let (fr, fh) = (fp(radial), fp(hom));
    let fpeak_diff = fr
        .iter()
        .zip(&fh)
        .map(|(a, b)| ((b - a) / a).abs())
        .fold(0.0, f64::max);
    let pass = !r.is_empty() && r.len() == h.len() && worst <= C6_ONSET_TOL;
    Part {
        pass,
        value: json!({
            "events_radial": r.len(), "events_homogeneous": h.len(),
            "onsets_radial_us": us_list(&r), "onsets_homogeneous_us": us_list(&h),
            "max_onset_shift_over_interval": worst, "max_onset_shift_us": worst_abs * 1e6,
            "rel_l2_F": l2, "max_rel_f_peak_diff": fpeak_diff,
        }),
        text: format!(
            "{} vs {} events; largest onset shift {} = {} of the interval; relative L2 \
             difference of F(t) {}; f_peak differs by ≤ {} %",
            h.len(),
            r.len(),
            fmt::time(worst_abs, 3),
            fmt::sig(worst, 2),
            fmt::sig(l2, 3),
            fmt::sig(100.0 * fpeak_diff, 2)
        ),
    }
}

/// C7 on fig4: f_peak falls event by event, the cycle amplitudes (max − min over
/// [t_{k−1}, t_k], k ≥ 2) of F, ⟨φ⟩ and ⟨ε⟩ fall, and the intervals still shrink.
pub fn c7_part(run: &RunOutput) -> Part {
    let ev = run.events.events();
    if ev.len() < 3 {
        return Part::fail(format!("{}: {} events, need ≥ 3", run.info.name, ev.len()));
    }
    let onsets = run.events.onsets_s();
    let f_peak: Vec<f64> = ev.iter().map(|e| e.f_peak_n).collect();
    let cycles = |y: &[f64]| -> Vec<f64> {
        onsets
            .windows(2)
            .map(|w| amplitude(run, y, w[0], w[1]))
            .collect()
    };
    let s = &run.series;
    let (amp_f, amp_phi, amp_eps) = (cycles(&s.f_n), cycles(&s.phi_mean), cycles(&s.eps_mean));
    let intervals = diffs(&onsets);
    let checks = [
        strictly_decreasing(&f_peak),
        strictly_decreasing(&amp_f),
        strictly_decreasing(&amp_phi),
        strictly_decreasing(&amp_eps),
        strictly_decreasing(&intervals),
    ];
    let mn = |v: &[f64]| v.iter().map(|x| x * 1e3).collect::<Vec<_>>();
    Part {
        pass: checks.iter().all(|&c| c),
        value: json!({
            "f_peak_mN": mn(&f_peak), "amp_F_mN": mn(&amp_f), "amp_phi": amp_phi,
            "amp_eps": amp_eps, "intervals_us": us_list(&intervals),
            "decreasing": { "f_peak": checks[0], "amp_F": checks[1], "amp_phi": checks[2],
                            "amp_eps": checks[3], "intervals": checks[4] },
        }),
        text: format!(
            "f_peak {} mN ({}); F cycle amplitude {} → {} mN ({}); ⟨φ⟩ {} → {} ({}); ⟨ε⟩ {} → \
             {} ({}); intervals {} → {} ({})",
            fmt::list(&mn(&f_peak), 3),
            word(checks[0]),
            fmt::sig(amp_f.first().copied().unwrap_or(f64::NAN) * 1e3, 3),
            fmt::sig(amp_f.last().copied().unwrap_or(f64::NAN) * 1e3, 3),
            word(checks[1]),
            fmt::sig(amp_phi.first().copied().unwrap_or(f64::NAN), 3),
            fmt::sig(amp_phi.last().copied().unwrap_or(f64::NAN), 3),
            word(checks[2]),
            fmt::sig(amp_eps.first().copied().unwrap_or(f64::NAN), 4),
            fmt::sig(amp_eps.last().copied().unwrap_or(f64::NAN), 4),
            word(checks[3]),
            fmt::time(intervals[0], 4),
            fmt::time(intervals.last().copied().unwrap_or(f64::NAN), 3),
            word(checks[4]),
        ),
    }
}

fn word(decreasing: bool) -> &'static str {
    if decreasing {
        "each lower"
    } else {
        "NOT monotone"
    }
}

/// C8 on the melt scene: complete melting at all times, |F| ≤ [`C8_FORCE_TOL`]·τmax·πa0²,
/// no event after t = 0, and X(t) = V0 t − (V0/ω) sin ωt within [`C8_X_TOL`].
///
/// The claim's premise is a film liquid from the start. A ≤ 0 gives one for the paper's
/// second-order film; a first-order film (docs/model.md#the-first-order-film) may instead
/// start as a metastable solid (run.json's `derived.metastable_solid`), which carries a force
/// until it melts: such a run does not test C8 and fails it with that reason.
pub fn c8_part(run: &RunOutput) -> Part {
    let s = &run.series;
    let info = &run.info;
    if info.derived.metastable_solid == Some(true) {
        return Part::fail(format!(
            "{}: the film starts solid (phi0 = {}; a first-order film's metastable solid above \
             the melting temperature): not the liquid start C8 is about",
            info.name,
            fmt::sig(info.derived.phi0, 4)
        ));
    }
    let Some(omega) = info.omega_rad_per_s() else {
        return Part::fail(format!("{}: not a spring drive", run.info.name));
    };
    // τmax·π·a0², the largest force the film can carry (run.json's derived melting_force).
    let f_scale = info.derived.melting_force;
    let f_max = s.f_n.iter().map(|f| f.abs()).fold(0.0, f64::max);
    let v0 = info.velocity_m_per_s();
    let x_free = |t: f64| v0 * t - v0 / omega * (omega * t).sin();
    let x_scale = s.t_s.iter().map(|&t| x_free(t).abs()).fold(0.0, f64::max);
    let x_err = s
        .t_s
        .iter()
        .zip(&s.x_m)
        .map(|(&t, &x)| (x - x_free(t)).abs())
        .fold(0.0, f64::max)
        / x_scale;
    let min_melted = s
        .melted_fraction
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    let later_events = run
        .events
        .events()
        .iter()
        .filter(|e| e.t_onset_s > s.t_s.first().copied().unwrap_or(0.0))
        .count();
    let pass = f_max <= C8_FORCE_TOL * f_scale
        && x_err <= C8_X_TOL
        && min_melted >= C8_MIN_MELTED
        && later_events == 0
        && !s.is_empty();
    Part {
        pass,
        value: json!({ "max_abs_F_N": f_max, "F_tolerance_N": C8_FORCE_TOL * f_scale,
                       "max_rel_X_error": x_err, "min_melted_fraction": min_melted,
                       "events_after_start": later_events }),
        text: format!(
            "max|F| = {} N (tolerance {} N); max|X − X_free|/max X_free = {}; melted fraction \
             ≥ {}; {later_events} events after t = 0",
            fmt::sig(f_max, 3),
            fmt::sig(C8_FORCE_TOL * f_scale, 2),
            fmt::sig(x_err, 2),
            fmt::sig(min_melted, 7)
        ),
    }
}

/// X-distances between successive onsets, m.
pub fn x_distances(run: &RunOutput) -> Vec<f64> {
    let x: Vec<f64> = run.events.events().iter().map(|e| e.x_onset_m).collect();
    diffs(&x)
}

/// C9 on fig2: coefficient of variation of the X-distance between successive onsets.
pub fn c9_periodic_part(run: &RunOutput) -> Part {
    let d = x_distances(run);
    let c = cv(&d);
    let ct = cv(&diffs(&run.events.onsets_s()));
    Part {
        pass: d.len() >= 2 && c < C9_MAX_CV_X,
        value: json!({ "x_distances_um": d.iter().map(|x| x * 1e6).collect::<Vec<_>>(),
                       "cv_x": c, "cv_time_intervals": ct }),
        text: format!(
            "{}: X-distances {} µm, CV {} (time intervals: CV {})",
            run.info.name,
            fmt::list(&d.iter().map(|x| x * 1e6).collect::<Vec<_>>(), 4),
            fmt::sig(c, 2),
            fmt::sig(ct, 3)
        ),
    }
}

/// C9 on fig4: last f_peak / first f_peak.
pub fn c9_damped_part(run: &RunOutput) -> Part {
    let ev = run.events.events();
    if ev.len() < 2 {
        return Part::fail(format!("{}: {} events, need ≥ 2", run.info.name, ev.len()));
    }
    let ratio = ev[ev.len() - 1].f_peak_n / ev[0].f_peak_n;
    let d = x_distances(run);
    Part {
        pass: ratio < C9_MAX_DAMPING_RATIO,
        value: json!({ "last_over_first_f_peak": ratio, "cv_x": cv(&d) }),
        text: format!(
            "{}: last/first f_peak = {} (X-distance CV {})",
            run.info.name,
            fmt::sig(ratio, 3),
            fmt::sig(cv(&d), 2)
        ),
    }
}

/// C10 on the slow rigid drive: coefficient of variation of the intervals between
/// successive onsets.
pub fn c10_part(run: &RunOutput) -> Part {
    let intervals = diffs(&run.events.onsets_s());
    let c = cv(&intervals);
    Part {
        pass: intervals.len() >= 2 && c < C10_MAX_CV,
        value: json!({ "events": run.events.len(), "intervals_us": us_list(&intervals), "cv": c }),
        text: format!(
            "{} events, intervals {} µs, CV {}",
            run.events.len(),
            fmt::list(&intervals.iter().map(|t| t * 1e6).collect::<Vec<_>>(), 2),
            fmt::sig(c, 3)
        ),
    }
}

/// A claim from its parts: it passes when every part passes (and there is one).
pub fn assemble(
    id: &'static str,
    statement: &'static str,
    criterion: String,
    reason: String,
    parts: Vec<(&'static str, Result<Part, String>)>,
) -> Claim {
    let mut value = serde_json::Map::new();
    let mut texts = Vec::new();
    let mut pass = !parts.is_empty();
    for (label, part) in parts {
        let part = part.unwrap_or_else(Part::fail);
        pass &= part.pass;
        value.insert(label.to_string(), part.value);
        texts.push(part.text);
    }
    Claim {
        id,
        statement,
        criterion,
        reason,
        value: Value::Object(value),
        value_text: texts.join("; "),
        pass,
    }
}

/// The probe radii of a run in µm as `2, 4, …, 18 µm`, or `the probe radii` without the run.
fn probe_radii_text(runs: &Runs, name: &str) -> String {
    runs.get(name)
        .ok()
        .filter(|r| !r.probes.radii_m.is_empty())
        .map_or_else(
            || "the probe radii".to_string(),
            |r| {
                let um: Vec<String> = r
                    .probes
                    .radii_m
                    .iter()
                    .map(|x| fmt::sig(x * 1e6, 3))
                    .collect();
                format!("r = {} µm", um.join(", "))
            },
        )
}

/// Evaluates C1–C10 on `runs` (fig2, fig3, fig4, homogeneous, melt, rigid).
pub fn evaluate(runs: &Runs) -> Vec<Claim> {
    let on = |name: &str, f: fn(&RunOutput) -> Part| runs.get(name).map(f);
    let fig3_probes = probe_radii_text(runs, "fig3");
    let nodes = runs
        .get("fig2")
        .map_or(crate::sizes::NODES, |r| r.info.nodes());
    let edge_nodes = runs.get("fig2").map_or_else(
        |_| "?".to_string(),
        |r| r.info.nodes_in_outer(C4_EDGE_BAND).to_string(),
    );
    let grid = runs.get("fig2").map_or_else(
        |_| "?".to_string(),
        |r| match r.info.grading() {
            Grading::Uniform => "uniform".to_string(),
            Grading::Edge { power } => format!("edge-graded, p = {power}"),
        },
    );
    let rigid_v0 = runs.get("rigid").map_or_else(
        |_| "?".to_string(),
        |r| format!("{:e}", r.info.velocity_m_per_s()),
    );
    vec![
        assemble(
            "C1",
            "Stick–slip: F(t) rises and drops repeatedly (fig2).",
            format!(
                "fig2 has ≥ {C1_MIN_EVENTS} melting events, and in every completed event F falls \
                 from its stick-phase peak by ≥ {:.0} % before the film has recovered (the \
                 event's t_end)",
                100.0 * C1_MIN_DROP
            ),
            "three events are two full cycles; a slip releases most of the force (Fig. 2a falls to ≈ 0)".into(),
            vec![("fig2", on("fig2", c1_part))],
        ),
        assemble(
            "C2",
            "The intervals between successive melting events shrink (fig2, fig4).",
            "every interval between successive onsets is shorter than the one before, in fig2 \
             and in fig4 (≥ 3 events each)"
                .into(),
            format!(
                "the paper's statement taken literally: strictly decreasing, no tolerance. {KINEMATIC}"
            ),
            vec![("fig2", on("fig2", c2_part)), ("fig4", on("fig4", c2_part))],
        ),
        assemble(
            "C3",
            "The first interval is the longest, with slower growth of F and ⟨ε⟩ before it.",
            "fig2: 0 → first onset is longer than every later interval, and the mean growth \
             rates (max − start value)/(time to max) of F and ⟨ε⟩ over the first stick phase are \
             below those of every later stick phase (a stick phase runs from the film's recovery \
             after the previous event, its t_end, to the next onset)"
                .into(),
            format!(
                "the paper's statement taken literally: strict inequalities, no tolerance. \
                 {KINEMATIC}"
            ),
            vec![("fig2", on("fig2", c3_part))],
        ),
        assemble(
            "C4",
            "Melting starts at the contact edge and moves to the centre (fig2b,d; fig3).",
            format!(
                "every event's first melted node has r ≥ {:.2}·a0 and the front reaches r = 0 \
                 strictly after the onset (fig2, fig3 events.csv); in fig3 the probes \
                 ({fig3_probes}) melt in order from outer to inner in every event",
                1.0 - C4_EDGE_BAND
            ),
            format!(
                "outer {:.0} % of the radius, which holds {edge_nodes} of the N = {nodes} nodes \
                 ({grid} grid): the edge, not the interior",
                100.0 * C4_EDGE_BAND,
            ),
            vec![
                ("fig2", on("fig2", c4_events_part)),
                ("fig3", on("fig3", c4_events_part)),
                ("fig3_probes", on("fig3", c4_probes_part)),
            ],
        ),
        assemble(
            "C5",
            "At every radius melting is followed at once by re-solidification (fig3).",
            format!(
                "fig3, every probe ({fig3_probes}) melts, re-solidifies before the next event, \
                 and its longest melted spell is < {:.0} % of the shortest interval between \
                 successive onsets",
                100.0 * C5_MAX_MELT_FRACTION
            ),
            format!(
                "\"at once\" = solid for almost the whole cycle: {:.0} % is ≪ 1",
                100.0 * C5_MAX_MELT_FRACTION
            ),
            vec![("fig3", on("fig3", c5_part))],
        ),
        assemble(
            "C6",
            "Inhomogeneity matters little: a homogeneous model gives a similar F(t).",
            format!(
                "homogeneous vs radial fig2: same event count, every onset within {:.0} % of the \
                 radial interval before it; relative L2 difference of F(t) reported",
                100.0 * C6_ONSET_TOL
            ),
            "relative to the local interval, not to t: events stay matched one to one".into(),
            vec![(
                "homogeneous_vs_fig2",
                runs.get("fig2")
                    .and_then(|r| runs.get("homogeneous").map(|h| c6_part(r, h))),
            )],
        ),
        assemble(
            "C7",
            "Rising temperature (fig4) lowers the amplitudes of F, ⟨φ⟩, ⟨ε⟩ while the event \
             frequency still grows.",
            "fig4: f_peak strictly decreasing event by event; cycle amplitudes (max − min \
             between successive onsets) of F, ⟨φ⟩, ⟨ε⟩ strictly decreasing; intervals strictly \
             decreasing"
                .into(),
            "the paper's statement taken literally: strict monotonicity, no tolerance".into(),
            vec![("fig4", on("fig4", c7_part))],
        ),
        assemble(
            "C8",
            "A ≤ 0: complete melting, F = 0, smooth sliding.",
            format!(
                "melt scene: melted fraction ≥ 1 − 1e-9 at all times, no event after t = 0, \
                 max|F| ≤ {C8_FORCE_TOL:.0e}·τmax·πa0², max|X − (V0t − (V0/ω) sin ωt)| ≤ \
                 {C8_X_TOL:.0e}·max X"
            ),
            format!(
                "F is exactly 0 in the model; {C8_X_TOL:.0e} of X lies above the drive \
                 integrator's own error (measured beside) and below what 2e-8 N of friction would do"
            ),
            vec![("melt", on("melt", c8_part))],
        ),
        assemble(
            "C9",
            "F(X) is periodic in X for fig2 and damped for fig4 (fig5).",
            format!(
                "fig2: CV of the X-distance between successive onsets < {C9_MAX_CV_X}; fig4: \
                 last f_peak / first f_peak < {C9_MAX_DAMPING_RATIO}"
            ),
            format!(
                "equal X spacing while the time intervals vary far more (their CV is shown \
                 beside); a {:.0} % fall is far above resolution. {KINEMATIC}",
                100.0 * (1.0 - C9_MAX_DAMPING_RATIO)
            ),
            vec![
                ("fig2", on("fig2", c9_periodic_part)),
                ("fig4", on("fig4", c9_damped_part)),
            ],
        ),
        assemble(
            "C10",
            "Rigid drive: events evenly spaced in time.",
            format!(
                "rigid drive V0 = {rigid_v0} m/s: CV of the intervals between successive onsets < \
                 {C10_MAX_CV} (≥ 3 events)"
            ),
            format!(
                "constant speed and identical cycles; {:.0} % allows only a short transient",
                100.0 * C10_MAX_CV
            ),
            vec![("rigid", on("rigid", c10_part))],
        ),
    ]
}
