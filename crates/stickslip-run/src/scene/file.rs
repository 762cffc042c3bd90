//! The scene file as written: the serde mirror of the scene TOML, generated with the key
//! registry ([`crate::keys::registry`]) so that each field is one of its entries.
//!
//! Unknown keys are rejected (`deny_unknown_fields` on every section). Which keys are required,
//! their defaults and their allowed ranges are decided when the scene is resolved
//! ([`super::resolve`]); the resolved scene is this same structure with every default filled in,
//! so it can be written to `run.json` and read back as a scene.
//!
//! Words are serde enums (the core's where it has them), so a misspelt word is a
//! deserialization error, translated into a message naming the key and the allowed words of
//! the registry.

pub use crate::keys::registry::{
    ContactSection, DriveSection, LubricantSection, NoiseSection, NumericsSection, OutputSection,
    Scene, TemperatureSection, TimeSection,
};
pub use crate::keys::words::{
    ContactModel, DriveKind, FilmStep, GridChoice, Integrator, NoiseKindName, OperatorChoice,
    Scheme, Stepping, Substrate, TemperatureLaw, Until,
};
