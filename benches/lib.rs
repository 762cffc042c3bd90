//! Shared helpers of the criterion benches (the benches themselves are the `[[bench]]` targets).

use std::path::Path;
pub use stickslip_run::keys::Setting;
use stickslip_run::{ResolvedScene, Scene};

/// The shipped scene `name` of `validation/scenes` with `sets` applied.
///
/// # Panics
/// If the scene does not resolve (the benches use fixed, valid overrides).
#[must_use]
pub fn scene(name: &str, sets: &[Setting]) -> ResolvedScene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../validation/scenes")
        .join(format!("{name}.toml"));
    Scene::from_path(&path, &[] as &[&str])
        .and_then(|s| s.with_settings(sets))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}
