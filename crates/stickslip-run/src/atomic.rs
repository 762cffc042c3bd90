//! The one atomic writer of the project: a file is written as `DIR/.<name>.tmp`, synced,
//! renamed into place and its directory synced, so a reader never sees a half-written file and
//! a crash leaves either the old file or the new one.
//!
//! A streamed [`AtomicFile`] knows its [`StreamPosition`] (length and checksum of what it has
//! written), so a checkpoint can record how far each file got and a resumed run can
//! [`reopen`](AtomicFile::reopen) it at exactly that point.

use serde::{Deserialize, Serialize};
use std::fs::{File, OpenOptions};
use std::io::{self, BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

/// Initial state of [`fnv1a64`].
pub const FNV1A64_INIT: u64 = 0xcbf2_9ce4_8422_2325;

/// Continues the 64-bit FNV-1a hash `state` over `bytes` (start from [`FNV1A64_INIT`]).
///
/// A checksum, not a cryptographic hash: it catches damaged or foreign files, cheaply enough to
/// run over every byte a run writes. Its definition is fixed, so values stored in a checkpoint
/// stay comparable across builds.
pub fn fnv1a64(mut state: u64, bytes: &[u8]) -> u64 {
    for &b in bytes {
        state ^= u64::from(b);
        state = state.wrapping_mul(0x0000_0100_0000_01b3);
    }
    state
}

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

impl AtomicFile {
    /// Creates `dir/.<name>.tmp` for writing; [`commit`](Self::commit) renames it to `dir/name`.
    ///
    /// # Errors
    /// If the temporary file cannot be created.
    pub fn create(dir: &Path, name: &str) -> io::Result<Self> {
        let tmp = dir.join(format!(".{name}.tmp"));
        let target = dir.join(name);
        let file = File::create(&tmp)?;
        Ok(Self {
            tmp,
            target,
            writer: Some(BufWriter::new(file)),
            position: StreamPosition::START,
        })
    }

    /// Continues the file `dir/name` of an interrupted run at `at`, which a checkpoint
    /// recorded: the first `at.bytes` bytes of the temporary file `dir/.<name>.tmp` are kept
    /// and whatever follows them (written after the checkpoint) is cut off. When the temporary
    /// file is gone because the run was killed while committing its output, those bytes are
    /// taken from the committed `dir/name` instead.
    ///
    /// # Errors
    /// [`io::ErrorKind::NotFound`] if neither file exists; [`io::ErrorKind::InvalidData`] if
    /// the file is shorter than `at.bytes` or its first `at.bytes` bytes do not have the
    /// recorded checksum (a damaged file, or one of another run); other I/O errors as they come.
    pub fn reopen(dir: &Path, name: &str, at: StreamPosition) -> io::Result<Self> {
        let tmp = dir.join(format!(".{name}.tmp"));
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
