//! The sweep file (SWEEP.toml) as written, and the errors of a bad one (each naming the key,
//! the value and what is allowed).

use crate::scene::SceneError;
use crate::summary::RegimeThresholds;
use serde::Deserialize;
use thiserror::Error;

/// SWEEP.toml as written (see INTERFACE.md): every field optional here, checked on
/// resolution.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepFile {
    /// Name of the sweep.
    pub name: Option<String>,
    /// Base scene, relative to the sweep file.
    pub scene: Option<String>,
    /// Values applied to every point, like `--set`.
    #[serde(default)]
    pub set: toml::Table,
    /// The axes; points are their cartesian product, the last axis fastest.
    #[serde(default)]
    pub axis: Vec<AxisFile>,
    /// Regime thresholds (SPEC §6).
    pub regime: Option<RegimeThresholds>,
}

/// One `[[axis]]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxisFile {
    /// A scene key.
    pub key: Option<String>,
    /// Explicit values (numbers, or words for a choice key).
    pub values: Option<Vec<toml::Value>>,
    /// Or a range.
    pub range: Option<RangeFile>,
}

/// `range = { from, to, count, scale }`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RangeFile {
    /// First value.
    pub from: f64,
    /// Last value.
    pub to: f64,
    /// Number of values (≥ 1).
    pub count: i64,
    /// `"linear"` (default) or `"log"`.
    pub scale: Option<String>,
}

/// A bad sweep (exit status 2): nothing is written.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SweepError {
    /// The file cannot be read or parsed.
    #[error("cannot read sweep file {path}: {message}")]
    Read {
        /// The path.
        path: String,
        /// What went wrong.
        message: String,
    },
    /// A value of the sweep file itself.
    #[error("sweep {key} = {value} is invalid; allowed: {allowed}")]
    Invalid {
        /// The sweep file's key (`axis[1].range.count`, `scene`, …).
        key: String,
        /// The value.
        value: String,
        /// What is allowed.
        allowed: String,
    },
    /// A point whose scene does not resolve.
    #[error("sweep point {point} ({values}): {error}")]
    Point {
        /// The point number.
        point: usize,
        /// Its axis values, `key = value, …`.
        values: String,
        /// The scene's error (names the key).
        error: Box<SceneError>,
    },
    /// The base scene (with `[set]`) does not resolve.
    #[error("sweep base scene {path} (with [set]): {error}")]
    Base {
        /// The scene path.
        path: String,
        /// The scene's error.
        error: Box<SceneError>,
    },
}

impl SweepError {
    /// The key the error is about.
    #[must_use]
    pub fn key(&self) -> Option<&str> {
        match self {
            Self::Invalid { key, .. } => Some(key),
            Self::Point { error, .. } | Self::Base { error, .. } => error.key(),
            Self::Read { .. } => None,
        }
    }

    /// A [`SweepError::Invalid`].
    pub fn invalid(key: impl Into<String>, value: impl std::fmt::Display, allowed: &str) -> Self {
        Self::Invalid {
            key: key.into(),
            value: value.to_string(),
            allowed: allowed.to_string(),
        }
    }
}
