//! The hash of the sources that decide a run's numbers and a study's records: every file under
//! the core's, the run library's and the studies' `src/`, their manifests and the workspace's
//! `Cargo.lock` (dependency versions, e.g. the linear algebra). The studies' sources count
//! because they make each point's scene (a sweep's axes, a spot check's refinement): a record
//! of a sweep or spot check is reused only by a build that would make it the same. Shared by `build.rs`, which records it in the build, and
//! the test that recomputes it from the tree and compares; it uses only `std`.

use std::io;
use std::path::{Path, PathBuf};

/// What is hashed, relative to the workspace root: directories are walked recursively.
pub const HASHED: [&str; 7] = [
    "crates/stickslip-core/src",
    "crates/stickslip-core/Cargo.toml",
    "crates/stickslip-run/src",
    "crates/stickslip-run/Cargo.toml",
    "crates/stickslip-studies/src",
    "crates/stickslip-studies/Cargo.toml",
    "Cargo.lock",
];

/// 64-bit FNV-1a of `bytes`, continued from `state`.
pub fn fnv(mut state: u64, bytes: &[u8]) -> u64 {
    for &b in bytes {
        state ^= u64::from(b);
        state = state.wrapping_mul(0x0000_0100_0000_01b3);
    }
    state
}

/// Initial state of [`fnv`].
pub const FNV_INIT: u64 = 0xcbf2_9ce4_8422_2325;

fn walk(path: &Path, out: &mut Vec<PathBuf>) -> io::Result<()> {
    if path.is_dir() {
        for entry in std::fs::read_dir(path)? {
            walk(&entry?.path(), out)?;
        }
    } else {
        out.push(path.to_path_buf());
    }
    Ok(())
}

/// The files of [`HASHED`] under `root`, sorted by their path relative to `root` ('/'
/// separators).
///
/// # Errors
/// If one of them is missing or cannot be listed.
pub fn files(root: &Path) -> io::Result<Vec<(String, PathBuf)>> {
    let mut paths = Vec::new();
    for rel in HASHED {
        let path = root.join(rel);
        if !path.exists() {
            return Err(io::Error::new(
                io::ErrorKind::NotFound,
                format!("{} is missing", path.display()),
            ));
        }
        walk(&path, &mut paths)?;
    }
    let mut named: Vec<(String, PathBuf)> = paths
        .into_iter()
        .map(|p| {
            let rel = p
                .strip_prefix(root)
                .unwrap_or(&p)
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect::<Vec<_>>()
                .join("/");
            (rel, p)
        })
        .collect();
    named.sort();
    Ok(named)
}

/// The hash of the files of [`HASHED`] under the workspace `root`: each file's relative path,
/// its length and its bytes.
///
/// # Errors
/// If a file is missing or cannot be read.
pub fn sources_hash(root: &Path) -> io::Result<u64> {
    let mut h = FNV_INIT;
    for (rel, path) in files(root)? {
        let bytes = std::fs::read(&path)?;
        h = fnv(h, rel.as_bytes());
        h = fnv(h, &[0]);
        h = fnv(h, &(bytes.len() as u64).to_le_bytes());
        h = fnv(h, &bytes);
    }
    Ok(h)
}
