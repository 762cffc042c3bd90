//! One writer per run directory. `run` and `resume` hold an advisory lock on
//! `DIR/.stickslip.lock` while they write: a second process that would write the same
//! directory (two `resume`s at once, a `run --force` into a directory a run is still
//! writing) is refused before it touches anything, instead of overwriting the first one's
//! run.json with its own failure. The kernel releases the lock when the process ends, however
//! it ends, so a killed run leaves no stale lock (only the empty file, which the next writer
//! locks again); a writer that ends normally removes the file while it still holds it.

use std::fs::{File, OpenOptions, TryLockError};
use std::io;
use std::path::{Path, PathBuf};

/// The lock file's name inside a run directory.
pub const FILE: &str = ".stickslip.lock";

/// Why a directory could not be locked.
#[derive(Debug)]
pub enum LockError {
    /// Another process holds the lock.
    Busy,
    /// The lock file cannot be opened or locked.
    Io(io::Error),
}

/// A held lock on a run directory, released when dropped (or when the process ends).
#[derive(Debug)]
pub struct DirLock {
    _file: File,
    path: PathBuf,
    /// Remove the file when dropped: it was created here, or the writing ended
    /// ([`DirLock::finished`]); a refused or failed start leaves a killed run's file as found.
    remove: bool,
}

impl Drop for DirLock {
    /// Removes the lock file while still holding it, so that a finished directory holds
    /// only its results; a process that opened the old file meanwhile finds it unlinked
    /// ([`DirLock::acquire`] compares the locked file with the path's) and is refused.
    fn drop(&mut self) {
        if self.remove {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

impl DirLock {
    /// The writing ended (whatever its outcome): the lock file goes with the lock.
    pub fn finished(&mut self) {
        self.remove = true;
    }

    /// Locks `dir` (which must exist) for writing.
    ///
    /// # Errors
    /// [`LockError::Busy`] when another process holds it, [`LockError::Io`] when the lock
    /// file cannot be opened or locked.
    pub fn acquire(dir: &Path) -> Result<Self, LockError> {
        let out_dir = LockError::Io;
        let path = dir.join(FILE);
        let existed = path.exists();
        let file = OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&path)
            .map_err(out_dir)?;
        match file.try_lock() {
            // Locked, but maybe a file a finished writer had already unlinked (it removes the
            // lock file on the way out): then another process may hold the path's new file.
            Ok(()) => {
                use std::os::unix::fs::MetadataExt as _;
                let same = match (file.metadata(), std::fs::metadata(&path)) {
                    (Ok(held), Ok(now)) => held.ino() == now.ino() && held.dev() == now.dev(),
                    _ => false,
                };
                if same {
                    Ok(Self {
                        _file: file,
                        path,
                        remove: !existed,
                    })
                } else {
                    Err(LockError::Busy)
                }
            }
            Err(TryLockError::WouldBlock) => Err(LockError::Busy),
            Err(TryLockError::Error(e)) => Err(out_dir(e)),
        }
    }
}
