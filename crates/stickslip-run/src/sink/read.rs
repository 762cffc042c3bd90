//! Reading the output directory of a run in any state: ended (`ok` or `failed`), interrupted,
//! or killed without a graceful stop (run.json still says `running`).
//!
//! An ended run and an interrupted one have every file under its documented name (an
//! interrupted run publishes copies of its streams, see [`super::dir`]): they are read as
//! they are. A killed run left its streams as `.<name>.tmp` and, if it got that far, a
//! checkpoint. Then the streams are read up to the positions the checkpoint recorded, the
//! events, counters and summary come from the checkpoint's state (nothing is simulated), and
//! the data are those of one consistent instant, the last checkpoint. Without a checkpoint
//! the complete rows the temporary files hold are read (series and probes rows cut to the
//! same count, profiles to whole profiles) and there are no events. An interrupted directory
//! of an earlier version (no published copies) is read like a killed one.

use crate::atomic::StreamPosition;
use crate::checkpoint::{self, Checkpoint};
use crate::driver::{Snapshot, warnings_of};
use crate::outcome::{RunStatus, StopReason};
use crate::schema::Table;
use crate::schema::events::Events;
use crate::schema::probes::Probes;
use crate::schema::profiles::Profiles;
use crate::schema::run_info::RunInfo;
use crate::schema::series::Series;
use crate::schema::slips::Slips;
use crate::schema::{self, RunOutput, SchemaError};
use crate::summary::RegimeThresholds;
use std::io;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Where the data of a run directory were read from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    /// The files under their documented names (an ended or interrupted run).
    Files,
    /// The temporary files of a run that was killed (or is still running), up to its last
    /// checkpoint.
    Checkpoint,
    /// The temporary files of a run killed before its first checkpoint: their complete rows,
    /// no events.
    Temporaries,
}

/// What [`read_run`] found.
#[derive(Debug, Clone, PartialEq)]
pub struct ReadRun {
    /// The run's output; `info.status` is run.json's.
    pub output: RunOutput,
    /// Where it came from.
    pub source: Source,
}

/// Why a directory could not be read as a run.
#[derive(Debug, Error)]
pub enum ReadError {
    /// No run there.
    #[error(
        "{} is not a run directory ({why}); allowed: the output directory of a run \
         (`stickslip run --out DIR`, or `out=DIR` in Python)",
        dir.display()
    )]
    Missing {
        /// The directory.
        dir: PathBuf,
        /// What is missing.
        why: String,
    },
    /// A file that does not read as its schema says.
    #[error(transparent)]
    Schema(#[from] SchemaError),
}

/// Reads the run in `dir`, whatever its state (see the module docs).
///
/// # Errors
/// [`ReadError::Missing`] without a directory or run.json there; [`ReadError::Schema`] for a
/// file that cannot be read or parsed.
pub fn read_run(dir: &Path) -> Result<ReadRun, ReadError> {
    let missing = |why: &str| ReadError::Missing {
        dir: dir.to_path_buf(),
        why: why.to_string(),
    };
    if !dir.is_dir() {
        return Err(missing(if dir.exists() {
            "not a directory"
        } else {
            "no such directory"
        }));
    }
    if !dir.join(schema::run_info::FILE).is_file() {
        return Err(missing("no run.json"));
    }
    let info = RunInfo::read(dir)?;
    let published = [
        schema::series::FILE,
        schema::events::FILE,
        schema::profiles::FILE,
        schema::probes::FILE,
    ]
    .iter()
    .all(|f| dir.join(f).is_file());
    // A run an I/O error ended kept its rows in the temporary files.
    let ended = matches!(info.status, RunStatus::Ok | RunStatus::Failed)
        && info.stop.as_deref() != Some(super::dir::IO_STOP);
    if ended || (info.status == RunStatus::Interrupted && published) {
        return Ok(ReadRun {
            output: RunOutput::read(dir)?,
            source: Source::Files,
        });
    }
    from_temporaries(dir, info)
}

/// The text of the stream `name`: its temporary file (or, for a run killed while committing,
/// the file renamed into place), up to `at` when that much is there, else up to its last
/// complete line; `None` when neither file exists (a stream lost, which then does not cut
/// the others' rows).
fn stream_text(
    dir: &Path,
    name: &str,
    at: Option<StreamPosition>,
) -> Result<Option<String>, ReadError> {
    let tmp = dir.join(format!(".{name}.tmp"));
    let bytes = match std::fs::read(&tmp) {
        Ok(b) => b,
        Err(e) if e.kind() == io::ErrorKind::NotFound => match std::fs::read(dir.join(name)) {
            Ok(b) => b,
            Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(SchemaError::io(&dir.join(name), &e).into()),
        },
        Err(e) => return Err(SchemaError::io(&tmp, &e).into()),
    };
    let end = match at.and_then(|p| usize::try_from(p.bytes).ok()) {
        Some(n) if n <= bytes.len() => n,
        _ => bytes.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1),
    };
    Ok(Some(String::from_utf8_lossy(&bytes[..end]).into_owned()))
}

/// `text` (a header and rows) with at most `rows` rows.
fn first_rows(text: &str, rows: usize) -> &str {
    let end = text
        .match_indices('\n')
        .nth(rows)
        .map_or(text.len(), |(i, _)| i + 1);
    &text[..end]
}

/// Rows of `text` after its header.
fn row_count(text: &str) -> usize {
    text.lines().count().saturating_sub(1)
}

/// A header line written by `write` when a stream has none yet.
fn or_header(text: String, write: impl FnOnce(&mut Vec<u8>) -> io::Result<()>) -> String {
    if !text.is_empty() {
        return text;
    }
    let mut out = Vec::new();
    // Writing to a Vec cannot fail.
    let _ = write(&mut out);
    String::from_utf8_lossy(&out).into_owned()
}

fn from_temporaries(dir: &Path, mut info: RunInfo) -> Result<ReadRun, ReadError> {
    // A checkpoint of another format or a damaged one is no checkpoint here; another build's
    // is: reading its state steps nothing.
    let checkpoint: Option<Checkpoint<'static>> = checkpoint::load(dir).ok();
    let at = checkpoint.as_ref().map(|c| c.streams);
    let probe_radii: Vec<f64> = info
        .scene
        .output
        .as_ref()
        .and_then(|o| o.probe_radii.clone())
        .unwrap_or_default();
    let series = stream_text(dir, schema::series::FILE, at.map(|a| a.series))?;
    let probes = stream_text(dir, schema::probes::FILE, at.map(|a| a.probes))?;
    // Series and probes rows are written together, profiles a whole profile at a time: rows
    // cut off by a kill are dropped so the tables agree (a stream that is lost altogether
    // cuts nothing: what the others hold is read).
    let series = series.map(|s| or_header(s, Series::write_header));
    let probes = probes.map(|p| or_header(p, |w| Probes::write_header(w, &probe_radii)));
    let rows = [&series, &probes]
        .into_iter()
        .flatten()
        .map(|text| row_count(text))
        .min()
        .unwrap_or(0);
    let series = series.unwrap_or_else(|| or_header(String::new(), Series::write_header));
    let probes = probes
        .unwrap_or_else(|| or_header(String::new(), |w| Probes::write_header(w, &probe_radii)));
    let profiles = or_header(
        stream_text(dir, schema::profiles::FILE, at.map(|a| a.profiles))?.unwrap_or_default(),
        Profiles::write_header,
    );
    let nodes = info.derived.nodes.max(1);
    let profile_rows = row_count(&profiles) / nodes * nodes;
    let mut output = RunOutput {
        series: Series::parse(first_rows(&series, rows))?,
        probes: Probes::parse(first_rows(&probes, rows))?,
        profiles: Profiles::parse(first_rows(&profiles, profile_rows))?,
        events: Events::default(),
        slips: Slips::default(),
        info: info.clone(),
    };
    let source = match checkpoint {
        Some(c) => {
            let snapshot = Snapshot {
                scene: &c.scene,
                preflight: &c.preflight,
                sim: &c.sim,
                driver: &c.driver,
                wall_seconds: c.driver.wall_before_s,
            };
            let outcome = snapshot.outcome(
                StopReason::Interrupted,
                None,
                warnings_of(&c.scene, &c.preflight),
                &RegimeThresholds::default(),
            );
            // Counters, time, events and summary as of the checkpoint; the status and the
            // stop reason stay run.json's.
            let (status, stop, failure) = (info.status, info.stop.take(), info.failure.take());
            info.finish(&outcome);
            info.status = status;
            info.stop = stop;
            if failure.is_some() {
                info.failure = failure;
            }
            output.events = Events(outcome.events);
            output.slips = Slips(outcome.slips);
            output.info = info;
            Source::Checkpoint
        }
        None => Source::Temporaries,
    };
    Ok(ReadRun { output, source })
}
