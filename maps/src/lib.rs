//! stickslip-maps: the showcase friction maps of `maps/*.toml`, run in-process through the run
//! library's sweep engine, drawn with the reporting kit, and checked against what physics says they
//! must show (docs/model.md#regimes-and-friction-maps). `cargo xtask maps` writes `reports/maps.md`
//! and `reports/maps_*.svg`.
//!
//! - [`rigid`]: rigid drive, speed × temperature (A0): sliding for A0 ≤ 0, stick–slip at slow
//!   speed, the loss of recovery at high speed, the critical speed on paper against the map;
//! - [`spring`]: spring stiffness × drive speed at the fig2 parameters: equal K·V0/m, equal
//!   results while time.end ≪ 2π/ω, and where that stops;
//! - [`model`]: film thickness × substrate modulus, radial against homogeneous model;
//! - [`model_first_order`]: the same for the first-order film, cell by cell against the
//!   second-order film's map (the paper's contrast);
//! - [`rigid_first_order`]: the first-order film under the rigid drive, melting strain × speed:
//!   the advance per cycle on paper, the fold's delay, the abrupt loss of recovery;
//! - [`steady`]: the rigid drive's regimes on the steady state (`time.until = "periodic"`), in a
//!   window and in one twice as long;
//! - [`viscous`]: the h0 = 1 nm contact's spring stiffness × film viscosity: where the stamp's
//!   slips stop, the kinetic friction against the Couette force, and the critical speed of the
//!   spring drive at two stiffnesses (`boundary` on the stamp's scale).
//!
//! Invariant: every number in the report's prose is computed from the maps it describes;
//! nothing here steps a simulation (the sweep engine does).

pub mod deeper;
pub mod model;
pub mod model_first_order;
pub mod rigid;
pub mod rigid_first_order;
pub mod spring;
pub mod steady;
pub mod viscous;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use stickslip_report::plot::{Panel, render_svg};
use stickslip_studies::sweep::exec::{self, Merge, SweepOptions};
use stickslip_studies::sweep::map::{MapJson, MapRow};
use stickslip_studies::sweep::{Sweep, value_number};

/// A check of a map: what physics says, the measured value, the verdict.
#[derive(Debug, Clone, PartialEq)]
pub struct Check {
    /// What must hold.
    pub claim: String,
    /// What was measured.
    pub measured: String,
    /// Whether it holds.
    pub pass: bool,
}

/// One map's section of the report.
#[derive(Debug, Clone)]
pub struct Section {
    /// Heading.
    pub title: String,
    /// What the map is and what to see in it (computed prose).
    pub text: String,
    /// SVG file name in reports/ and its panels.
    pub figure: (String, Vec<Panel>),
    /// The checks.
    pub checks: Vec<Check>,
}

/// A finished map: the sweep and its table.
#[derive(Debug, Clone)]
pub struct Map {
    /// The resolved sweep with its table (and its spot checks, `[verify]`).
    pub json: MapJson,
    /// Wall-clock seconds of this process's run of the points (0 when all were done).
    pub points_wall_s: f64,
    /// The spot checks whose regime changed, followed to 4N.
    pub deeper: Vec<deeper::Deeper>,
}

impl Map {
    /// The value of axis `key` in `row`, as a number.
    #[must_use]
    pub fn axis(&self, row: &MapRow, key: &str) -> f64 {
        let i = self
            .json
            .sweep
            .axes
            .iter()
            .position(|a| a.key == key)
            .unwrap_or(usize::MAX);
        row.values
            .get(i)
            .and_then(|v| v.parse::<f64>().ok())
            .unwrap_or(f64::NAN)
    }

    /// The word of axis `key` in `row`.
    #[must_use]
    pub fn word<'a>(&self, row: &'a MapRow, key: &str) -> &'a str {
        let i = self
            .json
            .sweep
            .axes
            .iter()
            .position(|a| a.key == key)
            .unwrap_or(usize::MAX);
        row.values.get(i).map_or("", String::as_str)
    }

    /// The file name of the sweep's base scene (for the report's prose).
    #[must_use]
    pub fn scene_file(&self) -> String {
        self.json
            .sweep
            .scene_path
            .file_name()
            .map_or(String::new(), |n| n.to_string_lossy().into_owned())
    }

    /// The sorted distinct numeric values of axis `key`.
    #[must_use]
    pub fn values(&self, key: &str) -> Vec<f64> {
        self.json
            .sweep
            .axes
            .iter()
            .find(|a| a.key == key)
            .map(|a| a.values.iter().map(value_number).collect())
            .unwrap_or_default()
    }

    /// The resolved scene of point 0 (the base scene with the axes' first values).
    ///
    /// # Errors
    /// If the scene does not resolve (it did when the sweep ran).
    pub fn base_scene(&self) -> Result<stickslip_run::ResolvedScene, String> {
        self.json.sweep.scene(0).map_err(|e| e.to_string())
    }

    /// The base scene with `[set]` applied and no axis value (its own values of the swept
    /// keys).
    ///
    /// # Errors
    /// If the scene does not resolve.
    pub fn unswept_scene(&self) -> Result<stickslip_run::ResolvedScene, String> {
        stickslip_run::Scene::resolve_table(self.json.sweep.base.clone(), &[] as &[&str])
            .map_err(|e| e.to_string())
    }
}

/// Runs (or finishes) the sweep in `file` into `dir` on `jobs` threads and merges it.
///
/// # Errors
/// A bad sweep file, a failed merge, or I/O errors, as text.
pub fn run_map(file: &Path, dir: &Path, jobs: usize, resume: bool) -> Result<Map, String> {
    let sweep = Sweep::load(file, false).map_err(|e| e.to_string())?;
    // Afresh unless asked to resume; a resumed map recomputes the points another build left
    // behind (the sweep's fingerprint holds the build identity of the numerics).
    exec::prepare(&sweep, dir, !resume).map_err(|e| e.to_string())?;
    let options = SweepOptions {
        jobs,
        ..SweepOptions::default()
    };
    let report =
        exec::run_shard(&sweep, dir, &options, None, &mut |_| {}).map_err(|e| e.to_string())?;
    println!(
        "maps: {}: {} points run, {} already done, {:.1} s",
        sweep.name, report.ran, report.skipped, report.wall_s
    );
    // A refined sweep's shard writes the map itself once every level is complete.
    let merge = match report.map {
        Some(m) => m,
        None => exec::after_shard(dir, &sweep.fingerprint(), options.shard)
            .map_err(|e| e.to_string())?,
    };
    if let Merge::Incomplete { missing, .. } = merge {
        return Err(format!("{}: {missing} points missing", sweep.name));
    }
    if let Some(spot) = &sweep.verify {
        let checks = stickslip_studies::sweep::spot::run_checks(
            &sweep,
            spot,
            dir,
            jobs,
            None,
            &mut |_, _| {},
        )
        .map_err(|e| e.to_string())?
        .ok_or_else(|| format!("{}: spot checks interrupted", sweep.name))?;
        println!(
            "maps: {}: {} spot checks ({} found done), {} changed regime, {:.1} s",
            sweep.name, checks.checked, checks.skipped, checks.changed, checks.wall_s
        );
    }
    let json = MapJson::read(dir).map_err(|e| e.to_string())?;
    let deeper = deeper::rerun(&sweep, &json)?;
    if !deeper.is_empty() {
        println!(
            "maps: {}: {} changed points rerun at {}N, {} settled",
            sweep.name,
            deeper.len(),
            deeper::FACTOR,
            deeper.iter().filter(|d| d.settled()).count()
        );
    }
    Ok(Map {
        json,
        points_wall_s: report.wall_s,
        deeper,
    })
}

/// The spot checks' table of the report: per map, the points checked, those whose regime
/// changed at 2N or at a tenth of the tolerance, the largest change of a number, and the
/// checks' cost against the map's (both as run by this process).
fn spot_checks_markdown(maps: &[(&str, &Map)]) -> String {
    let mut out = String::from(
        "\n## Spot checks\n\nEach map's `[verify]` reruns some of its points once it is complete, at \
         twice the nodes and at a tenth of the time tolerance (docs/reference.md, Spot checks): \
         an even sample in point order, and for maps without refinement every point next to a \
         regime boundary too (a refined map's boundary points are most of its points). A \
         regime that changes there is not converged at the map's resolution.\n\n\
         | map | checked (sampled, at boundaries) | regime changed | largest change of a number where the regime held | \
         checks' cost / map's |\n|---|---|---|---|---|\n",
    );
    for (title, m) in maps {
        let Some(r) = &m.json.spot_checks else {
            continue;
        };
        let changed = r.changed_points();
        let changed_text = if changed.is_empty() {
            "none".to_string()
        } else {
            let regimes: Vec<String> = r
                .checks
                .iter()
                .filter(|c| c.changed)
                .take(6)
                .map(|c| {
                    let to: Vec<&str> = c.runs.iter().map(|x| x.summary.regime.name()).collect();
                    format!("point {} {} → {}", c.point, c.regime, to.join("/"))
                })
                .collect();
            format!(
                "{} ({:.1} %): {}{}",
                changed.len(),
                100.0 * changed.len() as f64 / r.checked.max(1) as f64,
                regimes.join("; "),
                if changed.len() > 6 { "; …" } else { "" }
            )
        };
        let largest = r.max_change.as_ref().map_or("–".to_string(), |(c, v, p)| {
            format!("{:.2} % ({c}, point {p})", 100.0 * v)
        });
        let cost = if m.points_wall_s > 0.0 && r.skipped == 0 {
            format!("{:.2}", r.wall_s / m.points_wall_s)
        } else {
            "– (resumed)".to_string()
        };
        let _ = writeln!(
            out,
            "| {title} | {} ({}, {}) | {changed_text} | {largest} | {cost} |",
            r.checked, r.sampled, r.at_boundaries
        );
    }
    out.push_str(&spot_checks_discussion(maps));
    out
}

/// What the spot checks' changes mean, map by map: each changed point followed to 4N, and
/// the point whose numbers moved most where the regime held, with its regimes (a number of a
/// regime without it, such as the period of a film in steady sliding, may move freely).
fn spot_checks_discussion(maps: &[(&str, &Map)]) -> String {
    let mut out = format!(
        "\nEvery point whose regime changed in the spot checks is run again at {}N and a tenth \
         of the tolerance. Where that run agrees with the refined regime (2N's or the tenth \
         tolerance's, whichever changed), the map's regime at the point is a resolution \
         artefact of its N or its tolerance (a point next to a boundary, where the boundary \
         moves by less than a cell); where it does not, the point is unconverged, and the \
         verdicts of its map say so.\n\n",
        deeper::FACTOR
    );
    for (title, m) in maps {
        let Some(r) = &m.json.spot_checks else {
            continue;
        };
        let mut parts = Vec::new();
        if !m.deeper.is_empty() {
            parts.push(deeper::sentence(&m.deeper));
        }
        if let Some((column, v, p)) = &r.max_change {
            let regimes =
                m.json
                    .table
                    .rows
                    .iter()
                    .find(|row| row.point == *p)
                    .map_or(String::new(), |row| {
                        format!(
                            " (its regime {}, stamp regime {})",
                            row.summary.regime.name(),
                            row.summary
                                .stamp_regime
                                .map_or("–", stickslip_run::cycles::StampRegime::name)
                        )
                    });
            parts.push(format!(
                "where the regime held, `{column}` moved most, by {:.2} % at point {p}{regimes}",
                100.0 * v
            ));
        }
        if !parts.is_empty() {
            let _ = writeln!(out, "- **{title}**: {}.", parts.join("; "));
        }
    }
    out
}

/// What `cargo xtask maps` does.
#[derive(Debug, Clone)]
pub struct Options {
    /// Workspace root.
    pub root: PathBuf,
    /// Points run in parallel.
    pub jobs: usize,
    /// Keep the points an earlier, interrupted `cargo xtask maps` finished (else start afresh).
    pub resume: bool,
}

fn verdict(pass: bool) -> &'static str {
    if pass { "**pass**" } else { "**FAIL**" }
}

/// The report's Markdown.
fn markdown(sections: &[Section], spot: &str, notes: &[Option<String>]) -> String {
    let mut out = format!(
        "# Friction maps\n\n{}\n\n",
        stickslip_report::provenance::sentence(
            stickslip_report::provenance::Commit::of_workspace().as_ref()
        )
    );
    out.push_str(
        "Generated by `cargo xtask maps` from the sweeps in `maps/*.toml`: \
         each point is one in-process run of the driver, reduced to its summary and regime \
         (the rules: [docs/model.md](../docs/model.md#regimes-and-friction-maps) and \
         [docs/reference.md](../docs/reference.md#regimes)). Each map has a \
         regime panel (colours) and a panel of one continuous quantity; failed or refused \
         points would be marked with crosses (there are none unless a check says so). The \
         sweep directories are under `target/maps/`; `stickslip sweep plot DIR --quantity Q` \
         redraws any quantity.\n\n## Checks\n\n| map | what physics says | measured | verdict |\n\
         |---|---|---|---|\n",
    );
    for (s, note) in sections
        .iter()
        .zip(notes.iter().chain(std::iter::repeat(&None)))
    {
        for c in &s.checks {
            let _ = writeln!(
                out,
                "| {} | {} | {} | {}{} |",
                s.title,
                c.claim,
                c.measured,
                verdict(c.pass),
                note.as_deref().unwrap_or("")
            );
        }
    }
    out.push_str(spot);
    for s in sections {
        let _ = write!(
            out,
            "\n## {}\n\n![{}]({})\n\n{}\n",
            s.title, s.title, s.figure.0, s.text
        );
    }
    out
}

/// Runs every showcase map, writes its SVG and `reports/maps.md`; `Ok(true)` when every
/// check passes.
///
/// # Errors
/// A map that cannot run or a file that cannot be written, as text.
pub fn run(opts: &Options) -> Result<bool, String> {
    let maps_dir = opts.root.join("maps");
    let out = opts.root.join("target").join("maps");
    let reports = opts.root.join("reports");
    // maps/NAME.toml into target/maps/NAME.
    let showcase = |name: &str| {
        run_map(
            &maps_dir.join(format!("{name}.toml")),
            &out.join(name),
            opts.jobs,
            opts.resume,
        )
    };
    let rigid_map = showcase("rigid")?;
    let window = out.join("rigid_uniform_window");
    std::fs::create_dir_all(&window).map_err(|e| format!("{}: {e}", window.display()))?;
    let window_file = window.join("sweep.toml");
    let window_toml = rigid::uniform_window(&rigid_map, &maps_dir.join("rigid.toml"))?;
    std::fs::write(&window_file, window_toml)
        .map_err(|e| format!("{}: {e}", window_file.display()))?;
    let uniform_map = run_map(&window_file, &window.join("sweep"), opts.jobs, opts.resume)?;
    let spring_map = showcase("spring")?;
    let model_map = showcase("model")?;
    let model_fo_map = showcase("model_first_order")?;
    let rigid_fo_map = showcase("rigid_first_order")?;
    let steady_map = showcase("rigid_steady")?;
    let viscous_map = showcase("viscous")?;
    let sections = vec![
        rigid::section(&rigid_map, &uniform_map)?,
        spring::section(&spring_map)?,
        model::section(&model_map)?,
        model_first_order::section(&model_fo_map, &model_map)?,
        rigid_first_order::section(&rigid_fo_map)?,
        steady::section(&steady_map)?,
        viscous::section(&viscous_map, opts.jobs)?,
    ];
    let mut files = stickslip_report::files::ReportFiles::create(&reports)?;
    for s in &sections {
        let cols = 2;
        let svg = render_svg(
            &s.figure.1,
            cols,
            stickslip_report::map::PANEL_PX.0,
            stickslip_report::map::PANEL_PX.1,
        )?;
        files.put(&s.figure.0, svg)?;
    }
    let maps = [
        &rigid_map,
        &spring_map,
        &model_map,
        &model_fo_map,
        &rigid_fo_map,
        &steady_map,
        &viscous_map,
    ];
    let titled: Vec<(&str, &Map)> = sections
        .iter()
        .map(|s| s.title.as_str())
        .zip(maps)
        .collect();
    let notes: Vec<Option<String>> = maps
        .iter()
        .map(|m| deeper::verdict_note(&m.deeper))
        .collect();
    let md = markdown(&sections, &spot_checks_markdown(&titled), &notes);
    files.put("maps.md", md)?;
    let all = sections.iter().flat_map(|s| &s.checks).all(|c| c.pass);
    for s in &sections {
        for c in &s.checks {
            println!(
                "{} {}: {}",
                if c.pass { "pass" } else { "FAIL" },
                s.title,
                c.measured
            );
        }
    }
    println!("maps: wrote {}", reports.join("maps.md").display());
    Ok(all)
}
