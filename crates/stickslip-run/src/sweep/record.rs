//! One record per finished point: `DIR/points/<point>.json`, written atomically. A rerun
//! skips the points that have one; the merge reads them all.

use crate::atomic::write_atomic_recomputable;
use crate::outcome::{RunOutcome, StopReason};
use crate::summary::RunSummary;
use serde::{Deserialize, Serialize};
use std::io;
use std::path::{Path, PathBuf};

/// How a point ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PointStatus {
    /// The run finished.
    Ok,
    /// The numerics failed.
    Failed,
    /// The configuration was refused before the first step.
    Refused,
}

impl PointStatus {
    /// The name as written.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Ok => "ok",
            Self::Failed => "failed",
            Self::Refused => "refused",
        }
    }

    /// The status called `name`.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        [Self::Ok, Self::Failed, Self::Refused]
            .into_iter()
            .find(|s| s.name() == name)
    }
}

/// A finished point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PointRecord {
    /// Point number.
    pub point: usize,
    /// Its axis values.
    pub values: Vec<toml::Value>,
    /// How it ended.
    pub status: PointStatus,
    /// Summary and regime (also of a failed run, up to its failure).
    pub summary: RunSummary,
    /// Wall-clock seconds of the point (resolution, run, record).
    pub wall_s: f64,
    /// Of those, the seconds of the run itself (building the simulation and stepping it).
    #[serde(default)]
    pub run_s: f64,
    /// The failure or refusal, in one line (empty when ok).
    pub message: String,
}

impl PointRecord {
    /// The record of point `point` with `values` from its run's outcome.
    #[must_use]
    pub fn of(
        point: usize,
        values: Vec<toml::Value>,
        outcome: &RunOutcome,
        wall_s: f64,
        run_s: f64,
    ) -> Self {
        let status = match outcome.stop {
            StopReason::Refused => PointStatus::Refused,
            StopReason::Failure => PointStatus::Failed,
            _ => PointStatus::Ok,
        };
        let message = outcome
            .failure
            .as_ref()
            .map(|f| f.to_string().replace(['\n', '\r'], " "))
            .unwrap_or_default();
        Self {
            point,
            values,
            status,
            summary: outcome.summary.clone(),
            wall_s,
            run_s,
            message,
        }
    }

    /// Path of point `point`'s record in the sweep directory `dir`.
    #[must_use]
    pub fn path(dir: &Path, point: usize) -> PathBuf {
        dir.join("points").join(format!("{point:07}.json"))
    }

    /// Writes the record atomically but unsynced ([`write_atomic_recomputable`]): a killed
    /// sweep keeps every record it finished; after a power loss a record may be missing or
    /// damaged, and [`read`](Self::read) then reports the point as not finished, so it is run
    /// again. The fsync this saves cost about 0.4 ms per point here, 8 % of a small point's
    /// run, and more on a cluster's network file system.
    ///
    /// # Errors
    /// If it cannot be written.
    pub fn write(&self, dir: &Path) -> io::Result<()> {
        let points = dir.join("points");
        let text = serde_json::to_string(self).map_err(io::Error::other)?;
        write_atomic_recomputable(&points, &format!("{:07}.json", self.point), text.as_bytes())
    }

    /// Reads point `point`'s record; `None` if there is none, or if the file does not hold a
    /// complete record of this point (cut short or emptied by a power loss while unsynced,
    /// see [`write`](Self::write)): the point is then run again and its record rewritten.
    ///
    /// # Errors
    /// If it exists but cannot be read.
    pub fn read(dir: &Path, point: usize) -> io::Result<Option<Self>> {
        let path = Self::path(dir, point);
        match std::fs::read(&path) {
            Ok(bytes) => Ok(serde_json::from_slice::<Self>(&bytes)
                .ok()
                .filter(|r| r.point == point)),
            Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(None),
            Err(e) => Err(e),
        }
    }
}
