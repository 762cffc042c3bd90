//! `reports/build-timing.json`: what a fresh clone costs (P4 of reports/performance.md).
//!
//! Written by `cargo xtask build-timing`, which clones the repository's HEAD into
//! `target/build-timing/clone` (its own, empty `target/`) and times the README's two commands
//! there: `cargo xtask validate`, then `cargo xtask test`, whose stages (compile, Rust tests,
//! Python, Slurm) `cargo xtask test` itself records in a [`StageTimes`] file. Read by the
//! performance report. One type per file, writer and reader together.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// One timed stage of a command.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StageTime {
    /// Stage name (`rust build`, `rust tests`, `python`, `slurm`).
    pub name: String,
    /// Wall-clock seconds.
    pub seconds: f64,
    /// Whether the stage passed.
    pub ok: bool,
}

/// The stages `cargo xtask test` ran, written where `STICKSLIP_TEST_TIMES` points.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StageTimes {
    /// In the order run.
    pub stages: Vec<StageTime>,
}

/// The environment variable that makes `cargo xtask test` write its [`StageTimes`].
pub const STAGE_TIMES_ENV: &str = "STICKSLIP_TEST_TIMES";

/// A fresh clone's build and test times.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BuildTiming {
    /// The commit timed (`git rev-parse HEAD` of the clone).
    pub commit: String,
    /// Logical CPUs of the machine.
    pub cpus: usize,
    /// `cargo xtask validate` on the fresh clone, s (compiling included).
    pub validate_s: f64,
    /// Whether it exited 0.
    pub validate_ok: bool,
    /// `cargo xtask test` right after it, s.
    pub test_s: f64,
    /// Whether it exited 0.
    pub test_ok: bool,
    /// Its stages.
    pub test_stages: Vec<StageTime>,
    /// Whether the cargo registry already held the dependencies' sources (a machine that
    /// has never built a Rust project also downloads them).
    pub registry_warm: bool,
}

impl BuildTiming {
    /// File name in the reports directory.
    pub const FILE: &'static str = "build-timing.json";

    /// Path in `reports_dir`.
    #[must_use]
    pub fn path(reports_dir: &Path) -> PathBuf {
        reports_dir.join(Self::FILE)
    }

    /// The stage named `name`, s.
    #[must_use]
    pub fn stage_s(&self, name: &str) -> Option<f64> {
        self.test_stages
            .iter()
            .find(|s| s.name == name)
            .map(|s| s.seconds)
    }

    /// Writes it atomically into `reports_dir`.
    ///
    /// # Errors
    /// An I/O error, as text.
    pub fn write(&self, reports_dir: &Path) -> Result<(), String> {
        write_json(&Self::path(reports_dir), self)
    }

    /// Reads it from `reports_dir`; `None` when it was never measured.
    ///
    /// # Errors
    /// The file exists but does not parse.
    pub fn read(reports_dir: &Path) -> Result<Option<Self>, String> {
        read_json(&Self::path(reports_dir))
    }
}

impl StageTimes {
    /// Writes it atomically to `path`.
    ///
    /// # Errors
    /// An I/O error, as text.
    pub fn write(&self, path: &Path) -> Result<(), String> {
        write_json(path, self)
    }

    /// Reads it from `path`; `None` when the file does not exist.
    ///
    /// # Errors
    /// The file exists but does not parse.
    pub fn read(path: &Path) -> Result<Option<Self>, String> {
        read_json(path)
    }
}

fn write_json<T: Serialize>(path: &Path, value: &T) -> Result<(), String> {
    let text = serde_json::to_string_pretty(value).map_err(|e| e.to_string())? + "\n";
    crate::write_atomic(path, text.as_bytes()).map_err(|e| format!("{}: {e}", path.display()))
}

fn read_json<T: for<'de> Deserialize<'de>>(path: &Path) -> Result<Option<T>, String> {
    match std::fs::read(path) {
        Ok(bytes) => serde_json::from_slice(&bytes)
            .map(Some)
            .map_err(|e| format!("{}: {e}", path.display())),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(format!("{}: {e}", path.display())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_absence() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(BuildTiming::read(dir.path()).unwrap(), None);
        let t = BuildTiming {
            commit: "abc".into(),
            cpus: 2,
            validate_s: 180.5,
            validate_ok: true,
            test_s: 150.25,
            test_ok: true,
            test_stages: vec![StageTime {
                name: "rust build".into(),
                seconds: 64.8,
                ok: true,
            }],
            registry_warm: true,
        };
        t.write(dir.path()).unwrap();
        let back = BuildTiming::read(dir.path()).unwrap().unwrap();
        assert_eq!(back, t);
        assert_eq!(back.stage_s("rust build"), Some(64.8));
        assert_eq!(back.stage_s("python"), None);
    }
}
