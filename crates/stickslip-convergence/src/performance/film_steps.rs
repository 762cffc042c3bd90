//! Work–precision of the second-order film's two steps (`numerics.film_step`): the ramp
//! correction (the default) and the frozen-strain step before it, side by side, over
//! tolerances, on fig2 (N = [`super::T4_NODES`], against T4's same-N reference) and on the SFA
//! contact of P7 (against P7's reference): step evaluations and wall seconds against the
//! largest onset error.
//!
//! This module writes the section "Film steps: work–precision" and its figure;
//! [`super::report`] places them. Every number comes from the runs here.

use super::experiment::{
    P7_EVALUATIONS_GOAL, P7_ONSET_GOAL_S, PHI_ERROR_FLOOR, SfaBench, onset_deviations,
};
use super::{BenchSettings, T4_NODES, Timed, timed, timed_scene};
use serde::Serialize;
use std::fmt::Write as _;
use stickslip_report::fmt::{sig, tick};
use stickslip_report::palette::PALETTE;
use stickslip_report::plot::{Marker, Panel, Series, render_svg};
use stickslip_run::keys::words::FilmStep;
use stickslip_run::keys::{contact, numerics, time};

/// fig2's tolerances.
const FIG2_TOLERANCES: [f64; 5] = [1e-3, 3e-4, 1e-4, 5e-5, 1e-5];
/// The SFA contact's tolerances (its runs take seconds each); 5e-3, 100× the default, shows
/// the evaluations' floor: how few a far looser tolerance still takes.
const SFA_TOLERANCES: [f64; 4] = [5e-3, 5e-4, 1.5e-4, 5e-5];
/// The quick bench's tolerances, both scenes.
const QUICK_TOLERANCES: [f64; 2] = [1e-3, 1e-4];

/// The variants run: (film step, `numerics.phi_error_floor`): both steps with φ's error
/// relative down to the melt threshold (the default), and the ramp step with the floor.
const VARIANTS: [(FilmStep, f64); 3] = [
    (FilmStep::Ramp, 0.0),
    (FilmStep::Frozen, 0.0),
    (FilmStep::Ramp, PHI_ERROR_FLOOR),
];

/// One run: a scene at a tolerance with one film step.
#[derive(Debug, Clone, Serialize)]
pub struct FilmStepPoint {
    /// `fig2` or `sfa`.
    pub scene: String,
    /// `ramp` or `frozen`.
    pub film_step: String,
    /// `numerics.phi_error_floor` (0: the default).
    pub phi_error_floor: f64,
    /// `time.tolerance`.
    pub tolerance: f64,
    /// Step evaluations (accepted, rejected, onset retakes).
    pub evaluations: u64,
    /// Process wall time, s (median of the repeats for fig2, one run for SFA).
    pub wall_s: f64,
    /// Meltings of the run.
    pub meltings: usize,
    /// Meltings of the reference.
    pub reference_meltings: usize,
    /// Largest |onset − the reference's|, s (none when the counts differ).
    pub max_onset_error_s: Option<f64>,
}

impl FilmStepPoint {
    fn new(
        scene: &str,
        (step, floor): (FilmStep, f64),
        tolerance: f64,
        t: &Timed,
        reference_s: &[f64],
    ) -> Self {
        let deviations = onset_deviations(&t.event_values.onsets_s, reference_s);
        Self {
            scene: scene.into(),
            film_step: step_name(step).into(),
            phi_error_floor: floor,
            tolerance,
            evaluations: t.evaluations(),
            wall_s: t.wall_s,
            meltings: t.events,
            reference_meltings: reference_s.len(),
            max_onset_error_s: deviations.into_iter().reduce(f64::max),
        }
    }
}

/// The points of `scene` with `step` and `floor`, in the order run.
fn of<'a>(
    points: &'a [FilmStepPoint],
    scene: &str,
    step: &str,
    floor: f64,
) -> Vec<&'a FilmStepPoint> {
    points
        .iter()
        .filter(|p| p.scene == scene && p.film_step == step && p.phi_error_floor == floor)
        .collect()
}

/// A variant in words: `ramp`, `frozen`, `ramp, φ floor 0.1`.
fn variant_name(step: &str, floor: f64) -> String {
    if floor > 0.0 {
        format!("{step}, φ floor {floor}")
    } else {
        step.to_string()
    }
}

fn step_name(step: FilmStep) -> &'static str {
    match step {
        FilmStep::Ramp => "ramp",
        FilmStep::Frozen => "frozen",
    }
}

/// The runs: fig2 against `fig2_reference_s` (T4's same-N reference onsets), the SFA contact
/// with P7's settings against P7's reference.
///
/// # Errors
/// A run that does not start or fails.
pub fn measure(
    s: &BenchSettings,
    fig2_reference_s: &[f64],
    sfa: &SfaBench,
    progress: &dyn Fn(&str),
) -> Result<Vec<FilmStepPoint>, String> {
    let mut points = Vec::new();
    let (fig2_tols, sfa_tols): (&[f64], &[f64]) = if s.quick {
        (&QUICK_TOLERANCES, &QUICK_TOLERANCES)
    } else {
        (&FIG2_TOLERANCES, &SFA_TOLERANCES)
    };
    for variant @ (step, floor) in VARIANTS {
        for &tol in fig2_tols {
            progress(&format!(
                "film steps: fig2, {}, tolerance {tol:e}",
                variant_name(step_name(step), floor)
            ));
            let sets = vec![
                contact::NODES.set(T4_NODES as i64).to_string(),
                time::TOLERANCE.set(tol).to_string(),
                numerics::FILM_STEP.set(step).to_string(),
                numerics::PHI_ERROR_FLOOR.set(floor).to_string(),
            ];
            let t = timed(s, "film_steps", &sets, 2, s.repeats, fig2_reference_s)?;
            points.push(FilmStepPoint::new(
                "fig2",
                variant,
                tol,
                &t,
                fig2_reference_s,
            ));
        }
    }
    let sfa_scene = s.scene.with_file_name(super::experiment::SFA_SCENE);
    let sfa_reference_s = &sfa.p7.reference.event_values.onsets_s;
    for variant @ (step, floor) in VARIANTS {
        for &tol in sfa_tols {
            progress(&format!(
                "film steps: SFA, {}, tolerance {tol:e}",
                variant_name(step_name(step), floor)
            ));
            let mut sets = sfa.p7.settings.clone();
            sets.push(time::TOLERANCE.set(tol).to_string());
            sets.push(numerics::FILM_STEP.set(step).to_string());
            sets.push(numerics::PHI_ERROR_FLOOR.set(floor).to_string());
            let t = timed_scene(
                s,
                &sfa_scene,
                "film_steps_sfa",
                &sets,
                2,
                1,
                sfa_reference_s,
            )?;
            points.push(FilmStepPoint::new("sfa", variant, tol, &t, sfa_reference_s));
        }
    }
    Ok(points)
}

/// The section: per scene a table of both steps over the tolerances, and what the ramp step
/// saves at the default tolerance.
#[must_use]
pub fn section(points: &[FilmStepPoint]) -> String {
    let mut out = String::from(
        "## Film steps: work–precision\n\n\
         The second-order film's two steps (`numerics.film_step`): `ramp`, the frozen-strain \
         step corrected to first order in the film coefficient's change along the step's \
         strain ramp (the default), and `frozen`, the step before it; and the ramp step with \
         `numerics.phi_error_floor` = ",
    );
    let _ = write!(
        out,
        "{PHI_ERROR_FLOOR} (a node's φ error relative to max(φ, melt threshold, \
         {PHI_ERROR_FLOOR}·φ_s) rather than max(φ, melt threshold); φ floor in the table). fig2 \
         at N = ",
    );
    let _ = write!(
        out,
        "{T4_NODES} against T4's same-N reference; the SFA contact of P7 (K = {} N/m, to \
         1 s) against P7's reference. Largest onset error over all meltings; evaluations are \
         accepted steps, rejected attempts and onset retakes.\n\n\
         ![film steps](performance_film_steps.svg)\n\n\
         | scene | tolerance | ramp: evaluations | ramp: s | ramp: onset error | frozen: \
         evaluations | frozen: s | frozen: onset error | evaluations frozen/ramp | φ floor: \
         evaluations | φ floor: s | φ floor: onset error | evaluations ramp/φ floor |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
        super::experiment::SFA_STIFFNESS
    );
    let err = |p: &FilmStepPoint| match p.max_onset_error_s {
        Some(e) => format!("{} µs", sig(e * 1e6, 2)),
        None => format!("{} of {} meltings", p.meltings, p.reference_meltings),
    };
    for scene in ["fig2", "sfa"] {
        let floored = of(points, scene, "ramp", PHI_ERROR_FLOOR);
        for (k, (r, f)) in of(points, scene, "ramp", 0.0)
            .into_iter()
            .zip(of(points, scene, "frozen", 0.0))
            .enumerate()
        {
            let g = match floored.get(k) {
                Some(g) if g.tolerance == r.tolerance => format!(
                    "{} | {} | {} | {}",
                    g.evaluations,
                    sig(g.wall_s, 3),
                    err(g),
                    sig(r.evaluations as f64 / g.evaluations.max(1) as f64, 3)
                ),
                _ => "– | – | – | –".into(),
            };
            let _ = writeln!(
                out,
                "| {scene} | {} | {} | {} | {} | {} | {} | {} | {} | {g} |",
                tick(r.tolerance),
                r.evaluations,
                sig(r.wall_s, 3),
                err(r),
                f.evaluations,
                sig(f.wall_s, 3),
                err(f),
                sig(f.evaluations as f64 / r.evaluations.max(1) as f64, 3),
            );
        }
    }
    out.push('\n');
    floor_words(&mut out, points);
    out
}

/// How the ramp step's evaluations fall with the tolerance on each scene (the log–log slope
/// between its loosest and tightest runs), and for the SFA contact the fewest evaluations that
/// keep every onset within P7's accuracy goal, against P7's goal of evaluations.
fn floor_words(out: &mut String, points: &[FilmStepPoint]) {
    for (scene, floor) in [
        ("fig2", 0.0),
        ("sfa", 0.0),
        ("fig2", PHI_ERROR_FLOOR),
        ("sfa", PHI_ERROR_FLOOR),
    ] {
        let ramp = of(points, scene, "ramp", floor);
        let name = variant_name("ramp step", floor);
        let loose = ramp
            .iter()
            .max_by(|a, b| a.tolerance.total_cmp(&b.tolerance));
        let tight = ramp
            .iter()
            .min_by(|a, b| a.tolerance.total_cmp(&b.tolerance));
        if let (Some(l), Some(t)) = (loose, tight)
            && l.tolerance > t.tolerance
            && l.evaluations > 0
        {
            let slope = (t.evaluations as f64 / l.evaluations as f64).ln()
                / (l.tolerance / t.tolerance).ln();
            let _ = write!(
                out,
                "{scene}, {name}: from tolerance {} to {} ({}× tighter) the evaluations grow \
                 from {} to {}, like tolerance^−{}. ",
                tick(l.tolerance),
                tick(t.tolerance),
                sig(l.tolerance / t.tolerance, 3),
                l.evaluations,
                t.evaluations,
                sig(slope, 2)
            );
        }
        if scene == "sfa"
            && let Some(l) = loose
        {
            let within = ramp
                .iter()
                .filter(|p| p.max_onset_error_s.is_some_and(|e| e <= P7_ONSET_GOAL_S))
                .min_by_key(|p| p.evaluations);
            let err = match l.max_onset_error_s {
                Some(e) => format!("onsets up to {} µs off", sig(e * 1e6, 3)),
                None => format!("{} meltings against {}", l.meltings, l.reference_meltings),
            };
            let _ = write!(
                out,
                "The floor of P7 with the {name}: even at tolerance {} the run takes {} \
                 evaluations ({}× P7's goal of {P7_EVALUATIONS_GOAL}) with {err}",
                tick(l.tolerance),
                l.evaluations,
                sig(l.evaluations as f64 / P7_EVALUATIONS_GOAL as f64, 3),
            );
            match within {
                Some(w) => {
                    let _ = write!(
                        out,
                        "; the fewest evaluations that keep every onset within {} µs are {} \
                         (tolerance {}, {}× the goal).",
                        tick(P7_ONSET_GOAL_S * 1e6),
                        w.evaluations,
                        tick(w.tolerance),
                        sig(w.evaluations as f64 / P7_EVALUATIONS_GOAL as f64, 3)
                    );
                }
                None => {
                    let _ = write!(
                        out,
                        "; no run here keeps every onset within {} µs.",
                        tick(P7_ONSET_GOAL_S * 1e6)
                    );
                }
            }
            out.push(' ');
        }
    }
    out.push_str("\n\n");
}

/// The figure: per scene, the largest onset error against step evaluations, both steps
/// (labels: the tolerance).
///
/// # Errors
/// The plotting layer's.
pub fn figure(points: &[FilmStepPoint]) -> Result<String, String> {
    let mut panels = Vec::new();
    for (scene, title) in [
        ("fig2", format!("fig2, N = {T4_NODES}")),
        ("sfa", "the SFA contact, K = 500 N/m, to 1 s".to_string()),
    ] {
        let mut panel = Panel::new(
            &format!("{title}: largest onset error against step evaluations"),
            "step evaluations",
            "largest onset error (µs)",
        )
        .log_log();
        for (k, (step, floor, marker)) in [
            ("ramp", 0.0, Marker::Circle),
            ("frozen", 0.0, Marker::Square),
            ("ramp", PHI_ERROR_FLOOR, Marker::Triangle),
        ]
        .into_iter()
        .enumerate()
        {
            let shown: Vec<&FilmStepPoint> = of(points, scene, step, floor)
                .into_iter()
                .filter(|p| p.max_onset_error_s.is_some_and(|e| e > 0.0))
                .collect();
            let pts = shown
                .iter()
                .map(|p| {
                    (
                        p.evaluations as f64,
                        p.max_onset_error_s.unwrap_or(0.0) * 1e6,
                    )
                })
                .collect();
            let labels = shown.iter().map(|p| format!("{:e}", p.tolerance)).collect();
            panel.series.push(
                Series::new(variant_name(step, floor), pts, PALETTE[k])
                    .marker(marker)
                    .labels(labels),
            );
        }
        panels.push(panel);
    }
    render_svg(&panels, 2, 1100, 480)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(scene: &str, tolerance: f64, evaluations: u64, error_s: Option<f64>) -> FilmStepPoint {
        FilmStepPoint {
            scene: scene.into(),
            film_step: "ramp".into(),
            phi_error_floor: 0.0,
            tolerance,
            evaluations,
            wall_s: 1.0,
            meltings: 78,
            reference_meltings: 78,
            max_onset_error_s: error_s,
        }
    }

    #[test]
    fn the_floor_is_read_from_the_runs() {
        let points = [
            point("fig2", 1e-3, 1000, Some(1e-8)),
            point("fig2", 1e-5, 2000, Some(1e-9)),
            point("sfa", 5e-3, 60_000, Some(4e-3)),
            point("sfa", 5e-4, 120_000, Some(1.1e-4)),
            point("sfa", 1.5e-4, 170_000, Some(1.3e-5)),
            floored(point("sfa", 5e-3, 40_000, Some(3e-3))),
            floored(point("sfa", 5e-4, 57_000, Some(9.7e-5))),
        ];
        let mut out = String::new();
        floor_words(&mut out, &points);
        // 2× the evaluations over 100× the tolerance: slope ln 2 / ln 100 = 0.15.
        assert!(out.contains("like tolerance^−0.15"), "{out}");
        assert!(
            out.contains("takes 60000 evaluations (2.00× P7's goal"),
            "{out}"
        );
        assert!(out.contains("onsets up to 4000 µs off"), "{out}");
        assert!(
            out.contains("are 170000 (tolerance 1.5e-4, 5.67× the goal)"),
            "{out}"
        );
        // The floored variant's own statement, from its own points only.
        assert!(
            out.contains(
                "The floor of P7 with the ramp step, φ floor 0.1: even at tolerance 0.005 the run \
                 takes 40000 evaluations"
            ),
            "{out}"
        );
        assert!(
            out.contains("are 57000 (tolerance 5e-4, 1.90× the goal)"),
            "{out}"
        );
    }

    fn floored(p: FilmStepPoint) -> FilmStepPoint {
        FilmStepPoint {
            phi_error_floor: PHI_ERROR_FLOOR,
            ..p
        }
    }
}
