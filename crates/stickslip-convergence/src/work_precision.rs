//! Work–precision: error of fig2's event onsets, peak forces and stick-phase force against wall
//! seconds, one curve per method, against a reference much finer than any curve point.
//!
//! The reference is the accurate scheme at `ref_nodes` (twice the finest N of any curve point
//! by default) with three time steps, the coarsest no larger than the finest curve point's and
//! refined by 2: per event, Celik's procedure extrapolates onset and peak force in Δt, and its
//! GCI is the reference's own uncertainty; F(t) is extrapolated pointwise with the order of its
//! difference norms (see [`crate::simulation`]). Timings are medians of `repeats` runs of each
//! point, measured in the same process, one after the other.

use crate::celik;
use crate::fig2::{EventRecord, RunRecord, RunSpec, run};
use crate::simulation::{self, force_error, norm_order, scheme_name, stick_mask};
use crate::study::Refined;
use serde::{Deserialize, Serialize};
use stickslip_core::config::Scheme;

/// The fig2 reference solution.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Reference {
    /// Nodes of the reference runs.
    pub nodes: usize,
    /// Time steps of the three runs, coarse to fine, s.
    pub dts_s: Vec<f64>,
    /// Extrapolated onset per event, s.
    pub onsets_s: Vec<f64>,
    /// Its uncertainty per event (Celik GCI in s; |φ1 − φ2| where Celik failed).
    pub onset_uncertainty_s: Vec<f64>,
    /// Apparent order in Δt per event (None where Celik failed).
    pub onset_order: Vec<Option<f64>>,
    /// Extrapolated peak force per event, N.
    pub f_peaks_n: Vec<f64>,
    /// Its uncertainty per event, N.
    pub f_peak_uncertainty_n: Vec<f64>,
    /// Order of the F(t) difference norms in Δt.
    pub force_order: Option<f64>,
    /// GCI of the extrapolated F(t) in the stick-phase norm (relative).
    pub force_uncertainty_rel: Option<f64>,
    /// Wall seconds of the three runs.
    pub wall_s: Vec<f64>,
    /// The correction in N applied to the onsets and peak forces above (none: the reference
    /// is extrapolated in Δt only, at N = `nodes`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub n_extrapolation: Option<crate::n_reference::NExtrapolation>,
    /// Extrapolated F(t) samples (not written to JSON).
    #[serde(skip)]
    pub force_n: Vec<f64>,
}

/// One point of a work–precision curve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WpPoint {
    /// Method (scheme) name.
    pub method: String,
    /// Nodes N.
    pub nodes: usize,
    /// Time step, s.
    pub dt_s: f64,
    /// Median wall seconds over the repeats.
    pub wall_s: f64,
    /// All repeat timings, s.
    pub walls_s: Vec<f64>,
    /// max over events of |onset − reference onset|, s.
    pub onset_error_s: Option<f64>,
    /// max over events of |f_peak − reference|/reference.
    pub f_peak_error_rel: Option<f64>,
    /// Stick-phase RMS force error relative to max F.
    pub force_error_rel: Option<f64>,
    /// Events of the run (the reference has `Reference::onsets_s.len()`).
    pub events: usize,
    /// The events themselves (onsets, peak forces), so that a later reference can judge the
    /// point again; empty in studies made before they were kept.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub event_records: Vec<crate::fig2::EventRecord>,
    /// The core's error message if the run failed.
    pub failure: Option<String>,
}

/// The whole work–precision study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WorkPrecision {
    /// The reference.
    pub reference: Reference,
    /// The points, per method in order of refinement.
    pub points: Vec<WpPoint>,
    /// Repeats per point.
    pub repeats: usize,
}

/// Computes the reference from three accurate runs at `nodes` with `dts_s` (coarse to fine,
/// ratio 2). Returns it with the runs.
///
/// # Panics
/// If `dts_s` does not hold three steps, or the finest run fails.
#[track_caller]
pub fn reference(
    nodes: usize,
    dts_s: [f64; 3],
    progress: &mut dyn FnMut(&RunRecord),
) -> (Reference, Vec<RunRecord>) {
    let runs = simulation::run_levels(
        Scheme::Accurate,
        Refined::Dt,
        &dts_s,
        nodes as f64,
        crate::fig2::FIG2_END_S,
        progress,
    );
    assert!(
        runs[2].failure.is_none(),
        "reference run failed: {:?}",
        runs[2].failure
    );
    let events = runs.iter().map(|r| r.events.len()).min().unwrap_or(0);
    let h = [dts_s[2], dts_s[1], dts_s[0]];
    let mut r = Reference {
        nodes,
        dts_s: dts_s.to_vec(),
        onsets_s: Vec::new(),
        onset_uncertainty_s: Vec::new(),
        onset_order: Vec::new(),
        f_peaks_n: Vec::new(),
        f_peak_uncertainty_n: Vec::new(),
        force_order: None,
        force_uncertainty_rel: None,
        wall_s: runs.iter().map(|r| r.wall_s).collect(),
        n_extrapolation: None,
        force_n: Vec::new(),
    };
    let extrapolate = |k: usize, get: fn(&EventRecord) -> f64| -> (f64, f64, Option<f64>) {
        let v = [
            get(&runs[2].events[k]),
            get(&runs[1].events[k]),
            get(&runs[0].events[k]),
        ];
        match celik::three_grid(h, v) {
            Ok(c) if !c.oscillatory => (c.phi_ext, c.gci_fine_abs, Some(c.p)),
            _ => (v[0], (v[0] - v[1]).abs(), None),
        }
    };
    for k in 0..events {
        let (value, unc, p) = extrapolate(k, |e| e.onset_s);
        r.onsets_s.push(value);
        r.onset_uncertainty_s.push(unc);
        r.onset_order.push(p);
        let (value, unc, _) = extrapolate(k, |e| e.f_peak_n);
        r.f_peaks_n.push(value);
        r.f_peak_uncertainty_n.push(unc);
    }
    let onsets: Vec<f64> = runs[2].events.iter().map(|e| e.onset_s).collect();
    let len = runs[2].force_samples_n.len();
    let mask = stick_mask(&onsets, len);
    let scale = mask
        .iter()
        .fold(0.0_f64, |m, &j| m.max(runs[2].force_samples_n[j].abs()));
    let f = |i: usize| &runs[i].force_samples_n;
    let d21 = simulation::rms_on(&mask, f(1), f(2), scale);
    let d32 = simulation::rms_on(&mask, f(0), f(1), scale);
    r.force_n = match norm_order(h, d21, d32) {
        Ok((p, r21)) => {
            let rp = r21.powf(p);
            r.force_order = Some(p);
            r.force_uncertainty_rel = Some(1.25 * d21 / (rp - 1.0));
            f(2).iter()
                .zip(f(1))
                .map(|(&f1, &f2)| (rp * f1 - f2) / (rp - 1.0))
                .collect()
        }
        Err(_) => {
            r.force_uncertainty_rel = Some(d21);
            f(2).clone()
        }
    };
    (r, runs)
}

/// Errors of `run` against `reference`.
pub fn point(run: &RunRecord, reference: &Reference, walls_s: Vec<f64>) -> WpPoint {
    let ok = run.failure.is_none();
    let common = run.events.len().min(reference.onsets_s.len());
    let max_over = |f: &dyn Fn(usize) -> f64| -> Option<f64> {
        (ok && common > 0).then(|| (0..common).map(f).fold(0.0_f64, f64::max))
    };
    let onset_error_s = max_over(&|k| (run.events[k].onset_s - reference.onsets_s[k]).abs());
    let f_peak_error_rel = max_over(&|k| {
        ((run.events[k].f_peak_n - reference.f_peaks_n[k]) / reference.f_peaks_n[k]).abs()
    });
    let force_error_rel = force_error(run, &reference.force_n, &reference.onsets_s);
    WpPoint {
        method: scheme_name(run.spec.scheme).to_string(),
        nodes: run.spec.nodes,
        dt_s: run.spec.dt_s,
        wall_s: stickslip_report::stats::median(&walls_s),
        walls_s,
        onset_error_s,
        f_peak_error_rel,
        force_error_rel,
        events: run.events.len(),
        event_records: run.events.clone(),
        failure: run.failure.clone(),
    }
}

/// Runs every point `repeats` times and measures it against `reference`.
pub fn curve(
    scheme: Scheme,
    points: &[(usize, f64)],
    repeats: usize,
    reference: &Reference,
    progress: &mut dyn FnMut(&RunRecord),
) -> Vec<WpPoint> {
    points
        .iter()
        .map(|&(n, dt)| {
            let spec = RunSpec::fig2(scheme, n, dt);
            let mut walls = Vec::new();
            let mut first = None;
            for _ in 0..repeats.max(1) {
                let r = run(&spec);
                progress(&r);
                walls.push(r.wall_s);
                first.get_or_insert(r);
            }
            point(first.as_ref().expect("one run"), reference, walls)
        })
        .collect()
}
