//! Shared helpers of the criterion benches (the benches themselves are the `[[bench]]` targets).

use std::path::Path;
use stickslip_run::{ResolvedScene, Scene};

/// The shipped scene `name` of `validation/scenes` with `sets` applied.
///
/// # Panics
/// If the scene does not resolve (the benches use fixed, valid overrides).
#[must_use]
pub fn scene(name: &str, sets: &[&str]) -> ResolvedScene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../validation/scenes")
        .join(format!("{name}.toml"));
    Scene::from_path(&path, sets).unwrap_or_else(|e| panic!("{name}: {e}"))
}
