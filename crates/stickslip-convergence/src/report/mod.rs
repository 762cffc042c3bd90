//! The convergence report: `convergence.md`, `convergence.json` and the `convergence_*.svg`
//! figures, written from [`crate::Results`] by [`write_all`]. This file holds the entry
//! points, the page frame (introduction, definitions, how to reproduce), the quantities of the
//! shipped fig2 scene the prose quotes ([`Paper`]) and the lookups and table helpers the
//! sections share; each section (answers, operators, steppers, whole simulation,
//! work–precision, tolerance, noise, findings) has its own file with its text and figures.
//!
//! Every number in the text is computed from the results (or from the shipped scene and the
//! core's parameters), so re-rendering (`--render-only`) keeps text and data consistent.

mod answers;
mod findings;
mod grid;
mod noise;
mod operators;
mod steppers;
mod tolerance;
mod whole_simulation;
mod work_precision;

use crate::fig2::{self, MERGE_GAP_S, SAMPLE_DT_S};
use crate::study::{Refined, Study};
use crate::{Results, RunSummary};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use stickslip_core::noise::NoiseKind;
use stickslip_core::preflight::EULER_STABILITY_LIMIT;
use stickslip_report::files::ReportFiles;
use stickslip_report::fmt::{sig, tick};
use stickslip_report::stats;

/// Onset tolerance asked about in the issue, s.
pub const ONSET_TOL_S: f64 = 1e-7;

/// Errors below this are rounding and are not drawn on log axes.
pub const ROUNDING_FLOOR: f64 = 1e-13;

/// Writes the three kinds of output into `dir`; returns the files written.
///
/// # Errors
/// An I/O or rendering error, as text.
pub fn write_all(r: &Results, dir: &Path) -> Result<Vec<PathBuf>, String> {
    let mut files = ReportFiles::create(dir)?;
    files.put_json("convergence.json", r)?;
    for (name, svg) in figures(r)? {
        files.put(&name, svg)?;
    }
    files.put("convergence.md", markdown(r))?;
    Ok(files.into_written())
}

/// Every figure: (file name, SVG text).
fn figures(r: &Results) -> Result<Vec<(String, String)>, String> {
    let mut out = vec![
        ("convergence_operators.svg".into(), operators::figure(r)?),
        ("convergence_steppers.svg".into(), steppers::figure(r)?),
        (
            "convergence_simulation.svg".into(),
            whole_simulation::self_convergence_figure(r)?,
        ),
        (
            "convergence_vs_reference.svg".into(),
            whole_simulation::reference_figure(r)?,
        ),
        (
            "convergence_work_precision.svg".into(),
            work_precision::figure(r)?,
        ),
    ];
    if r.tolerance.is_some() {
        out.push(("convergence_tolerance.svg".into(), tolerance::figure(r)?));
    }
    if let Some(n) = &r.noise {
        out.push(("convergence_noise.svg".into(), noise::figure(n)?));
    }
    if let Some(g) = &r.grid {
        out.push(("convergence_grid.svg".into(), grid::figure(g)?));
    }
    Ok(out)
}

// ---------------------------------------------------------------------------------------------
// What the prose quotes from the shipped scene

/// Quantities of the shipped fig2 scene (and of the core) that the text quotes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Paper {
    /// The paper's N.
    pub nodes: usize,
    /// The paper's Δt, s.
    pub dt_s: f64,
    /// End time, s.
    pub end_s: f64,
    /// Contact radius a0, m.
    pub a0_m: f64,
    /// φ below which a node counts as melted.
    pub melt_threshold: f64,
    /// Deterministic noise floor of φ (None: the scene has no floor noise).
    pub noise_floor: Option<f64>,
    /// Explicit Euler's rate 2γAb/a at the solid equilibrium, 1/s.
    pub euler_rate_per_s: f64,
}

impl Paper {
    /// From the shipped scene.
    pub fn shipped() -> Self {
        let scene = fig2::shipped();
        let c = &scene.config;
        let l = &c.lubricant;
        let d = &scene.derived;
        Self {
            nodes: c.contact.nodes,
            dt_s: c.time.dt_s,
            end_s: c.time.end_s,
            a0_m: c.contact.radius_m,
            melt_threshold: c.melt_threshold,
            noise_floor: match c.noise {
                NoiseKind::Floor { floor } => Some(floor),
                NoiseKind::Off | NoiseKind::Gaussian { .. } => None,
            },
            euler_rate_per_s: 2.0 * l.gamma_per_pa_s * d.a_coeff_pa * d.b_pa / l.a_pa,
        }
    }

    /// Δt·2γAb/a, the literal scheme's Euler number at `dt_s`.
    pub fn euler_number(&self, dt_s: f64) -> f64 {
        dt_s * self.euler_rate_per_s
    }

    /// The largest stable explicit Euler step, s.
    pub fn euler_limit_s(&self) -> f64 {
        EULER_STABILITY_LIMIT / self.euler_rate_per_s
    }

    /// Whether `dt_s` is the paper's Δt.
    pub fn is_paper_dt(&self, dt_s: f64) -> bool {
        same(dt_s, self.dt_s)
    }
}

/// Equal to relative 1e-9 (levels written to JSON and read back).
pub(crate) fn same(a: f64, b: f64) -> bool {
    (a / b - 1.0).abs() < 1e-9
}

// ---------------------------------------------------------------------------------------------
// Lookups shared by the sections

/// The whole-simulation studies of one scheme, refinement and observable (one per event, or
/// one for F(t)).
pub(crate) fn sims<'a>(
    r: &'a Results,
    scheme: &str,
    refined: Refined,
    observable: &str,
) -> Vec<&'a Study> {
    r.studies
        .iter()
        .filter(|s| {
            s.study == "simulation"
                && s.scheme == scheme
                && s.refined == refined
                && s.observable == observable
        })
        .collect()
}

/// The runs of one study role (`N`, `dt`, `reference`, `work-precision`) and scheme.
pub(crate) fn runs<'a>(r: &'a Results, role: &str, scheme: &str) -> Vec<&'a RunSummary> {
    r.runs
        .iter()
        .filter(|x| x.role == role && x.scheme == scheme)
        .collect()
}

/// The run of `role` and `scheme` at (N, Δt).
pub(crate) fn run_at<'a>(
    r: &'a Results,
    role: &str,
    scheme: &str,
    n: usize,
    dt: f64,
) -> Option<&'a RunSummary> {
    r.runs
        .iter()
        .find(|x| x.role == role && x.scheme == scheme && x.nodes == n && same(x.dt_s, dt))
}

/// Per level, the largest error over `studies` (events) divided by `scale` (0: by the
/// level's own value, a relative error); levels without any error are left out.
pub(crate) fn max_error_per_level(studies: &[&Study], scale: f64) -> Vec<(f64, f64)> {
    let Some(first) = studies.first() else {
        return Vec::new();
    };
    (0..first.levels.len())
        .filter_map(|i| {
            let m = studies
                .iter()
                .filter_map(|s| {
                    let e = s.errors.get(i).copied().flatten()?;
                    let v = s.values.as_ref().and_then(|v| v[i]).unwrap_or(1.0);
                    Some(e / if scale > 0.0 { scale } else { v.abs() })
                })
                .fold(f64::NAN, f64::max);
            m.is_finite().then_some((first.levels[i], m))
        })
        .collect()
}

/// Celik's p of every study of (scheme, refined, observable) that has one.
pub(crate) fn celik_orders(r: &Results, scheme: &str, refined: Refined, obs: &str) -> Vec<f64> {
    sims(r, scheme, refined, obs)
        .iter()
        .filter_map(|s| s.gci.map(|g| g.p))
        .collect()
}

/// Median of Celik's p over the events (None: no study has one).
pub(crate) fn median_p(r: &Results, scheme: &str, refined: Refined, obs: &str) -> Option<f64> {
    let ps = celik_orders(r, scheme, refined, obs);
    (!ps.is_empty()).then(|| stats::median(&ps))
}

/// (studies whose three finest levels oscillate, studies) of (scheme, refined, observable).
pub(crate) fn oscillatory(
    r: &Results,
    scheme: &str,
    refined: Refined,
    obs: &str,
) -> (usize, usize) {
    let st = sims(r, scheme, refined, obs);
    let osc = st
        .iter()
        .filter(|s| s.gci.is_some_and(|g| g.oscillatory))
        .count();
    (osc, st.len())
}

/// The theoretical order of (scheme, refined, observable) as its theory column begins
/// (`2`, `3/2 to 2`, `none`).
pub(crate) fn theory_words(r: &Results, scheme: &str, refined: Refined, obs: &str) -> String {
    sims(r, scheme, refined, obs).first().map_or_else(
        || "–".to_string(),
        |s| s.theory.split(':').next().unwrap_or("").trim().to_string(),
    )
}

/// Events of the reference (every run that finishes should have as many).
pub(crate) fn event_count(r: &Results) -> usize {
    r.work_precision.reference.onsets_s.len()
}

/// The reference's onset uncertainty: its largest Δt GCI plus the N-error of the accurate N
/// study at the first level ≥ the reference's N (max over events), s.
pub(crate) fn reference_onset_uncertainty_s(r: &Results) -> f64 {
    let gci = r
        .work_precision
        .reference
        .onset_uncertainty_s
        .iter()
        .fold(0.0_f64, |m, &v| m.max(v));
    if r.work_precision.reference.n_extrapolation.is_some() {
        // The N part is inside the corrected reference's uncertainty already.
        return gci;
    }
    gci + reference_n_error_s(r).unwrap_or(0.0)
}

/// Largest relative uncertainty of the reference's peak forces.
pub(crate) fn reference_f_peak_uncertainty_rel(r: &Results) -> f64 {
    let rf = &r.work_precision.reference;
    rf.f_peak_uncertainty_n
        .iter()
        .zip(&rf.f_peaks_n)
        .fold(0.0_f64, |m, (u, f)| m.max((u / f).abs()))
}

/// The reference's uncertainty as a horizontal line on an error panel of `obs` (`onset` in
/// µs, `f_peak` relative): errors below it are not resolved by the reference.
pub(crate) fn reference_band(r: &Results, obs: &str) -> Option<(f64, String)> {
    let what = if r.work_precision.reference.n_extrapolation.is_some() {
        "reference ± (Δt and N GCI)"
    } else {
        "reference ± (Δt GCI + N error)"
    };
    match obs {
        "onset" => Some((reference_onset_uncertainty_s(r) * 1e6, what.to_string())),
        "f_peak" => Some((reference_f_peak_uncertainty_rel(r), what.to_string())),
        _ => None,
    }
    .filter(|(v, _)| *v > 0.0)
}

/// N-error of the reference's onsets, estimated by the accurate N study, s.
pub(crate) fn reference_n_error_s(r: &Results) -> Option<f64> {
    let i = r
        .settings
        .sim_nodes
        .iter()
        .position(|&n| n >= r.work_precision.reference.nodes)?;
    let m = sims(r, "accurate", Refined::Nodes, "onset")
        .iter()
        .filter_map(|s| s.errors.get(i).copied().flatten())
        .fold(f64::NAN, f64::max);
    m.is_finite().then_some(m)
}

/// Per event k (from 1): the literal onset limit in N (Celik extrapolation, or the finest
/// level where Celik fails or oscillates) minus the reference onset, s.
pub(crate) fn literal_gaps_s(r: &Results) -> Vec<(usize, f64)> {
    let reference = &r.work_precision.reference.onsets_s;
    sims(r, "literal", Refined::Nodes, "onset")
        .iter()
        .filter_map(|st| {
            let k = st.event?;
            let onset_ref = *reference.get(k.checked_sub(1)?)?;
            Some((k, literal_limit(st)? - onset_ref))
        })
        .collect()
}

/// The literal onset limit of one study: Celik's extrapolation, or the finest level.
pub(crate) fn literal_limit(st: &Study) -> Option<f64> {
    match st.gci {
        Some(g) if !g.oscillatory => Some(g.phi_ext),
        _ => st.values.iter().flatten().filter_map(|v| *v).next_back(),
    }
}

/// Smallest and largest of `values` (None when empty).
pub(crate) fn range(values: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
    values.into_iter().fold(None, |acc, v| match acc {
        None => Some((v, v)),
        Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
    })
}

/// `lo–hi` with `digits` significant digits (one value when they agree to those digits).
pub(crate) fn span(lo: f64, hi: f64, digits: usize) -> String {
    let (a, b) = (sig(lo, digits), sig(hi, digits));
    if a == b { a } else { format!("{a}–{b}") }
}

/// Observed orders of a study, two decimals, `–` where undefined.
pub(crate) fn orders(s: &Study) -> String {
    s.observed_order
        .iter()
        .map(|p| p2(*p))
        .collect::<Vec<_>>()
        .join(", ")
}

/// An order with two decimals, `–` for none.
pub(crate) fn p2(p: Option<f64>) -> String {
    p.map_or_else(|| "–".into(), |p| format!("{p:.2}"))
}

/// `N=125` or `Δt=1e-8`.
pub(crate) fn level_name(refined: Refined, l: f64) -> String {
    match refined {
        Refined::Nodes => format!("N={l:.0}"),
        Refined::Dt => format!("Δt={l:e}"),
    }
}

/// The refinement levels of the whole-simulation study along `refined`.
pub(crate) fn level_ticks(r: &Results, refined: Refined) -> Vec<f64> {
    match refined {
        Refined::Nodes => r.settings.sim_nodes.iter().map(|&n| n as f64).collect(),
        Refined::Dt => r.settings.sim_dts_s.clone(),
    }
}

/// `0.1 µs`: the onset tolerance as written.
pub(crate) fn tol_text() -> String {
    format!("{} µs", tick(ONSET_TOL_S * 1e6))
}

// ---------------------------------------------------------------------------------------------
// Tables

/// A Markdown table header with its rule.
pub(crate) fn header<S: AsRef<str>>(md: &mut String, columns: &[S]) {
    let names: Vec<&str> = columns.iter().map(AsRef::as_ref).collect();
    let _ = writeln!(md, "| {} |", names.join(" | "));
    let _ = writeln!(md, "|{}", "---|".repeat(names.len()));
}

/// A Markdown table row.
pub(crate) fn row<S: AsRef<str>>(md: &mut String, cells: &[S]) {
    let cells: Vec<&str> = cells.iter().map(AsRef::as_ref).collect();
    let _ = writeln!(md, "| {} |", cells.join(" | "));
}

// ---------------------------------------------------------------------------------------------
// The page

fn markdown(r: &Results) -> String {
    let mut md = String::new();
    let s = &r.settings;
    let paper = Paper::shipped();
    let _ = writeln!(md, "# Convergence: what accuracy costs in time\n");
    let _ = writeln!(
        md,
        "{}\n",
        stickslip_report::provenance::sentence(r.commit.as_ref())
    );
    let _ = writeln!(
        md,
        "Generated by `cargo xtask convergence` (crate `stickslip-convergence`; raw numbers in \
         `convergence.json`). Full study wall time on this machine ({}{} build): **{} s ({} \
         min)**. `cargo xtask convergence --render-only` redraws this page and the figures from \
         the JSON.\n",
        r.machine
            .as_ref()
            .map_or_else(String::new, |m| format!("{m}, ")),
        r.build_profile,
        sig(r.total_wall_s, 3),
        sig(r.total_wall_s / 60.0, 2)
    );
    let _ = writeln!(
        md,
        "Levels run: operators N = {:?}; whole simulation N = {:?} at Δt = {:e} s and Δt = {:?} s \
         at N = {}; work–precision points (N, Δt) = {:?} per scheme with {} timing repeat(s); \
         reference N = {} with Δt = {:?} s. {}\n",
        s.operator_nodes,
        s.sim_nodes,
        s.sim_nodes_dt_s,
        s.sim_dts_s,
        s.sim_dts_nodes,
        s.wp_points,
        s.repeats,
        s.ref_nodes,
        s.ref_dts_s,
        if s.sim_nodes.last() == Some(&paper.nodes) {
            format!("The N refinement reaches the paper's N = {}.", paper.nodes)
        } else {
            format!(
                "**N = {} was not run** (largest N {}, `--max-nodes {}`); statements about \
                 N = {} below are extrapolations and say so.",
                paper.nodes,
                s.sim_nodes.last().copied().unwrap_or(0),
                s.max_nodes,
                paper.nodes
            )
        }
    );
    answers::section(&mut md, r, &paper);
    definitions(&mut md, r, &paper);
    operators::section(&mut md, r);
    steppers::section(&mut md, r, &paper);
    whole_simulation::section(&mut md, r, &paper);
    work_precision::section(&mut md, r, &paper);
    tolerance::section(&mut md, r);
    noise::section(&mut md, r);
    findings::section(&mut md, r, &paper);
    if let Some(g) = &r.grid {
        grid::section(&mut md, g);
    }
    let _ = writeln!(md, "## Reproduce\n");
    let _ = writeln!(
        md,
        "```sh\ncargo xtask convergence                  # the full study (about {} min here)\n\
         cargo xtask convergence --max-nodes 500  # cap the N refinement\n\
         cargo xtask convergence --quick          # a one-minute smoke study\n\
         cargo xtask convergence --grid-only      # section 8 alone, merged into the JSON\n\
         cargo test -p stickslip-convergence      # the fast subset with asserted order bands\n```",
        (r.total_wall_s / 60.0).ceil()
    );
    md
}

/// What the events of the runs that finished have in common.
fn event_counts(r: &Results) -> String {
    let mut counts: Vec<usize> = r
        .runs
        .iter()
        .filter(|x| x.failure.is_none() && x.role != "work-precision")
        .map(|x| x.events.len())
        .chain(
            r.work_precision
                .points
                .iter()
                .filter(|p| p.failure.is_none())
                .map(|p| p.events),
        )
        .collect();
    counts.sort_unstable();
    counts.dedup();
    match counts.as_slice() {
        [n] => format!("Every run that finishes has the same {n} melting events."),
        [] => "No run finished.".to_string(),
        many => format!(
            "Event counts differ between runs ({}); the tables say where.",
            many.iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

fn definitions(md: &mut String, r: &Results, paper: &Paper) {
    let _ = writeln!(md, "## Definitions\n");
    let noise = paper.noise_floor.map_or_else(
        || "the scene's noise".to_string(),
        |f| format!("the deterministic floor noise φ ≥ {}", tick(f)),
    );
    let ratio = r
        .settings
        .sim_dts_s
        .windows(2)
        .map(|w| w[0] / w[1])
        .fold(f64::INFINITY, f64::min);
    let _ = writeln!(
        md,
        "- **Scene**: fig2 of the paper ([docs/model.md](../docs/model.md#the-papers-scenes)) \
         over {} ms with {noise}, both schemes of the core (`literal`: plain sums, explicit \
         Euler, lagged coupling; `accurate`: product \
         integration, exact Landau step, coupling solved each step, located re-solidification), \
         fixed steps, every run through the run library's driver. A melting that begins within \
         {} µs of the previous event's end continues that event (`output.event_merge_gap`). {}\n\
         - **onset** of event k: the accurate scheme locates it inside the step on the first \
         melting node's exact path, and this study takes the core's value; the literal scheme \
         flags the end of the first step with a melted node (φ < {}), so this study locates the \
         crossing inside that step by interpolating ln φ of each newly melted node linearly in \
         time and takes the earliest. The JSON keeps both (`onset_step_s`, `onset_s`).\n\
         - **f_peak** of event k: the core's largest step-end F since the previous event began.\n\
         - **F(t) over the stick phases**: F on a {} µs grid (linear between step ends), \
         excluding ±{} µs around every onset of the comparison solution; norm = RMS over the \
         remaining samples divided by max F.\n\
         - **Celik et al. 2008**: on the three finest levels (refinement ratio {} > {}), p from \
         |ln|ε32/ε21| + q(p)|/ln r21 by fixed-point iteration, φext = (r^p φ1 − φ2)/(r^p − 1), \
         e_a = |φ1 − φ2|/|φ1|, GCI_fine = 1.25·e_a/(r^p − 1); oscillatory when ε32/ε21 < 0. We \
         quote the GCI in the observable's units (1.25·|φ1 − φ2|/(r^p − 1)). The `observed p` \
         lists hold Celik's p for each three consecutive levels, coarse to fine. For F(t), p \
         comes from the norms of successive differences and F_ext is extrapolated pointwise. \
         Medians over events of an even count are the mean of the two middle values.\n\
         - **errors** without an exact answer: |φ − φext| against the extrapolation of the \
         three finest levels (or against the finest level where Celik fails or oscillates).\n\
         - **reference** (work–precision and the 'against the reference' errors): accurate \
         scheme at N = {} with Δt = {:?} s, extrapolated in Δt per event with Celik's procedure \
         (F(t) pointwise); see §4.\n",
        tick(paper.end_s * 1e3),
        tick(MERGE_GAP_S * 1e6),
        event_counts(r),
        tick(paper.melt_threshold),
        tick(SAMPLE_DT_S * 1e6),
        tick(crate::simulation::STICK_GUARD_S * 1e6),
        tick(ratio),
        crate::celik::MIN_RATIO,
        r.work_precision.reference.nodes,
        r.work_precision.reference.dts_s
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shipped_scene_gives_the_papers_numbers() {
        let p = Paper::shipped();
        assert_eq!(p.nodes, 2000);
        assert!(same(p.dt_s, 1e-8));
        // 2γAb/a = 2·10·1.5e6·2e6/1e6 = 6e7 1/s: explicit Euler is stable below 3.3e-8 s.
        assert!(same(p.euler_rate_per_s, 6e7), "{}", p.euler_rate_per_s);
        assert!(same(p.euler_limit_s(), 2.0 / 6e7));
        assert!(same(p.end_s, fig2::FIG2_END_S));
    }

    #[test]
    fn tables_and_spans() {
        let mut md = String::new();
        header(&mut md, &["a", "b"]);
        row(&mut md, &["1", "2"]);
        assert_eq!(md, "| a | b |\n|---|---|\n| 1 | 2 |\n");
        assert_eq!(span(1.0, 3.37, 2), "1.0–3.4");
        assert_eq!(span(0.1, 0.1, 2), "0.10");
    }
}
