//! The build identity of the numerics, recorded by `build.rs`: a sweep's points carry it, so a
//! point computed by another build is recomputed, never reused silently.
//!
//! It is a hash of the sources that decide a run's numbers and a study's records
//! ([`sources::HASHED`]: the core's, the run library's and the studies' sources and
//! manifests, `Cargo.lock`), of the compiler's version, the package version, the target and
//! the optimisation level. Commits that change none of these (documentation, reports, the
//! command line, Python) keep the identity, and the crates are
//! not rebuilt for it; any change to the numerics changes it. The test below recomputes the
//! hash from the tree and compares it with the recorded one, so a file that changes the
//! numbers cannot escape the list `build.rs` watches.

pub mod sources;

/// Hash of the sources ([`sources::sources_hash`]), 16 hex digits, or `unknown`.
pub const SOURCES_HASH: &str = env!("STICKSLIP_SOURCES_HASH");

/// The build identity: sources, compiler, target and optimisation level, 16 hex digits (or
/// `unknown-…`, different for every build, where the sources could not be read).
pub const BUILD_ID: &str = env!("STICKSLIP_BUILD_ID");

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn root() -> &'static Path {
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
    }

    #[test]
    fn the_recorded_identity_is_that_of_the_sources_in_the_tree() {
        let now = sources::sources_hash(root()).unwrap();
        assert_eq!(
            format!("{now:016x}"),
            SOURCES_HASH,
            "the build recorded another hash of the sources than the tree has now: a hashed \
             file is not watched by build.rs (cargo:rerun-if-changed)"
        );
        assert_eq!(BUILD_ID.len(), 16);
        assert_ne!(BUILD_ID, SOURCES_HASH);
    }

    #[test]
    fn changing_one_byte_of_the_numerics_changes_the_hash() {
        let tmp = tempfile::tempdir().unwrap();
        for (rel, path) in sources::files(root()).unwrap() {
            let to = tmp.path().join(&rel);
            std::fs::create_dir_all(to.parent().unwrap()).unwrap();
            std::fs::copy(path, to).unwrap();
        }
        let before = sources::sources_hash(tmp.path()).unwrap();
        assert_eq!(format!("{before:016x}"), SOURCES_HASH);
        let step = tmp.path().join("crates/stickslip-core/src/landau.rs");
        let mut text = std::fs::read(&step).unwrap();
        text.push(b'\n');
        std::fs::write(&step, text).unwrap();
        let after = sources::sources_hash(tmp.path()).unwrap();
        assert_ne!(before, after);
        // A file that is not among the hashed sources does not count.
        std::fs::write(tmp.path().join("README.md"), b"changed").unwrap();
        assert_eq!(sources::sources_hash(tmp.path()).unwrap(), after);
    }
}
