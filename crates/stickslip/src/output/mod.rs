//! Output files of a run: atomic writing (`DIR/.<name>.tmp`, fsync, rename), the CSV tables
//! ([`tables`]) and `run.json` ([`report`]).
//!
//! Numbers are written with Rust's `{:e}` formatting, the shortest text that parses back to
//! the same f64 (e.g. `1e-8`, `1.2540123e-3`, `0e0`), so identical runs give identical bytes.

pub mod report;
pub mod tables;

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

/// A file written under a temporary name in its directory and renamed into place on
/// [`AtomicFile::commit`]; a reader never sees a half-written file. Dropped without a commit,
/// the temporary file is removed.
#[derive(Debug)]
pub struct AtomicFile {
    tmp: PathBuf,
    target: PathBuf,
    writer: Option<BufWriter<File>>,
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
        })
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
    pub fn commit(mut self) -> io::Result<()> {
        let Some(writer) = self.writer.take() else {
            return Ok(());
        };
        let file = writer
            .into_inner()
            .map_err(io::IntoInnerError::into_error)?;
        file.sync_all()?;
        drop(file);
        std::fs::rename(&self.tmp, &self.target)?;
        if let Some(dir) = self.target.parent()
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
            Some(w) => w.write(buf),
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

/// Writes `x` in shortest round-trip scientific notation (`{:e}`).
///
/// # Errors
/// Those of the writer.
pub fn write_num(w: &mut impl Write, x: f64) -> io::Result<()> {
    write!(w, "{x:e}")
}
