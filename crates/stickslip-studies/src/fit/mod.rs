//! Fitting the model to a measured friction trace (`stickslip fit`, docs/fit.md): the film's
//! and contact's parameters that reproduce a trace F(t), with their uncertainties and the
//! combinations the data cannot determine.
//!
//! - [`data`]: the trace (CSV, columns renamed by `--columns`), its checks and noise level;
//! - [`params`]: the free parameters `KEY[=LO:HI]`, bounds from the key registry, the box
//!   coordinates (log space for positive bounds);
//! - [`events`] and [`misfit`]: the events of a trace, and the two misfits (`events`,
//!   `trace`) with their units and weights;
//! - [`forward`]: the forward runs (the scene with `--set` overrides, the driver, a null sink
//!   and an observer) at a tightened tolerance;
//! - [`problem`]: evaluations in parallel, failures as penalties, progress and Ctrl-C;
//! - [`optimise`]: the global sample and the bounded Levenberg–Marquardt stage with
//!   finite-difference Jacobians above the solver's noise; [`linalg`]: the SVD (faer);
//! - [`uncertainty`] and [`profile`]: covariance, intervals, correlations, singular values,
//!   unidentified combinations in words, and the profile likelihood;
//! - [`report`]: the result, [`report::FitReport`] (fit.json, writer and reader), and the
//!   fitted scene.

pub mod data;
pub mod discretisation;
pub mod error;
pub mod events;
pub mod forward;
pub mod linalg;
pub mod misfit;
pub mod optimise;
pub mod params;
pub mod pin;
pub mod problem;
pub mod profile;
pub mod replayed;
pub mod report;
pub mod scan;
pub mod uncertainty;

use crate::fit::report::{FitEvent, FitParameter, FitReport, finite};
pub use data::{Columns, Trace};
pub use error::FitError;
use events::Event;
use forward::Forward;
pub use forward::JacobianKind;
pub use misfit::MisfitKind;
use misfit::Target;
use params::Param;
use problem::{Eval, Problem};
pub use problem::{OnProgress, Progress};
use std::sync::atomic::AtomicBool;
use std::time::Instant;
use stickslip_run::scene::ResolvedScene;

/// The trace misfit's time shift is searched within ± this fraction of the trace's span.
pub const SHIFT_OF_SPAN: f64 = 0.05;

/// How the fit searches (docs/fit.md#the-profile-strategy).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Strategy {
    /// The global sample of the box, then the local stage from its best points.
    #[default]
    Direct,
    /// A parameter pinned by the first onset, the weakest one scanned, the rest fitted at
    /// each value ([`scan`]); the events misfit with three or more parameters.
    Profile,
}

impl Strategy {
    /// The strategy's name (`--strategy`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Direct => "direct",
            Self::Profile => "profile",
        }
    }

    /// The strategy named `name`.
    ///
    /// # Errors
    /// [`FitError::Input`] for another name.
    pub fn from_name(name: &str) -> Result<Self, FitError> {
        match name {
            "direct" => Ok(Self::Direct),
            "profile" => Ok(Self::Profile),
            _ => Err(FitError::input("--strategy", name, "direct or profile")),
        }
    }
}

/// How a fit is made.
#[derive(Default)]
pub struct FitOptions<'p> {
    /// The misfit.
    pub misfit: MisfitKind,
    /// The search.
    pub strategy: Strategy,
    /// σF, N (none: estimated from the data).
    pub noise_n: Option<f64>,
    /// Runs at a time.
    pub jobs: usize,
    /// The parameter to profile.
    pub profile: Option<String>,
    /// Set by Ctrl-C: the fit stops with the best model so far.
    pub interrupt: Option<&'p AtomicBool>,
    /// Progress, on the calling thread; returning true stops the fit as Ctrl-C does.
    pub progress: Option<&'p mut OnProgress<'p>>,
    /// Resume: the values (in the parameters' units, in their order) an interrupted fit of the
    /// same inputs had reached; the local stage starts there and the global sample is skipped.
    pub start: Option<Vec<f64>>,
    /// How the Jacobians are made (`--jacobian`; differences by default).
    pub jacobian: JacobianKind,
}

/// The fingerprint of a fit's inputs (fit.json's `inputs`): the resolved scene, the parameter
/// specifications, the misfit, the given noise and every number of the trace.
#[must_use]
pub fn inputs_fingerprint(
    scene: &ResolvedScene,
    params: &[String],
    misfit: MisfitKind,
    noise_n: Option<f64>,
    trace: &Trace,
) -> String {
    use stickslip_run::atomic::{FNV1A64_INIT, fnv1a64};
    let mut h = fnv1a64(FNV1A64_INIT, scene.resolved.to_toml_string().as_bytes());
    for p in params {
        h = fnv1a64(h, p.as_bytes());
        h = fnv1a64(h, b"\n");
    }
    h = fnv1a64(h, misfit.name().as_bytes());
    h = fnv1a64(h, &noise_n.unwrap_or(f64::NAN).to_bits().to_le_bytes());
    for column in [Some(&trace.t_s), Some(&trace.f_n), trace.x_m.as_ref()]
        .into_iter()
        .flatten()
    {
        for v in column {
            h = fnv1a64(h, &v.to_bits().to_le_bytes());
        }
        h = fnv1a64(h, b"|");
    }
    format!("{h:016x}")
}

/// A fit's results: fit.json's report, the fitted scene, and the curves of the figure.
#[derive(Debug, Clone)]
pub struct FitOutcome {
    /// fit.json.
    pub report: FitReport,
    /// fitted.toml: the scene with the fitted values and the fit's settings.
    pub fitted_toml: String,
    /// The data.
    pub trace: Trace,
    /// The fitted model's F at the data's times (shifted for the trace misfit), N.
    pub model_f_n: Vec<f64>,
}

fn fit_event(e: &Event) -> FitEvent {
    FitEvent {
        t_onset_s: e.t_onset_s,
        f_peak_n: e.f_peak_n,
        drop_n: e.drop_n,
    }
}

/// The free parameters of `specs` (`KEY[=LO:HI]`) in `scene`, and the trace misfit's shift.
///
/// # Errors
/// [`FitError::Input`] for a bad parameter, a key given twice, or none.
pub fn parameters(
    scene: &ResolvedScene,
    specs: &[String],
    kind: MisfitKind,
    trace: &Trace,
) -> Result<Vec<Param>, FitError> {
    if specs.is_empty() {
        return Err(FitError::input(
            "--param",
            "(none)",
            "at least one KEY[=LO:HI] to fit",
        ));
    }
    let table = scene.to_table();
    let mut out: Vec<Param> = Vec::new();
    for spec in specs {
        let key = spec
            .split_once('=')
            .map_or(spec.as_str(), |(k, _)| k)
            .trim();
        let current = stickslip_run::keys::lookup(&table, key).and_then(toml::Value::as_float);
        let p = params::parse(spec, current)?;
        if out.iter().any(|q| q.key == p.key) {
            return Err(FitError::input("--param", spec, "each key once"));
        }
        out.push(p);
    }
    if kind == MisfitKind::Trace {
        let span = trace.t_s[trace.t_s.len() - 1] - trace.t_s[0];
        out.push(params::time_shift(SHIFT_OF_SPAN * span));
    }
    Ok(out)
}

/// The scene settings that would stop the fit's model before the trace ends: the model must
/// run over the whole trace to be compared with it.
///
/// # Errors
/// [`FitError`] (bad input) naming the first such key.
pub fn refuse_cut_short(scene: &ResolvedScene) -> Result<(), FitError> {
    let allowed = "unset: the fit runs its model over the whole trace (a model cut short \
                   would be fitted to fewer events than the data hold)";
    if let Some(n) = scene.max_events {
        return Err(FitError::input("time.max_events", n.to_string(), allowed));
    }
    if let Some(t) = scene.max_open_event_s {
        return Err(FitError::input(
            "time.max_open_event",
            stickslip_run::keys::human(t),
            allowed,
        ));
    }
    if let Some(travel) = scene.resolved.time.as_ref().and_then(|t| t.travel) {
        return Err(FitError::input(
            "time.travel",
            stickslip_run::keys::human(travel),
            "unset: the fit ends its model's runs at the trace's end",
        ));
    }
    if scene.steady.stop {
        return Err(FitError::input(
            "time.until",
            "\"periodic\"",
            "\"end\": the fit runs its model over the whole trace",
        ));
    }
    Ok(())
}

/// How far above the scene's force scale τmax·πa0² a trace's force may reach: the model's
/// friction stays near it (a noise kick or a first-order film's peak adds a few times at
/// most), so a trace far above it is in other units or of another contact.
pub const MAX_FORCE_OF_SCALE: f64 = 1e3;

/// Refuses a trace whose force lies far beyond anything the scene's contact can give (a
/// trace in mN or dyn read as N, or of another contact).
///
/// # Errors
/// [`FitError::Input`] naming the trace's F with its largest value and the scene's scale.
fn refuse_foreign_units(scene: &ResolvedScene, trace: &Trace) -> Result<(), FitError> {
    let c = &scene.config;
    let scale = c.lubricant.tau_max_pa * std::f64::consts::PI * c.contact.radius_m.powi(2);
    let largest = trace.f_n.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if largest > MAX_FORCE_OF_SCALE * scale {
        return Err(FitError::input(
            "trace F",
            format!("up to {} N", stickslip_run::keys::human(largest)),
            format!(
                "forces within {MAX_FORCE_OF_SCALE:e} × the scene's scale τmax·πa0² = {} N (is \
                 the trace in N? is it of this contact?)",
                stickslip_run::keys::human(scale)
            ),
        ));
    }
    Ok(())
}

/// Refuses, before any run, a parameter the scene does not take at its bounds or midpoint
/// (a key that does not apply to this scene, or a box the scene's rules between keys
/// exclude): otherwise every forward run would be refused and the fit would end as a
/// numerical failure.
///
/// # Errors
/// [`FitError::Input`] naming the parameter, the value and the scene's reason.
fn refuse_inapplicable(forward: &Forward, params: &[Param]) -> Result<(), FitError> {
    for p in params.iter().filter(|p| p.scene_key) {
        for z in [0.0, 0.5, 1.0] {
            if let Err(e) = forward.scene(std::slice::from_ref(p), &[z]) {
                return Err(FitError::input(
                    "--param",
                    format!("{} (at {})", p.key, p.setting(z)),
                    format!("a key this scene takes over the whole box; it refuses it: {e}"),
                ));
            }
        }
    }
    Ok(())
}

/// Fits `params` (`KEY[=LO:HI]`) of `scene` to `trace`.
///
/// # Errors
/// [`FitError`]: bad input (exit 2), or no run that succeeded (exit 3).
pub fn fit(
    scene: &ResolvedScene,
    trace: Trace,
    params: &[String],
    options: FitOptions<'_>,
) -> Result<FitOutcome, FitError> {
    let started = Instant::now();
    refuse_cut_short(scene)?;
    refuse_foreign_units(scene, &trace)?;
    let inputs = inputs_fingerprint(scene, params, options.misfit, options.noise_n, &trace);
    let target = Target::new(trace, options.misfit, options.noise_n)?;
    let params = parameters(scene, params, options.misfit, &target.trace)?;
    let profiled = match &options.profile {
        Some(key) => Some(
            params
                .iter()
                .position(|p| &p.key == key)
                .ok_or_else(|| FitError::input("--profile", key, "one of the --param keys"))?,
        ),
        None => None,
    };
    let shift_max = params.iter().find(|p| !p.scene_key).map_or(0.0, |p| p.hi);
    let t_end = target.trace.t_s[target.trace.t_s.len() - 1];
    let forward = Forward::new(scene, t_end + shift_max)?;
    refuse_inapplicable(&forward, &params)?;
    let table = scene.to_table();
    let initial: Vec<Option<f64>> = params
        .iter()
        .map(|p| {
            if p.scene_key {
                stickslip_run::keys::lookup(&table, &p.key).and_then(toml::Value::as_float)
            } else {
                Some(0.0)
            }
        })
        .collect();
    // The scene's own values start the search too, when inside the box.
    let start: Option<Vec<f64>> = params
        .iter()
        .zip(&initial)
        .map(|(p, v)| v.map(|v| p.z(v)).filter(|z| (0.0..=1.0).contains(z)))
        .collect();
    let mut problem = Problem::new(&forward, &params, &target, options.jobs);
    problem.jacobian = options.jacobian;
    problem.interrupt = options.interrupt;
    problem.progress = options.progress;

    let resumed: Option<Vec<f64>> = match &options.start {
        Some(values) if values.len() == params.len() => Some(
            params
                .iter()
                .zip(values)
                .map(|(p, &v)| p.z(v).clamp(0.0, 1.0))
                .collect(),
        ),
        Some(values) => {
            return Err(FitError::input(
                "start",
                format!("{} values", values.len()),
                format!("one value per parameter ({})", params.len()),
            ));
        }
        None => None,
    };
    let profile_applies = options.misfit == MisfitKind::Events
        && params.iter().filter(|p| p.scene_key).count() >= 3
        && resumed.is_none();
    let use_profile = match options.strategy {
        Strategy::Direct => false,
        Strategy::Profile if profile_applies => true,
        Strategy::Profile => {
            return Err(FitError::input(
                "--strategy",
                "profile",
                "the events misfit with three or more parameters, not a resumed fit (or \
                 direct)",
            ));
        }
    };
    let mut steps = vec![optimise::FD_STEP_START; params.len()];
    let mut noise: Option<optimise::SolverNoise> = None;
    let mut scan_out = None;
    let mut local = None;
    if use_profile {
        // The scene's own values (the box's centre where outside it) start the scan.
        let z0 = start.clone().unwrap_or_else(|| vec![0.5; params.len()]);
        if let Some((l, sc)) = scan::profile_fit(&mut problem, z0, &mut steps, &mut noise) {
            local = Some(l);
            scan_out = Some(sc);
        }
        if problem.interrupted() && local.is_none() {
            return Err(FitError::Interrupted {
                evaluations: problem.evaluations,
            });
        }
        if local.is_none() {
            // Not applicable after all (the first onset does not move, or the start failed):
            // the direct search.
            problem.pin = None;
        }
    }
    let mut local = match local {
        Some(l) => l,
        None => {
            problem.stage = "global";
            direct_search(&mut problem, resumed, start, &mut steps, &mut noise)?
        }
    };
    // The parameters the local stage moves: with a pin, all but the pinned one.
    let free: Vec<usize> = (0..params.len())
        .filter(|&j| problem.pin.as_ref().is_none_or(|p| p.k != j))
        .collect();
    let mut best: Eval = match &problem.best {
        Some(b) if b.chi2 < local.best.chi2 && b.level == problem.level => b.clone(),
        _ => local.best.clone(),
    };
    let m = target.len();
    // The uncertainty from the Jacobian at the optimum, its steps grown above the solver's
    // noise measured there (not where the local stage started: the noise scales with the
    // residuals, and steps grown far off blur the derivative). Where that noise is too large
    // for the data the runs' tolerance is tightened and the local stage goes on from there.
    let mut unc = None;
    let mut discretisation = None;
    if !problem.interrupted() {
        problem.stage = "uncertainty";
        let mut n = noise.unwrap_or(optimise::SolverNoise {
            value: 0.0,
            at_chi2: f64::INFINITY,
        });
        // Measured afresh at the optimum.
        n.at_chi2 = f64::INFINITY;
        while let Some(true) = optimise::settle(&mut problem, &mut n, &mut best, &mut steps) {
            best = go_on(&mut problem, best, &free, &mut steps, &mut n, &mut local);
            problem.stage = "uncertainty";
            n.at_chi2 = f64::INFINITY;
        }
        noise = Some(n);
        let nu = n.value;
        // `settle` reports its runs as the noise stage; the Jacobian's are the uncertainty's.
        problem.stage = "uncertainty";
        // The intervals are every parameter's, the pinned one's too: its column from the
        // model itself, not solved along the first onset.
        problem.pin = None;
        let free: Vec<usize> = (0..params.len()).collect();
        if !problem.interrupted()
            && let Some(j) = optimise::jacobian(&mut problem, &best, &free, &mut steps, nu, true)
            && let Some(d) = linalg::svd(&j)
        {
            unc = Some(uncertainty::uncertainty(&params, &best.z, &d, best.chi2, m));
            problem.stage = "discretisation";
            discretisation = discretisation::estimate(
                &forward,
                (&params, &target),
                (&best, problem.level),
                &d,
                options.interrupt,
            );
        }
    }
    let mut profile_out = None;
    if let (Some(k), Some(u)) = (profiled, &unc)
        && !problem.interrupted()
    {
        let sz = u.intervals[k].stderr / params[k].slope(best.z[k]);
        let s2 = u.residual_sigma.powi(2);
        let mut n = noise.unwrap_or(optimise::SolverNoise {
            value: 0.0,
            at_chi2: best.chi2,
        });
        profile_out = profile::profile(&mut problem, &best, k, sz, s2, &mut steps, &mut n);
    }
    let interrupted = problem.interrupted();
    // Interrupted before the final Jacobian: the last one made (the local stage's, near the
    // best point) gives provisional intervals, marked so, rather than none.
    let mut provisional_intervals = false;
    if unc.is_none()
        && interrupted
        && let Some(last) = &problem.last_jacobian
        && last.free.len() == params.len()
        && let Some(d) = linalg::svd(&last.columns)
    {
        unc = Some(uncertainty::uncertainty(&params, &best.z, &d, best.chi2, m));
        provisional_intervals = true;
    }
    // The fitted model's curves (the interrupt no longer applies: one more run).
    problem.interrupt = None;
    let compared = problem.compare(&best.z).unwrap_or_default();
    let overrides = forward.overrides_at(&params, &best.z, problem.level);
    let mut source = forward.base.source.clone();
    for o in &overrides {
        stickslip_run::scene::overrides::apply_override(&mut source, o).map_err(Box::new)?;
    }
    let fitted_toml = stickslip_run::scene::toml_text::to_toml_string(&source);
    let parameters = params
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let iv = unc.as_ref().map(|u| &u.intervals[k]);
            FitParameter {
                key: p.key.clone(),
                unit: p.unit.to_string(),
                value: p.value(best.z[k]),
                stderr: iv.and_then(|i| finite(i.stderr)),
                lo95: iv.and_then(|i| finite(i.lo95)),
                hi95: iv.and_then(|i| finite(i.hi95)),
                lo: p.lo,
                hi: p.hi,
                log: p.log,
                initial: if p.scene_key { initial[k] } else { None },
                discretisation: discretisation
                    .as_ref()
                    .and_then(|d: &discretisation::Discretisation| finite(d.shifts[k])),
            }
        })
        .collect::<Vec<FitParameter>>();
    let warnings = parameters
        .iter()
        .filter_map(|p| {
            let (shift, se) = (p.discretisation?, p.stderr?);
            (shift > se).then(|| {
                format!(
                    "{}: the discretisation error {} {} exceeds the standard error {} {} (the \
                     model refined moves the value by more than the data allow): fit at more \
                     contact.nodes or a finer time.tolerance",
                    p.key,
                    stickslip_run::keys::human(shift),
                    p.unit,
                    stickslip_run::keys::human(se),
                    p.unit
                )
            })
        })
        .collect();
    let report = FitReport {
        scene: scene.name.clone(),
        status: if interrupted { "interrupted" } else { "ok" }.into(),
        provisional_intervals,
        misfit_kind: options.misfit.name().into(),
        parameters,
        correlation: unc.as_ref().map_or_else(Vec::new, |u| {
            u.correlation
                .iter()
                .map(|row| row.iter().map(|&c| finite(c)).collect())
                .collect()
        }),
        singular_values: unc
            .as_ref()
            .map_or_else(Vec::new, |u| u.singular_values.clone()),
        unidentified: unc
            .as_ref()
            .map_or_else(Vec::new, |u| u.unidentified.clone()),
        misfit: best.chi2,
        residuals: m,
        residual_sigma: unc.as_ref().map(|u| u.residual_sigma),
        noise_n: target.sigma_f_n,
        noise_estimated: target.sigma_estimated,
        noise_x_m: target.sigma_x_m,
        hysteresis_n: target.hysteresis_n,
        solver_noise: noise.map(|n| n.value),
        fd_steps: steps,
        time_tolerance: forward.tolerance_at(problem.level),
        settings: overrides,
        data_events: target.events.iter().map(fit_event).collect(),
        model_events: compared.model_events.iter().map(fit_event).collect(),
        iterations: local.iterations,
        converged: local.converged,
        evaluations: problem.evaluations,
        failed_runs: problem.failed_runs,
        first_failure: problem.first_failure.clone(),
        profile: profile_out,
        jacobian: replayed::words(&problem),
        strategy: if scan_out.is_some() {
            "profile"
        } else {
            "direct"
        }
        .into(),
        scan: scan_out,
        onset_runs: problem.onset_runs,
        wall_s: started.elapsed().as_secs_f64(),
        discretisation_settings: discretisation.map(|d| d.settings).unwrap_or_default(),
        warnings,
        inputs,
    };
    Ok(FitOutcome {
        report,
        fitted_toml,
        trace: target.trace,
        model_f_n: compared.model_f_n,
    })
}

/// The local stage gone on from `start` to convergence, its iterations and convergence
/// counted into `local`; its optimum.
fn go_on(
    problem: &mut Problem<'_, '_>,
    start: Eval,
    free: &[usize],
    steps: &mut [f64],
    noise: &mut optimise::SolverNoise,
    local: &mut optimise::Local,
) -> Eval {
    problem.stage = "local";
    let more =
        optimise::levenberg_marquardt(problem, start, free, steps, noise, optimise::MAX_ITERATIONS);
    local.iterations += more.iterations;
    local.converged = more.converged;
    more.best
}

/// The direct search: the global sample (or the resumed point), the local stage from its best
/// distinct points, and walks along the valley it ends in.
///
/// # Errors
/// [`FitError::Interrupted`] or [`FitError::NoRun`] when no run succeeded.
fn direct_search(
    problem: &mut Problem<'_, '_>,
    resumed: Option<Vec<f64>>,
    start: Option<Vec<f64>>,
    steps: &mut [f64],
    noise: &mut Option<optimise::SolverNoise>,
) -> Result<optimise::Local, FitError> {
    let params = problem.params;
    let global = match resumed {
        // An interrupted fit's best point: its global sample was made; the local stage goes
        // on from there.
        Some(z) => problem.evaluate_all(&[z], false).unwrap_or_default(),
        None => optimise::global(problem, start).unwrap_or_default(),
    };
    let Some(first) = global
        .iter()
        .find(|e| e.failed.is_none())
        .cloned()
        .or_else(|| problem.best.clone())
    else {
        return Err(if problem.interrupted() {
            FitError::Interrupted {
                evaluations: problem.evaluations,
            }
        } else {
            FitError::NoRun {
                evaluations: problem.evaluations,
                first: problem.first_failure.clone().unwrap_or_default(),
            }
        });
    };
    let free: Vec<usize> = (0..params.len()).collect();
    let mut local = optimise::Local {
        best: first.clone(),
        iterations: 0,
        converged: false,
    };
    if let Some(nu) = optimise::measure(problem, &first) {
        *noise = Some(nu);
        problem.stage = "local";
        // A few iterations from each start, then the best one on to convergence.
        let mut screened: Vec<(optimise::Local, Vec<f64>, optimise::SolverNoise)> = Vec::new();
        for s in optimise::starts(&global) {
            let (mut h, mut n) = (steps.to_vec(), nu);
            let l = optimise::levenberg_marquardt(
                problem,
                s,
                &free,
                &mut h,
                &mut n,
                optimise::SCREEN_ITERATIONS,
            );
            screened.push((l, h, n));
            if problem.interrupted() {
                break;
            }
        }
        if let Some((l, h, mut n)) = screened
            .into_iter()
            .min_by(|a, b| a.0.best.chi2.total_cmp(&b.0.best.chi2))
        {
            steps.copy_from_slice(&h);
            let spent = l.iterations;
            local = if l.converged || problem.interrupted() {
                l
            } else {
                let mut more = optimise::levenberg_marquardt(
                    problem,
                    l.best,
                    &free,
                    steps,
                    &mut n,
                    optimise::MAX_ITERATIONS,
                );
                more.iterations += spent;
                more
            };
            *noise = Some(n);
        }
    }
    // Walk the valley the local stage ended in: a sharply determined parameter makes a valley
    // narrower than the global sample's spacing, with further minima along it.
    if !problem.interrupted() && params.len() > 1 {
        let mut n = noise.unwrap_or(optimise::SolverNoise {
            value: 0.0,
            at_chi2: local.best.chi2,
        });
        for _ in 0..optimise::VALLEY_WALKS {
            problem.stage = "valley";
            let Some(j) = optimise::jacobian(problem, &local.best, &free, steps, n.value, false)
            else {
                break;
            };
            let Some(d) = linalg::svd(&j) else { break };
            let Some(points) = optimise::valley(problem, &local.best, &free, &d) else {
                break;
            };
            let Some(lower) = points
                .into_iter()
                .filter(|e| e.failed.is_none() && e.chi2 < local.best.chi2)
                .min_by(|a, b| a.chi2.total_cmp(&b.chi2))
            else {
                break;
            };
            local.best = go_on(problem, lower, &free, steps, &mut n, &mut local);
        }
        *noise = Some(n);
    }
    Ok(local)
}
