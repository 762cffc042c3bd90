//! The reference extrapolated in N as well as in Δt.
//!
//! The work–precision reference is the accurate scheme at N = `ref_nodes` (400 in the full
//! study), extrapolated in Δt. It judges runs up to N = 2000, finer than itself, so its own
//! spatial error would pass for theirs. The accurate N study (N = 125 … 2000 at Δt = 1e-8 s)
//! measures that error: Celik's procedure on its three finest levels gives the limit φ∞ and
//! the order p, and the error model e(N) = (φ_m − φ∞)·(m/N)^p from the level m nearest above
//! the reference's N gives e(ref_nodes). The reference's onsets and peak forces become
//! R − e(ref_nodes), with an uncertainty of the Δt GCI, plus the N extrapolation's GCI, plus
//! the spread of e(ref_nodes) between the two levels above it (how far the error model is from
//! a pure power). The correction assumes the Δt and N errors add, which the study's two
//! budgets separate (§2).
//!
//! Every run whose events are stored is judged again against the corrected reference. The
//! F(t) stick-phase errors, whose samples are not stored, stay against the N = `ref_nodes`
//! reference, and the report says so; work–precision points stored without their events get
//! the bound old error + largest correction.

use crate::celik;
use crate::study::Refined;
use crate::{Results, RunSummary};
use serde::{Deserialize, Serialize};

/// What the N extrapolation changed, per event (kept beside the corrected reference, so
/// that applying it twice is a no-op and the report can show it).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NExtrapolation {
    /// The N study levels Celik's procedure used (fine to coarse).
    pub levels: Vec<usize>,
    /// The reference's onsets at its own N (extrapolated in Δt only), s.
    pub onsets_at_ref_nodes_s: Vec<f64>,
    /// e(ref_nodes) subtracted from each onset, s.
    pub onset_correction_s: Vec<f64>,
    /// The N part of each onset's uncertainty (GCI plus the model's spread), s.
    pub onset_n_uncertainty_s: Vec<f64>,
    /// Observed order in N per event (None where Celik failed or oscillated).
    pub onset_order: Vec<Option<f64>>,
    /// The reference's peak forces at its own N, N.
    pub f_peaks_at_ref_nodes_n: Vec<f64>,
    /// e(ref_nodes) subtracted from each peak force, N.
    pub f_peak_correction_n: Vec<f64>,
    /// The N part of each peak force's uncertainty, N.
    pub f_peak_n_uncertainty_n: Vec<f64>,
    /// Work–precision points whose errors are bounds (stored without their events).
    pub bounded_points: usize,
}

impl NExtrapolation {
    /// Largest |onset correction|, s.
    #[must_use]
    pub fn max_onset_correction_s(&self) -> f64 {
        self.onset_correction_s
            .iter()
            .fold(0.0_f64, |m, v| m.max(v.abs()))
    }
}

/// e(target) and its uncertainty for one event, from the N study's `levels` (nodes, value)
/// sorted fine to coarse.
fn correction(levels: &[(usize, f64)], target: usize) -> Option<(f64, f64, Option<f64>)> {
    if levels.len() < 3 {
        return None;
    }
    let h = [0, 1, 2].map(|i| 1.0 / levels[i].0 as f64);
    let v = [0, 1, 2].map(|i| levels[i].1);
    let model = |c: celik::Celik| {
        // The levels at or above the target, nearest first: the model from each.
        let mut above: Vec<&(usize, f64)> = levels.iter().filter(|l| l.0 >= target).collect();
        above.sort_by_key(|l| l.0);
        let e = |l: &(usize, f64)| (l.1 - c.phi_ext) * (l.0 as f64 / target as f64).powf(c.p);
        let first = e(above.first()?);
        let spread = above.get(1).map_or(first.abs(), |l| (e(l) - first).abs());
        Some((first, c.gci_fine_abs + spread, Some(c.p)))
    };
    match celik::three_grid(h, v) {
        Ok(c) if !c.oscillatory => model(c),
        // No order: no correction, and the finest levels' spread as the N uncertainty.
        _ => Some((0.0, (v[0] - v[2]).abs(), None)),
    }
}

/// Max over the common events of |run − reference| (relative with `relative`).
fn max_error(
    run: &RunSummary,
    reference: &[f64],
    get: fn(&crate::fig2::EventRecord) -> f64,
    relative: bool,
) -> Option<f64> {
    let common = run.events.len().min(reference.len());
    (run.failure.is_none() && common > 0).then(|| {
        (0..common)
            .map(|k| {
                let d = (get(&run.events[k]) - reference[k]).abs();
                if relative { d / reference[k].abs() } else { d }
            })
            .fold(0.0_f64, f64::max)
    })
}

/// Corrects the reference of `r` in N and judges every stored run again (see the module
/// docs). A no-op when the reference is already corrected, or when the N study has fewer than
/// three accurate levels or none finer than the reference.
pub fn apply(r: &mut Results) {
    let wp = &r.work_precision.reference;
    if wp.n_extrapolation.is_some() {
        return;
    }
    let target = wp.nodes;
    let mut n_runs: Vec<&RunSummary> = r
        .runs
        .iter()
        .filter(|x| {
            x.role == Refined::Nodes.as_str() && x.scheme == "accurate" && x.failure.is_none()
        })
        .collect();
    n_runs.sort_by_key(|x| std::cmp::Reverse(x.nodes));
    if n_runs.len() < 3 || n_runs[0].nodes <= target {
        return;
    }
    let events = wp.onsets_s.len();
    let mut x = NExtrapolation {
        levels: n_runs.iter().take(3).map(|x| x.nodes).collect(),
        onsets_at_ref_nodes_s: wp.onsets_s.clone(),
        onset_correction_s: Vec::new(),
        onset_n_uncertainty_s: Vec::new(),
        onset_order: Vec::new(),
        f_peaks_at_ref_nodes_n: wp.f_peaks_n.clone(),
        f_peak_correction_n: Vec::new(),
        f_peak_n_uncertainty_n: Vec::new(),
        bounded_points: 0,
    };
    for k in 0..events {
        let level = |get: fn(&crate::fig2::EventRecord) -> f64| -> Vec<(usize, f64)> {
            n_runs
                .iter()
                .filter_map(|x| x.events.get(k).map(|e| (x.nodes, get(e))))
                .collect()
        };
        let (c, u, p) = correction(&level(|e| e.onset_s), target).unwrap_or((0.0, 0.0, None));
        x.onset_correction_s.push(c);
        x.onset_n_uncertainty_s.push(u);
        x.onset_order.push(p);
        let (c, u, _) = correction(&level(|e| e.f_peak_n), target).unwrap_or((0.0, 0.0, None));
        x.f_peak_correction_n.push(c);
        x.f_peak_n_uncertainty_n.push(u);
    }
    let reference = &mut r.work_precision.reference;
    for k in 0..events {
        reference.onsets_s[k] -= x.onset_correction_s[k];
        reference.onset_uncertainty_s[k] += x.onset_n_uncertainty_s[k];
        reference.f_peaks_n[k] -= x.f_peak_correction_n[k];
        reference.f_peak_uncertainty_n[k] += x.f_peak_n_uncertainty_n[k];
    }
    let onsets = reference.onsets_s.clone();
    let peaks = reference.f_peaks_n.clone();
    let max_c = x.max_onset_correction_s();
    let max_fc = x
        .f_peak_correction_n
        .iter()
        .zip(&peaks)
        .fold(0.0_f64, |m, (c, f)| m.max((c / f).abs()));
    for run in &mut r.runs {
        if run.events.is_empty() {
            // Stored without events: the error against the corrected reference is within the
            // largest correction of the old one; quote that bound.
            if run.failure.is_none() && run.onset_error_s.is_some() {
                x.bounded_points += 1;
            }
            run.onset_error_s = run.onset_error_s.map(|e| e + max_c);
            run.f_peak_error_rel = run.f_peak_error_rel.map(|e| e + max_fc);
            continue;
        }
        run.onset_error_s = max_error(run, &onsets, |e| e.onset_s, false);
        run.f_peak_error_rel = max_error(run, &peaks, |e| e.f_peak_n, true);
    }
    for p in &mut r.work_precision.points {
        if p.event_records.is_empty() {
            p.onset_error_s = p.onset_error_s.map(|e| e + max_c);
            p.f_peak_error_rel = p.f_peak_error_rel.map(|e| e + max_fc);
            continue;
        }
        let as_run = RunSummary {
            role: String::new(),
            scheme: p.method.clone(),
            nodes: p.nodes,
            dt_s: p.dt_s,
            wall_s: p.wall_s,
            events: p.event_records.clone(),
            failure: p.failure.clone(),
            onset_error_s: None,
            f_peak_error_rel: None,
            force_error_rel: None,
        };
        p.onset_error_s = max_error(&as_run, &onsets, |e| e.onset_s, false);
        p.f_peak_error_rel = max_error(&as_run, &peaks, |e| e.f_peak_n, true);
    }
    r.work_precision.reference.n_extrapolation = Some(x);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pure_power_error_is_removed_exactly() {
        // φ(N) = 1 + 3·N^-2: e(400) = 3/400², the spread between the levels above it 0.
        let levels: Vec<(usize, f64)> = [2000, 1000, 500, 250]
            .iter()
            .map(|&n| (n, 1.0 + 3.0 / (n as f64).powi(2)))
            .collect();
        let (c, u, p) = correction(&levels, 400).expect("three levels");
        assert!((c - 3.0 / 400.0_f64.powi(2)).abs() < 1e-12, "{c}");
        assert!((p.expect("order") - 2.0).abs() < 1e-9);
        assert!(u < 1e-6, "{u}");
    }

    #[test]
    fn oscillating_levels_give_no_correction_and_their_spread() {
        let levels = vec![(2000, 1.0), (1000, 1.1), (500, 0.95)];
        let (c, u, p) = correction(&levels, 400).expect("three levels");
        assert_eq!(c, 0.0);
        assert!(p.is_none());
        assert!((u - 0.05).abs() < 1e-12);
    }
}
