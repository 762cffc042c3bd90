//! The one atomic writer of the project: a file is written under a temporary name in its
//! directory, synced, renamed into place and its directory synced, so a reader never sees a
//! half-written file and a crash leaves either the old file or the new one.
//!
//! **Temporary names.** [`AtomicFile::create`] (and every `write_atomic*` function) writes
//! `DIR/.<name>.<pid>-<n>.tmp`, unique per process and per call (so per thread), created with
//! `create_new`: any number of processes and threads may write the same file at once (the
//! shards of a sweep writing `sweep.json`, merges writing `map.csv`); each rename is atomic and
//! the last one wins. A process killed while writing leaves its temporary file behind; readers
//! ignore dot files, and [`remove_temporaries`] clears them where one process owns the
//! directory. Only the streamed outputs of a run, which a resumed run must find again, use the
//! fixed name `DIR/.<name>.tmp` ([`AtomicFile::create_resumable`]): a run directory has one
//! writer.
//!
//! A streamed [`AtomicFile`] knows its [`StreamPosition`] (length and checksum of what it has
//! written), so a checkpoint can record how far each file got and a resumed run can
//! [`reopen`](AtomicFile::reopen) it at exactly that point.

use serde::{Deserialize, Serialize};
use std::fs::{File, OpenOptions};
use std::io::{self, BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// The 64-bit FNV-1a hash, the one the build's identity uses too: continues `state` over
/// `bytes` (start from [`FNV1A64_INIT`]).
///
/// A checksum, not a cryptographic hash: it catches damaged or foreign files, cheaply enough to
/// run over every byte a run writes. Its definition is fixed, so values stored in a checkpoint
/// stay comparable across builds.
pub use crate::build_id::sources::{FNV_INIT as FNV1A64_INIT, fnv as fnv1a64};

/// How far a streamed file has got: the bytes written and their checksum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct StreamPosition {
    /// Bytes written (header included).
    pub bytes: u64,
    /// [`fnv1a64`] of those bytes.
    pub fnv1a64: u64,
}

impl StreamPosition {
    /// An empty file.
    pub const START: Self = Self {
        bytes: 0,
        fnv1a64: FNV1A64_INIT,
    };

    fn advance(&mut self, bytes: &[u8]) {
        self.bytes += bytes.len() as u64;
        self.fnv1a64 = fnv1a64(self.fnv1a64, bytes);
    }
}

/// An [`io::ErrorKind::InvalidData`] error: a file is not what a checkpoint says it is.
fn invalid_data(message: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidData, message)
}

/// A file written under a temporary name in its directory and renamed into place on
/// [`AtomicFile::commit`]; a reader never sees a half-written file. Dropped without a commit,
/// the temporary file is removed.
#[derive(Debug)]
pub struct AtomicFile {
    tmp: PathBuf,
    target: PathBuf,
    writer: Option<BufWriter<File>>,
    position: StreamPosition,
}

/// Calls of [`unique_temporary`] in this process so far.
static TEMPORARIES: AtomicU64 = AtomicU64::new(0);

/// A temporary name for `name` that no other process or call of this process uses:
/// `.<name>.<pid>-<n>.tmp`.
fn unique_temporary(name: &str) -> String {
    let n = TEMPORARIES.fetch_add(1, Ordering::Relaxed);
    format!(".{name}.{}-{n}.tmp", std::process::id())
}

/// The fixed temporary name of a resumable stream: `.<name>.tmp`.
fn resumable_temporary(name: &str) -> String {
    format!(".{name}.tmp")
}

/// Removes every temporary file of `dir/name` (the resumable `.<name>.tmp` and the unique
/// `.<name>.<pid>-<n>.tmp` that killed writers left). Only where one process owns the
/// directory (a run's output directory): elsewhere it would remove files other writers are
/// still writing.
///
/// # Errors
/// If the directory cannot be listed or a file cannot be removed (a missing directory or file
/// is not an error).
pub fn remove_temporaries(dir: &Path, name: &str) -> io::Result<()> {
    let entries = match std::fs::read_dir(dir) {
        Ok(e) => e,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(e),
    };
    let prefix = format!(".{name}.");
    for entry in entries {
        let entry = entry?;
        let file = entry.file_name();
        let file = file.to_string_lossy();
        if file.starts_with(&prefix) && file.ends_with(".tmp") {
            match std::fs::remove_file(entry.path()) {
                Err(e) if e.kind() != io::ErrorKind::NotFound => return Err(e),
                _ => {}
            }
        }
    }
    Ok(())
}

impl AtomicFile {
    /// Creates a temporary file unique to this call (`dir/.<name>.<pid>-<n>.tmp`, see the
    /// module docs) for writing; [`commit`](Self::commit) renames it to `dir/name`.
    ///
    /// # Errors
    /// If the temporary file cannot be created.
    pub fn create(dir: &Path, name: &str) -> io::Result<Self> {
        let tmp = dir.join(unique_temporary(name));
        let file = OpenOptions::new().write(true).create_new(true).open(&tmp)?;
        Ok(Self {
            tmp,
            target: dir.join(name),
            writer: Some(BufWriter::new(file)),
            position: StreamPosition::START,
        })
    }

    /// Creates `dir/.<name>.tmp`, the fixed temporary name that [`reopen`](Self::reopen)
    /// finds again: for the streamed outputs of a run, which one process writes and a resumed
    /// run continues. An earlier file of that name is truncated.
    ///
    /// # Errors
    /// If the temporary file cannot be created.
    pub fn create_resumable(dir: &Path, name: &str) -> io::Result<Self> {
        let tmp = dir.join(resumable_temporary(name));
        let target = dir.join(name);
        let file = File::create(&tmp)?;
        Ok(Self {
            tmp,
            target,
            writer: Some(BufWriter::new(file)),
            position: StreamPosition::START,
        })
    }

    /// Whether `dir`'s streamed file `name` (its resumable temporary, or the final name an
    /// interrupted run published) still holds the first `at.bytes` bytes with the recorded
    /// checksum; `Ok(true)` when they are in the final name. Reads only, changes nothing: a
    /// resume checks every stream this way before it reopens any, so one that cannot go on
    /// leaves the directory as it found it.
    ///
    /// # Errors
    /// When neither file exists, it is shorter, or its first bytes differ.
    pub fn check_prefix(dir: &Path, name: &str, at: StreamPosition) -> io::Result<bool> {
        let tmp = dir.join(resumable_temporary(name));
        let target = dir.join(name);
        let (source, from_target) = if tmp.exists() {
            (tmp.clone(), false)
        } else if target.exists() {
            (target.clone(), true)
        } else {
            return Err(io::Error::new(
                io::ErrorKind::NotFound,
                format!("neither {} nor {} exists", tmp.display(), target.display()),
            ));
        };
        let mut prefix = File::open(&source)?.take(at.bytes);
        let mut seen = StreamPosition::START;
        let mut buf = vec![0u8; 1 << 16];
        loop {
            let n = prefix.read(&mut buf)?;
            if n == 0 {
                break;
            }
            seen.advance(&buf[..n]);
        }
        if seen.bytes < at.bytes {
            return Err(invalid_data(format!(
                "{} has {} bytes, the checkpoint recorded {}",
                source.display(),
                seen.bytes,
                at.bytes
            )));
        }
        if seen.fnv1a64 != at.fnv1a64 {
            return Err(invalid_data(format!(
                "the first {} bytes of {} are not those the checkpoint recorded (checksum \
                 {:016x}, recorded {:016x})",
                at.bytes,
                source.display(),
                seen.fnv1a64,
                at.fnv1a64
            )));
        }
        Ok(from_target)
    }

    /// Continues the file `dir/name` of an interrupted run at `at`, which a checkpoint
    /// recorded: the first `at.bytes` bytes of the temporary file `dir/.<name>.tmp` (written by
    /// [`create_resumable`](Self::create_resumable)) are kept
    /// and whatever follows them (written after the checkpoint) is cut off. When the temporary
    /// file is gone because the run was killed while committing its output, those bytes are
    /// taken from the committed `dir/name` instead.
    ///
    /// # Errors
    /// [`io::ErrorKind::NotFound`] if neither file exists; [`io::ErrorKind::InvalidData`] if
    /// the file is shorter than `at.bytes` or its first `at.bytes` bytes do not have the
    /// recorded checksum (a damaged file, or one of another run); other I/O errors as they come.
    pub fn reopen(dir: &Path, name: &str, at: StreamPosition) -> io::Result<Self> {
        let tmp = dir.join(resumable_temporary(name));
        let target = dir.join(name);
        let from_target = Self::check_prefix(dir, name, at)?;
        let mut file = if from_target {
            let mut file = File::create(&tmp)?;
            io::copy(&mut File::open(&target)?.take(at.bytes), &mut file)?;
            file
        } else {
            let file = OpenOptions::new().write(true).open(&tmp)?;
            file.set_len(at.bytes)?;
            file
        };
        file.seek(SeekFrom::Start(at.bytes))?;
        Ok(Self {
            tmp,
            target,
            writer: Some(BufWriter::new(file)),
            position: at,
        })
    }

    /// Flushes what is buffered, syncs it to disk and returns how far the file has got: a
    /// checkpoint taken after this refers only to bytes that are durably in the file.
    ///
    /// # Errors
    /// If flushing or syncing fails.
    pub fn sync_position(&mut self) -> io::Result<StreamPosition> {
        if let Some(w) = &mut self.writer {
            w.flush()?;
            w.get_ref().sync_data()?;
        }
        Ok(self.position)
    }

    /// Keeps the temporary file as it is after a failed write (a full disk): what is buffered
    /// is flushed as far as it goes, and the file is not removed, so the rows written so far
    /// stay readable and resumable.
    pub fn keep_after_failure(mut self) {
        if let Some(w) = &mut self.writer {
            let _ = w.flush();
        }
        self.writer = None;
    }

    /// Flushes and syncs the file and leaves it under its temporary name, for a resumed run
    /// to continue ([`AtomicFile::reopen`]); dropping it would remove it.
    ///
    /// # Errors
    /// If flushing or syncing fails.
    pub fn keep_for_resume(mut self) -> io::Result<()> {
        self.sync_position()?;
        self.writer = None;
        Ok(())
    }

    /// Writes what the stream holds so far to its final name, atomically (through a temporary
    /// name of its own, as [`write_atomic`]), and keeps streaming into the temporary file: an
    /// interrupted run's data become readable under the documented name while the resumable
    /// temporary stays for [`reopen`](Self::reopen); the resumed run's
    /// [`commit`](Self::commit) later replaces the copy with the whole file.
    ///
    /// # Errors
    /// If flushing, reading the temporary file or writing the copy fails.
    pub fn publish_copy(&mut self) -> io::Result<()> {
        let at = self.sync_position()?;
        let (Some(dir), Some(name)) = (self.target.parent(), self.target.file_name()) else {
            return Err(io::Error::other(format!(
                "{} has no directory or file name",
                self.target.display()
            )));
        };
        let mut copy = Self::create(dir, &name.to_string_lossy())?;
        let copied = io::copy(&mut File::open(&self.tmp)?.take(at.bytes), &mut copy)?;
        if copied != at.bytes {
            return Err(invalid_data(format!(
                "{} holds {copied} bytes, {} were written",
                self.tmp.display(),
                at.bytes
            )));
        }
        copy.commit()
    }

    /// Final path of the file.
    pub fn path(&self) -> &Path {
        &self.target
    }

    /// Flushes, fsyncs, renames into place and fsyncs the directory (best effort on platforms
    /// where directories cannot be opened).
    ///
    /// # Errors
    /// If any of these fails.
    pub fn commit(self) -> io::Result<()> {
        self.finish(Durability::Rename)
    }

    /// Renames the file into place as [`commit`](Self::commit) does, without syncing anything:
    /// a killed process loses nothing (the page cache outlives it), but after a power loss or
    /// an OS crash the file may be missing, empty or cut short. Only for files that are
    /// checked completely when read and recomputed when they fail the check (a sweep's point
    /// records: a damaged or missing point is run again). An fsync costs about 0.4 ms per file
    /// on a local disk here and far more on a cluster's network file system: for maps of
    /// small points it would be the sweep's largest overhead.
    ///
    /// # Errors
    /// If flushing or renaming fails.
    pub fn commit_unsynced(self) -> io::Result<()> {
        self.finish(Durability::None)
    }

    fn finish(mut self, durability: Durability) -> io::Result<()> {
        let Some(writer) = self.writer.take() else {
            return Ok(());
        };
        let file = writer
            .into_inner()
            .map_err(io::IntoInnerError::into_error)?;
        if durability != Durability::None {
            file.sync_all()?;
        }
        drop(file);
        std::fs::rename(&self.tmp, &self.target)?;
        if durability == Durability::Rename
            && let Some(dir) = self.target.parent()
            && let Ok(d) = File::open(dir)
        {
            // Directory fsync makes the rename durable; not every platform allows it.
            let _ = d.sync_all();
        }
        Ok(())
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match &mut self.writer {
            Some(w) => {
                let n = w.write(buf)?;
                self.position.advance(&buf[..n]);
                Ok(n)
            }
            None => Err(io::Error::other("file already committed")),
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        match &mut self.writer {
            Some(w) => w.flush(),
            None => Ok(()),
        }
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.writer.take().is_some() {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// Writes `bytes` to `dir/name` atomically.
///
/// # Errors
/// If the file cannot be written, synced or renamed.
pub fn write_atomic(dir: &Path, name: &str, bytes: &[u8]) -> io::Result<()> {
    let mut f = AtomicFile::create(dir, name)?;
    f.write_all(bytes)?;
    f.commit()
}

/// As [`write_atomic`], committed with [`AtomicFile::commit_unsynced`]: other processes see
/// the old file or the whole new one, but nothing is durable across a power loss; for files
/// whose reader checks them completely and recomputes them when damaged.
///
/// # Errors
/// If the file cannot be written or renamed.
pub fn write_atomic_recomputable(dir: &Path, name: &str, bytes: &[u8]) -> io::Result<()> {
    let mut f = AtomicFile::create(dir, name)?;
    f.write_all(bytes)?;
    f.commit_unsynced()
}

/// What a commit makes durable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Durability {
    /// The content and the rename (the directory is synced too).
    Rename,
    /// Nothing: the rename is atomic for other processes, not across a power loss.
    None,
}

/// Writes `bytes` to `path` atomically, creating its directory if needed.
///
/// # Errors
/// If the directory cannot be created or the file cannot be written, synced or renamed.
pub fn write_atomic_path(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    std::fs::create_dir_all(dir)?;
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::other(format!("{} has no file name", path.display())))?;
    write_atomic(dir, &name.to_string_lossy(), bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Names in `dir` (dot files included).
    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn many_threads_writing_one_file_at_once_all_succeed_and_leave_one_whole_file() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        // Each writer's content is long enough that interleaved writes into one shared
        // temporary file would show as a mix.
        let content = |i: usize| format!("{i:04}\n").repeat(20_000);
        for _ in 0..20 {
            std::thread::scope(|s| {
                for i in 0..8 {
                    let bytes = content(i);
                    s.spawn(move || {
                        write_atomic(dir, "shared.json", bytes.as_bytes())
                            .expect("every concurrent writer commits");
                        write_atomic_recomputable(dir, "unsynced.json", bytes.as_bytes())
                            .expect("every concurrent writer commits");
                    });
                }
            });
            for f in ["shared.json", "unsynced.json"] {
                let got = std::fs::read_to_string(dir.join(f)).unwrap();
                assert!(
                    (0..8).any(|i| got == content(i)),
                    "{f} is not one writer's whole content ({} bytes)",
                    got.len()
                );
            }
            assert_eq!(names(dir), ["shared.json", "unsynced.json"]);
        }
    }

    #[test]
    fn a_published_copy_is_readable_and_the_stream_goes_on() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        let mut f = AtomicFile::create_resumable(dir, "s.csv").unwrap();
        f.write_all(b"t\n1e0\n").unwrap();
        f.publish_copy().unwrap();
        assert_eq!(std::fs::read(dir.join("s.csv")).unwrap(), b"t\n1e0\n");
        f.write_all(b"2e0\n").unwrap();
        let at = f.sync_position().unwrap();
        f.keep_for_resume().unwrap();
        // The copy is a snapshot: later rows go to the temporary only.
        assert_eq!(std::fs::read(dir.join("s.csv")).unwrap(), b"t\n1e0\n");
        let mut again = AtomicFile::reopen(dir, "s.csv", at).unwrap();
        again.write_all(b"3e0\n").unwrap();
        again.commit().unwrap();
        assert_eq!(
            std::fs::read(dir.join("s.csv")).unwrap(),
            b"t\n1e0\n2e0\n3e0\n"
        );
        assert_eq!(names(dir), ["s.csv"]);
    }

    #[test]
    fn temporary_names_are_unique_and_removable() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        let a = AtomicFile::create(dir, "x.csv").unwrap();
        let b = AtomicFile::create(dir, "x.csv").unwrap();
        assert_ne!(a.tmp, b.tmp);
        let pid = std::process::id().to_string();
        assert!(a.tmp.to_string_lossy().contains(&pid));
        // As a killed writer would leave them.
        std::mem::forget(a);
        std::mem::forget(b);
        let resumable = AtomicFile::create_resumable(dir, "x.csv").unwrap();
        resumable.keep_for_resume().unwrap();
        std::fs::write(dir.join("x.csv.keep"), b"").unwrap();
        assert_eq!(names(dir).len(), 4);
        remove_temporaries(dir, "x.csv").unwrap();
        assert_eq!(names(dir), ["x.csv.keep"]);
        remove_temporaries(&dir.join("missing"), "x.csv").unwrap();
    }
}
