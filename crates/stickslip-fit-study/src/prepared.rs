//! A case prepared for its fits: the scene (the scene file with the case's settings), its
//! window placed on the true model's meltings, the true model's clean curve; then its noisy
//! traces and their fits through the run library's typed API (`stickslip_studies::fit::fit`, as
//! `stickslip fit` makes them), with a progress line now and then.

use crate::cases::{Case, Window};
use crate::synth;
use std::path::Path;
use std::time::{Duration, Instant};
use stickslip_run::Scene;
use stickslip_run::scene::ResolvedScene;
use stickslip_studies::fit::misfit::ModelCurve;
use stickslip_studies::fit::{
    FitOptions, FitOutcome, JacobianKind, MisfitKind, Progress, Strategy, Trace,
};

/// How often a long fit reports its progress.
const PROGRESS_EVERY: Duration = Duration::from_secs(60);

/// A case ready to fit: its window placed, its scene, the true model's curve.
pub struct Prepared {
    /// The case, its window's end and samples set.
    pub case: Case,
    /// The scene the fits start from (the scene file with the case's settings).
    pub scene: ResolvedScene,
    /// The true model's F up to the window's end.
    pub curve: ModelCurve,
}

/// Prepares `case` (scene files under `root/validation/scenes`).
///
/// # Errors
/// The scene does not resolve, the true model fails, or has too few meltings.
pub fn prepare(root: &Path, mut case: Case) -> Result<Prepared, String> {
    let path = root.join("validation/scenes").join(&case.scene);
    let scene = Scene::from_path(&path, &case.settings).map_err(|e| e.to_string())?;
    let truth = case.truth_settings();
    if !matches!(case.window, Window::Fixed(_)) {
        let horizon = case.window.horizon_s();
        let long = synth::clean_curve(&scene, &truth, horizon)?;
        let onsets = synth::onsets(&long, horizon, case.spacing_s);
        let end = case
            .window
            .end_s(&onsets)
            .map_err(|e| format!("{}: {e}", case.id))?;
        case.set_end(end);
    }
    // The truth run to the window's end exactly, as the fit's runs go.
    let curve = synth::clean_curve(&scene, &truth, case.end_s)?;
    Ok(Prepared { case, scene, curve })
}

impl Prepared {
    /// The noisy trace of `seed` at `samples` samples over the window.
    ///
    /// # Errors
    /// A trace the fit refuses.
    pub fn trace(&self, samples: usize, seed: u64) -> Result<Trace, String> {
        let t = synth::sample_times(self.case.end_s, samples);
        synth::noisy(&self.curve, &t, self.case.noise_n, seed)
    }

    /// Fits `trace` with `kind`, `jobs` runs at a time, σF estimated from the data (as a
    /// user's fit does) or, with `known_noise`, the case's.
    ///
    /// # Errors
    /// The fit's error, in words.
    pub fn fit(
        &self,
        trace: Trace,
        kind: MisfitKind,
        jobs: usize,
        known_noise: bool,
    ) -> Result<FitOutcome, String> {
        self.fit_with(
            trace,
            kind,
            (jobs, known_noise),
            (Strategy::Direct, JacobianKind::Differences),
            None,
        )
    }

    /// As [`Prepared::fit`], with the search `strategy` and the kind of `jacobian`; with
    /// `start` (values in the order of the case's parameters) the local stage starts there
    /// and the global search is skipped, as when a fit resumes.
    ///
    /// # Errors
    /// The fit's error, in words.
    pub fn fit_with(
        &self,
        trace: Trace,
        kind: MisfitKind,
        (jobs, known_noise): (usize, bool),
        (strategy, jacobian): (Strategy, JacobianKind),
        start: Option<Vec<f64>>,
    ) -> Result<FitOutcome, String> {
        let (mut last, mut stage, mut level) = (Instant::now(), "", 0);
        let began = Instant::now();
        let mut progress = |p: &Progress| {
            if p.stage != stage || last.elapsed() >= PROGRESS_EVERY || p.level != level {
                eprintln!(
                    "fit-study:   {} {} stage at {:.0} s, {} runs, best χ² {:.6}, tolerance level {}",
                    self.case.id,
                    p.stage,
                    began.elapsed().as_secs_f64(),
                    p.evaluations,
                    p.best_chi2,
                    p.level
                );
                (last, stage, level) = (Instant::now(), p.stage, p.level);
            }
            false
        };
        stickslip_studies::fit::fit(
            &self.scene,
            trace,
            &self.case.params,
            FitOptions {
                misfit: kind,
                strategy,
                jacobian,
                jobs,
                noise_n: known_noise.then_some(self.case.noise_n),
                progress: Some(&mut progress),
                start,
                ..FitOptions::default()
            },
        )
        .map_err(|e| format!("{}: {e}", self.case.id))
    }
}
