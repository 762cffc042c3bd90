//! The sweep directory and its one sweep: `DIR/sweep.json` holds the sweep as resolved and its
//! fingerprint (definition and build); every record, shard table and map in the directory is
//! that sweep's.
//!
//! - [`prepare`] readies a directory, idempotently: any number of processes (the tasks of a
//!   Slurm array, started together) may prepare it at once; each writes the same sweep.json
//!   through the atomic writer (a temporary file of its own, renamed) and reads it back, so a
//!   process whose sweep lost a race to another sweep is refused, never half-read.
//! - The same sweep by another build takes the directory over without `force` (its points
//!   are then recomputed, see [`super::record::Found::OtherBuild`]); another sweep needs
//!   `force`, which starts afresh: sweep.json first, then points/, runs/, shards/ and the map
//!   are removed, also for the same sweep.
//! - [`LockWatch`] lets a running process notice that its directory was taken over (a
//!   `force` by another sweep): it looks at sweep.json's metadata before each record it
//!   writes and rereads the file only when that changed.

use super::Sweep;
use serde::{Deserialize, Serialize};
use std::io;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use stickslip_run::atomic::write_atomic;
pub use stickslip_run::layout::sweep::{CHECKS_DIR, SWEEP_DIRS, SWEEP_FILE};
use stickslip_run::layout::sweep::{CSV_FILE, JSON_FILE};
use thiserror::Error;

/// Why a sweep could not run or merge.
#[derive(Debug, Error)]
pub enum SweepRunError {
    /// The directory holds another sweep (exit 2).
    #[error(
        "{dir} holds the results of another sweep (its sweep.json differs); allowed: the \
         directory of this sweep, a new one, or --force to replace them"
    )]
    Other {
        /// The directory.
        dir: String,
    },
    /// No sweep in the directory (exit 2).
    #[error("no sweep in {dir} ({why}); allowed: a directory written by `stickslip sweep run`")]
    Missing {
        /// The directory.
        dir: String,
        /// What is missing.
        why: String,
    },
    /// The directory cannot be created or written (exit 2, as for `run --out`).
    #[error("cannot write to sweep directory {path}: {source}; allowed: a writable directory")]
    OutDir {
        /// The directory.
        path: PathBuf,
        /// The I/O error.
        source: io::Error,
    },
    /// A record (or shard table) in the directory belongs to another sweep (exit 2).
    #[error(
        "{path} is not a result of this sweep: {why}; allowed: only this sweep's results in \
         its directory (use a new directory, or --force to start this sweep afresh)"
    )]
    Foreign {
        /// The record or table.
        path: PathBuf,
        /// What differs.
        why: String,
    },
    /// Another sweep took the directory over while this process ran (exit 2).
    #[error(
        "{dir} now holds another sweep (its sweep.json changed while this process ran, e.g. \
         a --force of another sweep); this process stopped without writing more records"
    )]
    TakenOver {
        /// The directory.
        dir: String,
    },
    /// An I/O error (exit 1).
    #[error("sweep directory {path}: {source}")]
    Io {
        /// The path.
        path: PathBuf,
        /// The error.
        source: io::Error,
    },
}

impl SweepRunError {
    /// Exit status of the command line: 1 for an I/O error during the sweep, 2 otherwise.
    #[must_use]
    pub fn exit(&self) -> stickslip_run::exit::Exit {
        match self {
            Self::Io { .. } => stickslip_run::exit::Exit::Io,
            _ => stickslip_run::exit::Exit::BadInput,
        }
    }
}

/// An [`SweepRunError::Io`] at `path`.
pub fn io_err(path: &Path) -> impl FnOnce(io::Error) -> SweepRunError + '_ {
    move |source| SweepRunError::Io {
        path: path.to_path_buf(),
        source,
    }
}

fn out_dir_err(path: &Path) -> impl FnOnce(io::Error) -> SweepRunError + '_ {
    move |source| SweepRunError::OutDir {
        path: path.to_path_buf(),
        source,
    }
}

/// `DIR/sweep.json`: the resolved sweep and its fingerprint.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepLock {
    /// What decides every point's outcome ([`Sweep::fingerprint`]).
    pub fingerprint: String,
    /// The build of the numerics that writes the points ([`stickslip_run::build_id::BUILD_ID`]).
    #[serde(default)]
    pub build: String,
    /// The sweep.
    pub sweep: Sweep,
}

impl SweepLock {
    /// The lock of `sweep` by this build.
    #[must_use]
    pub fn of(sweep: &Sweep) -> Self {
        Self {
            fingerprint: sweep.fingerprint(),
            build: stickslip_run::build_id::BUILD_ID.to_string(),
            sweep: sweep.clone(),
        }
    }
}

/// What [`prepare`] found.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Prepared {
    /// The directory held this sweep by another build (its identity): its points are
    /// recomputed as they come.
    pub previous_build: Option<String>,
    /// `force` removed earlier results.
    pub started_afresh: bool,
    /// The directory's sweep.json could not be read (why): it was damaged, not another
    /// sweep's, so it was rewritten for this sweep. Each point record names its sweep, so a
    /// record of another sweep is still refused when it is read.
    pub repaired: Option<String>,
}

fn remove_if_present(path: &Path, dir: bool) -> io::Result<()> {
    let r = if dir {
        std::fs::remove_dir_all(path)
    } else {
        std::fs::remove_file(path)
    };
    match r {
        Err(e) if e.kind() != io::ErrorKind::NotFound => Err(e),
        _ => Ok(()),
    }
}

/// Why a `sweep.json` that exists cannot be read as a sweep's lock.
#[derive(Debug, thiserror::Error)]
enum Unreadable {
    /// Not a lock's JSON (cut short, edited, emptied).
    #[error(transparent)]
    Json(#[from] serde_json::Error),
    /// Not text, or larger than a lock can be.
    #[error(transparent)]
    Text(io::Error),
}

/// Reads `DIR/sweep.json`: `Ok(None)` when there is none.
fn read_lock(dir: &Path) -> Result<Option<Result<SweepLock, Unreadable>>, SweepRunError> {
    match stickslip_run::bounded::read_text(
        &dir.join(SWEEP_FILE),
        stickslip_run::bounded::SWEEP_LOCK,
    ) {
        Ok(text) => Ok(Some(
            serde_json::from_str::<SweepLock>(&text).map_err(Unreadable::from),
        )),
        Err(e) if e.kind() == io::ErrorKind::InvalidData => Ok(Some(Err(Unreadable::Text(e)))),
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(io_err(dir)(e)),
    }
}

/// Readies `dir` for `sweep`: creates it and writes `sweep.json`, or checks that the one there
/// is this sweep's. Safe to call from any number of processes at once (see the module docs).
/// `force` starts afresh: earlier results, of this sweep or another, are removed first.
///
/// # Errors
/// [`SweepRunError::Other`] for another sweep's directory without `force` (or when another
/// sweep prepared it at the same moment); [`SweepRunError::OutDir`] when it cannot be created
/// or written; I/O errors.
pub fn prepare(sweep: &Sweep, dir: &Path, force: bool) -> Result<Prepared, SweepRunError> {
    let lock = SweepLock::of(sweep);
    let mut prepared = Prepared::default();
    std::fs::create_dir_all(dir).map_err(out_dir_err(dir))?;
    if force {
        // sweep.json first: a process of another sweep still running here stops at its next
        // record (LockWatch), and a crash midway leaves no sweep.json beside old results.
        let earlier = dir.join(SWEEP_FILE).exists();
        remove_if_present(&dir.join(SWEEP_FILE), false).map_err(io_err(dir))?;
        for sub in SWEEP_DIRS {
            remove_if_present(&dir.join(sub), true).map_err(io_err(dir))?;
        }
        for f in [CSV_FILE, JSON_FILE] {
            remove_if_present(&dir.join(f), false).map_err(io_err(dir))?;
        }
        prepared.started_afresh = earlier;
    } else {
        match read_lock(dir)? {
            Some(Ok(old)) if old.fingerprint == lock.fingerprint => {
                std::fs::create_dir_all(dir.join("points")).map_err(out_dir_err(dir))?;
                return Ok(prepared);
            }
            Some(Ok(old)) if old.sweep.definition() == sweep.definition() => {
                // This sweep, by another build: the stale map goes, the points are recomputed
                // as they come (their records say which build computed them).
                prepared.previous_build = Some(if old.build.is_empty() {
                    "an earlier version".to_string()
                } else {
                    old.build
                });
                for f in [CSV_FILE, JSON_FILE] {
                    remove_if_present(&dir.join(f), false).map_err(io_err(dir))?;
                }
            }
            Some(Ok(_)) => {
                return Err(SweepRunError::Other {
                    dir: dir.display().to_string(),
                });
            }
            Some(Err(why)) => {
                // Damaged (cut short, edited, emptied), not another sweep's: the records keep
                // their own fingerprints, so rewriting it loses nothing and accepts nothing
                // foreign. The stale map goes with it.
                for f in [CSV_FILE, JSON_FILE] {
                    remove_if_present(&dir.join(f), false).map_err(io_err(dir))?;
                }
                prepared.repaired = Some(why.to_string());
            }
            None => {}
        }
    }
    std::fs::create_dir_all(dir.join("points")).map_err(out_dir_err(dir))?;
    let text = serde_json::to_string_pretty(&lock).map_err(|e| io_err(dir)(io::Error::other(e)))?;
    write_atomic(dir, SWEEP_FILE, text.as_bytes()).map_err(out_dir_err(dir))?;
    // Read back: another sweep preparing the same directory at the same moment may have won.
    match read_lock(dir)? {
        Some(Ok(now)) if now.fingerprint == lock.fingerprint => Ok(prepared),
        _ => Err(SweepRunError::Other {
            dir: dir.display().to_string(),
        }),
    }
}

/// Reads `DIR/sweep.json`.
///
/// # Errors
/// [`SweepRunError::Missing`] when there is none or it cannot be parsed.
pub fn load_lock(dir: &Path) -> Result<SweepLock, SweepRunError> {
    let missing = |why: String| SweepRunError::Missing {
        dir: dir.display().to_string(),
        why,
    };
    match read_lock(dir)? {
        Some(Ok(lock)) => Ok(lock),
        Some(Err(e)) => Err(missing(format!("{SWEEP_FILE}: {e}"))),
        None => Err(missing(format!("{SWEEP_FILE}: not found"))),
    }
}

/// What identifies a version of sweep.json without reading it: length, modification time and
/// (on unix) the inode, which every atomic rewrite changes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Stamp {
    len: u64,
    modified: Option<std::time::SystemTime>,
    inode: u64,
}

fn stamp(path: &Path) -> io::Result<Stamp> {
    let m = std::fs::metadata(path)?;
    #[cfg(unix)]
    let inode = std::os::unix::fs::MetadataExt::ino(&m);
    #[cfg(not(unix))]
    let inode = 0;
    Ok(Stamp {
        len: m.len(),
        modified: m.modified().ok(),
        inode,
    })
}

/// Watches `DIR/sweep.json` for a change of sweep (see the module docs).
#[derive(Debug)]
pub struct LockWatch {
    dir: PathBuf,
    fingerprint: String,
    seen: Mutex<Option<Stamp>>,
}

impl LockWatch {
    /// A watch of `dir` for the sweep of `fingerprint`.
    #[must_use]
    pub fn new(dir: &Path, fingerprint: &str) -> Self {
        Self {
            dir: dir.to_path_buf(),
            fingerprint: fingerprint.to_string(),
            seen: Mutex::new(None),
        }
    }

    /// Checks that sweep.json still holds this sweep: one metadata look-up, and a read only
    /// when the file changed since the last check.
    ///
    /// # Errors
    /// [`SweepRunError::TakenOver`] when it is gone or holds another sweep.
    pub fn check(&self) -> Result<(), SweepRunError> {
        let taken = || SweepRunError::TakenOver {
            dir: self.dir.display().to_string(),
        };
        let path = self.dir.join(SWEEP_FILE);
        let now = stamp(&path).map_err(|_| taken())?;
        let mut seen = self
            .seen
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if *seen == Some(now) {
            return Ok(());
        }
        match read_lock(&self.dir) {
            Ok(Some(Ok(lock))) if lock.fingerprint == self.fingerprint => {
                *seen = Some(now);
                Ok(())
            }
            _ => Err(taken()),
        }
    }
}
