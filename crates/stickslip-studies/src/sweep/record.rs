//! One record per finished point: `DIR/points/<point>.json`, written atomically, carrying
//! the sweep's fingerprint (its definition and the build that computed it) and the point's
//! values. A rerun skips the points whose record is this sweep's and this build's
//! ([`Found::Current`]), recomputes those of another build or damaged ones, and refuses a
//! record of another sweep ([`Found::OtherSweep`]); so does the merge.

use serde::{Deserialize, Serialize};
use std::io;
use std::path::{Path, PathBuf};
use stickslip_run::atomic::write_atomic_recomputable;
use stickslip_run::outcome::{RunOutcome, StopReason};
use stickslip_run::summary::{Regime, RunSummary};

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
    /// The sweep's fingerprint ([`super::Sweep::fingerprint`]: definition and build) when the
    /// point was computed; empty in records of earlier versions.
    #[serde(default)]
    pub fingerprint: String,
    /// The point's level in a refined sweep (0: the base grid, and every point of a sweep
    /// without `[refine]`; not written then).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub level: usize,
}

#[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
fn is_zero(n: &usize) -> bool {
    *n == 0
}

/// What the record file of a point holds, checked against the sweep.
#[derive(Debug, Clone, PartialEq)]
pub enum Found {
    /// No record.
    Missing,
    /// A file that is not a complete record of this point (cut short or emptied by a power
    /// loss): the point runs again.
    Damaged,
    /// A record of this sweep by this build.
    Current(Box<PointRecord>),
    /// A record of this sweep computed by another build (or by a version before records
    /// carried the build): the point runs again.
    OtherBuild {
        /// That build's identity (`an earlier version` when the record does not say).
        build: String,
    },
    /// A record of another sweep: its fingerprint or its values are not this sweep's.
    OtherSweep {
        /// Why, in words (the fingerprints or values that differ).
        why: String,
    },
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
            fingerprint: String::new(),
            level: 0,
        }
    }

    /// The record of point `point` whose scene does not resolve (a sweep too large to validate
    /// every point before it runs): `refused`, with the scene's error as the message.
    #[must_use]
    pub fn refused(point: usize, values: Vec<toml::Value>, message: &str, wall_s: f64) -> Self {
        Self {
            point,
            values,
            status: PointStatus::Refused,
            summary: RunSummary::without_numbers(Regime::NoMelting),
            wall_s,
            run_s: 0.0,
            message: message.replace(['\n', '\r'], " "),
            fingerprint: String::new(),
            level: 0,
        }
    }

    /// Checks the record against the sweep whose fingerprint is `fingerprint` and whose point
    /// `point` has `values`.
    #[must_use]
    pub fn check(self, point: usize, values: &[toml::Value], fingerprint: &str) -> Found {
        if self.point != point {
            return Found::Damaged;
        }
        let (definition, _) = super::split_fingerprint(fingerprint).unwrap_or((fingerprint, ""));
        let values_differ = self.values != values;
        let shown = |v: &[toml::Value]| {
            v.iter()
                .map(super::value_text)
                .collect::<Vec<_>>()
                .join(", ")
        };
        if self.fingerprint == fingerprint && !values_differ {
            return Found::Current(Box::new(self));
        }
        match super::split_fingerprint(&self.fingerprint) {
            Some((d, build)) if d == definition && !values_differ => Found::OtherBuild {
                build: build.to_string(),
            },
            None if self.fingerprint.is_empty() && !values_differ => Found::OtherBuild {
                build: "an earlier version".to_string(),
            },
            _ if values_differ => Found::OtherSweep {
                why: format!(
                    "its values ({}) are not this sweep's point {point} ({})",
                    shown(&self.values),
                    shown(values)
                ),
            },
            _ => Found::OtherSweep {
                why: format!(
                    "its sweep fingerprint {} is not this sweep's {definition}",
                    super::split_fingerprint(&self.fingerprint)
                        .map_or(self.fingerprint.as_str(), |(d, _)| d)
                ),
            },
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

    /// Reads point `point`'s record, unchecked against a sweep (see [`Self::find`]); `None` if
    /// there is none, or if the file does not hold a complete record of this point (cut short
    /// or emptied by a power loss while unsynced, see [`write`](Self::write)): the point is
    /// then run again and its record rewritten.
    ///
    /// # Errors
    /// If it exists but cannot be read.
    pub fn read(dir: &Path, point: usize) -> io::Result<Option<Self>> {
        let path = Self::path(dir, point);
        match stickslip_run::bounded::read(&path, stickslip_run::bounded::POINT_RECORD) {
            Ok(bytes) => Ok(serde_json::from_slice::<Self>(&bytes)
                .ok()
                .filter(|r| r.point == point)),
            // Not a record this program wrote: run the point again and rewrite it.
            Err(e) if e.kind() == io::ErrorKind::InvalidData => Ok(None),
            Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(None),
            Err(e) => Err(e),
        }
    }

    /// Reads point `point`'s record and checks it against the sweep of `fingerprint` whose
    /// point has `values` ([`PointRecord::check`]).
    ///
    /// # Errors
    /// If it exists but cannot be read.
    pub fn find(
        dir: &Path,
        point: usize,
        values: &[toml::Value],
        fingerprint: &str,
    ) -> io::Result<Found> {
        let path = Self::path(dir, point);
        match stickslip_run::bounded::read(&path, stickslip_run::bounded::POINT_RECORD) {
            Ok(bytes) => Ok(match serde_json::from_slice::<Self>(&bytes) {
                Ok(r) => r.check(point, values, fingerprint),
                Err(_) => Found::Damaged,
            }),
            Err(e) if e.kind() == io::ErrorKind::InvalidData => Ok(Found::Damaged),
            Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(Found::Missing),
            Err(e) => Err(e),
        }
    }
}

/// The point numbers of the record files in `DIR/points/` (names only, nothing read), sorted:
/// one listing instead of a look-up per point.
///
/// # Errors
/// If the directory exists but cannot be listed.
pub fn listed(dir: &Path) -> io::Result<Vec<usize>> {
    let entries = match std::fs::read_dir(dir.join("points")) {
        Ok(e) => e,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(e),
    };
    let mut out = Vec::new();
    for entry in entries {
        let name = entry?.file_name();
        let name = name.to_string_lossy();
        if let Some(n) = name.strip_suffix(".json")
            && !n.starts_with('.')
            && let Ok(p) = n.parse::<usize>()
        {
            out.push(p);
        }
    }
    out.sort_unstable();
    Ok(out)
}
