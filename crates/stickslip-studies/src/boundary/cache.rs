//! The runs of a boundary search kept on disk as they end (`stickslip boundary --out DIR`),
//! so that an interrupted search loses none: the same command with the same `--out` finds each
//! run it has already made in `DIR/probes.jsonl` and makes only the rest. A bisection is
//! deterministic, so the rerun asks for the same values in the same order.
//!
//! One JSON line per run: the fingerprint of what decides its regime (the base scene as
//! resolved, the key, the value's bits, the scale, the regime thresholds and the build), and
//! the regime's name. Lines are appended and flushed one at a time; a line cut short by a kill
//! is skipped when read.

use super::{Label, Scale};
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use stickslip_run::scene::ResolvedScene;
use stickslip_run::summary::{Regime, RegimeThresholds};

/// The file of a search's runs in its output directory.
pub const FILE: &str = "probes.jsonl";

/// Largest probes file read, bytes (a line is about 60 bytes: a million runs).
const MAX_BYTES: u64 = 64 << 20;

/// One kept run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct Line {
    /// What decides the run's regime (see the module docs).
    fingerprint: String,
    /// The regime's name.
    regime: String,
}

/// The runs kept for a search, and the file new ones are appended to.
#[derive(Debug)]
pub struct ProbeCache {
    path: PathBuf,
    known: Mutex<HashMap<String, String>>,
    /// Runs found kept (and so not made again) so far.
    pub reused: std::sync::atomic::AtomicUsize,
}

impl ProbeCache {
    /// The cache in `dir` (created when absent), with the runs it already holds.
    ///
    /// # Errors
    /// When the directory cannot be created or the file is unreadable or over its cap.
    pub fn open(dir: &Path) -> io::Result<Self> {
        std::fs::create_dir_all(dir)?;
        let path = dir.join(FILE);
        let mut known = HashMap::new();
        match std::fs::metadata(&path) {
            Ok(m) if !m.is_file() || m.len() > MAX_BYTES => {
                return Err(io::Error::new(
                    io::ErrorKind::InvalidData,
                    format!(
                        "{}: not a regular file, or larger than {MAX_BYTES} bytes",
                        path.display()
                    ),
                ));
            }
            Ok(_) => {
                let text = std::fs::read_to_string(&path)?;
                for line in text.lines() {
                    if let Ok(l) = serde_json::from_str::<Line>(line) {
                        known.insert(l.fingerprint, l.regime);
                    }
                }
                // A line cut short by a kill is ended, so that the next one starts afresh.
                if !text.is_empty() && !text.ends_with('\n') {
                    std::fs::OpenOptions::new()
                        .append(true)
                        .open(&path)?
                        .write_all(b"\n")?;
                }
            }
            Err(e) if e.kind() == io::ErrorKind::NotFound => {}
            Err(e) => return Err(e),
        }
        Ok(Self {
            path,
            known: Mutex::new(known),
            reused: std::sync::atomic::AtomicUsize::new(0),
        })
    }

    /// Runs the file holds (kept by earlier searches or this one).
    #[must_use]
    pub fn len(&self) -> usize {
        self.known.lock().map_or(0, |k| k.len())
    }

    /// Whether it holds none.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The fingerprint of the run of `base` with `key = value` on `scale`.
    #[must_use]
    pub fn fingerprint(
        base: &ResolvedScene,
        key: &str,
        value: f64,
        (scale, thresholds): (Scale, RegimeThresholds),
    ) -> String {
        use stickslip_run::atomic::{FNV1A64_INIT, fnv1a64};
        let mut h = fnv1a64(FNV1A64_INIT, base.resolved.to_toml_string().as_bytes());
        h = fnv1a64(h, key.as_bytes());
        h = fnv1a64(h, &value.to_bits().to_le_bytes());
        h = fnv1a64(h, scale.name().as_bytes());
        h = fnv1a64(h, format!("{thresholds:?}").as_bytes());
        h = fnv1a64(h, stickslip_run::build_id::BUILD_ID.as_bytes());
        format!("{h:016x}")
    }

    /// The kept regime of the run with `fingerprint` on `scale`.
    #[must_use]
    pub fn get(&self, fingerprint: &str, scale: Scale) -> Option<Label> {
        let name = self.known.lock().ok()?.get(fingerprint)?.clone();
        let label = match scale {
            Scale::Film => Label::Film(Regime::from_name(&name)?),
            Scale::Stamp => Label::Stamp(stickslip_run::cycles::StampRegime::from_name(&name)?),
        };
        self.reused
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        Some(label)
    }

    /// Keeps a run's regime: appended to the file and flushed (a failure to write loses the
    /// keeping, not the run).
    pub fn put(&self, fingerprint: String, label: Label) {
        let Ok(mut known) = self.known.lock() else {
            return;
        };
        let line = Line {
            fingerprint: fingerprint.clone(),
            regime: label.name().to_string(),
        };
        if let Ok(text) = serde_json::to_string(&line) {
            let appended = std::fs::OpenOptions::new()
                .create(true)
                .append(true)
                .open(&self.path)
                .and_then(|mut f| {
                    f.write_all(format!("{text}\n").as_bytes())?;
                    f.sync_data()
                });
            if appended.is_ok() {
                known.insert(fingerprint, line.regime);
            }
        }
    }
}
