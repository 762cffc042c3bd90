//! Typed facts about a run, read from its run.json ([`RunInfo`], the run library's schema): the
//! scene values (resolved, defaults filled in) and derived numbers that the claims, figures
//! and reports need, so that no number in them is typed in by hand.

use serde::Serialize;
use stickslip_core::grid::{Grading, Grid};
use stickslip_core::mdr::OperatorForm;
use stickslip_run::Scene;
use stickslip_run::keys::words::GridChoice;
use stickslip_run::scene::file::{Scheme, Stepping};
use stickslip_run::schema::run_info::RunInfo;

/// The serde name of a scene word (`"accurate"`, `"adaptive"`, …).
pub fn word<T: Serialize>(v: &T) -> String {
    serde_json::to_value(v)
        .ok()
        .and_then(|v| v.as_str().map(str::to_string))
        .unwrap_or_else(|| "?".into())
}

/// What the validation reads from a run's run.json besides its counters.
pub trait Facts {
    /// Contact radius a0, m.
    fn radius_m(&self) -> f64;
    /// Film thickness h0, m.
    fn film_thickness_m(&self) -> f64;
    /// Melting threshold of φ.
    fn melt_threshold(&self) -> f64;
    /// Drive velocity V0, m/s.
    fn velocity_m_per_s(&self) -> f64;
    /// ω = √(K/m) of a spring drive, rad/s (None for the rigid drive).
    fn omega_rad_per_s(&self) -> Option<f64>;
    /// Nodes simulated (1 for the homogeneous model).
    fn nodes(&self) -> usize;
    /// How the radial nodes are spread (`contact.grid`, `contact.grading`).
    fn grading(&self) -> Grading;
    /// The nodes in the outer `band` fraction of the radius, r ≥ (1 − band)·a0, on the run's
    /// grid.
    fn nodes_in_outer(&self, band: f64) -> usize {
        let a0 = self.radius_m();
        Grid::graded(a0, self.nodes(), self.grading()).map_or(0, |g| {
            g.radii_m()
                .iter()
                .filter(|&&r| r >= (1.0 - band) * a0)
                .count()
        })
    }
    /// `time.dt`, s (the step with fixed stepping, the first step tried with adaptive steps).
    fn dt_s(&self) -> f64;
    /// Time scheme.
    fn scheme(&self) -> Scheme;
    /// Fixed or adaptive steps.
    fn stepping(&self) -> Stepping;
    /// `time.tolerance` (adaptive steps only).
    fn tolerance(&self) -> Option<f64>;
    /// The MDR operator the run used (`numerics.operator`, `auto` resolved as the engine does).
    fn operator(&self) -> Option<OperatorForm>;
    /// `output.series_interval`, s.
    fn series_interval_s(&self) -> f64;
    /// `output.event_merge_gap`, s.
    fn event_merge_gap_s(&self) -> f64;
    /// How the run stepped, in words: `fixed steps Δt = 1e-8 s: 130000 steps` or `adaptive
    /// steps (tolerance 5e-5, …): 3010 accepted steps, 43 rejected attempts, 10 retaken to end
    /// at a located onset`.
    fn stepping_text(&self) -> String;
}

impl Facts for RunInfo {
    fn radius_m(&self) -> f64 {
        self.scene
            .contact
            .as_ref()
            .and_then(|c| c.radius)
            .unwrap_or(f64::NAN)
    }
    fn film_thickness_m(&self) -> f64 {
        self.scene
            .contact
            .as_ref()
            .and_then(|c| c.film_thickness)
            .unwrap_or(f64::NAN)
    }
    fn melt_threshold(&self) -> f64 {
        self.scene
            .lubricant
            .as_ref()
            .and_then(|l| l.melt_threshold)
            .unwrap_or(f64::NAN)
    }
    fn velocity_m_per_s(&self) -> f64 {
        self.scene
            .drive
            .as_ref()
            .and_then(|d| d.velocity)
            .unwrap_or(f64::NAN)
    }
    fn omega_rad_per_s(&self) -> Option<f64> {
        (self.derived.omega > 0.0).then_some(self.derived.omega)
    }
    fn nodes(&self) -> usize {
        self.derived.nodes
    }
    fn grading(&self) -> Grading {
        let c = self.scene.contact.as_ref();
        match (c.and_then(|c| c.grid), c.and_then(|c| c.grading)) {
            (Some(GridChoice::Graded), Some(power)) => Grading::Edge { power },
            _ => Grading::Uniform,
        }
    }
    fn dt_s(&self) -> f64 {
        self.scene
            .time
            .as_ref()
            .and_then(|t| t.dt)
            .unwrap_or(f64::NAN)
    }
    fn scheme(&self) -> Scheme {
        self.scene
            .time
            .as_ref()
            .and_then(|t| t.scheme)
            .unwrap_or(Scheme::Accurate)
    }
    fn stepping(&self) -> Stepping {
        self.scene
            .time
            .as_ref()
            .and_then(|t| t.stepping)
            .unwrap_or(Stepping::Fixed)
    }
    fn tolerance(&self) -> Option<f64> {
        self.scene.time.as_ref().and_then(|t| t.tolerance)
    }
    fn operator(&self) -> Option<OperatorForm> {
        // The resolved scene keeps `auto`; resolving it again gives the engine's choice.
        Scene::resolve_table(self.scene.to_table(), &[] as &[&str])
            .ok()
            .map(|s| s.config.operator_form())
    }
    fn series_interval_s(&self) -> f64 {
        self.scene
            .output
            .as_ref()
            .and_then(|o| o.series_interval)
            .unwrap_or(f64::NAN)
    }
    fn event_merge_gap_s(&self) -> f64 {
        self.scene
            .output
            .as_ref()
            .and_then(|o| o.event_merge_gap)
            .unwrap_or(f64::NAN)
    }
    fn stepping_text(&self) -> String {
        match self.stepping() {
            Stepping::Fixed => {
                format!("fixed steps Δt = {:e} s: {} steps", self.dt_s(), self.steps)
            }
            Stepping::Adaptive => format!(
                "adaptive steps (tolerance {:e}, first step {:e} s, longest allowed {:e} s): {} \
                 accepted steps, {} rejected attempts, {} retaken to end at a located onset",
                self.tolerance().unwrap_or(f64::NAN),
                self.dt_s(),
                self.scene
                    .time
                    .as_ref()
                    .and_then(|t| t.dt_max)
                    .unwrap_or(f64::NAN),
                self.accepted_steps,
                self.rejected_steps,
                self.onset_retakes
            ),
        }
    }
}
