//! The records of a sweep's spot checks (`[verify]`, run by [`super::spot`]): one per checked
//! point, `DIR/checks/<point>.json`, written atomically with the sweep's fingerprint and read
//! back as current only for this sweep, this build and the point's values; and what the
//! checks found, map.json's `spot_checks`. Writer and reader together.

use super::record::PointStatus;
use serde::{Deserialize, Serialize};
use std::io;
use std::path::{Path, PathBuf};
use stickslip_run::atomic::write_atomic_recomputable;
use stickslip_run::layout::sweep::CHECKS_DIR;
use stickslip_run::summary::RunSummary;

/// `[verify]` as resolved.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SpotChecks {
    /// Share of the map's points sampled (0 < f ≤ 1), when given.
    pub sample: Option<f64>,
    /// Number of points sampled, when given instead.
    pub points: Option<usize>,
    /// Also every point next to a regime boundary.
    pub boundaries: bool,
}

/// Why a point is checked.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Reason {
    /// Drawn in the sample.
    Sample,
    /// Next to a regime boundary.
    Boundary,
    /// Both.
    Both,
}

/// One refined rerun of a checked point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CheckRun {
    /// `"2N"` or `"tolerance/10"` (`"dt/2"` with fixed steps).
    pub refinement: String,
    /// How it ended.
    pub status: PointStatus,
    /// Its summary.
    pub summary: RunSummary,
    /// The largest relative change of a summary number against the point's own run (over
    /// the numbers both runs have), and its column.
    pub max_change: Option<(String, f64)>,
    /// Wall-clock seconds.
    pub wall_s: f64,
}

/// A checked point: `DIR/checks/<point>.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CheckRecord {
    /// Point number.
    pub point: usize,
    /// Its axis values.
    pub values: Vec<toml::Value>,
    /// The sweep's fingerprint (definition and build).
    pub fingerprint: String,
    /// Why it was checked.
    pub reason: Reason,
    /// The regime at the map's resolution.
    pub regime: String,
    /// The refined reruns.
    pub runs: Vec<CheckRun>,
    /// Whether a rerun's regime (or status) differs from the map's.
    pub changed: bool,
}

impl CheckRecord {
    fn path(dir: &Path, point: usize) -> PathBuf {
        dir.join(CHECKS_DIR).join(format!("{point:07}.json"))
    }

    /// This point's record if it is current (this sweep, this build, these values).
    pub(super) fn current(
        dir: &Path,
        point: usize,
        values: &[toml::Value],
        fingerprint: &str,
    ) -> Option<Self> {
        let bytes = stickslip_run::bounded::read(
            &Self::path(dir, point),
            stickslip_run::bounded::CHECK_RECORD,
        )
        .ok()?;
        serde_json::from_slice::<Self>(&bytes)
            .ok()
            .filter(|r| r.point == point && r.fingerprint == fingerprint && r.values == values)
    }

    pub(super) fn write(&self, dir: &Path) -> io::Result<()> {
        let text = serde_json::to_string(self).map_err(io::Error::other)?;
        write_atomic_recomputable(
            &dir.join(CHECKS_DIR),
            &format!("{:07}.json", self.point),
            text.as_bytes(),
        )
    }
}

/// What the spot checks found: map.json's `spot_checks`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpotReport {
    /// `[verify]` as resolved.
    pub config: SpotChecks,
    /// Points checked.
    pub checked: usize,
    /// Of those, drawn in the sample (boundary points also sampled included).
    pub sampled: usize,
    /// Of those, next to a regime boundary.
    pub at_boundaries: usize,
    /// Points whose regime changed at a refined resolution.
    pub changed: usize,
    /// The largest relative change of a summary number over the checks whose regime held,
    /// its column and point.
    pub max_change: Option<(String, f64, usize)>,
    /// Every check.
    pub checks: Vec<CheckRecord>,
    /// Seconds the checks took in this process (those found done cost none).
    pub wall_s: f64,
    /// Checks found done by an earlier process.
    pub skipped: usize,
}

impl SpotReport {
    /// The points whose regime changed.
    #[must_use]
    pub fn changed_points(&self) -> Vec<usize> {
        self.checks
            .iter()
            .filter(|c| c.changed)
            .map(|c| c.point)
            .collect()
    }
}
