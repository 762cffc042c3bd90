//! Scenes: parse the TOML, apply `--set` overrides, fill in the defaults, validate, and hand back
//! a [`ResolvedScene`] (the engine's [`SimConfig`] plus the output settings).
//!
//! Pipeline (each stage stops at the first problem, as a [`SceneError`] naming the key, the
//! value and the allowed range; nothing here panics on any input):
//! 1. the text is parsed as a TOML table ([`toml_text`]);
//! 2. `--set` overrides are applied to the table ([`overrides`]);
//! 3. the table is deserialized into [`Scene`] (unknown keys, wrong types and misspelt words
//!    are rejected, [`error`]);
//! 4. required keys, defaults and rules between keys are resolved, single-key ranges checked
//!    against the key registry [`crate::keys`] ([`resolve`]);
//! 5. [`SimConfig::validate`] and the scene-level checks (output times and radii, step count,
//!    no non-finite number anywhere) run.
//!
//! The defaults, ranges and words are the key registry's ([`crate::keys`]).

pub mod error;
pub mod file;
pub mod overrides;
mod resolve;
pub mod toml_text;

pub use error::SceneError;
pub use file::{
    ContactSection, DriveSection, LubricantSection, NoiseSection, NumericsSection, OutputSection,
    Scene, TemperatureSection, TimeSection,
};
pub use resolve::resolve;

use serde::{Deserialize, Serialize};
use stickslip_core::config::{Derived, SimConfig};

/// Default `time.tolerance` (adaptive stepping), from the registry: fig2 at N = 200 against a
/// same-N converged reference gives onsets within 2 ns, f_peak within 7.3e-5 relative.
pub const DEFAULT_TOLERANCE: f64 = match crate::keys::time::TOLERANCE.fixed_default() {
    Some(v) => v,
    None => panic!("time.tolerance has a fixed default"),
};
pub use crate::keys::MAX_STEPS;

/// What the driver records, besides the simulation itself.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OutputSettings {
    /// Times of the profiles, s, as given (each within [0, time.end]).
    pub profile_times_s: Vec<f64>,
    /// Radii of the φ(t) probes, m, as given (each within [0, a0)).
    pub probe_radii_m: Vec<f64>,
    /// Interval between rows of series.csv and probes.csv, s (> 0).
    pub series_interval_s: f64,
    /// A slip's drop as a fraction of τmax·πa0² (`output.slip_drop`, in (0, 1]).
    pub slip_drop: f64,
}

impl OutputSettings {
    /// A slip's drop of the drive force, N: `slip_drop` × τmax·πa0² of `config`.
    #[must_use]
    pub fn slip_drop_n(&self, config: &SimConfig) -> f64 {
        let a0 = config.contact.radius_m;
        self.slip_drop * config.lubricant.tau_max_pa * std::f64::consts::PI * a0 * a0
    }

    /// The profile times, s, sorted and deduplicated.
    #[must_use]
    pub fn sorted_profile_times_s(&self) -> Vec<f64> {
        let mut times_s = self.profile_times_s.clone();
        times_s.sort_by(f64::total_cmp);
        times_s.dedup();
        times_s
    }
}

/// A validated scene, ready to run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ResolvedScene {
    /// The scene's `name`.
    pub name: String,
    /// The engine configuration.
    pub config: SimConfig,
    /// Output settings.
    pub output: OutputSettings,
    /// Stop once this many events have ended (`time.max_events`).
    pub max_events: Option<u64>,
    /// Stop once an event has stayed open this long, s (`time.max_open_event`).
    pub max_open_event_s: Option<f64>,
    /// When the run counts as steady, and whether it stops there (`time.until`,
    /// `time.steady_cycles`, `time.steady_rtol`).
    #[serde(default)]
    pub steady: crate::steady::SteadyRule,
    /// The scene with every default filled in (written to run.json, printed by `check`).
    pub resolved: Scene,
    /// The scene as written, overrides applied: what [`ResolvedScene::with_overrides`]
    /// starts from (derived defaults such as `time.dt_max` follow a changed `time.end`).
    pub source: toml::Table,
    /// Derived parameters b, A, εc, φ0, ω.
    pub derived: Derived,
    /// Number of steps: ⌈end/dt − 1e-9⌉, all of length dt except the last, which lands on end
    /// (fixed stepping; with adaptive steps only a scale for the progress bar).
    pub steps: u64,
}

/// Number of steps for `end_s` and `dt_s`: ⌈end/dt − 1e-9⌉, at least 1.
#[must_use]
pub fn step_count(end_s: f64, dt_s: f64) -> u64 {
    let n = (end_s / dt_s - 1e-9).ceil();
    if n.is_finite() && n >= 1.0 {
        // Validation caps end/dt at MAX_STEPS, far inside u64.
        n as u64
    } else {
        1
    }
}

impl Scene {
    /// Reads a scene file as UTF-8 text: a regular file of at most [`crate::bounded::SCENE`]'s
    /// cap, checked before it is read.
    ///
    /// # Errors
    /// [`SceneError::Read`] if the file cannot be read, is not a regular file, is too large or
    /// is not UTF-8.
    pub fn read_text(path: &std::path::Path) -> Result<String, SceneError> {
        crate::bounded::read_text(path, crate::bounded::SCENE).map_err(|e| SceneError::Read {
            path: path.display().to_string(),
            message: e.to_string(),
        })
    }

    /// Parses `text` into a TOML table.
    ///
    /// # Errors
    /// [`SceneError::Syntax`] naming line and column.
    pub fn parse_table(text: &str) -> Result<toml::Table, SceneError> {
        text.parse().map_err(|e| toml_text::syntax_error(text, &e))
    }

    /// Applies `overrides` (`section.key=value`, in order) to `table`, resolves defaults and
    /// validates.
    ///
    /// # Errors
    /// The first problem, as a [`SceneError`] naming key, value and allowed range.
    pub fn resolve_table<S: AsRef<str>>(
        mut root: toml::Table,
        overrides: &[S],
    ) -> Result<ResolvedScene, SceneError> {
        for o in overrides {
            overrides::apply_override(&mut root, o.as_ref())?;
        }
        error::check_sections(&root)?;
        // serde reads a TOML date as a string; a name is text.
        if let Some(v) = root.get(crate::keys::NAME.path)
            && !v.is_str()
        {
            return Err(SceneError::WrongType {
                key: crate::keys::NAME.path.to_string(),
                value: error::show_value(v),
                allowed: "a string (name = \"...\")".to_string(),
            });
        }
        let scene: Scene = root
            .clone()
            .try_into()
            .map_err(|e| error::from_de_error(&root, &e))?;
        let mut resolved = resolve(&scene).map_err(|e| e.with_all_missing(&root))?;
        toml_text::check_finite(&root, &mut Vec::new())?;
        resolved.source = root;
        Ok(resolved)
    }

    /// Parses `text`, applies `overrides` (`section.key=value`, in order), resolves defaults and
    /// validates.
    ///
    /// # Errors
    /// The first problem, as a [`SceneError`] naming key, value and allowed range.
    ///
    /// # Example
    /// ```
    /// use stickslip_run::Scene;
    /// const SCENE: &str = r#"
    /// name = "example"
    /// [lubricant]
    /// tau_max = 1e6
    /// eps_max = 1
    /// a = 1e6
    /// gamma = 10
    /// [contact]
    /// radius = 2e-5
    /// film_thickness = 1e-7
    /// g_eff = 1e9
    /// nodes = 20
    /// [drive]
    /// stiffness = 500
    /// mass = 0.1
    /// velocity = 1
    /// [time]
    /// end = 2e-4
    /// [output]
    /// profile_times = []
    /// "#;
    /// let scene = Scene::from_toml_str(SCENE, &["contact.nodes=40"]).unwrap();
    /// assert_eq!(scene.config.contact.nodes, 40);
    /// // Defaults are filled in: the accurate scheme's time step, in s.
    /// assert_eq!(scene.config.time.dt_s, 1e-8);
    /// // A value out of range names the key, the value and what is allowed.
    /// let err = Scene::from_toml_str(SCENE, &["contact.radius=-1"]).unwrap_err();
    /// assert!(err.to_string().contains("contact.radius"));
    /// ```
    pub fn from_toml_str<S: AsRef<str>>(
        text: &str,
        overrides: &[S],
    ) -> Result<ResolvedScene, SceneError> {
        Self::resolve_table(Self::parse_table(text)?, overrides)
    }

    /// [`Scene::read_text`] then [`Scene::from_toml_str`].
    ///
    /// # Errors
    /// As those two.
    pub fn from_path<S: AsRef<str>>(
        path: &std::path::Path,
        overrides: &[S],
    ) -> Result<ResolvedScene, SceneError> {
        Self::from_toml_str(&Self::read_text(path)?, overrides)
    }

    /// [`Scene::from_path`] with the keys `unset` removed from the file first (a key the
    /// file does not set is left as it is: its default applies either way), then `overrides`
    /// applied: `--unset drive.stiffness --unset drive.mass --set drive.kind=rigid` turns a
    /// spring scene rigid without editing the file.
    ///
    /// # Errors
    /// [`SceneError::Unset`] for a name that is no scene key; else as [`Scene::from_path`].
    pub fn from_path_unsetting<S: AsRef<str>, U: AsRef<str>>(
        path: &std::path::Path,
        unset: &[U],
        overrides: &[S],
    ) -> Result<ResolvedScene, SceneError> {
        let mut table = Self::parse_table(&Self::read_text(path)?)?;
        for key in unset {
            let key = key.as_ref();
            if crate::keys::find(key).is_none() {
                return Err(SceneError::Unset {
                    key: key.to_string(),
                    problem: "no such scene key".into(),
                });
            }
            let (section, name) = key.rsplit_once('.').unwrap_or(("", key));
            let holder = if section.is_empty() {
                Some(&mut table)
            } else {
                section.split('.').try_fold(&mut table, |t, part| {
                    t.get_mut(part).and_then(toml::Value::as_table_mut)
                })
            };
            if let Some(t) = holder {
                t.remove(name);
            }
        }
        Self::resolve_table(table, overrides)
    }

    /// The scene as a TOML table.
    #[must_use]
    pub fn to_table(&self) -> toml::Table {
        toml::Table::try_from(self).unwrap_or_default()
    }

    /// The scene as TOML text, numbers in shortest round-trip `{:e}` form (e.g. `1e-8`); the
    /// text parses back to the same scene.
    #[must_use]
    pub fn to_toml_string(&self) -> String {
        toml_text::to_toml_string(&self.to_table())
    }
}

impl ResolvedScene {
    /// The resolved scene as a TOML table (every default filled in).
    #[must_use]
    pub fn to_table(&self) -> toml::Table {
        self.resolved.to_table()
    }

    /// The same scene with `overrides` applied to it as written (defaults derived from
    /// other keys follow the new values).
    ///
    /// # Errors
    /// As [`Scene::resolve_table`].
    pub fn with_overrides<S: AsRef<str>>(&self, overrides: &[S]) -> Result<Self, SceneError> {
        Scene::resolve_table(self.source.clone(), overrides)
    }

    /// The same scene with typed `settings` applied to it as written (see
    /// [`crate::keys::Key::set`]; derived defaults follow the new values).
    ///
    /// # Errors
    /// As [`Scene::resolve_table`].
    pub fn with_settings(&self, settings: &[crate::keys::Setting]) -> Result<Self, SceneError> {
        let mut table = self.source.clone();
        for s in settings {
            s.apply(&mut table);
        }
        Scene::resolve_table(table, &[] as &[&str])
    }

    /// Warnings for values outside their key's usual range (likely unit slips).
    #[must_use]
    pub fn unusual_values(&self) -> Vec<(String, String)> {
        crate::keys::unusual_values(&self.to_table())
    }
}
