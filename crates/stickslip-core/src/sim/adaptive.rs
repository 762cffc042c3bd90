//! Adaptive stepping: step doubling with error control, on top of [`Simulation::step`].

use super::{NumericalFailure, SimState, Simulation};
use serde::Serialize;

/// What one unit of local error means for each checked quantity (adaptive stepping).
///
/// The error of a step is max(|Δφ|/φ_s, |Δε|/ε_s, |ΔX|/X_s) / tolerance over all nodes, Δ the
/// difference between one whole step and two half steps.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ErrorScales {
    /// φ scale: the solid equilibrium √(A/a) at t = 0 (1 when A ≤ 0).
    pub phi: f64,
    /// Strain scale: εc at t = 0 (εmax when A ≤ 0).
    pub eps: f64,
    /// Stamp-position scale: the film thickness h0, m.
    pub x_m: f64,
}

impl Simulation {
    /// The error scales of adaptive stepping.
    pub fn error_scales(&self) -> ErrorScales {
        self.error_scales
    }

    /// One error-controlled step (scene `time.stepping = "adaptive"`), ending at most at
    /// `t_stop_s`; returns the length of the accepted step, s.
    ///
    /// A step of length h is taken whole and as two halves from the same state; the halves
    /// are kept if their difference (see [`ErrorScales`]) is within the tolerance, otherwise
    /// the state is rolled back and h shrinks. A sub-step that fails numerically counts as a
    /// rejection too, until h reaches `dt_min`. The next h = h·clamp(0.9/√err, 0.2, 2):
    /// the local difference of the (first-order) scheme scales as h².
    ///
    /// # Errors
    /// [`NumericalFailure`] from a sub-step at `dt_min`.
    ///
    /// # Panics
    /// If the configuration is not adaptive.
    pub fn step_adaptive(&mut self, t_stop_s: f64) -> Result<f64, NumericalFailure> {
        let ctl = self
            .config
            .time
            .adaptive
            .expect("step_adaptive needs time.adaptive");
        let mut saved = self
            .saved
            .take()
            .unwrap_or_else(|| Box::new(self.state.clone()));
        let mut whole = self
            .whole_step
            .take()
            .unwrap_or_else(|| Box::new(self.state.clone()));
        let result = self.adaptive_attempts(&ctl, t_stop_s, &mut saved, &mut whole);
        self.saved = Some(saved);
        self.whole_step = Some(whole);
        result
    }

    fn adaptive_attempts(
        &mut self,
        ctl: &crate::config::AdaptiveConfig,
        t_stop_s: f64,
        saved: &mut SimState,
        whole: &mut SimState,
    ) -> Result<f64, NumericalFailure> {
        let mut h_try = if self.state.next_dt_s > 0.0 {
            self.state.next_dt_s
        } else {
            self.config.time.dt_s
        };
        loop {
            let remaining = t_stop_s - self.state.drive.t_s;
            let mut h = h_try.min(ctl.dt_max_s);
            // Land on t_stop without leaving a sliver: stretch by up to 10 %, or split evenly.
            if h >= remaining / 1.1 {
                h = remaining;
            } else if h > 0.5 * remaining {
                h = 0.5 * remaining;
            }
            let landing = h == remaining;
            let at_floor = h <= ctl.dt_min_s;
            saved.clone_from(&self.state);
            let outcome = self.step(h).and_then(|()| {
                whole.clone_from(&self.state);
                self.state.clone_from(saved);
                self.step(0.5 * h)?;
                self.step(0.5 * h)
            });
            let err = match outcome {
                Ok(()) => self.step_difference(whole) / ctl.tolerance,
                Err(failure) if at_floor => return Err(failure),
                Err(_) => f64::INFINITY,
            };
            if err <= 1.0 || at_floor {
                if err > 1.0 {
                    self.state.forced_steps += 1;
                }
                self.state.accepted_steps += 1;
                if landing {
                    // Two half steps may miss t_stop by an ulp; outputs due there need it exact.
                    self.state.drive.t_s = t_stop_s;
                }
                let grow = if err > 0.0 {
                    (0.9 / err.sqrt()).clamp(0.2, 2.0)
                } else {
                    2.0
                };
                // A step shortened only to land on t_stop says nothing about the next one.
                self.state.next_dt_s = (h * grow).max(h_try.min(ctl.dt_max_s) * grow.min(1.0));
                return Ok(h);
            }
            self.state.clone_from(saved);
            self.state.rejected_steps += 1;
            let shrink = if err.is_finite() {
                (0.9 / err.sqrt()).clamp(0.2, 0.9)
            } else {
                0.25
            };
            h_try = (h * shrink).max(ctl.dt_min_s);
        }
    }

    /// Largest scaled difference between the current state and `other` (see [`ErrorScales`]).
    fn step_difference(&self, other: &SimState) -> f64 {
        let s = &self.state;
        let sc = &self.error_scales;
        let mut worst = ((s.drive.x_m - other.drive.x_m) / sc.x_m).abs();
        for i in 0..s.phi.len() {
            let dphi = ((s.phi[i] - other.phi[i]) / sc.phi).abs();
            let deps = ((s.eps[i] - other.eps[i]) / sc.eps).abs();
            worst = worst.max(dphi).max(deps);
        }
        if worst.is_nan() { f64::INFINITY } else { worst }
    }
}
