//! `stickslip verify --target REL`: the cheapest N and tolerance whose estimated error of the
//! first onset and of the peak force before it are within REL (relative).
//!
//! The search runs the scene to its first event only (`time.max_events = 1`):
//! 1. **Space.** N doubles from [`FIRST_NODES`] at a hundredth of the scene's tolerance (so that
//!    the time error is far below the spatial one); each level's spatial error comes from the
//!    level and the next two (Celik's procedure with its safety factors, [`super::estimate`]),
//!    and the ladder stops at the first level within REL/2, or at the node limit.
//! 2. **Time.** At that N the tolerance falls tenfold from a hundred times the scene's; each
//!    level's time error comes from the level and the next two, and the ladder stops at the
//!    first level within REL/2.
//! 3. **The pair.** Every (N, tolerance) of the two ladders whose errors add up to at most REL
//!    is a candidate; its cost is estimated from the two ladders' wall times (the run at N and
//!    the small tolerance, scaled by how the tolerance changed the cost at the chosen N); the
//!    cheapest is run once more, and its measured cost is reported.
//!
//! The errors are estimates from the scene's own refinements, with the uncertainty's safety
//! factors of `verify`: 1.25 times the distance to the extrapolation in the asymptotic range,
//! 3 times the larger of it and the levels' spread outside.

use super::estimate::{self, Estimate};
use super::{ADAPTIVE_ORDER, SCHEME_ORDER, VerifyError, space_order};
use serde::{Deserialize, Serialize};
use stickslip_core::config::{ContactModel, MAX_NODES};
use stickslip_core::grid::Grading;
use stickslip_run::driver::{Control, NullSink};
use stickslip_run::keys::{contact, time};
use stickslip_run::scene::ResolvedScene;

/// The first N of the space ladder.
pub const FIRST_NODES: usize = 25;
/// The largest tolerance of the time ladder.
pub const MAX_TOLERANCE: f64 = 1e-2;
/// The smallest tolerance the time ladder goes to.
pub const MIN_TOLERANCE: f64 = 1e-11;

/// One run of the search.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Probe {
    /// `space` or `time` ladder, or `chosen` (the confirming run).
    pub ladder: String,
    /// N.
    pub nodes: usize,
    /// time.tolerance.
    pub tolerance: f64,
    /// The first onset, s (none: no event before time.end, or a failed run).
    pub t_first_onset: Option<f64>,
    /// The peak force before it, N.
    pub f_peak_first: Option<f64>,
    /// Steps taken.
    pub steps: u64,
    /// Wall seconds.
    pub wall_s: f64,
}

/// The pair found.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Choice {
    /// The scene's grid (the search keeps it).
    pub grid: Grading,
    /// N.
    pub nodes: usize,
    /// time.tolerance.
    pub tolerance: f64,
    /// Estimated relative spatial error of the first onset and of the peak force.
    pub space_error: [f64; 2],
    /// Estimated relative time error of the first onset and of the peak force.
    pub time_error: [f64; 2],
    /// The cost estimated before the confirming run, s.
    pub estimated_wall_s: f64,
    /// The confirming run's wall time, s.
    pub wall_s: f64,
    /// The confirming run's first onset, s.
    pub t_first_onset: Option<f64>,
    /// The confirming run's peak force, N.
    pub f_peak_first: Option<f64>,
}

impl Choice {
    /// The estimated total relative error of (first onset, peak force).
    #[must_use]
    pub fn total_error(&self) -> [f64; 2] {
        [
            self.space_error[0] + self.time_error[0],
            self.space_error[1] + self.time_error[1],
        ]
    }

    /// The overrides that select the pair, as `--set` words (with the grid when it is the
    /// graded one: the pair's errors are that grid's).
    #[must_use]
    pub fn overrides(&self) -> Vec<String> {
        let mut out = vec![
            format!("{}={}", contact::NODES.path, self.nodes),
            format!(
                "{}={}",
                time::TOLERANCE.path,
                stickslip_run::keys::human(self.tolerance)
            ),
        ];
        if let Grading::Edge { power } = self.grid {
            out.push(format!("{}=graded", contact::GRID.path));
            out.push(format!(
                "{}={}",
                contact::GRADING.path,
                stickslip_run::keys::human(power)
            ));
        }
        out
    }

    /// The overrides as a TOML file (a scene's sections).
    #[must_use]
    pub fn overrides_toml(&self, scene: &str, target: f64) -> String {
        format!(
            "# The cheapest resolution of scene \"{scene}\" whose estimated error of the first \
             onset\n# and of its peak force is within {} (relative), found by\n# `stickslip \
             verify --target {}`: first onset ±{:.2e}, peak force ±{:.2e} (relative),\n# \
             {:.3} s to the first event. Use it as --set {}\n# or copy the sections \
             into the scene.\n\n[contact]\nnodes = {}\n{}\n[time]\ntolerance = {}\n",
            stickslip_run::keys::human(target),
            stickslip_run::keys::human(target),
            self.total_error()[0],
            self.total_error()[1],
            self.wall_s,
            self.overrides().join(" --set "),
            self.nodes,
            match self.grid {
                Grading::Edge { power } => format!(
                    "grid = \"graded\"\ngrading = {}\n",
                    stickslip_run::keys::human(power)
                ),
                Grading::Uniform => String::new(),
            },
            stickslip_run::keys::human(self.tolerance)
        )
    }
}

/// What the search found.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TargetReport {
    /// The scene's name.
    pub scene: String,
    /// The relative error asked for.
    pub target: f64,
    /// Every run, in order.
    pub probes: Vec<Probe>,
    /// The pair (none: the node limit or the smallest tolerance was reached first).
    pub choice: Option<Choice>,
    /// Why there is no pair, when there is none.
    pub note: Option<String>,
}

/// The relative error of the level at `i` of a ladder from it and the next two, for both
/// quantities; none while the next two are missing or a level has no event.
fn ladder_error(
    probes: &[Probe],
    i: usize,
    spacing: fn(&Probe) -> f64,
    orders: [f64; 2],
) -> Option<[Estimate; 2]> {
    let three = probes.get(i..i + 3)?;
    let h = [spacing(&three[0]), spacing(&three[1]), spacing(&three[2])];
    let pick = |q: usize, p: &Probe| {
        if q == 0 {
            p.t_first_onset
        } else {
            p.f_peak_first
        }
    };
    let mut out = Vec::new();
    for (q, &order) in orders.iter().enumerate() {
        let phi = [
            pick(q, &three[0])?,
            pick(q, &three[1])?,
            pick(q, &three[2])?,
        ];
        out.push(estimate::estimate(h, phi, order));
    }
    Some([out[0].clone(), out[1].clone()])
}

/// An estimate's uncertainty relative to its value.
fn relative(e: &Estimate) -> f64 {
    if e.value == 0.0 {
        f64::INFINITY
    } else {
        e.uncertainty / e.value.abs()
    }
}

fn run_probe(
    scene: &ResolvedScene,
    ladder: &str,
    nodes: usize,
    tolerance: f64,
) -> Result<Probe, VerifyError> {
    let s = scene
        .with_settings(&[
            contact::NODES.set(nodes as i64),
            time::TOLERANCE.set(tolerance),
            time::MAX_EVENTS.set(1),
        ])
        .map_err(|error| VerifyError::Scene {
            what: format!("N = {nodes}, time.tolerance = {tolerance:e}"),
            error: Box::new(error),
        })?;
    let o = stickslip_run::driver::run(&s, &mut NullSink, &mut Control::default()).map_err(
        |error| VerifyError::Start {
            what: format!("N = {nodes}, time.tolerance = {tolerance:e}"),
            error: Box::new(error),
        },
    )?;
    let ok = o.failure.is_none();
    Ok(Probe {
        ladder: ladder.to_string(),
        nodes,
        tolerance,
        t_first_onset: o.summary.t_first_onset.filter(|_| ok),
        f_peak_first: o.summary.f_peak_first.filter(|_| ok),
        steps: o.counts.steps,
        wall_s: o.wall_seconds,
    })
}

/// One ladder's runs and, from the third on, the relative errors (onset, peak force) of the
/// level two below each.
struct Ladder {
    runs: Vec<Probe>,
    errors: Vec<[f64; 2]>,
}

/// Runs `levels` (N, tolerance) in order until a level's error, from it and the next two, is
/// within `within` for both quantities; the ladder and that level's index (none: the levels
/// ran out). Every run is logged and kept in `probes` too.
#[allow(clippy::too_many_arguments)]
fn climb(
    scene: &ResolvedScene,
    name: &str,
    levels: impl Iterator<Item = (usize, f64)>,
    spacing: fn(&Probe) -> f64,
    orders: [f64; 2],
    within: f64,
    log: &mut dyn FnMut(&Probe),
    probes: &mut Vec<Probe>,
) -> Result<(Ladder, Option<usize>), VerifyError> {
    let mut ladder = Ladder {
        runs: Vec::new(),
        errors: Vec::new(),
    };
    for (nodes, tolerance) in levels {
        let p = run_probe(scene, name, nodes, tolerance)?;
        log(&p);
        probes.push(p.clone());
        ladder.runs.push(p);
        if ladder.runs.len() >= 3 {
            let i = ladder.runs.len() - 3;
            let e = ladder_error(&ladder.runs, i, spacing, orders)
                .map_or([f64::INFINITY; 2], |e| [relative(&e[0]), relative(&e[1])]);
            ladder.errors.push(e);
            if e[0] <= within && e[1] <= within {
                return Ok((ladder, Some(i)));
            }
        }
    }
    Ok((ladder, None))
}

/// Searches the cheapest N and tolerance of `scene` within `target`; `log` receives a line per
/// run.
///
/// # Errors
/// A bad target, a scene without adaptive steps or a radial contact, or a run that cannot
/// start.
pub fn search(
    scene: &ResolvedScene,
    target: f64,
    log: &mut dyn FnMut(&Probe),
) -> Result<TargetReport, VerifyError> {
    if !(target.is_finite() && target > 0.0 && target < 1.0) {
        return Err(VerifyError::Option {
            option: "--target",
            value: stickslip_run::keys::human(target),
            allowed: "finite, > 0 and < 1 (a relative error)",
        });
    }
    let c = &scene.config;
    let Some(adaptive) = c.time.adaptive else {
        return Err(VerifyError::Option {
            option: "--target",
            value: "with time.stepping = \"fixed\"".into(),
            allowed: "time.stepping = \"adaptive\" (the search sets time.tolerance)",
        });
    };
    if c.contact.model != ContactModel::Radial {
        return Err(VerifyError::Option {
            option: "--target",
            value: "with contact.model = \"homogeneous\"".into(),
            allowed: "contact.model = \"radial\" (the search sets contact.nodes)",
        });
    }
    let graded = !c.contact.grid.is_uniform();
    let orders_space = [space_order("t_first_onset", graded), SCHEME_ORDER];
    let orders_time = [ADAPTIVE_ORDER, ADAPTIVE_ORDER];
    let mut probes: Vec<Probe> = Vec::new();
    let report = |probes: Vec<Probe>, choice, note: Option<String>| TargetReport {
        scene: scene.name.clone(),
        target,
        probes,
        choice,
        note,
    };

    // 1. Space.
    let tol_space = (adaptive.tolerance / 100.0).max(MIN_TOLERANCE * 100.0);
    let nodes = std::iter::successors(Some(FIRST_NODES), |n| Some(n * 2))
        .take_while(|&n| n <= MAX_NODES)
        .map(|n| (n, tol_space));
    let (space, chosen_space) = climb(
        scene,
        "space",
        nodes,
        |p| 1.0 / p.nodes as f64,
        orders_space,
        target / 2.0,
        log,
        &mut probes,
    )?;
    let Some(chosen_space) = chosen_space else {
        return Ok(report(
            probes,
            None,
            Some(format!(
                "the spatial error stays above {} of the target up to the node limit \
                 N = {MAX_NODES}",
                stickslip_run::keys::human(target / 2.0)
            )),
        ));
    };
    let (space_ladder, space_errors) = (space.runs, space.errors);
    let n_star = space_ladder[chosen_space].nodes;

    // 2. Time, at that N.
    let first_tolerance = (adaptive.tolerance * 100.0).min(MAX_TOLERANCE);
    let tolerances = std::iter::successors(Some(first_tolerance), |t| Some(t / 10.0))
        .take_while(|&t| t >= MIN_TOLERANCE)
        .map(|t| (n_star, t));
    let (time, chosen_time) = climb(
        scene,
        "time",
        tolerances,
        |p| p.tolerance,
        orders_time,
        target / 2.0,
        log,
        &mut probes,
    )?;
    let Some(chosen_time) = chosen_time else {
        return Ok(report(
            probes,
            None,
            Some(format!(
                "the time error stays above {} of the target down to time.tolerance = \
                 {MIN_TOLERANCE:e}",
                stickslip_run::keys::human(target / 2.0)
            )),
        ));
    };
    let (time_ladder, time_errors) = (time.runs, time.errors);

    // 3. The cheapest pair of the two ladders within the target.
    // The cost of the time ladder's tolerance relative to the space ladder's, at N*: the
    // space ladder's tolerance is not on the time ladder in general, so its cost at N* is the
    // space ladder's run.
    let base = space_ladder[chosen_space].wall_s.max(1e-9);
    let mut best: Option<(usize, usize, f64)> = None;
    for (k, es) in space_errors.iter().enumerate() {
        for (j, et) in time_errors.iter().enumerate() {
            if es[0] + et[0] <= target && es[1] + et[1] <= target {
                let cost = space_ladder[k].wall_s * time_ladder[j].wall_s / base;
                if best.is_none_or(|b| cost < b.2) {
                    best = Some((k, j, cost));
                }
            }
        }
    }
    let (k, j, estimated_wall_s) =
        best.unwrap_or((chosen_space, chosen_time, space_ladder[chosen_space].wall_s));
    let confirm = run_probe(
        scene,
        "chosen",
        space_ladder[k].nodes,
        time_ladder[j].tolerance,
    )?;
    log(&confirm);
    probes.push(confirm.clone());
    let choice = Choice {
        grid: c.contact.grid,
        nodes: space_ladder[k].nodes,
        tolerance: time_ladder[j].tolerance,
        space_error: space_errors[k],
        time_error: time_errors[j],
        estimated_wall_s,
        wall_s: confirm.wall_s,
        t_first_onset: confirm.t_first_onset,
        f_peak_first: confirm.f_peak_first,
    };
    Ok(report(probes, Some(choice), None))
}
