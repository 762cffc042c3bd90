//! Bounded reads: every input file the program reads (a scene, a sweep file, a sweep's lock,
//! tables and point records) is checked before it is read — a regular file (never a device,
//! a FIFO or a directory, which could block or never end) no larger than its kind's cap — and
//! read no further than the cap, so no input costs more memory than its cap. The caps are far
//! above any real file of the kind and are documented in the reference.

use std::io::{self, Read};
use std::path::Path;

/// One kind of input file and the largest such file read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cap {
    /// What the file is, for messages (`scene file`).
    pub what: &'static str,
    /// Largest size read, bytes.
    pub max_bytes: u64,
}

/// A scene file: a real one is a few kB.
pub const SCENE: Cap = Cap {
    what: "scene file",
    max_bytes: 1 << 20,
};
/// A sweep file (its values listed inline at most).
pub const SWEEP: Cap = Cap {
    what: "sweep file",
    max_bytes: 16 << 20,
};
/// A sweep's `sweep.json` (the definition and a fingerprint).
pub const SWEEP_LOCK: Cap = Cap {
    what: "sweep.json",
    max_bytes: 16 << 20,
};
/// A sweep point's record (`points/*.json`).
pub const POINT_RECORD: Cap = Cap {
    what: "sweep point record",
    max_bytes: 1 << 20,
};
/// A shard's table of a sweep (`shards/*.json`: a row per point of the shard).
pub const SHARD_TABLE: Cap = Cap {
    what: "shard table",
    max_bytes: 1 << 30,
};

/// A sweep's spot-check record (`DIR/checks/<point>.json`): a few runs' summaries.
pub const CHECK_RECORD: Cap = Cap {
    what: "sweep spot-check record",
    max_bytes: 1 << 20,
};

/// A measured friction trace for `stickslip fit` (a few columns of numbers per sample: 64 MB
/// holds about a million samples).
pub const TRACE: Cap = Cap {
    what: "trace file",
    max_bytes: 64 << 20,
};

/// Every cap, for the reference.
pub const ALL: [Cap; 7] = [
    SCENE,
    SWEEP,
    SWEEP_LOCK,
    POINT_RECORD,
    SHARD_TABLE,
    CHECK_RECORD,
    TRACE,
];

/// Why a file was not read (the size and the cap; callers name the path).
fn refused(why: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidData, why)
}

/// The bytes of `path` if it is a regular file of at most `cap.max_bytes`.
///
/// # Errors
/// The open or read error, or [`io::ErrorKind::InvalidData`] for a path that is not a regular
/// file (a device, FIFO, socket or directory) or a file larger than the cap.
pub fn read(path: &Path, cap: Cap) -> io::Result<Vec<u8>> {
    // Checked before opening: opening a FIFO for reading blocks until a writer comes.
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(refused(format!(
            "not a regular file (a directory, device, FIFO or socket); allowed: a {} of at \
                 most {} bytes",
            cap.what, cap.max_bytes
        )));
    }
    let too_large = |size: u64| {
        refused(format!(
            "a {} of {size} bytes is larger than allowed: at most {} bytes",
            cap.what, cap.max_bytes
        ))
    };
    if meta.len() > cap.max_bytes {
        return Err(too_large(meta.len()));
    }
    let mut bytes = Vec::with_capacity(usize::try_from(meta.len()).unwrap_or(0));
    // One byte past the cap tells a file that grew since the check.
    std::fs::File::open(path)?
        .take(cap.max_bytes + 1)
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > cap.max_bytes {
        return Err(too_large(bytes.len() as u64));
    }
    Ok(bytes)
}

/// [`read`] as UTF-8 text.
///
/// # Errors
/// As [`read`], and [`io::ErrorKind::InvalidData`] for text that is not UTF-8.
pub fn read_text(path: &Path, cap: Cap) -> io::Result<String> {
    String::from_utf8(read(path, cap)?).map_err(|e| refused(format!("not UTF-8 text ({e})")))
}

/// The caps as a Markdown paragraph (docs/reference.md).
#[must_use]
pub fn markdown() -> String {
    let caps: Vec<String> = ALL
        .iter()
        .map(|c| format!("{} {} MiB", c.what, c.max_bytes >> 20))
        .collect();
    format!(
        "Input files are read only if they are regular files (never a device, FIFO or \
         directory) no larger than their kind's cap: {}. Anything else exits 2 at once, naming \
         the file, its size and the cap.\n",
        caps.join(", ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_directories_and_oversized_files_are_refused_before_reading() {
        let dir = tempfile::tempdir().unwrap();
        let e = read(Path::new("/dev/zero"), SCENE).unwrap_err();
        assert!(e.to_string().contains("not a regular file"), "{e}");
        let e = read(dir.path(), SCENE).unwrap_err();
        assert!(e.to_string().contains("not a regular file"), "{e}");
        let big = dir.path().join("big.toml");
        let f = std::fs::File::create(&big).unwrap();
        // Sparse: the size is checked, nothing is read.
        f.set_len(3 << 30).unwrap();
        let e = read(&big, SCENE).unwrap_err();
        assert!(
            e.to_string().contains(
                "a scene file of 3221225472 bytes is larger than allowed: at most 1048576 bytes"
            ),
            "{e}"
        );
        let ok = dir.path().join("ok.toml");
        std::fs::write(&ok, "name = \"x\"\n").unwrap();
        assert_eq!(read_text(&ok, SCENE).unwrap(), "name = \"x\"\n");
        std::fs::write(&ok, [0xff, 0xfe]).unwrap();
        assert!(
            read_text(&ok, SCENE)
                .unwrap_err()
                .to_string()
                .contains("not UTF-8")
        );
    }
}
