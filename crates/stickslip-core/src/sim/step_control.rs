//! Step-size control for adaptive stepping: a PI controller on a scaled error estimate,
//! kept apart from any stepper so every φ-step reuses it.
//!
//! The controller sees only `err`, the step's estimated local error divided by the
//! tolerance (1 = exactly at the tolerance), and the order of that estimate: the accurate
//! scheme is second order, so its local error scales as h³ and the exponent is 1/3. A
//! first-order model (h ∝ err^(−1/2)), as step doubling used before, over-reacts to every
//! change of err and rejects more steps than it needs to.
//!
//! The rule (Gustafsson's PI controller, as in Hairer & Wanner, *Solving ODEs II*, §IV.2,
//! and SUNDIALS' CVODE): with k = estimate order,
//!
//! h_next = h · (ρ/err)^(0.7/k) · (err_prev/ρ)^(0.4/k),
//!
//! clamped to [`StepController::shrink_min`, `StepController::grow_max`]. Written with the
//! target ρ inside both factors, a steady error model settles at err = ρ; the textbook form
//! h·0.9·err^(−0.7/k)·err_prev^(0.4/k) settles at err = 0.9^(k/0.3) = 0.35 for k = 3, i.e.
//! at steps 30 % shorter than needed. After a rejected
//! attempt the retry uses the plain rule h·safety·err^(−1/k) (clamped to at most
//! `shrink_max`), and the step accepted right after a rejection may not grow: the error
//! model was just wrong, so it is not trusted to grow again at once.

/// What the controller remembers between steps; part of the checkpointed state so that a
/// resumed run takes the same steps.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ControllerMemory {
    /// The step to try next, s (0 = start from `time.dt`).
    pub next_dt_s: f64,
    /// Scaled error of the last accepted step (0 before the first).
    pub err_prev: f64,
    /// Whether the last attempt was rejected.
    pub rejected_last: bool,
}

/// The PI step-size controller (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepController {
    /// Exponent k of the error model err ∝ h^k (3 for a second-order scheme's local error).
    pub order: f64,
    /// Safety factor of a retry after a rejection.
    pub safety: f64,
    /// The error ρ (in units of the tolerance) the accepted steps aim at.
    pub target: f64,
    /// Largest growth of the step from one accepted step to the next.
    pub grow_max: f64,
    /// Smallest factor of a retry after a rejection.
    pub shrink_min: f64,
    /// Largest factor of a retry after a rejection (a retry always shrinks).
    pub shrink_max: f64,
}

impl StepController {
    /// The controller for an error estimate of order `order` (local error ∝ h^order).
    #[must_use]
    pub fn of_order(order: f64) -> Self {
        Self {
            order,
            safety: 0.9,
            target: 0.5,
            grow_max: 5.0,
            shrink_min: 0.1,
            shrink_max: 0.9,
        }
    }

    /// The next step after an accepted step of length `h_s` with scaled error `err` (≤ 1).
    pub fn accepted(&self, h_s: f64, err: f64, memory: &mut ControllerMemory) -> f64 {
        let k = self.order;
        let err = err.max(1e-10);
        let prev = if memory.err_prev > 0.0 {
            memory.err_prev.max(1e-10)
        } else {
            err
        };
        let rho = self.target;
        let factor = (rho / err).powf(0.7 / k) * (prev / rho).powf(0.4 / k);
        let grow = if memory.rejected_last {
            1.0
        } else {
            self.grow_max
        };
        memory.err_prev = err;
        memory.rejected_last = false;
        h_s * factor.clamp(self.shrink_min, grow)
    }

    /// The retry after an attempt of length `h_s` was rejected with scaled error `err` (> 1,
    /// or infinite when the attempt failed numerically).
    pub fn rejected(&self, h_s: f64, err: f64, memory: &mut ControllerMemory) -> f64 {
        memory.rejected_last = true;
        let factor = if err.is_finite() {
            self.safety * err.powf(-1.0 / self.order)
        } else {
            0.25
        };
        h_s * factor.clamp(self.shrink_min, self.shrink_max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_error_at_the_target_keeps_the_step() {
        let c = StepController::of_order(3.0);
        let mut m = ControllerMemory {
            err_prev: c.target,
            ..ControllerMemory::default()
        };
        let h = c.accepted(1e-6, c.target, &mut m);
        assert!((h / 1e-6 - 1.0).abs() < 1e-12, "{h}");
    }

    #[test]
    fn a_rejection_uses_the_order_and_the_next_accepted_step_does_not_grow() {
        // err = 8 with order 3: the retry is h·0.9·8^(−1/3) = 0.45·h.
        let c = StepController::of_order(3.0);
        let mut m = ControllerMemory::default();
        let retry = c.rejected(1.0, 8.0, &mut m);
        assert!((retry - 0.9 / 2.0).abs() < 1e-12, "{retry}");
        // Right after a rejection the accepted step does not grow, however small its error.
        let next = c.accepted(retry, 1e-6, &mut m);
        assert_eq!(next, retry);
        // Afterwards it may grow, at most by grow_max.
        let next2 = c.accepted(next, 1e-12, &mut m);
        assert_eq!(next2, next * c.grow_max);
    }

    #[test]
    fn a_failed_attempt_shrinks_by_a_fixed_factor() {
        let c = StepController::of_order(3.0);
        let mut m = ControllerMemory::default();
        assert_eq!(c.rejected(1.0, f64::INFINITY, &mut m), 0.25);
        assert!(m.rejected_last);
    }

    #[test]
    fn a_steady_error_model_settles_the_step_where_err_is_the_target() {
        // err = (h/h*)³: the controller settles at err = ρ within a few dozen steps.
        let c = StepController::of_order(3.0);
        let mut m = ControllerMemory::default();
        let h_star: f64 = 1e-6;
        let mut h: f64 = 1e-9;
        for _ in 0..60 {
            let err = (h / h_star).powi(3);
            h = if err <= 1.0 {
                c.accepted(h, err, &mut m)
            } else {
                c.rejected(h, err, &mut m)
            };
        }
        let err = (h / h_star).powi(3);
        assert!((err / c.target - 1.0).abs() < 1e-3, "err {err}, h {h}");
    }
}
