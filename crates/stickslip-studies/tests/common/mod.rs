//! Helpers shared by the studies' integration tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// Path of a scene in validation/scenes.
pub fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../validation/scenes")
        .join(format!("{name}.toml"))
}
