//! Records the build identity of the numerics (see `src/build_id/mod.rs`): the hash of the
//! sources that decide a run's numbers, and with the compiler, target and optimisation level
//! the identity a sweep's points carry. Reruns when those sources change, not on every commit.

#[path = "src/build_id/sources.rs"]
mod sources;

use std::path::PathBuf;
use std::process::Command;

fn main() {
    let manifest = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
    let root = manifest.join("../..");
    for rel in sources::HASHED {
        println!("cargo:rerun-if-changed=../../{rel}");
    }
    // Outside the workspace (the sources cannot all be read) the identity is unknown: every
    // build then counts as different, which recomputes rather than reuses.
    let sources = match sources::sources_hash(&root) {
        Ok(h) => format!("{h:016x}"),
        Err(e) => {
            println!("cargo:warning=stickslip-run: build identity unknown: {e}");
            "unknown".to_string()
        }
    };
    let rustc = std::env::var_os("RUSTC").unwrap_or_else(|| "rustc".into());
    let compiler = Command::new(rustc)
        .arg("-vV")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
        .unwrap_or_default();
    let mut h = sources::fnv(sources::FNV_INIT, sources.as_bytes());
    for var in [
        "CARGO_PKG_VERSION",
        "TARGET",
        "OPT_LEVEL",
        "CARGO_ENCODED_RUSTFLAGS",
    ] {
        h = sources::fnv(h, &[0]);
        h = sources::fnv(h, std::env::var(var).unwrap_or_default().as_bytes());
    }
    h = sources::fnv(h, compiler.as_bytes());
    let build = if sources == "unknown" {
        // A different identity for every such build: the time of the build.
        let now = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos());
        format!("unknown-{now}")
    } else {
        format!("{h:016x}")
    };
    println!("cargo:rustc-env=STICKSLIP_SOURCES_HASH={sources}");
    println!("cargo:rustc-env=STICKSLIP_BUILD_ID={build}");
}
