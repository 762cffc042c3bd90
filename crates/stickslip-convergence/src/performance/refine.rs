//! M1–M2: phase diagrams without brute force.
//!
//! - **M1** the rigid drive's speed × temperature map (maps/rigid.toml's ranges and settings, N =
//!   50) refined to the resolution of a 257 × 257 grid (a 17 × 17 base, 4 levels of `[refine]`)
//!   by `stickslip sweep run`: its points against the uniform grid's 66049, and every 4th value
//!   of that grid along each axis (a 65 × 65 uniform sweep, run too) compared point by point
//!   with the refined map through the run library's `refine::agreement`: where both ran a point,
//!   and where the refined map answers by the cell that holds it.
//! - **M2** the critical speed of the same scene at A0 = [`M2_A0_PA`] by the run library's
//!   `boundary` (what `stickslip boundary` runs), bisected to [`M2_RTOL`]: the runs it takes.

use super::BenchSettings;
use serde::Serialize;
use std::path::Path;
use std::time::Instant;
use stickslip_run::Scene;
use stickslip_run::keys::{Setting, contact, time};
use stickslip_studies::sweep::map::MapJson;
use stickslip_studies::sweep::refine::agreement;

/// M1 goal: the refined map's points as a fraction of the uniform grid's.
pub const M1_FRACTION_GOAL: f64 = 0.10;
/// M1: base values per axis and levels (finest grid (17 − 1)·2⁴ + 1 = 257 per axis).
pub const M1_BASE: usize = 17;
/// M1: levels of refinement.
pub const M1_LEVELS: u32 = 4;
/// M1: the uniform sample takes every this-many-th finest value per axis.
pub const M1_SAMPLE_STRIDE: usize = 4;
/// M2 goal: most runs.
pub const M2_RUNS_GOAL: usize = 20;
/// M2: relative tolerance.
pub const M2_RTOL: f64 = 1e-3;
/// M2: the temperature of the search, Pa.
pub const M2_A0_PA: f64 = 1e6;

/// The sweep settings shared by M1's sweeps and M2's scene (maps/rigid.toml's `[set]`).
fn shared_settings() -> [Setting; 4] {
    [
        contact::NODES.set(50),
        time::END.set(2e-3),
        time::MAX_EVENTS.set(6),
        time::MAX_OPEN_EVENT.set(2e-5),
    ]
}

/// What M1 and M2 measured.
#[derive(Debug, Clone, Default, Serialize)]
pub struct RefineBench {
    /// Levels of refinement run.
    pub levels: u32,
    /// Points of the finest (uniform) grid.
    pub uniform_points: usize,
    /// Points the refined map ran.
    pub refined_points: usize,
    /// Wall time of the refined sweep (2 jobs), s.
    pub refined_wall_s: f64,
    /// Points of the uniform sample.
    pub sample_points: usize,
    /// Wall time of the uniform sample (2 jobs), s.
    pub sample_wall_s: f64,
    /// Sample points the refined map ran too.
    pub shared: usize,
    /// Of those, with another regime.
    pub shared_differ: usize,
    /// Sample points inside refined cells.
    pub inferred: usize,
    /// Of those, with another regime.
    pub inferred_differ: usize,
    /// Sample points off the finest grid (0 unless the comparison is broken).
    pub off_grid: usize,
    /// M2: the critical speed, m/s.
    pub critical_speed: f64,
    /// M2: the final bracket's relative width.
    pub bracket_rel: f64,
    /// M2: runs taken.
    pub boundary_runs: usize,
    /// M2: the regimes either side.
    pub boundary_regimes: (String, String),
    /// M2: wall time, s.
    pub boundary_wall_s: f64,
}

impl RefineBench {
    /// The refined points as a fraction of the uniform grid's.
    #[must_use]
    pub fn fraction(&self) -> f64 {
        self.refined_points as f64 / self.uniform_points.max(1) as f64
    }
}

/// A sweep file over the rigid drive's ranges: `axes` as TOML tables, `refine` appended.
fn sweep_toml(scene: &Path, name: &str, axes: &[toml::Table], refine: Option<u32>) -> String {
    let mut t = toml::Table::new();
    t.insert("name".into(), name.into());
    t.insert("scene".into(), scene.display().to_string().into());
    let mut set = toml::Table::new();
    for setting in shared_settings() {
        set.insert(setting.path.into(), setting.value);
    }
    set.insert(
        "output.profile_times".into(),
        toml::Value::Array(vec![toml::Value::Float(2e-3)]),
    );
    t.insert("set".into(), toml::Value::Table(set));
    t.insert(
        "axis".into(),
        toml::Value::Array(axes.iter().cloned().map(toml::Value::Table).collect()),
    );
    if let Some(levels) = refine {
        let mut r = toml::Table::new();
        r.insert("levels".into(), i64::from(levels).into());
        r.insert("on".into(), "regime".into());
        t.insert("refine".into(), toml::Value::Table(r));
    }
    toml::to_string(&t).unwrap_or_default()
}

/// A range axis.
fn range_axis(key: &str, from: f64, to: f64, count: usize, scale: &str) -> toml::Table {
    let mut r = toml::Table::new();
    r.insert("from".into(), from.into());
    r.insert("to".into(), to.into());
    r.insert("count".into(), i64::try_from(count).unwrap_or(0).into());
    r.insert("scale".into(), scale.into());
    let mut a = toml::Table::new();
    a.insert("key".into(), key.into());
    a.insert("range".into(), toml::Value::Table(r));
    a
}

/// Runs `file` with `stickslip sweep run --jobs 2` into `out` (afresh) and reads its map.
fn run_sweep(s: &BenchSettings, file: &Path, out: &Path) -> Result<(MapJson, f64), String> {
    let inv = super::sweep::run_sweep(s, file, out, 2)?;
    let json = MapJson::read(out).map_err(|e| format!("{}: {e}", out.display()))?;
    Ok((json, inv.wall_s))
}

/// Runs M1 and M2.
///
/// # Errors
/// A sweep or a search that could not run.
pub fn measure(s: &BenchSettings, rigid_scene: &Path) -> Result<RefineBench, String> {
    let (base, levels) = if s.quick {
        (5, 2)
    } else {
        (M1_BASE, M1_LEVELS)
    };
    let dir = s.work_dir.join("refine");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let axes = [
        range_axis("drive.velocity", 1e-3, 3.0, base, "log"),
        range_axis("temperature.A0", -3e5, 1.5e6, base, "linear"),
    ];
    let refined_file = dir.join("refined.toml");
    std::fs::write(
        &refined_file,
        sweep_toml(rigid_scene, "bench-refined", &axes, Some(levels)),
    )
    .map_err(|e| format!("{}: {e}", refined_file.display()))?;
    let (refined, refined_wall_s) = run_sweep(s, &refined_file, &dir.join("refined"))?;
    let sweep = &refined.sweep;
    let refine = sweep
        .refine
        .as_ref()
        .ok_or("the refined sweep has no [refine]")?;
    // The uniform sample: every M1_SAMPLE_STRIDE-th finest value, listed exactly.
    let sample_axes = agreement::subgrid_axes(sweep, M1_SAMPLE_STRIDE, &[]);
    let sample_file = dir.join("sample.toml");
    std::fs::write(
        &sample_file,
        sweep_toml(rigid_scene, "bench-uniform-sample", &sample_axes, None),
    )
    .map_err(|e| format!("{}: {e}", sample_file.display()))?;
    let (sample, sample_wall_s) = run_sweep(s, &sample_file, &dir.join("sample"))?;
    let a = agreement::agreement(
        sweep,
        refine,
        &refined.table.rows,
        &sample.sweep,
        &sample.table.rows,
    );

    // M2: the critical speed by bisection.
    let mut sets: Vec<String> = shared_settings().iter().map(ToString::to_string).collect();
    sets.push(
        stickslip_run::keys::temperature::A0
            .set(M2_A0_PA)
            .to_string(),
    );
    let scene = Scene::from_path(rigid_scene, &sets)
        .map_err(|e| format!("{}: {e}", rigid_scene.display()))?;
    let start = Instant::now();
    let b = stickslip_studies::boundary::find(
        &scene,
        "drive.velocity",
        (1e-3, 3.0),
        M2_RTOL,
        stickslip_run::summary::RegimeThresholds::default(),
        None,
        &mut |_| {},
    )
    .map_err(|e| e.to_string())?;
    let boundary_wall_s = start.elapsed().as_secs_f64();
    Ok(RefineBench {
        levels,
        uniform_points: sweep.points,
        refined_points: refined.table.rows.len(),
        refined_wall_s,
        sample_points: sample.table.rows.len(),
        sample_wall_s,
        shared: a.shared,
        shared_differ: a.shared_differ.len(),
        inferred: a.inferred,
        inferred_differ: a.inferred_differ.len(),
        off_grid: a.off_grid,
        critical_speed: b.value,
        bracket_rel: (b.above.value - b.below.value).abs() / b.value,
        boundary_runs: b.runs,
        boundary_regimes: (b.below.regime.name().into(), b.above.regime.name().into()),
        boundary_wall_s,
    })
}
