//! Checkpoints: a run in progress is saved every few seconds of wall time, so that
//! `stickslip resume DIR` can finish it after the process was killed (SIGKILL, power loss)
//! with output files bit-identical to those of an uninterrupted run.
//!
//! ## What is saved
//! `DIR/checkpoint.cbor`, written atomically (temporary file, fsync, rename): the header line
//! `stickslip checkpoint 3\n` (the format's version), the payload length and its FNV-1a
//! checksum (two little-endian u64), then the payload in CBOR. CBOR stores every f64 with its
//! exact bits (±inf included, which the event tracker holds), which JSON or TOML would not
//! guarantee. The payload is this module's own type, format 3 (`checkpoint/format3.rs`),
//! mapped field by field to and from the types it saves: the build identity of the numerics
//! that wrote it ([`BUILD_ID`]), the resolved scene, typed (so resume needs no scene file and
//! resolves nothing again), the preflight at t = 0, the engine's [`SimState`] part by part
//! (physical state, stepper and controller memory, counters, events; noise generator positions
//! included), the driver's [`DriverState`] (loop index, recording marks, step schedule, wall
//! time so far, the slip tracker), the length and checksum of each streamed file, and the earlier resumes of the
//! run across builds. Every field must be there: nothing is filled in by default, and a file of
//! another format version (format 1, before the state was split into its parts and bound to
//! the build; format 2, before the driver followed the stamp's slips) is refused as such.
//!
//! ## Bound to the build
//! Another build of the numerics (other sources, compiler or target) may take other steps, so
//! its checkpoint would not continue the run it started: [`check_build`] refuses it unless the
//! caller allows it (`stickslip resume --allow-other-build`), and then the crossing is recorded
//! in run.json (`resumed_across_builds`) and carried by every later checkpoint of the run.
//! Reading a killed run's data ([`crate::sink::read`]) takes any build's checkpoint: it steps
//! nothing.
//!
//! ## Why the resumed output is bit-identical
//! The streamed CSV files grow as `DIR/.<name>.tmp` and are renamed into place at the end.
//! Before each checkpoint they are flushed and synced, and their length and checksum are
//! recorded; so the checkpoint refers only to bytes that are on disk. A resumed run cuts each
//! file back to the recorded length (dropping rows written after the checkpoint), checks the
//! checksum, restores the simulation state into a simulation built from the same scene and
//! continues the same loop from the next index. Every step and every row then repeats what the
//! uninterrupted run computed, from the same bits. events.csv is written from the state when
//! the run ends (and, with the events so far, when it is interrupted); run.json is rewritten
//! at the end. Copies of the streams an interrupted run published under the final names are
//! replaced when the resumed run commits its files. run.json differs only in `wall_seconds` (the
//! sum over the processes of the time spent in the loop up to their last checkpoint, plus the
//! final one's).
//!
//! ## Life cycle
//! A run interrupted by a signal writes a checkpoint at once (whatever the interval). The
//! checkpoint is removed when the run has ended (finished or failed numerically) and all its
//! output is written. If the process is killed while committing its output, the files already
//! renamed into place serve as the source of the recorded bytes on resume.
//!
//! This module knows the file and its payload; the output directory's sink
//! ([`crate::sink::dir`]) decides when to write one. It does not depend on that sink.

use crate::atomic::{FNV1A64_INIT, StreamPosition, fnv1a64, write_atomic};
pub use crate::build_id::BUILD_ID;
use crate::driver::DriverState;
use crate::scene::ResolvedScene;
use crate::schema::run_info::{BuildCrossing, RunInfo, RunStatus};
use serde::{Deserialize, Serialize};
use std::borrow::Cow;
use std::io::{self, Read};
use std::path::{Path, PathBuf};
use std::time::Duration;
use stickslip_core::preflight::Preflight;
use stickslip_core::sim::SimState;
use thiserror::Error;

mod format3;

/// File name of the checkpoint in the output directory.
pub const FILE_NAME: &str = "checkpoint.cbor";
/// Default wall-clock interval between checkpoints, s: a killed run loses at most about this
/// much work, and the checkpoint's cost (a few fsyncs) stays far below it.
pub const DEFAULT_EVERY_S: f64 = 2.0;
/// The format version this build writes and reads.
pub const FORMAT: u32 = 3;
/// First bytes of every checkpoint file, followed by the format version and a newline.
const HEADER: &[u8] = b"stickslip checkpoint ";
/// First bytes of a checkpoint file of this format.
const MAGIC: &[u8] = b"stickslip checkpoint 3\n";
/// Largest checkpoint read, bytes: far above a real one (the state of 20000 nodes is about
/// 2 MB; a million events about 200 MB), so that no file makes `resume` exhaust memory.
pub const MAX_BYTES: u64 = 4 << 30;

/// Length and checksum of each streamed file at the checkpoint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct StreamPositions {
    /// series.csv so far.
    pub series: StreamPosition,
    /// probes.csv so far.
    pub probes: StreamPosition,
    /// profiles.csv so far.
    pub profiles: StreamPosition,
}

/// Everything a resumed run needs, in memory (the file holds it as format 3, see the module
/// docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Checkpoint<'a> {
    /// Build identity of the numerics that wrote it ([`BUILD_ID`]): another build may step
    /// differently, so resume refuses it unless allowed ([`check_build`]).
    pub build: Cow<'a, str>,
    /// Wall-clock interval between checkpoints of the run, s (0 = none); a resume keeps it
    /// unless told otherwise.
    pub checkpoint_every_s: f64,
    /// The resolved scene.
    pub scene: Cow<'a, ResolvedScene>,
    /// The preflight at t = 0 (run.json reports it; it is not recomputed from a later state).
    pub preflight: Cow<'a, Preflight>,
    /// The driver's state after its last completed iteration (wall time so far included).
    pub driver: Cow<'a, DriverState>,
    /// The engine's state after that iteration.
    pub sim: Cow<'a, SimState>,
    /// How far each streamed file had got.
    pub streams: StreamPositions,
    /// Earlier resumes of this run by another build than the checkpoint's (run.json's
    /// `resumed_across_builds`), kept so that a later resume records them too.
    pub resumed_across_builds: Cow<'a, [BuildCrossing]>,
}

impl Checkpoint<'_> {
    /// The file contents: header, payload length, payload checksum, CBOR payload.
    ///
    /// # Errors
    /// If the payload cannot be encoded.
    pub fn encode(&self) -> io::Result<Vec<u8>> {
        let mut payload = Vec::new();
        ciborium::into_writer(&format3::Payload::from(self), &mut payload)
            .map_err(io::Error::other)?;
        let mut bytes = Vec::with_capacity(MAGIC.len() + 16 + payload.len());
        bytes.extend_from_slice(MAGIC);
        bytes.extend_from_slice(&(payload.len() as u64).to_le_bytes());
        bytes.extend_from_slice(&fnv1a64(FNV1A64_INIT, &payload).to_le_bytes());
        bytes.extend_from_slice(&payload);
        Ok(bytes)
    }

    /// Reads the file contents written by [`Checkpoint::encode`].
    ///
    /// # Errors
    /// What is wrong with `bytes`: another format version ([`format_of`] tells which), wrong
    /// header, truncated, checksum mismatch, undecodable or a field missing.
    pub fn decode(bytes: &[u8]) -> Result<Checkpoint<'static>, DecodeError> {
        let Some(rest) = bytes.strip_prefix(MAGIC) else {
            return Err(match format_of(bytes) {
                Some(found) => DecodeError::Format(found),
                None => DecodeError::Header,
            });
        };
        let word = |i: usize| -> Option<u64> {
            let b = rest.get(8 * i..8 * i + 8)?;
            Some(u64::from_le_bytes(b.try_into().ok()?))
        };
        let (Some(len), Some(sum)) = (word(0), word(1)) else {
            return Err(DecodeError::TruncatedHeader);
        };
        let payload = &rest[16..];
        if payload.len() as u64 != len {
            return Err(DecodeError::Length {
                found: payload.len(),
                recorded: len,
            });
        }
        let found = fnv1a64(FNV1A64_INIT, payload);
        if found != sum {
            return Err(DecodeError::Checksum {
                found,
                recorded: sum,
            });
        }
        ciborium::from_reader::<format3::Payload<'static>, _>(payload)
            .map(Checkpoint::from)
            .map_err(|e| DecodeError::Payload(e.to_string()))
    }
}

/// The format version in the header of `bytes` when it is a checkpoint of another format than
/// this build's ([`FORMAT`]); `None` for this format and for anything else.
#[must_use]
pub fn format_of(bytes: &[u8]) -> Option<String> {
    let rest = bytes.strip_prefix(HEADER)?;
    let end = rest.iter().take(20).position(|&b| b == b'\n')?;
    let version = std::str::from_utf8(&rest[..end]).ok()?;
    let number: u32 = version.parse().ok()?;
    (number != FORMAT).then(|| version.to_string())
}

/// Why a directory cannot be resumed.
#[derive(Debug, Error)]
pub enum CheckpointError {
    /// No checkpoint (exit 2).
    #[error(
        "no checkpoint in {dir} ({why}); allowed: the output directory of a run interrupted \
         after its first checkpoint"
    )]
    Missing {
        /// The directory.
        dir: PathBuf,
        /// What is there instead.
        why: &'static str,
    },
    /// The run in the directory has ended; nothing to resume (exit 0 if it finished, 3 if it
    /// failed numerically).
    #[error(
        "nothing to resume: the run in {dir} has already ended with status {status:?}{}",
        failure.as_ref().map(|f| format!(": {f}")).unwrap_or_default()
    )]
    Finished {
        /// The directory.
        dir: PathBuf,
        /// `status` of its run.json (`"ok"` or `"failed"`).
        status: String,
        /// `failure` of its run.json.
        failure: Option<String>,
    },
    /// A checkpoint that cannot be used (exit 2).
    #[error(
        "corrupt checkpoint {path}: {reason}; allowed: a checkpoint written by `stickslip run` \
         with its output files (start over with `stickslip run`)"
    )]
    Corrupt {
        /// The checkpoint file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// A checkpoint of another format version, e.g. format 1, written before the state was
    /// split into its parts and checkpoints were bound to the build (exit 2).
    #[error(
        "{path} is a checkpoint of format {found}, and this build resumes format {FORMAT} only \
         (checkpoints bound to the build); rerun the scene with `stickslip run` (--force \
         replaces the directory's files)"
    )]
    Format {
        /// The checkpoint file.
        path: PathBuf,
        /// The format version in its header.
        found: String,
    },
    /// A checkpoint written by another build of the numerics (exit 2).
    #[error(
        "{path} was written by build {checkpoint_build} and this is build {build}: its numbers \
         would differ; rerun, or resume with --allow-other-build to continue anyway"
    )]
    OtherBuild {
        /// The checkpoint file.
        path: PathBuf,
        /// The build that wrote it.
        checkpoint_build: String,
        /// This build ([`BUILD_ID`]).
        build: String,
    },
}

impl CheckpointError {
    /// Exit status of the command line: 0 for a run that finished, 3 for one that failed
    /// numerically, 2 otherwise.
    pub fn exit(&self) -> crate::exit::Exit {
        match self {
            Self::Finished { status, .. } if status == "ok" => crate::exit::Exit::Success,
            Self::Finished { .. } => crate::exit::Exit::Numerical,
            Self::Missing { .. }
            | Self::Corrupt { .. }
            | Self::Format { .. }
            | Self::OtherBuild { .. } => crate::exit::Exit::BadInput,
        }
    }

    /// A [`CheckpointError::Corrupt`] for the checkpoint in `dir`.
    pub fn corrupt(dir: &Path, reason: impl std::fmt::Display) -> Self {
        Self::Corrupt {
            path: path(dir),
            reason: reason.to_string(),
        }
    }
}

/// What is wrong with a checkpoint file's bytes (see [`Checkpoint::decode`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DecodeError {
    /// Another format version's header.
    #[error("checkpoint format {0}, this build reads {FORMAT}")]
    Format(String),
    /// Not a checkpoint's header at all.
    #[error("not a stickslip checkpoint (wrong header)")]
    Header,
    /// The header's length and checksum words are cut.
    #[error("truncated header")]
    TruncatedHeader,
    /// The payload is not as long as the header says.
    #[error("payload has {found} bytes, the header says {recorded} (truncated or extended)")]
    Length {
        /// The payload's bytes.
        found: usize,
        /// The header's length.
        recorded: u64,
    },
    /// The payload's FNV-1a checksum differs from the header's.
    #[error("payload checksum {found:016x} differs from the recorded {recorded:016x} (damaged)")]
    Checksum {
        /// Computed.
        found: u64,
        /// Recorded.
        recorded: u64,
    },
    /// The payload is not a checkpoint's CBOR (a field missing, a value of another type): the
    /// decoder's message.
    #[error("cannot decode the payload: {0}")]
    Payload(String),
}

/// Path of the checkpoint in `dir`.
pub fn path(dir: &Path) -> PathBuf {
    dir.join(FILE_NAME)
}

/// Writes `checkpoint` into `dir` atomically.
///
/// # Errors
/// If it cannot be encoded or written.
pub fn save(dir: &Path, checkpoint: &Checkpoint<'_>) -> io::Result<()> {
    write_atomic(dir, FILE_NAME, &checkpoint.encode()?)
}

/// Removes the checkpoint in `dir`, if there is one, and the temporary file of a checkpoint
/// whose writing was interrupted.
///
/// # Errors
/// If one exists and cannot be removed.
pub fn remove(dir: &Path) -> io::Result<()> {
    match std::fs::remove_file(path(dir)) {
        Err(e) if e.kind() != io::ErrorKind::NotFound => return Err(e),
        _ => {}
    }
    // A process killed while saving a checkpoint leaves its temporary file.
    crate::atomic::remove_temporaries(dir, FILE_NAME)
}

/// Reads and checks the checkpoint in `dir` (its format and checksum; not its build, see
/// [`check_build`]).
///
/// # Errors
/// [`CheckpointError::Finished`] when there is no checkpoint but the run.json of an ended run
/// and no partial output; [`CheckpointError::Missing`] when there is no checkpoint otherwise;
/// [`CheckpointError::Format`] for another format version; [`CheckpointError::Corrupt`] when
/// it cannot be read or decoded.
pub fn load(dir: &Path) -> Result<Checkpoint<'static>, CheckpointError> {
    let file = path(dir);
    let corrupt = |why: String| CheckpointError::corrupt(dir, why);
    // Checked before reading: a device or FIFO would never end, and a file longer than its
    // header says is refused without reading its payload.
    let meta = match std::fs::metadata(&file) {
        Ok(m) => m,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Err(no_checkpoint(dir)),
        Err(e) => return Err(corrupt(format!("cannot read it: {e}"))),
    };
    if !meta.is_file() {
        return Err(corrupt(
            "not a regular file (a directory, device, FIFO or socket)".to_string(),
        ));
    }
    if meta.len() > MAX_BYTES {
        return Err(corrupt(format!(
            "{} bytes, more than the {MAX_BYTES} a checkpoint may have",
            meta.len()
        )));
    }
    let read = || -> io::Result<Vec<u8>> {
        let mut f = std::fs::File::open(&file)?;
        let mut head = Vec::with_capacity(MAGIC.len() + 16);
        (&mut f)
            .take((MAGIC.len() + 16) as u64)
            .read_to_end(&mut head)?;
        // The header decides before the payload is read: a large file that is not a
        // checkpoint of this format costs its first bytes, not its size in memory.
        if !head.starts_with(MAGIC) {
            return Ok(head);
        }
        if let Some(len) = head
            .strip_prefix(MAGIC)
            .and_then(|r| r.get(..8))
            .and_then(|b| b.try_into().ok())
            .map(u64::from_le_bytes)
        {
            let expected = (MAGIC.len() + 16) as u64 + len;
            if meta.len() != expected {
                return Err(io::Error::new(
                    io::ErrorKind::InvalidData,
                    format!(
                        "the header says {len} payload bytes, the file has {} (truncated or \
                         extended)",
                        meta.len() - (MAGIC.len() + 16) as u64
                    ),
                ));
            }
        }
        let mut bytes = head;
        f.take(MAX_BYTES).read_to_end(&mut bytes)?;
        Ok(bytes)
    };
    let bytes = match read() {
        Ok(b) => b,
        Err(e) if e.kind() == io::ErrorKind::InvalidData => return Err(corrupt(e.to_string())),
        Err(e) => return Err(corrupt(format!("cannot read it: {e}"))),
    };
    if let Some(found) = format_of(&bytes) {
        return Err(CheckpointError::Format { path: file, found });
    }
    Checkpoint::decode(&bytes).map_err(|e| corrupt(e.to_string()))
}

/// Whether this build may resume `checkpoint` (read from `dir`): `None` when this build wrote
/// it; the crossing to record when another build did and `allow_other_build` is set.
///
/// # Errors
/// [`CheckpointError::OtherBuild`] when another build wrote it and it is not allowed.
pub fn check_build(
    dir: &Path,
    checkpoint: &Checkpoint<'_>,
    allow_other_build: bool,
) -> Result<Option<BuildCrossing>, CheckpointError> {
    if checkpoint.build == BUILD_ID {
        return Ok(None);
    }
    if !allow_other_build {
        return Err(CheckpointError::OtherBuild {
            path: path(dir),
            checkpoint_build: checkpoint.build.to_string(),
            build: BUILD_ID.to_string(),
        });
    }
    Ok(Some(BuildCrossing {
        checkpoint_build: checkpoint.build.to_string(),
        build: BUILD_ID.to_string(),
    }))
}

/// The error for a directory without a checkpoint: an ended run, or nothing to resume.
fn no_checkpoint(dir: &Path) -> CheckpointError {
    let missing = |why| CheckpointError::Missing {
        dir: dir.to_path_buf(),
        why,
    };
    if !dir.is_dir() {
        return missing("no such directory");
    }
    if dir.join(".series.csv.tmp").exists() {
        return missing(
            "the run there was killed before its first checkpoint, or ran with \
             --checkpoint-every 0; rerun it with `stickslip run`",
        );
    }
    match RunInfo::read(dir) {
        Ok(info) if matches!(info.status, RunStatus::Ok | RunStatus::Failed) => {
            CheckpointError::Finished {
                dir: dir.to_path_buf(),
                status: info.status.name().to_string(),
                failure: info.failure.map(|f| f.message),
            }
        }
        _ => missing("no interrupted run there"),
    }
}

/// The interval `every_s` (s) as a duration; `None` for 0 (never) and for intervals too long
/// to come due.
pub(crate) fn interval(every_s: f64) -> Option<Duration> {
    Duration::try_from_secs_f64(every_s)
        .ok()
        .filter(|d| !d.is_zero())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::driver::{FixedSchedule, RecorderState};
    use stickslip_core::sim::Simulation;

    fn sample() -> Checkpoint<'static> {
        let scene = crate::scene::Scene::from_toml_str(
            include_str!("../../../validation/scenes/fig2.toml"),
            &["contact.nodes=8"],
        )
        .unwrap();
        let sim = Simulation::new(scene.config.clone()).unwrap();
        let preflight = sim.preflight();
        Checkpoint {
            build: Cow::Borrowed(BUILD_ID),
            checkpoint_every_s: 0.5,
            preflight: Cow::Owned(preflight),
            driver: Cow::Owned(DriverState {
                loop_index: 7,
                recorder: RecorderState {
                    next_profile: 1,
                    next_mark: 3.0,
                    last_series_t_s: Some(-0.0),
                    series_rows: 2,
                },
                schedule: FixedSchedule {
                    dt_s: 1e-8,
                    first_index: 0,
                    steps: 10,
                },
                wall_before_s: 1.5,
                slips: {
                    let mut slips = crate::slips::SlipTracker::new(1e-4, 1.0);
                    for (t, f) in [(0.0, 0.0), (0.1, 3e-4), (0.2, 0.0), (0.3, 5e-4)] {
                        let now = crate::slips::Moment {
                            t_s: t,
                            f_n: f,
                            x_m: -t,
                            dissipated_j: t,
                        };
                        slips.observe(now, f, &[]);
                    }
                    assert_eq!(slips.slips.len(), 1);
                    slips
                },
            }),
            streams: StreamPositions {
                series: StreamPosition::START,
                probes: StreamPosition {
                    bytes: 10,
                    fnv1a64: u64::MAX,
                },
                profiles: StreamPosition::START,
            },
            sim: Cow::Owned(sim.state().clone()),
            scene: Cow::Owned(scene),
            resumed_across_builds: Cow::Owned(vec![BuildCrossing {
                checkpoint_build: "0123456789abcdef".to_string(),
                build: BUILD_ID.to_string(),
            }]),
        }
    }

    /// `payload` as a checkpoint file of this format.
    fn file_of(payload: &[u8]) -> Vec<u8> {
        let mut bytes = MAGIC.to_vec();
        bytes.extend_from_slice(&(payload.len() as u64).to_le_bytes());
        bytes.extend_from_slice(&fnv1a64(FNV1A64_INIT, payload).to_le_bytes());
        bytes.extend_from_slice(payload);
        bytes
    }

    #[test]
    fn round_trip_keeps_every_bit() {
        let mut c = sample();
        let state = c.sim.to_mut();
        // Values JSON could not carry, and ones that need all 64 bits, in every part.
        state.physical.force_n = f64::NEG_INFINITY;
        state.physical.phi[0] = 0.1 + 0.2;
        state.physical.phi[1] = f64::MIN_POSITIVE / 3.0;
        state.physical.u0_m[2] = -0.0;
        state.stepper.u3d_prev2_m = vec![f64::MIN_POSITIVE; 8];
        state.stepper.accel_change_prev_m_per_s2 = -1e300;
        state.stepper.mean_v_m_per_s = 1.0 / 3.0;
        state.stepper.viscous_v_m_per_s = -0.0;
        state.stepper.viscous_rate_prev_m_per_s = vec![1e-300; 8];
        state.controller.next_dt_s = 1e-9 / 3.0;
        state.controller.rejected_last = true;
        state.counters.onset_retakes = u64::MAX;
        state.events.last_melt_s[3] = 2.5e-4;
        state.events.swept[4] = true;
        let back = Checkpoint::decode(&c.encode().unwrap()).unwrap();
        assert_eq!(back, c);
        assert_eq!(back.sim.physical.u0_m[2].to_bits(), (-0.0f64).to_bits());
        assert_eq!(
            back.sim.stepper.viscous_v_m_per_s.to_bits(),
            (-0.0f64).to_bits()
        );
        assert_eq!(
            back.driver.recorder.last_series_t_s.map(f64::to_bits),
            Some(1 << 63)
        );
    }

    #[test]
    fn damage_is_detected() {
        let bytes = sample().encode().unwrap();
        let mut flipped = bytes.clone();
        let mid = MAGIC.len() + 16 + (bytes.len() - MAGIC.len() - 16) / 2;
        flipped[mid] ^= 0x10;
        assert!(
            Checkpoint::decode(&flipped)
                .unwrap_err()
                .to_string()
                .contains("checksum")
        );
        let cut = &bytes[..bytes.len() - 1];
        assert!(matches!(
            Checkpoint::decode(cut),
            Err(DecodeError::Length { .. })
        ));
        assert!(
            Checkpoint::decode(cut)
                .unwrap_err()
                .to_string()
                .contains("truncated")
        );
        assert_eq!(Checkpoint::decode(b"{}").unwrap_err(), DecodeError::Header);
        assert!(Checkpoint::decode(&bytes[..MAGIC.len() + 3]).is_err());
    }

    #[test]
    fn another_format_is_named_and_a_missing_field_is_refused() {
        // Format 1 (before checkpoints were bound to the build): refused as such.
        let mut old = b"stickslip checkpoint 1\n".to_vec();
        old.extend_from_slice(&sample().encode().unwrap()[MAGIC.len()..]);
        assert_eq!(format_of(&old).as_deref(), Some("1"));
        assert!(
            Checkpoint::decode(&old)
                .unwrap_err()
                .to_string()
                .contains("checkpoint format 1, this build reads 3")
        );
        // Format 2 (before the driver followed the stamp's slips): refused as such.
        let mut two = b"stickslip checkpoint 2\n".to_vec();
        two.extend_from_slice(&sample().encode().unwrap()[MAGIC.len()..]);
        assert!(
            Checkpoint::decode(&two)
                .unwrap_err()
                .to_string()
                .contains("checkpoint format 2, this build reads 3")
        );
        assert_eq!(format_of(&sample().encode().unwrap()), None);
        assert_eq!(format_of(b"not a checkpoint"), None);
        // A payload without one of its fields is not filled in by default.
        let bytes = sample().encode().unwrap();
        let payload: ciborium::Value = ciborium::from_reader(&bytes[MAGIC.len() + 16..]).unwrap();
        let mut payload = payload.into_map().unwrap();
        let sim = payload
            .iter_mut()
            .find(|(k, _)| k.as_text() == Some("sim"))
            .map(|(_, v)| v.as_map_mut().unwrap())
            .unwrap();
        let stepper = sim
            .iter_mut()
            .find(|(k, _)| k.as_text() == Some("stepper"))
            .map(|(_, v)| v.as_map_mut().unwrap())
            .unwrap();
        stepper.retain(|(k, _)| k.as_text() != Some("prev_dt_s"));
        let mut cut = Vec::new();
        ciborium::into_writer(&ciborium::Value::Map(payload), &mut cut).unwrap();
        let err = Checkpoint::decode(&file_of(&cut)).unwrap_err().to_string();
        assert!(err.contains("prev_dt_s"), "{err}");
    }

    #[test]
    fn another_build_is_refused_unless_allowed() {
        let dir = Path::new("out");
        let mut c = sample();
        assert_eq!(check_build(dir, &c, false).unwrap(), None);
        c.build = Cow::Borrowed("0123456789abcdef");
        let err = check_build(dir, &c, false).unwrap_err();
        assert_eq!(err.exit(), crate::exit::Exit::BadInput);
        assert_eq!(
            err.to_string(),
            format!(
                "{} was written by build 0123456789abcdef and this is build {BUILD_ID}: its \
                 numbers would differ; rerun, or resume with --allow-other-build to continue \
                 anyway",
                path(dir).display()
            )
        );
        assert_eq!(
            check_build(dir, &c, true).unwrap(),
            Some(BuildCrossing {
                checkpoint_build: "0123456789abcdef".to_string(),
                build: BUILD_ID.to_string(),
            })
        );
    }

    #[test]
    fn zero_and_unreachable_intervals_never_come_due() {
        assert_eq!(interval(0.0), None);
        assert_eq!(interval(1e300), None);
        assert_eq!(interval(0.5), Some(Duration::from_millis(500)));
    }
}
