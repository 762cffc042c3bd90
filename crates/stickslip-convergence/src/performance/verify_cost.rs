//! V1–V2: what a number's error costs.
//!
//! - **V1** `stickslip verify` of fig2 at N = [`V1_NODES`] (its default 2 jobs), as a user runs
//!   it, against the finest run it makes — 4N and a hundredth of the tolerance, each run alone
//!   as `stickslip run` — process wall times; verify.json read back through its type for the
//!   levels it ran.
//! - **V2** a [`V2_SIDE`] × [`V2_SIDE`] friction map of the rigid drive (P5's axes and settings,
//!   N = 50) by `stickslip sweep run` with 2 jobs, without and with `[verify] sample = 0.1`
//!   (`boundaries = false`: the sample alone), and once more with the boundary points too,
//!   for information; each variant run `repeats` times (at most 5), interleaved, medians
//!   compared.

use super::BenchSettings;
use super::sweep::run_sweep;
use serde::Serialize;
use stickslip_report::binary;
use stickslip_report::fmt::first_line;
use stickslip_report::stats::median;
use stickslip_run::keys::{contact, time};
use stickslip_studies::sweep::map::MapJson;
use stickslip_studies::verify::VerifyReport;

/// V1: the nodes of the verified scene.
pub const V1_NODES: usize = 200;
/// V1 goal: verify's wall time over its finest run's.
pub const V1_RATIO_GOAL: f64 = 5.0;
/// V2: points per axis.
pub const V2_SIDE: usize = 17;
/// V2: the share of points sampled.
pub const V2_SAMPLE: f64 = 0.1;
/// V2 goal: the map with its spot checks over the map without.
pub const V2_RATIO_GOAL: f64 = 1.3;

/// What V1 and V2 measured.
#[derive(Debug, Clone, Default, Serialize)]
pub struct VerifyCost {
    /// V1: wall time of `stickslip verify`, s.
    pub verify_wall_s: f64,
    /// V1: the levels verify ran: (what, steps, wall s inside verify).
    pub levels: Vec<(String, u64, f64)>,
    /// V1: wall time of the run at 4N alone, s.
    pub finest_space_s: f64,
    /// V1: wall time of the run at a hundredth of the tolerance alone, s.
    pub finest_time_s: f64,
    /// V1: quantities within verify's rtol, of all.
    pub within: (usize, usize),
    /// V2: points of the map.
    pub map_points: usize,
    /// V2: runs of each variant (the wall times are their medians).
    pub repeats: usize,
    /// V2: wall time of the map without spot checks, s.
    pub map_s: f64,
    /// V2: wall time with the sample, s.
    pub map_sampled_s: f64,
    /// V2: points checked with the sample.
    pub sampled_checked: usize,
    /// V2: of those, with another regime at 2N or tolerance/10.
    pub sampled_changed: usize,
    /// V2: wall time with the sample and the boundary points, s.
    pub map_boundaries_s: f64,
    /// V2: points checked then.
    pub boundaries_checked: usize,
    /// V2: of those, with another regime.
    pub boundaries_changed: usize,
}

impl VerifyCost {
    /// V1's ratio: verify over the costlier of its finest runs.
    #[must_use]
    pub fn v1_ratio(&self) -> f64 {
        self.verify_wall_s / self.finest_space_s.max(self.finest_time_s)
    }

    /// V2's ratio: the map with its sample over the map alone.
    #[must_use]
    pub fn v2_ratio(&self) -> f64 {
        self.map_sampled_s / self.map_s
    }
}

/// The V2 sweep file: P5's map at [`V2_SIDE`] × [`V2_SIDE`] points, N = 50, with `verify`
/// appended.
fn map_toml(s: &BenchSettings, verify: &str) -> String {
    super::sweep::sweep_toml(&s.scene.with_file_name("rigid.toml"), V2_SIDE, 50) + verify
}

/// Measures V1 and V2.
///
/// # Errors
/// A process that fails, or outputs that do not read.
pub fn measure(s: &BenchSettings) -> Result<VerifyCost, String> {
    let mut m = VerifyCost::default();
    let nodes = contact::NODES.set(V1_NODES as i64).to_string();
    // V1: verify as a user runs it.
    let out = s.work_dir.join("v1_verify");
    let _ = std::fs::remove_dir_all(&out);
    let args: Vec<String> = vec![
        "verify".into(),
        s.scene.display().to_string(),
        "--set".into(),
        nodes.clone(),
        "--out".into(),
        out.display().to_string(),
    ];
    let inv = binary::invoke(&s.binary, &args, &[])?;
    // Exit 4 (a quantity not within rtol) is a result, not a failure.
    if !matches!(inv.code, Some(0 | 4)) {
        return Err(format!(
            "stickslip verify failed (exit {:?}): {}",
            inv.code,
            first_line(&inv.stderr)
        ));
    }
    m.verify_wall_s = inv.wall_s;
    let text = std::fs::read_to_string(out.join("verify.json"))
        .map_err(|e| format!("{}: {e}", out.display()))?;
    let report: VerifyReport =
        serde_json::from_str(&text).map_err(|e| format!("verify.json: {e}"))?;
    m.levels = report
        .levels
        .iter()
        .map(|l| {
            let what = match l.tolerance {
                Some(t) => format!("N = {}, tolerance {t:e}", l.nodes),
                None => format!("N = {}, dt {:e}", l.nodes, l.dt_s.unwrap_or(f64::NAN)),
            };
            (what, l.steps, l.wall_s)
        })
        .collect();
    m.within = (
        report
            .quantities
            .iter()
            .filter(|q| q.verdict == stickslip_studies::verify::Verdict::Within)
            .count(),
        report.quantities.len(),
    );
    let tolerance = report
        .levels
        .iter()
        .filter_map(|l| l.tolerance)
        .fold(f64::INFINITY, f64::min);
    let finest = |tag: &str, sets: Vec<String>| -> Result<f64, String> {
        let out = s.work_dir.join(tag);
        let run = binary::run_scene(&s.binary, &s.scene, &out, &sets, &[])?;
        if !run.process.ok() {
            return Err(format!(
                "{tag} failed (exit {:?}): {}",
                run.process.code,
                first_line(&run.process.stderr)
            ));
        }
        Ok(run.process.wall_s)
    };
    m.finest_space_s = finest(
        "v1_finest_space",
        vec![contact::NODES.set(4 * V1_NODES as i64).to_string()],
    )?;
    m.finest_time_s = finest(
        "v1_finest_time",
        vec![nodes, time::TOLERANCE.set(tolerance).to_string()],
    )?;
    // V2: the map without and with its spot checks.
    let dir = s.work_dir.join("v2");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let variants = [
        ("plain", String::new()),
        (
            "sampled",
            format!("\n[verify]\nsample = {V2_SAMPLE}\nboundaries = false\n"),
        ),
        (
            "boundaries",
            format!("\n[verify]\nsample = {V2_SAMPLE}\nboundaries = true\n"),
        ),
    ];
    // Each variant `repeats` times, interleaved so that a change of the host's speed falls on
    // all of them alike; the medians are compared.
    let repeats = if s.quick { 1 } else { s.repeats.clamp(1, 5) };
    let mut walls: [Vec<f64>; 3] = Default::default();
    for _ in 0..repeats {
        for (k, (tag, verify)) in variants.iter().enumerate() {
            let file = dir.join(format!("{tag}.toml"));
            std::fs::write(&file, map_toml(s, verify))
                .map_err(|e| format!("{}: {e}", file.display()))?;
            let out = dir.join(tag);
            let inv = run_sweep(s, &file, &out, 2)?;
            walls[k].push(inv.wall_s);
            let json = MapJson::read(&out).map_err(|e| format!("{}: {e}", out.display()))?;
            let counts = json
                .spot_checks
                .as_ref()
                .map_or((0, 0), |r| (r.checked, r.changed));
            match k {
                0 => m.map_points = json.table.rows.len(),
                1 => (m.sampled_checked, m.sampled_changed) = counts,
                _ => (m.boundaries_checked, m.boundaries_changed) = counts,
            }
        }
    }
    m.repeats = repeats;
    m.map_s = median(&walls[0]);
    m.map_sampled_s = median(&walls[1]);
    m.map_boundaries_s = median(&walls[2]);
    Ok(m)
}
