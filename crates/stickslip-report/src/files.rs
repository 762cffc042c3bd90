//! The one report writer: a report's files (its page, its JSON record, its figures) written
//! into one directory, each atomically, an error naming the file, and the list of what was
//! written for the generator's summary.

use serde::Serialize;
use std::path::{Path, PathBuf};

/// A directory that a report generator writes its files into.
#[derive(Debug)]
pub struct ReportFiles {
    dir: PathBuf,
    written: Vec<PathBuf>,
}

impl ReportFiles {
    /// The directory `dir`, created when missing.
    ///
    /// # Errors
    /// The directory cannot be created (the message names it).
    pub fn create(dir: &Path) -> Result<Self, String> {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        Ok(Self {
            dir: dir.to_path_buf(),
            written: Vec::new(),
        })
    }

    /// Writes `text` to `name` in the directory, atomically (a reader sees the old file or
    /// the new one, never a part). A file that says the same but when and where it was made
    /// ([`crate::provenance::same_but_when`]) is kept as it is: regenerating unchanged
    /// results changes no file.
    ///
    /// # Errors
    /// The file cannot be written (the message names it).
    pub fn put(&mut self, name: &str, text: impl AsRef<[u8]>) -> Result<(), String> {
        let path = self.dir.join(name);
        let unchanged = std::fs::read(&path).is_ok_and(|old| {
            match (
                std::str::from_utf8(&old),
                std::str::from_utf8(text.as_ref()),
            ) {
                (Ok(old), Ok(new)) => crate::provenance::same_but_when(old, new),
                _ => old == text.as_ref(),
            }
        });
        if !unchanged {
            crate::write_atomic(&path, text.as_ref())
                .map_err(|e| format!("{}: {e}", path.display()))?;
        }
        self.written.push(path);
        Ok(())
    }

    /// Writes `value` as pretty-printed JSON with a final newline to `name`.
    ///
    /// # Errors
    /// As [`ReportFiles::put`], or `value` cannot be serialised.
    pub fn put_json<T: Serialize>(&mut self, name: &str, value: &T) -> Result<(), String> {
        let text = serde_json::to_string_pretty(value).map_err(|e| format!("{name}: {e}"))?;
        self.put(name, text + "\n")
    }

    /// The files written so far, in order.
    #[must_use]
    pub fn written(&self) -> &[PathBuf] {
        &self.written
    }

    /// The files written, in order.
    #[must_use]
    pub fn into_written(self) -> Vec<PathBuf> {
        self.written
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn files_are_written_listed_and_errors_name_the_file() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("reports");
        let mut files = ReportFiles::create(&dir).unwrap();
        files.put("a.md", "page\n").unwrap();
        files.put_json("a.json", &[1.5, 2.0]).unwrap();
        assert_eq!(std::fs::read_to_string(dir.join("a.md")).unwrap(), "page\n");
        assert_eq!(
            std::fs::read_to_string(dir.join("a.json")).unwrap(),
            "[\n  1.5,\n  2.0\n]\n"
        );
        assert_eq!(files.written(), [dir.join("a.md"), dir.join("a.json")]);
        // A directory where the file should go: the error names the file.
        std::fs::create_dir(dir.join("b.svg")).unwrap();
        let err = files.put("b.svg", "<svg/>").unwrap_err();
        assert!(err.contains("b.svg"), "{err}");
        assert_eq!(files.into_written().len(), 2);
    }
}
