//! Same-N references: a converged solution in Δt at the very N of the runs it judges, so that
//! a time-stepping error is not mixed with the spatial error of another N.
//!
//! Fixed steps of the accurate scheme are second order in Δt (onsets, t_end, f_peak, F(t)), so
//! the reference is the Richardson extrapolation of the two finest of three fixed-step levels
//! h, h/2, h/4: R = (4·f(h/4) − f(h/2))/3. The coarsest level gives a second extrapolation
//! R' = (4·f(h/2) − f(h))/3; |R − R'| is stated as the reference's uncertainty (an upper
//! estimate: R' is the less accurate of the two), and log2(|f(h) − f(h/2)| / |f(h/2) −
//! f(h/4)|) is the observed order that justifies the extrapolation. The functions here are
//! pure; the convergence study feeds them in-process runs, `cargo xtask bench` the CLI's
//! events.csv.

use serde::{Deserialize, Serialize};

/// Richardson extrapolation of a second-order quantity from steps h (`coarse`) and h/2
/// (`fine`).
#[must_use]
pub fn richardson(coarse: f64, fine: f64) -> f64 {
    (4.0 * fine - coarse) / 3.0
}

/// Observed order of three levels with step ratio 2 (coarse to fine), `None` when the
/// differences vanish, are not finite or alternate in sign.
#[must_use]
pub fn observed_order(coarse: f64, mid: f64, fine: f64) -> Option<f64> {
    let (d1, d2) = (mid - coarse, fine - mid);
    let p = (d1 / d2).log2();
    (d1 * d2 > 0.0 && p.is_finite()).then_some(p)
}

/// The event quantities of one run that the references and errors compare.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct EventValues {
    /// Onset per event, s.
    pub onsets_s: Vec<f64>,
    /// t_end per event (None while open at the end), s.
    pub t_ends_s: Vec<Option<f64>>,
    /// f_peak per event, N.
    pub f_peaks_n: Vec<f64>,
}

impl EventValues {
    /// Events.
    #[must_use]
    pub fn len(&self) -> usize {
        self.onsets_s.len()
    }

    /// Whether there are none.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.onsets_s.is_empty()
    }
}

/// A same-N reference of the event quantities (and, when given, of F(t) samples).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SameNReference {
    /// Nodes N.
    pub nodes: usize,
    /// The three fixed steps, coarse to fine (ratio 2), s.
    pub dts_s: Vec<f64>,
    /// Extrapolated onset per event, s.
    pub onsets_s: Vec<f64>,
    /// Extrapolated t_end per event, s (NaN where a level had none).
    pub t_ends_s: Vec<f64>,
    /// Extrapolated f_peak per event, N.
    pub f_peaks_n: Vec<f64>,
    /// max over events of |R − R'| for onsets, s.
    pub onset_uncertainty_s: f64,
    /// The same for t_end, s.
    pub t_end_uncertainty_s: f64,
    /// The same for f_peak, relative to f_peak.
    pub f_peak_uncertainty_rel: f64,
    /// Median over events of the observed order of onsets, t_end, f_peak (None: undefined).
    pub orders: [Option<f64>; 3],
    /// Stick-phase RMS of R − R' for F(t), relative to max F (None without F samples).
    pub force_uncertainty_rel: Option<f64>,
    /// Wall seconds of the three runs.
    pub wall_s: Vec<f64>,
    /// Extrapolated F(t) samples (not written to JSON).
    #[serde(skip)]
    pub force_n: Vec<f64>,
}

fn median_of(v: Vec<f64>) -> Option<f64> {
    (!v.is_empty()).then(|| stickslip_report::stats::median(&v))
}

impl SameNReference {
    /// The reference from three fixed-step levels (coarse to fine, ratio 2) of the same N.
    /// Events are compared up to the smallest count of the three.
    #[must_use]
    pub fn from_levels(nodes: usize, dts_s: [f64; 3], levels: [&EventValues; 3]) -> Self {
        let events = levels.iter().map(|l| l.len()).min().unwrap_or(0);
        let [c, m, f] = levels;
        let extrapolate = |get: &dyn Fn(&EventValues, usize) -> f64| {
            let mut values = Vec::new();
            let mut unc = 0.0_f64;
            let mut orders = Vec::new();
            for k in 0..events {
                let (a, b, z) = (get(c, k), get(m, k), get(f, k));
                let r = richardson(b, z);
                unc = unc.max((r - richardson(a, b)).abs());
                orders.extend(observed_order(a, b, z));
                values.push(r);
            }
            (values, unc, median_of(orders))
        };
        let (onsets_s, onset_unc, p_onset) = extrapolate(&|l, k| l.onsets_s[k]);
        let (t_ends_s, t_end_unc, p_end) = extrapolate(&|l, k| l.t_ends_s[k].unwrap_or(f64::NAN));
        let (f_peaks_n, f_unc, p_f) = extrapolate(&|l, k| l.f_peaks_n[k]);
        let f_scale = f_peaks_n.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        Self {
            nodes,
            dts_s: dts_s.to_vec(),
            onsets_s,
            t_ends_s,
            f_peaks_n,
            onset_uncertainty_s: onset_unc,
            t_end_uncertainty_s: t_end_unc,
            f_peak_uncertainty_rel: if f_scale > 0.0 { f_unc / f_scale } else { 0.0 },
            orders: [p_onset, p_end, p_f],
            force_uncertainty_rel: None,
            wall_s: Vec::new(),
            force_n: Vec::new(),
        }
    }

    /// Adds the extrapolated F(t) from the samples of the three levels; `mask` selects the
    /// stick-phase samples of the uncertainty's norm.
    pub fn with_force(mut self, samples: [&[f64]; 3], mask: &[usize]) -> Self {
        let len = samples.iter().map(|s| s.len()).min().unwrap_or(0);
        let fine: Vec<f64> = (0..len)
            .map(|j| richardson(samples[1][j], samples[2][j]))
            .collect();
        let coarse: Vec<f64> = (0..len)
            .map(|j| richardson(samples[0][j], samples[1][j]))
            .collect();
        let mask: Vec<usize> = mask.iter().copied().filter(|&j| j < len).collect();
        let scale = mask.iter().fold(0.0_f64, |m, &j| m.max(fine[j].abs()));
        self.force_uncertainty_rel = Some(crate::simulation::rms_on(&mask, &fine, &coarse, scale));
        self.force_n = fine;
        self
    }
}

/// Errors of one run's event quantities against a same-N reference.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct EventErrors {
    /// |first onset − reference|, s.
    pub first_onset_s: Option<f64>,
    /// max over events of |onset − reference|, s.
    pub max_onset_s: Option<f64>,
    /// max over events of |t_end − reference|, s.
    pub max_t_end_s: Option<f64>,
    /// max over events of |f_peak − reference| / reference.
    pub max_f_peak_rel: Option<f64>,
}

/// The errors of `run` against `reference`; all `None` when the event counts differ (an
/// event missed or split is not an error of a few ns).
#[must_use]
pub fn event_errors(run: &EventValues, reference: &SameNReference) -> EventErrors {
    let n = reference.onsets_s.len();
    if run.len() != n || n == 0 {
        return EventErrors::default();
    }
    let max = |f: &dyn Fn(usize) -> f64| (0..n).map(f).fold(0.0_f64, f64::max);
    EventErrors {
        first_onset_s: Some((run.onsets_s[0] - reference.onsets_s[0]).abs()),
        max_onset_s: Some(max(&|k| (run.onsets_s[k] - reference.onsets_s[k]).abs())),
        max_t_end_s: (0..n)
            .all(|k| run.t_ends_s[k].is_some() && reference.t_ends_s[k].is_finite())
            .then(|| max(&|k| (run.t_ends_s[k].unwrap_or(f64::NAN) - reference.t_ends_s[k]).abs())),
        max_f_peak_rel: Some(max(&|k| {
            ((run.f_peaks_n[k] - reference.f_peaks_n[k]) / reference.f_peaks_n[k]).abs()
        })),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn richardson_removes_a_second_order_error() {
        // f(h) = 1 + 3h² + h³: the extrapolation leaves only the third-order part.
        let f = |h: f64| 1.0 + 3.0 * h * h + h * h * h;
        let h = 0.1;
        let r = richardson(f(h / 2.0), f(h / 4.0));
        assert!((r - 1.0).abs() < 0.2 * (f(h / 4.0) - 1.0).abs());
        let p = observed_order(f(h), f(h / 2.0), f(h / 4.0)).unwrap();
        assert!((p - 2.0).abs() < 0.1, "{p}");
        assert_eq!(observed_order(1.0, 2.0, 1.5), None);
    }
}
