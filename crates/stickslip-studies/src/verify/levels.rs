//! A verify's level runs reduced to what its report needs, and kept on disk as they end, so
//! that an interrupted verify (Ctrl-C, SIGTERM, a time limit) loses no finished level: the
//! same command with the same `--out` reuses them and runs only the rest.
//!
//! Each finished level is `DIR/levels/level-K.json` (K from 0, the scene's own run first),
//! written atomically. A record is reused only for the same level scene (its resolved TOML
//! text) computed by the same build ([`stickslip_run::build_id::BUILD_ID`]); any other record is
//! ignored and rewritten. An interrupted level's run is not kept: it runs again whole.

use serde::{Deserialize, Serialize};
use std::io;
use std::path::{Path, PathBuf};
use stickslip_run::outcome::RunOutcome;
use stickslip_run::scene::ResolvedScene;
use stickslip_run::summary::RunSummary;

/// The subdirectory of a verify's output directory holding its levels.
pub const DIR: &str = "levels";

/// Largest level record read, bytes (a record is a summary and the onsets: a million onsets
/// is about 25 MB).
const MAX_BYTES: u64 = 64 << 20;

/// What a verify's report takes from one level's run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LevelResult {
    /// The level's resolved scene as TOML text (a record is reused only for the same text).
    pub scene: String,
    /// The build that computed it.
    pub build: String,
    /// The run's status (`ok`, `failed`, …).
    pub status: String,
    /// The numerical failure, in words, when it failed.
    pub failure: Option<String>,
    /// Steps taken.
    pub steps: u64,
    /// Wall time of its loop, s.
    pub wall_s: f64,
    /// Its summary.
    pub summary: RunSummary,
    /// The melting onsets, s.
    pub onsets_s: Vec<f64>,
}

impl LevelResult {
    /// The result of `scene`'s run `o`.
    #[must_use]
    pub fn of(scene: &ResolvedScene, o: &RunOutcome) -> Self {
        Self {
            scene: scene.resolved.to_toml_string(),
            build: stickslip_run::build_id::BUILD_ID.to_string(),
            status: o.status().name().to_string(),
            failure: o.failure.as_ref().map(ToString::to_string),
            steps: o.counts.steps,
            wall_s: o.wall_seconds,
            summary: o.summary.clone(),
            onsets_s: o.events.iter().map(|e| e.t_onset_s).collect(),
        }
    }

    /// Whether the run failed numerically (its summary then holds no values).
    #[must_use]
    pub fn failed(&self) -> bool {
        self.failure.is_some()
    }
}

/// The record of level `k` under `dir`.
#[must_use]
pub fn path(dir: &Path, k: usize) -> PathBuf {
    dir.join(DIR).join(format!("level-{k}.json"))
}

/// The kept result of level `k` of `dir` when it is `scene`'s by this build; `None` otherwise
/// (absent, damaged, another scene's or another build's: it runs again).
#[must_use]
pub fn load(dir: &Path, k: usize, scene: &ResolvedScene) -> Option<LevelResult> {
    let file = path(dir, k);
    let meta = std::fs::metadata(&file).ok()?;
    if !meta.is_file() || meta.len() > MAX_BYTES {
        return None;
    }
    let text = std::fs::read_to_string(&file).ok()?;
    let r: LevelResult = serde_json::from_str(&text).ok()?;
    (r.build == stickslip_run::build_id::BUILD_ID && r.scene == scene.resolved.to_toml_string())
        .then_some(r)
}

/// Keeps `result` as level `k` of `dir`, atomically.
///
/// # Errors
/// I/O errors creating the directory or writing the record.
pub fn save(dir: &Path, k: usize, result: &LevelResult) -> io::Result<()> {
    let levels = dir.join(DIR);
    std::fs::create_dir_all(&levels)?;
    let json = serde_json::to_vec_pretty(result).map_err(io::Error::other)?;
    stickslip_run::atomic::write_atomic(&levels, &format!("level-{k}.json"), &json)
}

/// How many levels `dir` holds records of (whatever their scene), for messages.
#[must_use]
pub fn count(dir: &Path) -> usize {
    std::fs::read_dir(dir.join(DIR)).map_or(0, |d| {
        d.filter_map(Result::ok)
            .filter(|e| {
                e.file_name()
                    .to_str()
                    .is_some_and(|n| n.starts_with("level-") && n.ends_with(".json"))
            })
            .count()
    })
}
