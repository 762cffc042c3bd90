//! Whole-simulation convergence of fig2 (no exact answer): event onsets, peak forces per event
//! and the stick-phase force, refining N and Δt separately for each scheme.
//!
//! Observables, per run (see [`crate::fig2`]):
//! - `onset`: the onset of event k located inside its step (the core's, on the node's exact
//!   path, for the accurate scheme; ln φ interpolated to the threshold for the literal one);
//! - `f_peak`: the core's peak force before event k (largest step-end F since the previous
//!   event began);
//! - `force_stick_rms`: F(t) on the common 0.1 µs grid, restricted to the stick phases S (all
//!   sample times farther than [`STICK_GUARD_S`] from every onset of the comparison run), in the
//!   norm ‖g‖ = √(mean_S g²) / max_S |F_ref|: a relative RMS force error over the stick phases.
//!
//! Scalar observables go through Celik's procedure directly. For F(t) the three-grid order comes
//! from the norms of successive differences, p from ‖F3 − F2‖/‖F2 − F1‖ (Celik's iteration with
//! s = +1); F_ext(t) = (r^p·F1 − F2)/(r^p − 1) pointwise, errors are ‖F_k − F_ext‖ and the
//! GCI is 1.25·‖F1 − F2‖/(r^p − 1), already relative to the force scale. The share of sample
//! times whose differences alternate in sign is reported as the oscillatory share.

use crate::celik::{self, Celik, CelikFailure};
use crate::fig2::{RunRecord, RunSpec, SAMPLE_DT_S};
use crate::study::{ErrorKind, Refined, Study};
use stickslip_core::config::Scheme;

/// Half-width of the window around each onset excluded from the stick phases, s.
pub const STICK_GUARD_S: f64 = 5e-6;

/// Name of a scheme in tables.
pub fn scheme_name(s: Scheme) -> &'static str {
    match s {
        Scheme::Literal => "literal",
        Scheme::Accurate => "accurate",
    }
}

/// Sample indices of the stick phases: farther than [`STICK_GUARD_S`] from every onset in
/// `onsets_s`, and below `len`.
pub fn stick_mask(onsets_s: &[f64], len: usize) -> Vec<usize> {
    (0..len)
        .filter(|&j| {
            let t = RunRecord::sample_time_s(j);
            onsets_s.iter().all(|&o| (t - o).abs() > STICK_GUARD_S)
        })
        .collect()
}

/// √(mean over `mask` of (a − b)²) / `scale`.
pub fn rms_on(mask: &[usize], a: &[f64], b: &[f64], scale: f64) -> f64 {
    if mask.is_empty() {
        return f64::NAN;
    }
    let s: f64 = mask.iter().map(|&j| (a[j] - b[j]).powi(2)).sum();
    (s / mask.len() as f64).sqrt() / scale
}

/// Relative stick-phase RMS error of `run`'s F(t) against `reference` samples, on the stick
/// phases of `reference_onsets_s`. `None` when the run failed before the end.
pub fn force_error(run: &RunRecord, reference: &[f64], reference_onsets_s: &[f64]) -> Option<f64> {
    if run.failure.is_some() || run.force_samples_n.len() < reference.len() {
        return None;
    }
    let mask = stick_mask(reference_onsets_s, reference.len());
    let scale = mask.iter().fold(0.0_f64, |m, &j| m.max(reference[j].abs()));
    Some(rms_on(&mask, &run.force_samples_n, reference, scale))
}

/// The theory of a whole-simulation observable (`onset`, `f_peak`, `force_stick_rms`):
/// (order, words).
pub fn theory(scheme: Scheme, refined: Refined, observable: &str) -> (Option<f64>, &'static str) {
    match (scheme, refined, observable) {
        (Scheme::Accurate, Refined::Nodes, "onset") => (
            Some(2.0),
            "2: first melting at the outermost node, which the default edge-graded grid puts \
             a0·N^-3 from the edge (on the uniform grid, a0/N: order 1, section 8)",
        ),
        (Scheme::Accurate, Refined::Nodes, _) => (
            Some(2.0),
            "2: product integration on the edge-graded grid is second order up to the edge \
             (on the uniform grid 3/2 with a square-root edge layer: smooth pair of section 1)",
        ),
        (Scheme::Literal, Refined::Nodes, "onset") => (
            None,
            "none: decided at the axis, where u3D = 0 for every N (a different limit)",
        ),
        (Scheme::Literal, Refined::Nodes, _) => (
            Some(0.5),
            "1/2: the skipped singular term of the plain sums",
        ),
        (Scheme::Literal, Refined::Dt, _) => (
            Some(1.0),
            "1: explicit Euler, lagged coupling, one reset per step",
        ),
        (Scheme::Accurate, Refined::Dt, _) => (
            Some(2.0),
            "2: exact Landau step under the θ-weighted strain, substrate predicted by \
             extrapolation, melting located inside the step",
        ),
    }
}

/// Runs fig2 with `scheme` at every level of `refined` (`levels`: N or Δt, coarse to fine),
/// the other resolution held at `fixed` (Δt in s, or N), up to `end_s` (fig2: 1.3e-3).
/// `progress` is told about each run.
pub fn run_levels(
    scheme: Scheme,
    refined: Refined,
    levels: &[f64],
    fixed: f64,
    end_s: f64,
    progress: &mut dyn FnMut(&RunRecord),
) -> Vec<RunRecord> {
    levels
        .iter()
        .map(|&l| {
            let mut spec = match refined {
                Refined::Nodes => RunSpec::fig2(scheme, l as usize, fixed),
                Refined::Dt => RunSpec::fig2(scheme, fixed as usize, l),
            };
            spec.end_s = end_s;
            let r = crate::fig2::run(&spec);
            progress(&r);
            r
        })
        .collect()
}

/// The studies of one refinement sequence `runs` (coarse to fine, same scheme).
///
/// # Panics
/// If `runs` is empty.
#[track_caller]
pub fn studies(refined: Refined, runs: &[RunRecord]) -> Vec<Study> {
    assert!(!runs.is_empty(), "no runs");
    let scheme = runs[0].spec.scheme;
    let levels: Vec<f64> = runs
        .iter()
        .map(|r| match refined {
            Refined::Nodes => r.spec.nodes as f64,
            Refined::Dt => r.spec.dt_s,
        })
        .collect();
    let fixed = match refined {
        Refined::Nodes => format!("dt = {:e} s", runs[0].spec.dt_s),
        Refined::Dt => format!("N = {}", runs[0].spec.nodes),
    };
    let events = runs
        .iter()
        .filter(|r| r.failure.is_none())
        .map(|r| r.events.len())
        .max()
        .unwrap_or(0);
    let counts: Vec<String> = runs.iter().map(|r| r.events.len().to_string()).collect();
    let count_note = if runs
        .iter()
        .any(|r| r.failure.is_none() && r.events.len() != events)
    {
        format!("event counts per level differ: {}", counts.join(", "))
    } else {
        String::new()
    };
    let mut out = Vec::new();
    for k in 0..events {
        let value = |f: &dyn Fn(&crate::fig2::EventRecord) -> f64| -> Vec<Option<f64>> {
            runs.iter()
                .map(|r| {
                    if r.failure.is_some() {
                        None
                    } else {
                        r.events.get(k).map(f)
                    }
                })
                .collect()
        };
        out.push(
            Study::self_convergence(
                "simulation",
                "onset",
                scheme_name(scheme),
                refined,
                levels.clone(),
                &fixed,
                "s",
                value(&|e| e.onset_s),
                theory(scheme, refined, "onset"),
            )
            .with_event(k + 1)
            .with_note(&count_note),
        );
        out.push(
            Study::self_convergence(
                "simulation",
                "f_peak",
                scheme_name(scheme),
                refined,
                levels.clone(),
                &fixed,
                "N",
                value(&|e| e.f_peak_n),
                theory(scheme, refined, "f_peak"),
            )
            .with_event(k + 1)
            .with_note(&count_note),
        );
    }
    out.push(force_study(
        refined,
        runs,
        &levels,
        &fixed,
        theory(scheme, refined, "force_stick_rms"),
    ));
    out
}

/// The F(t) stick-phase study described in the module documentation.
fn force_study(
    refined: Refined,
    runs: &[RunRecord],
    levels: &[f64],
    fixed: &str,
    theory: (Option<f64>, &str),
) -> Study {
    let scheme = runs[0].spec.scheme;
    let ok: Vec<usize> = (0..runs.len())
        .filter(|&i| runs[i].failure.is_none())
        .collect();
    let mut study = Study {
        study: "simulation".into(),
        observable: "force_stick_rms".into(),
        scheme: scheme_name(scheme).into(),
        refined,
        levels: levels.to_vec(),
        fixed: fixed.to_string(),
        event: None,
        unit: "relative (RMS over stick phases / max F)".into(),
        values: None,
        errors: vec![None; runs.len()],
        error_kind: ErrorKind::VsExtrapolated,
        observed_order: vec![None; runs.len().saturating_sub(2)],
        theory_order: theory.0,
        theory: theory.1.to_string(),
        gci: None,
        gci_failure: None,
        note: String::new(),
        early_stick_rel_diff: None,
    };
    let Some(&finest) = ok.last() else {
        study.gci_failure = Some(CelikFailure::NonFinite);
        return study;
    };
    let onsets: Vec<f64> = runs[finest].events.iter().map(|e| e.onset_s).collect();
    let len = runs[finest].force_samples_n.len();
    let mask = stick_mask(&onsets, len);
    let scale = mask.iter().fold(0.0_f64, |m, &j| {
        m.max(runs[finest].force_samples_n[j].abs())
    });
    let f = |i: usize| &runs[i].force_samples_n;
    let usable = |i: usize| runs[i].failure.is_none() && runs[i].force_samples_n.len() >= len;
    let h = |i: usize| refined.spacing(levels[i]);
    // Apparent order of each consecutive triple from difference norms.
    for k in 0..study.observed_order.len() {
        if usable(k) && usable(k + 1) && usable(k + 2) {
            let d21 = rms_on(&mask, f(k + 2), f(k + 1), scale);
            let d32 = rms_on(&mask, f(k + 1), f(k), scale);
            study.observed_order[k] = norm_order([h(k + 2), h(k + 1), h(k)], d21, d32)
                .ok()
                .map(|(p, _)| p);
        }
    }
    let valid: Vec<usize> = (0..runs.len()).filter(|&i| usable(i)).collect();
    if valid.len() < 3 {
        study.gci_failure = Some(CelikFailure::NonFinite);
        return study;
    }
    if let Some(&t1) = onsets.first() {
        let j = ((0.5 * t1) / SAMPLE_DT_S).round() as usize;
        let fa = f(*valid.last().expect("three levels"))[j];
        study.early_stick_rel_diff = Some(
            valid
                .iter()
                .map(|&i| ((f(i)[j] - fa) / fa).abs())
                .fold(0.0_f64, f64::max),
        );
    }
    let [a, b, c] = [
        valid[valid.len() - 1],
        valid[valid.len() - 2],
        valid[valid.len() - 3],
    ];
    let d21 = rms_on(&mask, f(b), f(a), scale);
    let d32 = rms_on(&mask, f(c), f(b), scale);
    match norm_order([h(a), h(b), h(c)], d21, d32) {
        Ok((p, r21)) => {
            let rp = r21.powf(p);
            let f_ext: Vec<f64> = f(a)
                .iter()
                .zip(f(b))
                .map(|(&f1, &f2)| (rp * f1 - f2) / (rp - 1.0))
                .collect();
            for i in 0..runs.len() {
                if usable(i) {
                    study.errors[i] = Some(rms_on(&mask, f(i), &f_ext, scale));
                }
            }
            let oscillating = mask
                .iter()
                .filter(|&&j| (f(c)[j] - f(b)[j]) * (f(b)[j] - f(a)[j]) < 0.0)
                .count();
            let share = oscillating as f64 / mask.len().max(1) as f64;
            let e_ext = rms_on(&mask, f(a), &f_ext, scale);
            study.gci = Some(Celik {
                r21,
                r32: h(c) / h(b),
                p,
                phi_ext: 0.0,
                e_a: d21,
                e_ext,
                gci_fine: 1.25 * d21 / (rp - 1.0),
                gci_fine_abs: 1.25 * d21 / (rp - 1.0) * scale,
                oscillatory: share > 0.5,
                iterations: 0,
            });
            let first = onsets.first().copied().unwrap_or(f64::INFINITY) - STICK_GUARD_S;
            let before = valid
                .iter()
                .flat_map(|&i| {
                    mask.iter()
                        .filter(|&&j| RunRecord::sample_time_s(j) < first)
                        .map(move |&j| (f(i)[j] - f(a)[j]).abs() / scale)
                })
                .fold(0.0_f64, f64::max);
            study.note = format!(
                "stick phases: {} of {} samples (0.1 us grid, +-{} us around {} onsets excluded); \
                 differences alternate in sign at {:.0} % of them; before the first onset all \
                 levels agree with the finest to {:.1e} of max F",
                mask.len(),
                len,
                STICK_GUARD_S * 1e6,
                onsets.len(),
                100.0 * share,
                before
            );
        }
        Err(e) => {
            study.gci_failure = Some(e);
            for i in 0..runs.len() {
                if usable(i) && i != a {
                    study.errors[i] = Some(rms_on(&mask, f(i), f(a), scale));
                }
            }
            study.error_kind = ErrorKind::VsFinest;
        }
    }
    study
}

/// Celik's order for difference norms d21 = ‖f2 − f1‖, d32 = ‖f3 − f2‖ (s = +1): (p, r21).
///
/// # Errors
/// As [`celik::three_grid`].
pub fn norm_order(h: [f64; 3], d21: f64, d32: f64) -> Result<(f64, f64), CelikFailure> {
    let c = celik::three_grid(h, [0.0, d21, d21 + d32])?;
    Ok((c.p, c.r21))
}

/// Common sample count of F(t) records (the end time over [`SAMPLE_DT_S`], plus one).
pub fn samples_for(end_s: f64) -> usize {
    (end_s / SAMPLE_DT_S).floor() as usize + 1
}

/// Where the Δt error of the onsets is made: the first onset with a coarse step throughout,
/// a fine step throughout, and switched between the two `lead_s` before the onset.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Localisation {
    /// Scheme.
    pub scheme: String,
    /// Nodes.
    pub nodes: usize,
    /// Coarse and fine step, s.
    pub dts_s: (f64, f64),
    /// Time of the switch, s (a multiple of the coarse step).
    pub t_switch_s: f64,
    /// First onset: coarse, fine, coarse then fine, fine then coarse, s.
    pub onsets_s: [f64; 4],
}

/// Runs the four variants of [`Localisation`] up to just after the first event.
pub fn localise(
    scheme: Scheme,
    nodes: usize,
    coarse_s: f64,
    fine_s: f64,
    lead_s: f64,
    progress: &mut dyn FnMut(&RunRecord),
) -> Localisation {
    let end = 6.2e-4;
    let mut run = |dt: f64, switch: Option<(f64, f64)>| {
        let mut spec = RunSpec::fig2(scheme, nodes, dt);
        spec.end_s = end;
        spec.switch = switch;
        let r = crate::fig2::run(&spec);
        progress(&r);
        r.events.first().map_or(f64::NAN, |e| e.onset_s)
    };
    let coarse = run(coarse_s, None);
    let fine = run(fine_s, None);
    let t_switch = ((fine - lead_s) / coarse_s).floor() * coarse_s;
    let coarse_fine = run(coarse_s, Some((t_switch, fine_s)));
    let fine_coarse = run(fine_s, Some((t_switch, coarse_s)));
    Localisation {
        scheme: scheme_name(scheme).to_string(),
        nodes,
        dts_s: (coarse_s, fine_s),
        t_switch_s: t_switch,
        onsets_s: [coarse, fine, coarse_fine, fine_coarse],
    }
}
