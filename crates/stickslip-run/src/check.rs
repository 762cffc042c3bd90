//! What `stickslip check` reports: the resolved scene, the preflight (derived, stability and
//! quasi-static numbers, the verdict), warnings for unusual values, and a cost estimate from
//! a short probe of the scene itself (a fixed count of steps, timed).

use crate::driver::{Control, Driver, Limit, NullSink, StartError, warnings_of};
use crate::scene::ResolvedScene;
use serde::Serialize;
use std::time::Instant;
use stickslip_core::preflight::{Finding, Preflight};

/// The probe's work in node-steps: it takes this many divided by the nodes, within
/// [`PROBE_MIN_STEPS`] and [`PROBE_MAX_STEPS`] (about 50–90 ms on 2 cores for fig2 at N = 2000
/// and the h0 = 1 nm contact at N = 200). A count, not a wall time, so that what the probe
/// finds (its pace, the output's size, whether it contradicts the step estimate) is the same
/// on a busy machine as on an idle one; only its seconds per step are a wall time.
const PROBE_NODE_STEPS: u64 = 800_000;
/// Fewest loop iterations the probe takes.
const PROBE_MIN_STEPS: u64 = 16;
/// Most loop iterations the probe takes.
const PROBE_MAX_STEPS: u64 = 4096;

/// The probe's loop iterations for a scene of `nodes` nodes (see [`PROBE_NODE_STEPS`]).
fn probe_step_count(nodes: usize) -> u64 {
    (PROBE_NODE_STEPS / nodes.max(1) as u64).clamp(PROBE_MIN_STEPS, PROBE_MAX_STEPS)
}
/// Adaptive step evaluations per stick–slip cycle at [`ADAPTIVE_REFERENCE_TOLERANCE`], for the
/// estimate: `stickslip run validation/scenes/fig2.toml --set contact.nodes=200` takes 3010
/// accepted steps, 43 rejected and 10 onset retakes for its approach and 10 events, 278 per
/// cycle; the steps crowd into the film's slowing down before each melting.
pub const ADAPTIVE_STEPS_PER_CYCLE: f64 = 280.0;
/// The tolerance [`ADAPTIVE_STEPS_PER_CYCLE`] was counted at; steps scale as its cube root.
pub const ADAPTIVE_REFERENCE_TOLERANCE: f64 = 5e-5;

/// How far the probe's own pace may exceed the estimate before the estimate counts as
/// contradicted: the probe's steps per simulated second, carried to `time.end`, against the
/// estimated steps.
pub const PROBE_CONTRADICTS_FACTOR: f64 = 3.0;

/// Whether a probe that took `probe_steps` steps over the fraction `covered` of `time.end`
/// contradicts an estimate of `estimated_steps` for the whole run: at its own pace the run
/// would take more than [`PROBE_CONTRADICTS_FACTOR`] times as many (a probe that reached the
/// end measured the whole run and contradicts nothing).
#[must_use]
pub fn probe_contradicts(covered: f64, probe_steps: f64, estimated_steps: f64) -> bool {
    let pace = pace_steps(covered, probe_steps);
    covered < 1.0 && (pace.is_nan() || pace > PROBE_CONTRADICTS_FACTOR * estimated_steps)
}

/// A probe's `probe_steps` over the fraction `covered` of `time.end`, carried at that pace to
/// the end (infinite when it covered nothing).
fn pace_steps(covered: f64, probe_steps: f64) -> f64 {
    if covered > 0.0 {
        probe_steps / covered
    } else {
        f64::INFINITY
    }
}

/// A rough cost estimate.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CostEstimate {
    /// Loop iterations timed by the probe.
    pub probe_steps: u64,
    /// Measured wall seconds per simulation step in the probe.
    pub seconds_per_step: f64,
    /// Estimated simulation steps of the whole run.
    pub steps: f64,
    /// Estimated wall seconds of the whole run; `None` (unknown) when the probe contradicts
    /// the step estimate: at the probe's own pace the run would take more than
    /// [`PROBE_CONTRADICTS_FACTOR`] times the estimated steps.
    pub seconds: Option<f64>,
    /// The probe's steps carried at its pace to `time.end`, and their wall time, s: what the
    /// first steps alone imply.
    pub probe_pace_seconds: f64,
    /// The probe's steps carried at its pace to `time.end`: the steps of the stick phases,
    /// as the output-size estimate counts them.
    pub probe_pace_steps: f64,
    /// How the step count was estimated (and why it is unknown, when it is).
    pub basis: String,
}

/// The report of `check`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CheckReport {
    /// The preflight.
    pub preflight: Preflight,
    /// Notes and warnings (preflight, unusual values, a coarse resolution).
    pub warnings: Vec<Finding>,
    /// Cost estimate.
    pub cost: CostEstimate,
    /// The first event at N and at 2N.
    pub resolution: ResolutionProbe,
    /// The contact's edge layer and the N it needs (none without an elastic radial contact).
    pub edge: Option<crate::edge_layer::EdgeLayer>,
    /// The output's expected size.
    pub output: crate::output_size::OutputSize,
}

/// Steps each run of the resolution probe may take (a count, not a time, so that what `check`
/// says does not depend on the machine's load): the h0 = 1 nm contact reaches its first event
/// in about 11 000.
pub const RESOLUTION_MAX_STEPS: u64 = 30_000;
/// A first event that moves by more than this (relative) from N to 2N draws a warning.
pub const RESOLUTION_WARN: f64 = 0.01;

/// The scene's first event at its N and at 2N: a cheap sign of a too coarse resolution.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ResolutionProbe {
    /// N and 2N.
    pub nodes: [usize; 2],
    /// The first onset at each, s.
    pub first_onset_s: [Option<f64>; 2],
    /// The peak force before it at each, N.
    pub f_peak_first_n: [Option<f64>; 2],
    /// The larger relative change of the two from N to 2N.
    pub relative_change: Option<f64>,
    /// Why the probe did not compare (one node, no event, over its time budget).
    pub skipped: Option<String>,
}

/// Runs the scene to its first event at N and 2N (each within [`RESOLUTION_MAX_STEPS`]).
fn resolution_probe(scene: &ResolvedScene) -> ResolutionProbe {
    let n = scene.config.contact.nodes;
    let mut probe = ResolutionProbe {
        nodes: [n, 2 * n],
        first_onset_s: [None, None],
        f_peak_first_n: [None, None],
        relative_change: None,
        skipped: None,
    };
    if scene.config.contact.model == stickslip_core::config::ContactModel::Homogeneous {
        probe.skipped = Some("one node: nothing to refine".to_string());
        return probe;
    }
    for (i, nodes) in [n, 2 * n].into_iter().enumerate() {
        let Ok(s) = scene.with_settings(&[
            crate::keys::contact::NODES.set(nodes as i64),
            crate::keys::time::MAX_EVENTS.set(1),
        ]) else {
            probe.skipped = Some(format!("N = {nodes} is not a valid scene"));
            return probe;
        };
        let mut over = false;
        let mut poll = |p: &crate::driver::Progress| {
            over = p.loop_index > RESOLUTION_MAX_STEPS;
            over
        };
        let mut control = Control {
            poll: Some(&mut poll),
            ..Control::default()
        };
        let Ok(o) = crate::driver::run(&s, &mut NullSink, &mut control) else {
            probe.skipped = Some(format!("the run at N = {nodes} could not start"));
            return probe;
        };
        if over {
            probe.skipped = Some(format!(
                "the first event lies beyond the probe's {RESOLUTION_MAX_STEPS} steps at N = \
                 {nodes}"
            ));
            return probe;
        }
        probe.first_onset_s[i] = o.summary.t_first_onset;
        probe.f_peak_first_n[i] = o.summary.f_peak_first;
    }
    let rel = |[a, b]: [Option<f64>; 2]| match (a, b) {
        (Some(a), Some(b)) if b != 0.0 => Some(((a - b) / b).abs()),
        _ => None,
    };
    probe.relative_change = match (rel(probe.first_onset_s), rel(probe.f_peak_first_n)) {
        (Some(x), Some(y)) => Some(x.max(y)),
        (x, y) => x.or(y),
    };
    if probe.relative_change.is_none() {
        probe.skipped = Some("no event before time.end at both N".to_string());
    }
    probe
}

/// Whether a run of the scene goes ahead.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Verdict {
    /// The run goes ahead (warnings may say its result is doubtful).
    Run,
    /// The preflight refuses it: `run` stops before the first step (run.json's `refused`).
    Refused,
}

impl Verdict {
    /// The name as printed (`run` or `refused`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Run => "run",
            Self::Refused => "refused",
        }
    }
}

impl CheckReport {
    /// The verdict: refused when the preflight has a refusal among its findings.
    #[must_use]
    pub fn verdict(&self) -> Verdict {
        if self.preflight.refusal().is_some() {
            Verdict::Refused
        } else {
            Verdict::Run
        }
    }
}

/// Checks `scene`: preflight, warnings and a timed probe of its first steps.
///
/// # Errors
/// When the engine rejects the configuration.
pub fn check(scene: &ResolvedScene) -> Result<CheckReport, StartError> {
    let mut sink = NullSink;
    let mut driver = Driver::start(scene, &mut sink)?;
    let preflight = driver.preflight().clone();
    let mut warnings = warnings_of(scene, &preflight);
    let resolution = resolution_probe(scene);
    let edge = crate::edge_layer::EdgeLayer::of(scene);
    let nodes = scene.config.contact.nodes;
    if let Some(e) = edge.filter(|e| e.too_coarse(nodes)) {
        // On the uniform grid the graded one is the cheaper way to the layer: say so.
        let uniform = scene.config.contact.grid.is_uniform();
        warnings.push(Finding {
            severity: stickslip_core::preflight::Severity::Warning,
            key: crate::keys::contact::NODES.path.to_string(),
            message: format!(
                "contact.nodes = {nodes} leaves the outermost node {:.3e} m from the contact's \
                 edge, {:.0} times the width a0/(8·rho²) = {:.3e} m of the edge layer where the first \
                 melting starts (rho = {:.3}): its onset may be percents off. This grid needs N \
                 >= {:.0} to reach the layer{}; `stickslip verify --target REL` finds the \
                 cheapest N and tolerance for an accuracy",
                e.outermost_gap_m,
                e.outermost_gap_m / e.width_m,
                e.width_m,
                e.rho,
                e.nodes_needed,
                if uniform {
                    format!(
                        ", contact.grid = \"graded\" N >= {:.0}",
                        e.nodes_needed_graded
                    )
                } else {
                    String::new()
                }
            ),
        });
    }
    if let Some(change) = resolution.relative_change.filter(|&c| c > RESOLUTION_WARN) {
        warnings.push(Finding {
            severity: stickslip_core::preflight::Severity::Warning,
            key: crate::keys::contact::NODES.path.to_string(),
            message: format!(
                "contact.nodes = {} may be too coarse for this scene: the first event moves by \
                 {:.1} % from N = {} to {} (onset {} → {} s, peak force {} → {} N); `stickslip \
                 verify` gives every number's error",
                resolution.nodes[0],
                100.0 * change,
                resolution.nodes[0],
                resolution.nodes[1],
                show(resolution.first_onset_s[0]),
                show(resolution.first_onset_s[1]),
                show(resolution.f_peak_first_n[0]),
                show(resolution.f_peak_first_n[1]),
            ),
        });
    }
    let cost = cost_of(scene, &mut driver)?;
    if let Some(w) = long_run_warning(scene, &preflight, &cost) {
        warnings.push(w);
    }
    let output = crate::output_size::estimate_clustered(
        scene,
        cost.steps,
        if cost.probe_pace_steps.is_finite() {
            cost.probe_pace_steps
        } else {
            cost.steps
        },
    );
    if let Some(interval) = output.interval_for_limit_s {
        warnings.push(Finding {
            severity: stickslip_core::preflight::Severity::Warning,
            key: crate::keys::output::SERIES_INTERVAL.path.to_string(),
            message: format!(
                "the output will be about {:.0} MB ({:.3e} rows of series.csv at \
                 output.series_interval = {} s); output.series_interval = {} s keeps it under \
                 {:.0} MB",
                output.bytes / 1e6,
                output.series_rows,
                crate::keys::human(scene.output.series_interval_s),
                crate::keys::human(interval),
                crate::output_size::LARGE_BYTES / 1e6
            ),
        });
    }
    Ok(CheckReport {
        cost,
        preflight,
        warnings,
        resolution,
        edge,
        output,
    })
}

/// The cost estimate of a run of `scene` alone (what `check` reports as `cost`), without the
/// rest of the check.
///
/// # Errors
/// When the engine rejects the configuration.
pub fn cost_estimate(scene: &ResolvedScene) -> Result<CostEstimate, StartError> {
    let mut driver = Driver::start(scene, &mut NullSink)?;
    cost_of(scene, &mut driver)
}

/// The timed probe of `driver` (fresh, at t = 0) and the step estimate of `scene`.
fn cost_of(scene: &ResolvedScene, driver: &mut Driver) -> Result<CostEstimate, StartError> {
    let mut sink = NullSink;
    let preflight = driver.preflight().clone();
    let mut control = Control::default();
    let started = Instant::now();
    let mut probe_steps = 0;
    let mut batch = 8;
    let steps_before = driver.simulation().state().counters.step;
    let target = probe_step_count(scene.config.contact.nodes);
    while probe_steps < target {
        let batch_now = batch.min(target - probe_steps);
        match driver.advance(&mut sink, &mut control, Limit::Steps(batch_now))? {
            None => probe_steps += batch_now,
            Some(_) => break,
        }
        batch *= 2;
    }
    let sim_steps = (driver.simulation().state().counters.step - steps_before).max(1);
    let seconds_per_step = started.elapsed().as_secs_f64() / sim_steps as f64;
    let t = &scene.config.time;
    // The probe's pace carried to the end (a probe that reached the end measured it all).
    let covered = (driver.simulation().time_s() / t.end_s).clamp(0.0, 1.0);
    let pace = pace_steps(covered, sim_steps as f64);
    let (steps, basis) = match t.adaptive {
        None => (
            scene.steps as f64,
            format!("{} fixed steps of time.dt", scene.steps),
        ),
        Some(a) => {
            // A travel that overflowed counts no events (check says the travel is unknown).
            let events = if preflight.critical_displacement_m > 0.0
                && preflight.stamp_travel_m.is_finite()
            {
                (preflight.stamp_travel_m.abs() / preflight.critical_displacement_m).floor()
            } else {
                0.0
            };
            let per_cycle =
                ADAPTIVE_STEPS_PER_CYCLE * (ADAPTIVE_REFERENCE_TOLERANCE / a.tolerance).cbrt();
            let floor = (t.end_s / a.dt_max_s).ceil();
            (
                (per_cycle * (events + 1.0)).max(floor),
                format!(
                    "adaptive: about {per_cycle:.0} steps per stick–slip cycle at time.tolerance \
                     = {:e} ({ADAPTIVE_STEPS_PER_CYCLE} at {ADAPTIVE_REFERENCE_TOLERANCE:e}, \
                     times the cube root of their ratio) for the approach and at most \
                     {events:.0} events (stamp travel / eps_c·h0), and at least \
                     time.end/time.dt_max = {floor:.0}; rough",
                    a.tolerance
                ),
            )
        }
    };
    let backed = !probe_contradicts(covered, sim_steps as f64, steps);
    let basis = if backed {
        basis
    } else {
        format!(
            "unknown: the first {sim_steps} steps covered {} of time.end, a pace of {:.3e} \
             steps to the end, more than {PROBE_CONTRADICTS_FACTOR} times the {steps:.0} \
             estimated ({basis})",
            if covered > 0.0 {
                format!("{:.2e}", covered)
            } else {
                "nothing".to_string()
            },
            pace
        )
    };
    Ok(CostEstimate {
        probe_steps,
        seconds_per_step,
        steps,
        seconds: backed.then_some(steps * seconds_per_step),
        probe_pace_seconds: pace * seconds_per_step,
        probe_pace_steps: pace,
        basis,
    })
}

/// Wall seconds above which `check` warns loudly about a run's cost.
pub const LONG_RUN_S: f64 = 3600.0;
/// Melting cycles above which a long run's cost is laid on the drive's travel.
const MANY_CYCLES: f64 = 1e5;

/// A loud warning when the run would take more than [`LONG_RUN_S`], naming the key most
/// likely mistyped: the drive's speed (or `time.end`) when the stamp's travel holds very many
/// melting cycles (a speed typed in m/s for µm/s), else the film's viscosity when it has one,
/// else `time.end`.
fn long_run_warning(scene: &ResolvedScene, p: &Preflight, cost: &CostEstimate) -> Option<Finding> {
    let seconds = cost.seconds.unwrap_or(cost.probe_pace_seconds);
    if seconds.is_nan() || seconds <= LONG_RUN_S {
        return None;
    }
    let cycles = if p.critical_displacement_m > 0.0 {
        p.stamp_travel_m.abs() / p.critical_displacement_m
    } else {
        0.0
    };
    let c = &scene.config;
    let eta = c.lubricant.viscosity_pa_s;
    let (key, why) = if cycles > MANY_CYCLES {
        (
            crate::keys::drive::VELOCITY.path,
            format!(
                "the stamp travels {:.3e} m by time.end = {} s, about {cycles:.2e} melting cycles \
                 of eps_c·h0 = {:.3e} m each: is drive.velocity in m/s (1 µm/s = 1e-6)? Or \
                 shorten time.end",
                p.stamp_travel_m,
                crate::keys::human(c.time.end_s),
                p.critical_displacement_m
            ),
        )
    } else if eta > 0.0 {
        (
            crate::keys::lubricant::VISCOSITY.path,
            format!(
                "lubricant.viscosity = {} Pa·s sets the film's viscous time η·a0/(h0·G*) = \
                 {:.3e} s, which the steps must resolve: is it in Pa·s?",
                crate::keys::human(eta),
                eta * c.contact.radius_m / (c.contact.film_thickness_m * c.contact.g_eff_pa)
            ),
        )
    } else {
        (
            crate::keys::time::END.path,
            format!(
                "time.end = {} s at this resolution",
                crate::keys::human(c.time.end_s)
            ),
        )
    };
    Some(Finding {
        severity: stickslip_core::preflight::Severity::Warning,
        key: key.to_string(),
        message: format!(
            "THIS RUN WOULD TAKE ABOUT {}: {why}",
            duration_words(seconds)
        ),
    })
}

/// Seconds in the largest unit that keeps the number above 1 (s, min, h, days, years).
fn duration_words(s: f64) -> String {
    if s.is_infinite() {
        return "FOREVER (its first steps covered nothing of time.end)".to_string();
    }
    const UNITS: [(f64, &str); 5] = [
        (365.25 * 86400.0, "years"),
        (86400.0, "days"),
        (3600.0, "hours"),
        (60.0, "minutes"),
        (1.0, "seconds"),
    ];
    let (size, name) = UNITS
        .iter()
        .find(|(size, _)| s >= *size)
        .copied()
        .unwrap_or((1.0, "seconds"));
    format!("{:.3} {name}", s / size)
}

/// A probe's number as printed: seven digits, or `none`.
#[must_use]
pub fn show(v: Option<f64>) -> String {
    v.map_or_else(|| "none".to_string(), |x| format!("{x:.6e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_probe_that_covers_too_little_makes_the_cost_unknown() {
        // 2000 steps over 0.2 % of the run: 1e6 steps at that pace, against 3000 estimated.
        assert!(probe_contradicts(0.002, 2000.0, 3000.0));
        // Nothing covered (the clock did not move): nothing backs the estimate.
        assert!(probe_contradicts(0.0, 8.0, 3000.0));
        // A pace within 3x of the estimate, or a probe that ran the whole scene, backs it.
        assert!(!probe_contradicts(0.5, 2000.0, 3000.0));
        assert!(!probe_contradicts(1.0, 2000.0, 10.0));
        assert!(probe_contradicts(0.1, 2000.0, 6000.0));
    }
}
