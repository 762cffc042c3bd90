//! One fig2 run recorded for convergence studies: event onsets, peak forces, F(t) samples, time.
//!
//! The run is the shipped fig2 scene (floor noise φ ≥ 1e-6, deterministic) with the scheme, N,
//! fixed Δt and end time given, driven by the run library's driver; an observer reads the
//! simulation after every step (F between step ends for the samples, φ for the literal
//! scheme's located onsets). Events that begin within [`MERGE_GAP_S`] of the previous one's
//! end are merged: the literal scheme's axis node melts alone 1–3 µs before each front (its
//! u3D(0) = 0), and the study compares one onset per front across both schemes.

use serde::{Deserialize, Serialize};
use std::time::Instant;
use stickslip_core::config::{FilmStep, Scheme};
use stickslip_run::driver::{Control, Driver, Limit, NullSink};
use stickslip_run::keys::words::{GridChoice, NoiseKindName, Stepping};
use stickslip_run::keys::{contact, noise, numerics, output, time};
use stickslip_run::{ResolvedScene, Scene, StopReason};

/// Gap within which a new melting continues the previous event, s.
pub const MERGE_GAP_S: f64 = 1e-5;

/// End time of fig2, s.
pub const FIG2_END_S: f64 = 1.3e-3;

/// Spacing of the common time grid on which F(t) is sampled, s.
pub const SAMPLE_DT_S: f64 = 1e-7;

/// The shipped fig2 scene.
const FIG2_SCENE: &str = include_str!("../../../validation/scenes/fig2.toml");

/// The shipped fig2 scene as resolved, without overrides: the paper's N and Δt, the melt
/// threshold, the noise floor, the contact radius and the lubricant the reports quote.
///
/// # Panics
/// If the shipped scene does not resolve (its own tests would fail first).
#[must_use]
#[track_caller]
pub fn shipped() -> ResolvedScene {
    Scene::from_toml_str(FIG2_SCENE, &[] as &[String])
        .unwrap_or_else(|e| panic!("validation/scenes/fig2.toml: {e}"))
}

/// What to run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunSpec {
    /// Stepping scheme.
    pub scheme: Scheme,
    /// Radial nodes N.
    pub nodes: usize,
    /// Time step Δt, s.
    pub dt_s: f64,
    /// End time, s (fig2: 1.3e-3).
    pub end_s: f64,
    /// Optional change of step: from time t (s) on, step with Δt' (s) instead of `dt_s`.
    pub switch: Option<(f64, f64)>,
    /// `Some(tolerance)`: the default adaptive stepping with this `time.tolerance` (`dt_s` is
    /// then the first step tried); `None`: fixed steps of `dt_s`.
    pub tolerance: Option<f64>,
    /// `Some((σ, seed))`: gaussian noise of amplitude σ from `seed` instead of the scene's
    /// floor (fixed steps only: the scene refuses adaptive steps with gaussian noise).
    pub noise: Option<(f64, u64)>,
    /// The second-order film's step (`numerics.film_step`; the default: the ramp-corrected
    /// one).
    pub film_step: FilmStep,
    /// `contact.grid` when not the scheme's default (the accurate scheme's is the edge-graded
    /// grid, the literal scheme's the uniform one).
    pub grid: Option<GridChoice>,
}

impl RunSpec {
    /// fig2 with `scheme`, `nodes`, `dt_s` over the paper's 1.3 ms.
    pub fn fig2(scheme: Scheme, nodes: usize, dt_s: f64) -> Self {
        Self {
            scheme,
            nodes,
            dt_s,
            end_s: FIG2_END_S,
            switch: None,
            tolerance: None,
            noise: None,
            film_step: FilmStep::Ramp,
            grid: None,
        }
    }

    /// fig2 with the default adaptive stepping at `tolerance` and `nodes` over the paper's
    /// 1.3 ms (the scene's Δt is the first step tried).
    pub fn adaptive(nodes: usize, tolerance: f64) -> Self {
        Self {
            tolerance: Some(tolerance),
            ..Self::fig2(Scheme::Accurate, nodes, 1e-8)
        }
    }

    /// The scene of this run: fig2 with fixed steps of `dt_s` (or adaptive steps) to `end_s`.
    ///
    /// # Panics
    /// If the overrides do not resolve (N ≥ 1 and 0 < Δt ≤ end always do).
    #[must_use]
    #[track_caller]
    pub fn scene(&self) -> ResolvedScene {
        let mut sets = vec![
            time::SCHEME.set(self.scheme),
            contact::NODES.set(self.nodes as i64),
            time::DT.set(self.dt_s),
            time::END.set(self.end_s),
            output::PROFILE_TIMES.set(vec![self.end_s]),
            output::EVENT_MERGE_GAP.set(MERGE_GAP_S),
            // Nothing but the observer records: one row at the end.
            output::SERIES_INTERVAL.set(self.end_s),
        ];
        match self.tolerance {
            Some(tol) => {
                sets.push(time::STEPPING.set(Stepping::Adaptive));
                sets.push(time::TOLERANCE.set(tol));
            }
            None => sets.push(time::STEPPING.set(Stepping::Fixed)),
        }
        sets.push(numerics::FILM_STEP.set(self.film_step));
        if let Some(grid) = self.grid {
            sets.push(contact::GRID.set(grid));
        }
        if let Some((sigma, seed)) = self.noise {
            sets.push(noise::KIND.set(NoiseKindName::Gaussian));
            sets.push(noise::SIGMA.set(sigma));
            sets.push(noise::SEED.set(seed as i64));
        }
        let sets: Vec<String> = sets.iter().map(ToString::to_string).collect();
        Scene::from_toml_str(FIG2_SCENE, &sets).unwrap_or_else(|e| panic!("fig2 run {self:?}: {e}"))
    }
}

/// One melting event as recorded.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct EventRecord {
    /// The core's onset, s: located inside the step on the node's exact path by the accurate
    /// scheme, the end of the first step with a melted node for the literal one.
    pub onset_step_s: f64,
    /// The onset this study uses, s: the core's for the accurate scheme (its melting is
    /// instantaneous, so φ at step ends never shows it); for the literal scheme located inside
    /// the step from the public state — per newly melted node, ln φ interpolated linearly in
    /// time between the two step ends to the threshold, the earliest node counting.
    pub onset_s: f64,
    /// The core's `f_peak`: largest step-end F since the previous event began, N.
    pub f_peak_n: f64,
    /// Radius of the outermost node melted at the onset, m.
    pub r_first_m: f64,
    /// The core's `t_end`: when the film had recovered, located inside the step (None while
    /// open at the end, and in studies written before it was recorded), s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub t_end_s: Option<f64>,
}

/// Everything a study needs from one run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunRecord {
    /// What was run.
    pub spec: RunSpec,
    /// Merged melting events in order.
    pub events: Vec<EventRecord>,
    /// F at t_j = j·[`SAMPLE_DT_S`], j = 0, 1, …, linearly interpolated between step ends, N.
    pub force_samples_n: Vec<f64>,
    /// Wall-clock seconds for building the simulation and stepping it to the end.
    pub wall_s: f64,
    /// The core's error message if a step failed (the record then stops there).
    pub failure: Option<String>,
    /// Steps kept (fixed steps: all of them; adaptive: the accepted ones).
    pub steps: u64,
    /// Adaptive: rejected attempts (0 with fixed steps).
    pub rejected_steps: u64,
    /// Adaptive: accepted attempts that brought an onset and were taken again ending at the
    /// located melting time (each one more evaluation of the step; 0 with fixed steps).
    pub onset_retakes: u64,
}

impl RunRecord {
    /// Evaluations of the accurate (or literal) step: one per step kept, per rejected attempt
    /// and per onset retake.
    pub fn evaluations(&self) -> u64 {
        self.steps + self.rejected_steps + self.onset_retakes
    }

    /// Time of force sample j, s.
    pub fn sample_time_s(j: usize) -> f64 {
        j as f64 * SAMPLE_DT_S
    }
}

/// Runs `spec` once and records it.
///
/// # Panics
/// If the scene does not resolve or a null sink fails (neither can happen for fig2).
#[track_caller]
pub fn run(spec: &RunSpec) -> RunRecord {
    let start = Instant::now();
    let scene = spec.scene();
    let thr = scene.config.melt_threshold;
    let mut sink = NullSink;
    let mut driver = Driver::start(&scene, &mut sink).expect("valid fig2 configuration");
    let samples = (spec.end_s / SAMPLE_DT_S).floor() as usize + 1;
    let mut force = Vec::with_capacity(samples);
    let sim0 = driver.simulation();
    force.push(sim0.state().physical.force_n);
    let mut prev_phi = sim0.state().physical.phi.clone();
    let mut prev_t = sim0.time_s();
    let mut prev_f = sim0.state().physical.force_n;
    let mut onsets: Vec<Option<f64>> = Vec::new();
    let located_by_core = spec.scheme == Scheme::Accurate;
    let mut observe = |sim: &stickslip_core::sim::Simulation| {
        let t = sim.time_s();
        let state = sim.state();
        let f = state.physical.force_n;
        while force.len() < samples {
            let ts = RunRecord::sample_time_s(force.len());
            if ts > t + 1e-3 * (t - prev_t) {
                break;
            }
            let w = ((ts - prev_t) / (t - prev_t)).clamp(0.0, 1.0);
            force.push(prev_f + w * (f - prev_f));
        }
        if sim.events().len() > onsets.len() {
            let mut theta_min: Option<f64> = None;
            for (&p0, &p1) in prev_phi.iter().zip(&state.physical.phi) {
                if p1 < thr && p0 >= thr {
                    let theta = if p1 > 0.0 {
                        (p0 / thr).ln() / (p0 / p1).ln()
                    } else {
                        1.0
                    };
                    theta_min = Some(theta_min.map_or(theta, |m: f64| m.min(theta)));
                }
            }
            onsets.push(if located_by_core {
                None
            } else {
                theta_min.map(|th| prev_t + th * (t - prev_t))
            });
        }
        prev_phi.copy_from_slice(&state.physical.phi);
        prev_t = t;
        prev_f = f;
    };
    let mut control = Control {
        observer: Some(&mut observe),
        ..Control::default()
    };
    let mut stop = None;
    if let Some((t_switch, dt)) = spec.switch {
        let until = t_switch - 1e-3 * spec.dt_s.min(dt);
        stop = driver
            .advance(&mut sink, &mut control, Limit::Time(until))
            .expect("null sink");
        driver.set_fixed_dt(dt);
    }
    let stop = match stop {
        Some(s) => s,
        None => driver
            .advance(&mut sink, &mut control, Limit::None)
            .expect("null sink")
            .unwrap_or(StopReason::End),
    };
    let outcome = driver.outcome(stop, &Default::default());
    let wall_s = start.elapsed().as_secs_f64();
    let events = outcome
        .events
        .iter()
        .zip(&onsets)
        .map(|(e, onset_s)| EventRecord {
            onset_step_s: e.t_onset_s,
            onset_s: onset_s.unwrap_or(e.t_onset_s),
            f_peak_n: e.f_peak_n,
            r_first_m: e.r_first_m,
            t_end_s: e.t_end_s,
        })
        .collect();
    RunRecord {
        spec: *spec,
        events,
        force_samples_n: force,
        wall_s,
        failure: outcome.failure.as_ref().map(ToString::to_string),
        steps: outcome.counts.steps,
        rejected_steps: outcome.counts.rejected_steps,
        onset_retakes: outcome.counts.onset_retakes,
    }
}
