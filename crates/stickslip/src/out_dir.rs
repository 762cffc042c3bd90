//! The output directory of `verify` and `fit`, made and checked before any computing: a run of
//! minutes or hours must not end in "cannot write". `--out` that holds files is refused
//! unless `--force` (as `run` refuses an earlier run's results); the directory is created and
//! a file written and removed in it, so that an unwritable place, a full disk or a name the
//! file system refuses fail now, with exit 1, not after the work.

use std::path::{Path, PathBuf};
use stickslip_run::exit::Exit;

/// A fresh directory `PREFIX-NAME`, `PREFIX-NAME-2`, … that does not exist yet (`verify`'s
/// and `fit`'s default output directory).
pub fn fresh_dir(prefix: &str, name: &str) -> PathBuf {
    let safe: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "-_.".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    (1..)
        .map(|k| {
            PathBuf::from(if k == 1 {
                format!("{prefix}-{safe}")
            } else {
                format!("{prefix}-{safe}-{k}")
            })
        })
        .find(|p| !p.exists())
        .unwrap_or_else(|| PathBuf::from(prefix))
}

/// An output directory checked before the work.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct OutDir {
    /// Where.
    pub path: PathBuf,
    /// Whether this check created it (so that an error before any output may remove it).
    pub created: bool,
}

impl OutDir {
    /// Removes the directory again if this check created it and nothing was written to it:
    /// a command that stops on bad input leaves no empty directory behind.
    pub fn discard_if_unused(&self) {
        if self.created {
            let _ = std::fs::remove_dir(&self.path);
        }
    }
}

/// The directory `out` (or a fresh `PREFIX-NAME`), checked and created; the message and exit
/// status when it cannot be used.
///
/// # Errors
/// Exit 2 for an `--out` that is a file or holds files without `force`; exit 1 when it cannot
/// be created or written.
pub fn prepare(
    out: Option<&Path>,
    prefix: &str,
    name: &str,
    force: bool,
) -> Result<OutDir, (String, Exit)> {
    prepare_resumable(out, prefix, name, force, &[])
}

/// As [`prepare`], a directory holding only the entries `kept` (an interrupted command's
/// finished work, which it reuses) accepted without `force`.
///
/// # Errors
/// As [`prepare`].
pub fn prepare_resumable(
    out: Option<&Path>,
    prefix: &str,
    name: &str,
    force: bool,
    kept: &[&str],
) -> Result<OutDir, (String, Exit)> {
    let dir = out.map_or_else(|| fresh_dir(prefix, name), Path::to_path_buf);
    let created = !dir.exists();
    if !created {
        if !dir.is_dir() {
            return Err((
                format!("--out {} is a file, not a directory", dir.display()),
                Exit::BadInput,
            ));
        }
        let used = std::fs::read_dir(&dir)
            .map(|mut entries| {
                entries.any(|e| {
                    e.ok()
                        .and_then(|e| e.file_name().to_str().map(str::to_string))
                        .is_none_or(|n| !kept.contains(&n.as_str()))
                })
            })
            .unwrap_or(false);
        if used && !force {
            return Err((
                format!(
                    "--out {} already holds files (an earlier result?); choose another \
                     directory, or add --force to write over it",
                    dir.display()
                ),
                Exit::BadInput,
            ));
        }
    }
    let probe = dir.join(format!(".{prefix}-write-check.{}", std::process::id()));
    std::fs::create_dir_all(&dir)
        .and_then(|()| std::fs::write(&probe, b"stickslip"))
        .and_then(|()| std::fs::remove_file(&probe))
        .map_err(|e| (format!("cannot write in {}: {e}", dir.display()), Exit::Io))?;
    Ok(OutDir { path: dir, created })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_used_directory_needs_force_and_a_file_is_refused() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("v");
        let made = prepare(Some(&dir), "verify", "x", false).unwrap();
        assert_eq!(made.path, dir);
        assert!(made.created);
        // Empty after the check: the write probe is gone; unused, it can go again.
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
        made.discard_if_unused();
        assert!(!dir.exists());
        let made = prepare(Some(&dir), "verify", "x", false).unwrap();
        assert!(prepare(Some(&dir), "verify", "x", false).is_ok_and(|d| !d.created));
        drop(made);
        std::fs::write(dir.join("verify.json"), b"{}").unwrap();
        let (msg, exit) = prepare(Some(&dir), "verify", "x", false).unwrap_err();
        assert_eq!(exit, Exit::BadInput);
        assert!(msg.contains("--force"), "{msg}");
        assert!(prepare(Some(&dir), "verify", "x", true).is_ok());
        let file = tmp.path().join("f");
        std::fs::write(&file, b"").unwrap();
        let (msg, exit) = prepare(Some(&file), "fit", "x", true).unwrap_err();
        assert_eq!(exit, Exit::BadInput);
        assert!(msg.contains("is a file"), "{msg}");
    }
}
