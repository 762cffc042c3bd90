//! The misfit: a vector of residuals, each a difference between model and data divided by its
//! standard deviation (so every residual is in units of its own noise, and ½‖r‖² is the
//! negative log-likelihood of independent normal errors up to a constant). Two kinds
//! (docs/fit.md#misfits):
//!
//! - **events** (the default): the events of the data and of the model, found the same way
//!   ([`super::events`]) at the data's times, matched in order. Residuals, for data events
//!   1…n: the first onset, each interval between consecutive onsets, each peak force, each
//!   drop, and one residual for the model's extra events. Onsets are found on F averaged
//!   over [`SMOOTH`] samples, whose noise is σs = σF/√[`SMOOTH`]; peaks and least values
//!   are parabolas' extremes through the raw samples near them, whose variances are σF²
//!   times the parabola's factor vₚ, vₗ. σ of an onset: σs/|dF/dt| at the crossing; of an
//!   interval: its two onsets' added in quadrature; of a peak: σF·√vₚ; of a drop:
//!   σF·√(vₚ + vₗ). A data event the model does not have counts as if the model's were at the
//!   trace's end with zero peak and drop; the model's extra events count as drops the data do
//!   not have, √(Σ drop²)/(√2·σF).
//! - **trace**: F at each of the data's times, the model's at t + shift (a fitted time shift),
//!   over σF; and when the trace has the stamp's position X, X at each of the data's times
//!   likewise, over σX (estimated from the data as σF is). The events misfit uses F alone.

use super::data::{Trace, noise_sigma, noise_sigma_n};
use super::error::FitError;
use super::events::{Event, SMOOTH, Windows, find, refine, refine_model};

/// Which misfit a fit minimises.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MisfitKind {
    /// Events matched one by one.
    #[default]
    Events,
    /// F at the data's times, with a time shift.
    Trace,
}

impl MisfitKind {
    /// The kind's name (`events`, `trace`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Events => "events",
            Self::Trace => "trace",
        }
    }

    /// The kind called `name`.
    ///
    /// # Errors
    /// [`FitError::Input`] naming `--misfit`.
    pub fn from_name(name: &str) -> Result<Self, FitError> {
        match name {
            "events" => Ok(Self::Events),
            "trace" => Ok(Self::Trace),
            _ => Err(FitError::input("--misfit", name, "events or trace")),
        }
    }
}

/// The event hysteresis as a multiple of the noise: a zigzag of F within this many σF is
/// noise, not an event.
pub const HYSTERESIS_SIGMAS: f64 = 10.0;
/// The event hysteresis as a fraction of F's span at least: small wiggles of a trace without
/// noise are no events either.
pub const HYSTERESIS_OF_RANGE: f64 = 0.05;

/// The model's force and stamp position over time, as a forward run recorded them (every
/// step).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ModelCurve {
    /// Step times, s (increasing).
    pub t_s: Vec<f64>,
    /// Friction force at those times, N.
    pub f_n: Vec<f64>,
    /// The stamp's position at those times, m (empty: not recorded, taken as 0).
    pub x_m: Vec<f64>,
}

impl ModelCurve {
    /// F at `t`, linearly interpolated between steps (the nearest end outside them).
    #[must_use]
    pub fn at(&self, t: f64) -> f64 {
        interpolate(&self.t_s, &self.f_n, t)
    }

    /// X at `t`, likewise (0 when X was not recorded).
    #[must_use]
    pub fn x_at(&self, t: f64) -> f64 {
        interpolate(&self.t_s, &self.x_m, t)
    }
}

/// `v(t)` linearly interpolated between the times `t_s` (the nearest end outside them; 0 when
/// `v` does not have a value per time).
fn interpolate(t_s: &[f64], v: &[f64], t: f64) -> f64 {
    let n = t_s.len();
    if n == 0 || v.len() != n {
        return 0.0;
    }
    let i = t_s.partition_point(|&x| x <= t);
    if i == 0 {
        return v[0];
    }
    if i == n {
        return v[n - 1];
    }
    let (t0, t1) = (t_s[i - 1], t_s[i]);
    let w = (t - t0) / (t1 - t0);
    v[i - 1] + w * (v[i] - v[i - 1])
}

/// What a fit compares with: the data, their noise, and (events misfit) their events.
#[derive(Debug, Clone)]
pub struct Target {
    /// The misfit's kind.
    pub kind: MisfitKind,
    /// The data.
    pub trace: Trace,
    /// σF, N: given, or estimated from the data.
    pub sigma_f_n: f64,
    /// σX, m, estimated from the data, when the trace has X and the misfit is the trace's.
    pub sigma_x_m: Option<f64>,
    /// Whether σF was estimated from the data.
    pub sigma_estimated: bool,
    /// The events' hysteresis, N: max(10σF, 5 % of F's span).
    pub hysteresis_n: f64,
    /// The data's events.
    pub events: Vec<Event>,
    /// The data's events as found, with their windows (the model's are measured over them).
    pub found: Vec<(Event, Windows)>,
    /// σ of each data event's onset, s.
    pub sigma_onset_s: Vec<f64>,
}

/// The residuals of one model, with what they were made of (for the figure and fit.json).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Compared {
    /// The residuals, each in units of its σ.
    pub residuals: Vec<f64>,
    /// The model's F at the data's times (shifted, for the trace misfit), N.
    pub model_f_n: Vec<f64>,
    /// The model's events (events misfit).
    pub model_events: Vec<Event>,
}

impl Target {
    /// The target of `trace` for misfit `kind`; `noise_n` the given σF (else estimated).
    ///
    /// # Errors
    /// [`FitError::Input`]: a given noise that is not finite and > 0; for the events misfit,
    /// a trace without events.
    pub fn new(trace: Trace, kind: MisfitKind, noise_n: Option<f64>) -> Result<Self, FitError> {
        if let Some(s) = noise_n
            && !(s.is_finite() && s > 0.0)
        {
            return Err(FitError::input(
                "--noise",
                stickslip_run::keys::human(s),
                "a finite standard deviation of F > 0 N (omit it to estimate it from the data)",
            ));
        }
        // A noise as large as the signal leaves nothing to fit (and hides every event): the
        // option is wrong, not the trace.
        if let Some(s) = noise_n
            && s >= trace.f_range_n()
        {
            return Err(FitError::input(
                "--noise",
                stickslip_run::keys::human(s),
                format!(
                    "a standard deviation of F below the trace's span of F, {} N (is it in N?); \
                     omit it to estimate it from the data",
                    stickslip_run::keys::human(trace.f_range_n())
                ),
            ));
        }
        let sigma_f_n = noise_n.unwrap_or_else(|| noise_sigma_n(&trace));
        let hysteresis_n =
            (HYSTERESIS_SIGMAS * sigma_f_n).max(HYSTERESIS_OF_RANGE * trace.f_range_n());
        let found = find(&trace.t_s, &trace.f_n, hysteresis_n);
        let events = refine(&trace.t_s, &trace.f_n, &found);
        if kind == MisfitKind::Events && events.is_empty() {
            return Err(FitError::input(
                "trace events",
                "none",
                format!(
                    "a trace with at least one drop of F larger than the hysteresis {hysteresis_n:e} \
                     N (max(10·noise, 5 % of F's span)) for --misfit events; use --misfit trace \
                     for a trace without slips"
                ),
            ));
        }
        let sigma_x_m = match (kind, &trace.x_m) {
            (MisfitKind::Trace, Some(x)) => Some(noise_sigma(x)),
            _ => None,
        };
        let sigma_onset_s = events
            .iter()
            .map(|e| {
                // The noise's share alone: the onset's sampling error (`interpolation_s`) is
                // common to the data and the model, which are sampled at the same times and
                // located by the same rule, so it cancels in the residual at the truth. Added
                // in quadrature it made the intervals' residuals at the truth a third of their
                // σ, and γ's intervals about three times too wide. A crossing on a flat
                // stretch (no slope between its samples) is known to the sample spacing.
                if e.slope_n_per_s > 0.0 {
                    sigma_f_n / (SMOOTH as f64).sqrt() / e.slope_n_per_s
                } else {
                    local_spacing(&trace.t_s, e.t_onset_s)
                }
            })
            .collect();
        Ok(Self {
            kind,
            trace,
            sigma_f_n,
            sigma_x_m,
            sigma_estimated: noise_n.is_none(),
            hysteresis_n,
            events,
            found,
            sigma_onset_s,
        })
    }

    /// How many residuals the misfit has.
    #[must_use]
    pub fn len(&self) -> usize {
        match self.kind {
            MisfitKind::Events => 3 * self.events.len() + 1,
            MisfitKind::Trace => self.trace.t_s.len() * (1 + usize::from(self.sigma_x_m.is_some())),
        }
    }

    /// Whether the misfit has no residuals (never, for a checked target).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The residuals of `model`, its times moved by `shift_s` (trace misfit; 0 for events).
    #[must_use]
    pub fn compare(&self, model: &ModelCurve, shift_s: f64) -> Compared {
        let t = &self.trace.t_s;
        let model_f_n: Vec<f64> = t.iter().map(|&ti| model.at(ti + shift_s)).collect();
        match self.kind {
            MisfitKind::Trace => {
                // The model's events too, for fit.json and the figure (not in the misfit).
                let found = find(t, &model_f_n, self.hysteresis_n);
                let model_events = refine_model(t, &|x| model.at(x + shift_s), &self.found, &found);
                let mut residuals: Vec<f64> = model_f_n
                    .iter()
                    .zip(&self.trace.f_n)
                    .map(|(m, d)| (m - d) / self.sigma_f_n)
                    .collect();
                if let (Some(sx), Some(x)) = (self.sigma_x_m, &self.trace.x_m) {
                    residuals.extend(
                        t.iter()
                            .zip(x)
                            .map(|(&ti, d)| (model.x_at(ti + shift_s) - d) / sx),
                    );
                }
                Compared {
                    residuals,
                    model_f_n,
                    model_events,
                }
            }
            MisfitKind::Events => {
                let found = find(t, &model_f_n, self.hysteresis_n);
                let model_events = refine_model(t, &|x| model.at(x), &self.found, &found);
                Compared {
                    residuals: self.event_residuals(&model_events),
                    model_f_n,
                    model_events,
                }
            }
        }
    }

    fn event_residuals(&self, model: &[Event]) -> Vec<f64> {
        let n = self.events.len();
        let t_end = self.trace.t_s.last().copied().unwrap_or(0.0);
        let sf = self.sigma_f_n;
        // A missing model event: at the trace's end, with zero peak and drop.
        let onset = |k: usize| model.get(k).map_or(t_end, |e| e.t_onset_s);
        let mut r = Vec::with_capacity(self.len());
        r.push((onset(0) - self.events[0].t_onset_s) / self.sigma_onset_s[0]);
        for k in 1..n {
            let model_gap = onset(k) - onset(k - 1);
            let data_gap = self.events[k].t_onset_s - self.events[k - 1].t_onset_s;
            let s = self.sigma_onset_s[k].hypot(self.sigma_onset_s[k - 1]);
            r.push((model_gap - data_gap) / s);
        }
        for (k, d) in self.events.iter().enumerate() {
            let s = (sf * d.peak_variance.sqrt()).hypot(d.peak_resolution_n);
            r.push((model.get(k).map_or(0.0, |e| e.f_peak_n) - d.f_peak_n) / s);
        }
        for (k, d) in self.events.iter().enumerate() {
            let s = (sf * (d.peak_variance + d.least_variance).sqrt())
                .hypot(d.peak_resolution_n)
                .hypot(d.least_resolution_n);
            r.push((model.get(k).map_or(0.0, |e| e.drop_n) - d.drop_n) / s);
        }
        let extra: f64 = model.iter().skip(n).map(|e| e.drop_n * e.drop_n).sum();
        r.push(extra.sqrt() / (2f64.sqrt() * sf));
        r
    }

    /// The residuals of a model that could not be run: every data event missing (events), or
    /// F = 0 (and X = 0) throughout (trace); a failed run costs as much as a model without any
    /// of the data.
    #[must_use]
    pub fn failed(&self) -> Vec<f64> {
        self.compare(&ModelCurve::default(), 0.0).residuals
    }
}

/// The sample spacing around `t`, s.
fn local_spacing(t: &[f64], at: f64) -> f64 {
    let i = t.partition_point(|&x| x <= at).clamp(1, t.len() - 1);
    t[i] - t[i - 1]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sawtooth(shift: f64) -> Trace {
        let t: Vec<f64> = (0..400).map(|i| i as f64 * 1e-6).collect();
        let f = t
            .iter()
            .map(|&x| {
                let y = (x - shift) / 1e-4;
                y - y.floor()
            })
            .collect();
        Trace::new(t, f, None).unwrap()
    }

    #[test]
    fn events_residuals_vanish_for_the_data_and_grow_with_a_shift() {
        let target = Target::new(sawtooth(0.0), MisfitKind::Events, Some(1e-3)).unwrap();
        assert_eq!(target.events.len(), 3);
        assert_eq!(target.len(), 10);
        let data = ModelCurve {
            t_s: target.trace.t_s.clone(),
            f_n: target.trace.f_n.clone(),
            x_m: Vec::new(),
        };
        let same = target.compare(&data, 0.0);
        assert_eq!(same.residuals.len(), target.len());
        assert!(
            same.residuals.iter().all(|r| r.abs() < 1e-9),
            "{:?}",
            same.residuals
        );
        // The model's events 2.5 µs early.
        let s = sawtooth(-2.5e-6);
        let shifted = ModelCurve {
            t_s: s.t_s.clone(),
            f_n: s.f_n,
            x_m: Vec::new(),
        };
        let r = target.compare(&shifted, 0.0).residuals;
        assert!(r[0] < -1.0, "an earlier onset: {r:?}");
        assert!(
            r[1].abs() < 1e-6 && r[2].abs() < 1e-6,
            "the same intervals: {r:?}"
        );
        // The model's own shift undone by the trace misfit's time shift.
        let trace = Target::new(sawtooth(0.0), MisfitKind::Trace, Some(1e-3)).unwrap();
        let back = trace.compare(&shifted, -2.5e-6).residuals;
        let off = back.iter().filter(|r| r.abs() > 1e-6).count();
        assert!(off <= 6, "{off} samples off");
        // A failed run is no better than missing every event.
        assert!(target.failed().iter().map(|r| r * r).sum::<f64>() > 1.0);
    }

    #[test]
    fn the_trace_misfit_fits_x_when_the_trace_has_it() {
        // F a sawtooth, X a staircase rising by 1 µm at each drop.
        let s = sawtooth(0.0);
        let x: Vec<f64> = s.t_s.iter().map(|&t| 1e-6 * (t / 1e-4).floor()).collect();
        let trace = Trace::new(s.t_s.clone(), s.f_n.clone(), Some(x.clone())).unwrap();
        let target = Target::new(trace.clone(), MisfitKind::Trace, Some(1e-3)).unwrap();
        let n = trace.t_s.len();
        assert_eq!(target.len(), 2 * n);
        let sx = target.sigma_x_m.unwrap();
        assert!(sx > 0.0 && sx < 1e-6, "{sx}");
        let model = |dx: f64| ModelCurve {
            t_s: trace.t_s.clone(),
            f_n: trace.f_n.clone(),
            x_m: x.iter().map(|v| v + dx).collect(),
        };
        let same = target.compare(&model(0.0), 0.0).residuals;
        assert_eq!(same.len(), 2 * n);
        assert!(same.iter().all(|r| r.abs() < 1e-9));
        // X off by 3σX everywhere: every X residual is 3, every F residual 0.
        let off = target.compare(&model(3.0 * sx), 0.0).residuals;
        assert!(off[..n].iter().all(|r| r.abs() < 1e-9));
        assert!(
            off[n..].iter().all(|r| (r - 3.0).abs() < 1e-6),
            "{:?}",
            &off[n..n + 3]
        );
        // The events misfit leaves X out.
        let events = Target::new(trace, MisfitKind::Events, Some(1e-3)).unwrap();
        assert!(events.sigma_x_m.is_none());
        assert_eq!(events.len(), 3 * events.events.len() + 1);
    }

    #[test]
    fn a_trace_without_events_is_refused_for_the_events_misfit() {
        let t: Vec<f64> = (0..50).map(|i| i as f64).collect();
        let flat = Trace::new(t.clone(), t.clone(), None).unwrap();
        let e = Target::new(flat.clone(), MisfitKind::Events, None).unwrap_err();
        assert!(e.to_string().starts_with("trace events = none"), "{e}");
        assert!(Target::new(flat, MisfitKind::Trace, None).is_ok());
        let e = Target::new(sawtooth(0.0), MisfitKind::Trace, Some(-1.0)).unwrap_err();
        assert!(e.to_string().starts_with("--noise = -1"), "{e}");
    }
}
