//! Friction maps: a sweep of one base scene over the cartesian product of axes, each point one
//! in-process run reduced to its summary and regime (docs/model.md#regimes-and-friction-maps).
//!
//! - [`file`]: SWEEP.toml as written and its errors (each naming the key and its line);
//! - [`file_keys`]: the sweep file's keys in one table (the reference's rows, held to the reader);
//! - this module: the resolved [`Sweep`] (axes, points, every point's scene validated before
//!   anything runs, or, beyond [`MAX_POINTS`], each axis value at once and each point when
//!   it runs), its limits and its identity ([`Sweep::fingerprint`]);
//! - [`lock`]: the sweep directory (`sweep.json`: one sweep per directory), its preparation
//!   by any number of processes at once, and the watch that stops a process whose directory
//!   another sweep took over;
//! - [`record`]: one record per finished point, `DIR/points/<point>.json`, written atomically,
//!   carrying the sweep's fingerprint and the point's values;
//! - [`map`]: `map.csv` and `map.json`, writer and reader;
//! - [`exec`]: running points (jobs, shards, resumable, interruptible);
//! - [`merge`]: a shard's table (`DIR/shards/I-of-N.json`) and the merge into the map, from
//!   the tables of a complete set of shards (O(P) for the whole array) or from the records;
//! - [`slurm`]: the job-array script;
//! - [`refine`]: adaptive refinement (`[refine]`): the finest grid, the cells that split, the
//!   next level's points from the results so far, and a refined map's geometry;
//! - [`checks`]: the spot checks' records and report (writer and reader);
//! - [`spot`]: spot checks of the finished map (`[verify]`): the points checked, their
//!   records (`DIR/checks/`), and what changed at a refined resolution, into map.json;
//! - [`reference`]: the sweeps part of `docs/reference.md`, from these definitions.
//!
//! Points are numbered 0 … P−1 in the order of the cartesian product, the last axis fastest
//! (in a refined sweep, of the finest grid's axes). A shard I/N runs the points with index mod
//! N = I (in a refined sweep, every N-th point of each level). Results do not depend on jobs or shards:
//! each point is a deterministic run of its own scene.

pub mod checks;
pub mod exec;
pub mod file;
pub mod file_keys;
pub mod lock;
pub mod map;
pub mod merge;
pub mod record;
pub mod reference;
pub mod refine;
pub mod slurm;
pub mod spot;

pub use file::SweepError;

use file::{AxisFile, SweepFile};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use stickslip_run::atomic::{FNV1A64_INIT, fnv1a64};
use stickslip_run::keys::{self, ValueType};
use stickslip_run::scene::{ResolvedScene, Scene, SceneError};
use stickslip_run::summary::RegimeThresholds;

/// Largest number of points a sweep may have without `allow_large`; up to this many, every
/// point's scene is validated before anything runs.
pub const MAX_POINTS: usize = 100_000;

/// Largest number of points a sweep may have at all (with `allow_large`): point records are
/// files of one directory, numbered with seven digits. Beyond [`MAX_POINTS`] each axis value
/// is validated at once and each point's scene when it runs (a point whose combination of
/// values is invalid is a `refused` row).
pub const HARD_MAX_POINTS: usize = 10_000_000;

/// The point at fraction `f` of a log range from `from` to `to` (both > 0). A point a whole
/// number of decades from either end is that end with its decimal exponent shifted, parsed
/// from text: exactly the nearest double to 1e8 in 1e7 … 1e10, not 1.0000000000000018e8, so
/// values written by hand (`--set`, `[set]`, grouping on 1e8) match them.
fn log_point(from: f64, to: f64, f: f64) -> f64 {
    let decades = f * (to.log10() - from.log10());
    let shifted = |end: f64, k: f64| {
        let text = format!("{end:e}");
        let (mantissa, exponent) = text.split_once('e')?;
        let exponent: i64 = exponent.parse().ok()?;
        format!("{mantissa}e{}", exponent + k as i64)
            .parse::<f64>()
            .ok()
    };
    let whole = |d: f64| (d - d.round()).abs() < 1e-9 && d.round().abs() < 600.0;
    let from_to = decades - (to.log10() - from.log10());
    if whole(decades)
        && let Some(v) = shifted(from, decades.round())
    {
        return v;
    }
    if whole(from_to)
        && let Some(v) = shifted(to, from_to.round())
    {
        return v;
    }
    (from.ln() + f * (to.ln() - from.ln())).exp()
}

/// Whether listed values are log-spaced: all positive, and (sorted) their ratios more even
/// than their differences — [0.3, 1, 3, 10] is, [1, 2, 3, 4] is not; two values when they
/// span a decade or more.
fn log_spaced(values: &[f64]) -> bool {
    if values.len() < 2 || !values.iter().all(|&x| x > 0.0 && x.is_finite()) {
        return false;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    if v.len() == 2 {
        return v[1] / v[0] >= 10.0;
    }
    // Spread of the steps: largest over smallest.
    let spread = |steps: Vec<f64>| {
        let lo = steps.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = steps.iter().copied().fold(0.0, f64::max);
        if lo > 0.0 { hi / lo } else { f64::INFINITY }
    };
    let linear = spread(v.windows(2).map(|w| w[1] - w[0]).collect());
    let ratios = spread(v.windows(2).map(|w| (w[1] / w[0]).ln()).collect());
    ratios < linear
}

/// One axis of a sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Axis {
    /// The scene key it varies.
    pub key: String,
    /// Its values, in order (numbers, or words of a choice key).
    pub values: Vec<toml::Value>,
    /// Values spaced logarithmically (from `range.scale = "log"`, or explicit positive
    /// values whose ratios are more even than their differences): plotted on a log axis.
    pub log: bool,
}

impl Axis {
    /// The values as numbers (NaN for words).
    #[must_use]
    pub fn numbers(&self) -> Vec<f64> {
        self.values.iter().map(value_number).collect()
    }

    /// The unit of the axis key.
    #[must_use]
    pub fn unit(&self) -> &'static str {
        keys::KEYS
            .iter()
            .find(|k| k.path == self.key)
            .map_or("", |k| k.unit)
    }
}

/// A number from a TOML value (NaN for anything else).
#[must_use]
pub fn value_number(v: &toml::Value) -> f64 {
    match v {
        toml::Value::Float(f) => *f,
        toml::Value::Integer(i) => *i as f64,
        _ => f64::NAN,
    }
}

/// A value as written in map.csv: `{:e}` for numbers, the word itself otherwise.
#[must_use]
pub fn value_text(v: &toml::Value) -> String {
    match v {
        toml::Value::Float(f) => format!("{f:e}"),
        toml::Value::Integer(i) => i.to_string(),
        toml::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// A resolved sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sweep {
    /// Name.
    pub name: String,
    /// The sweep file, absolute.
    pub file: PathBuf,
    /// The base scene, absolute.
    pub scene_path: PathBuf,
    /// `[set]`, applied to every point.
    pub set: toml::Table,
    /// The axes.
    pub axes: Vec<Axis>,
    /// Regime thresholds.
    pub thresholds: RegimeThresholds,
    /// Number of points.
    pub points: usize,
    /// The base scene as written (parsed), with `[set]` applied.
    pub base: toml::Table,
    /// `[refine]`, when given: then [`Sweep::axes`] hold the finest grid's values,
    /// [`Sweep::points`] counts that grid, and the points run are the base grid's and those
    /// of the split cells ([`refine`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refine: Option<refine::Refine>,
    /// `[verify]`, when given: spot checks of the finished map ([`spot`]). Not part of the
    /// sweep's definition: the points' results do not depend on it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub verify: Option<spot::SpotChecks>,
}

/// Inserts `value` at the dotted `path` of `table`, creating tables on the way.
fn insert(table: &mut toml::Table, path: &str, value: toml::Value) {
    let parts: Vec<&str> = path.split('.').collect();
    let Some((last, parents)) = parts.split_last() else {
        return;
    };
    let mut t = table;
    for p in parents {
        let entry = t
            .entry((*p).to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        if !entry.is_table() {
            *entry = toml::Value::Table(toml::Table::new());
        }
        let toml::Value::Table(sub) = entry else {
            return;
        };
        t = sub;
    }
    t.insert((*last).to_string(), value);
}

/// `[set]` keys as dotted paths: `"contact.nodes" = 100` or `[set.contact] nodes = 100`.
fn flatten(table: &toml::Table, prefix: &str, out: &mut Vec<(String, toml::Value)>) {
    for (k, v) in table {
        let path = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match v {
            toml::Value::Table(sub) => flatten(sub, &path, out),
            other => out.push((path, other.clone())),
        }
    }
}

/// A value of `values` equal to another one (numbers compared as numbers), found in
/// O(n log n): axes may have 100 000 values.
fn first_duplicate(values: &[toml::Value]) -> Option<&toml::Value> {
    let mut words = std::collections::HashSet::new();
    let mut numbers: Vec<(f64, usize)> = Vec::with_capacity(values.len());
    for (j, v) in values.iter().enumerate() {
        match v {
            toml::Value::String(s) => {
                if !words.insert(s.as_str()) {
                    return Some(v);
                }
            }
            _ => numbers.push((value_number(v), j)),
        }
    }
    numbers.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    numbers
        .windows(2)
        .find(|w| w[0].0 == w[1].0)
        .map(|w| &values[w[1].1])
}

/// Up to 12 values as text, `…` for the rest.
fn shown(values: &[toml::Value]) -> String {
    let mut out: Vec<String> = values.iter().take(12).map(value_text).collect();
    if values.len() > 12 {
        out.push("…".into());
    }
    out.join(", ")
}

fn resolve_axis(i: usize, a: &AxisFile, seen: &[String]) -> Result<Axis, SweepError> {
    let name = |field: &str| format!("axis[{i}].{field}");
    let key = a.key.clone().ok_or_else(|| {
        SweepError::invalid(name("key"), "none", "a scene key (see `stickslip keys`)")
    })?;
    let Some(spec) = keys::KEYS.iter().find(|k| k.path == key) else {
        return Err(SweepError::invalid(
            name("key"),
            format!("{key:?}"),
            "a scene key (see `stickslip keys`)",
        ));
    };
    if key == "name" {
        return Err(SweepError::invalid(
            name("key"),
            "\"name\"",
            "a scene key other than name",
        ));
    }
    if seen.contains(&key) {
        return Err(SweepError::invalid(
            name("key"),
            format!("{key:?}"),
            "a key not already swept by an earlier axis",
        ));
    }
    let (values, log) = match (&a.values, &a.range) {
        (Some(_), Some(_)) | (None, None) => {
            return Err(SweepError::invalid(
                format!("axis[{i}] ({key})"),
                "values and range",
                "exactly one of `values = [...]` or `range = { from, to, count, scale }`",
            ));
        }
        (Some(values), None) => {
            if values.is_empty() {
                return Err(SweepError::invalid(
                    name("values"),
                    "[]",
                    "a non-empty array of values",
                ));
            }
            for v in values {
                let ok = match (spec.value, v) {
                    (ValueType::Choice(words), toml::Value::String(s)) => {
                        words.contains(&s.as_str())
                    }
                    (ValueType::Real | ValueType::Integer, toml::Value::Float(f)) => f.is_finite(),
                    (ValueType::Real | ValueType::Integer, toml::Value::Integer(_)) => true,
                    _ => false,
                };
                if !ok {
                    return Err(SweepError::invalid(
                        name("values"),
                        stickslip_run::scene::error::show_value(v),
                        &format!("values of {key}: {}", spec.allowed()),
                    ));
                }
            }
            if let Some(dup) = first_duplicate(values) {
                return Err(SweepError::invalid(
                    name("values"),
                    stickslip_run::scene::error::show_value(&toml::Value::Array(values.clone())),
                    &format!(
                        "distinct values ({} is listed twice: the same point would run twice)",
                        value_text(dup)
                    ),
                ));
            }
            let nums: Vec<f64> = values.iter().map(value_number).collect();
            (values.clone(), log_spaced(&nums))
        }
        (None, Some(r)) => {
            if !matches!(spec.value, ValueType::Real | ValueType::Integer) {
                return Err(SweepError::invalid(
                    name("range"),
                    "a range",
                    &format!("`values = [...]` for {key}, which takes words"),
                ));
            }
            if r.count < 1 {
                return Err(SweepError::invalid(
                    name("range.count"),
                    r.count,
                    "an integer >= 1",
                ));
            }
            if !(r.from.is_finite() && r.to.is_finite()) {
                return Err(SweepError::invalid(
                    name("range"),
                    format!("from = {}, to = {}", r.from, r.to),
                    "finite bounds",
                ));
            }
            let log = match r.scale.as_deref() {
                None | Some("linear") => false,
                Some("log") => true,
                Some(other) => {
                    return Err(SweepError::invalid(
                        name("range.scale"),
                        format!("{other:?}"),
                        "\"linear\" or \"log\"",
                    ));
                }
            };
            if log && !(r.from > 0.0 && r.to > 0.0) {
                return Err(SweepError::invalid(
                    name("range"),
                    format!("from = {}, to = {}", r.from, r.to),
                    "bounds > 0 with scale = \"log\"",
                ));
            }
            let n = usize::try_from(r.count).unwrap_or(usize::MAX);
            if n > MAX_POINTS {
                return Err(SweepError::invalid(
                    name("range.count"),
                    r.count,
                    &format!("at most {MAX_POINTS} values per axis (also with --allow-large)"),
                ));
            }
            let at = |j: usize| {
                if n == 1 {
                    return r.from;
                }
                let f = j as f64 / (n - 1) as f64;
                if log {
                    log_point(r.from, r.to, f)
                } else {
                    r.from + f * (r.to - r.from)
                }
            };
            let values: Vec<toml::Value> = (0..n)
                .map(|j| {
                    let v = if j == n - 1 { r.to } else { at(j) };
                    if spec.value == ValueType::Integer {
                        toml::Value::Integer(v.round() as i64)
                    } else {
                        toml::Value::Float(v)
                    }
                })
                .collect();
            if let Some(dup) = first_duplicate(&values) {
                let distinct = {
                    let mut d: Vec<String> = values.iter().map(value_text).collect();
                    d.dedup();
                    d.len()
                };
                let allowed = if spec.value == ValueType::Integer {
                    format!(
                        "{key} takes integers: from = {} to {} in {} steps gives {} twice \
                         (rounded: {}); a count of at most {distinct}, or `values = [...]` \
                         with the integers wanted",
                        r.from,
                        r.to,
                        r.count,
                        value_text(dup),
                        shown(&values)
                    )
                } else {
                    format!(
                        "from = {} to {} in {} steps gives {} twice (the same point run \
                         again); bounds that differ, or count = 1 for one value",
                        r.from,
                        r.to,
                        r.count,
                        value_text(dup)
                    )
                };
                return Err(SweepError::invalid(name("range.count"), r.count, &allowed));
            }
            (values, log && n >= 2)
        }
    };
    Ok(Axis { key, values, log })
}

impl Sweep {
    /// Reads and resolves the sweep file at `path`; every point's scene is resolved and
    /// validated. `allow_large` lifts the [`MAX_POINTS`] limit.
    ///
    /// # Errors
    /// The first problem, as a [`SweepError`] naming the key.
    pub fn load(path: &Path, allow_large: bool) -> Result<Self, SweepError> {
        let read_err = |message: String| SweepError::Read {
            path: path.display().to_string(),
            message,
        };
        let text = stickslip_run::bounded::read_text(path, stickslip_run::bounded::SWEEP)
            .map_err(|e| read_err(e.to_string()))?;
        let file = file::parse(&text, &path.display().to_string(), true)?;
        let file_path = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
        Self::resolve(&file, &file_path, allow_large).map_err(|e| e.located(&text))
    }

    /// Resolves a parsed sweep file located at `file_path` (for the relative scene path).
    ///
    /// # Errors
    /// As [`Sweep::load`].
    pub fn resolve(
        file: &SweepFile,
        file_path: &Path,
        allow_large: bool,
    ) -> Result<Self, SweepError> {
        let name = file
            .name
            .clone()
            .filter(|n| !n.trim().is_empty())
            .ok_or_else(|| SweepError::invalid("name", "none", "a non-empty string"))?;
        let scene_rel = file.scene.clone().ok_or_else(|| {
            SweepError::invalid("scene", "none", "a scene file, relative to the sweep file")
        })?;
        let dir = file_path.parent().unwrap_or(Path::new("."));
        let scene_path = dir.join(&scene_rel);
        let text = stickslip_run::bounded::read_text(&scene_path, stickslip_run::bounded::SCENE)
            .map_err(|e| {
                SweepError::invalid(
                    "scene",
                    format!("{scene_rel:?}"),
                    &format!("a readable scene file ({e})"),
                )
            })?;
        let mut base = Scene::parse_table(&text).map_err(|error| SweepError::Base {
            path: scene_path.display().to_string(),
            error: Box::new(error),
            line: None,
        })?;
        let mut set = Vec::new();
        flatten(&file.set, "", &mut set);
        for (key, value) in &set {
            if !keys::KEYS.iter().any(|k| k.path == *key) {
                return Err(SweepError::invalid(
                    format!("set.\"{key}\""),
                    stickslip_run::scene::error::show_value(value),
                    "a scene key (see `stickslip keys`)",
                ));
            }
            insert(&mut base, key, value.clone());
        }
        let thresholds = file.regime.unwrap_or_default();
        if let Err((key, value, allowed)) = thresholds.validate() {
            return Err(SweepError::invalid(
                key,
                stickslip_core::config::bounds::human(value),
                &allowed,
            ));
        }
        let mut axes: Vec<Axis> = Vec::new();
        for (i, a) in file.axis.iter().enumerate() {
            let seen: Vec<String> = axes.iter().map(|a| a.key.clone()).collect();
            let axis = resolve_axis(i, a, &seen)?;
            if set.iter().any(|(k, _)| *k == axis.key) {
                return Err(SweepError::invalid(
                    format!("axis[{i}].key"),
                    format!("{:?}", axis.key),
                    "a key that [set] does not also fix",
                ));
            }
            axes.push(axis);
        }
        if axes.is_empty() {
            return Err(SweepError::invalid("axis", "none", "at least one [[axis]]"));
        }
        // The base grid counts against the limits (the points run up front); a refined
        // sweep's finest grid against the directory's hard limit (refine::resolve).
        let mut points = point_count(&axes, allow_large)?;
        let refine = match &file.refine {
            Some(r) => {
                let (refine, fine) = refine::resolve(r, &axes, &file.axis)?;
                axes = fine;
                points = axes.iter().map(|a| a.values.len()).product();
                Some(refine)
            }
            None => None,
        };
        let verify = file.verify.as_ref().map(spot::resolve).transpose()?;
        Scene::resolve_table(base.clone(), &[] as &[&str]).map_err(|error| SweepError::Base {
            path: scene_path.display().to_string(),
            error: Box::new(error),
            line: None,
        })?;
        let sweep = Self {
            name,
            file: file_path.to_path_buf(),
            scene_path,
            set: file.set.clone(),
            axes,
            thresholds,
            points,
            base,
            refine,
            verify,
        };
        for p in sweep.points_validated_up_front() {
            let scene = sweep.scene(p).map_err(|error| SweepError::Point {
                point: p,
                values: sweep.describe(p),
                error: Box::new(error),
                line: None,
            })?;
            // The spot checks rerun points at 2N and a tenth of the tolerance once the map is
            // complete: a point where they cannot be made is refused now, not after the map.
            if sweep.verify.is_some()
                && let Err(e) = crate::verify::refinements(&scene)
            {
                return Err(SweepError::invalid(
                    "verify",
                    format!("point {p} ({})", sweep.describe(p)),
                    &format!(
                        "points whose spot checks (2N, a tenth of the tolerance) can be made; \
                         here {e} (remove [verify], or change the point's values)"
                    ),
                ));
            }
        }
        Ok(sweep)
    }

    /// Whether every point's scene was validated when the sweep was resolved (at most
    /// [`MAX_POINTS`] points); beyond that, each axis value was, and each point's scene is
    /// validated when the point runs.
    #[must_use]
    pub fn validated_up_front(&self) -> bool {
        self.points <= MAX_POINTS
    }

    /// The points whose scenes [`Sweep::resolve`] validates: all of them up to
    /// [`MAX_POINTS`]; beyond, one point per axis value (that value with every other axis at
    /// its first value).
    fn points_validated_up_front(&self) -> Box<dyn Iterator<Item = usize> + '_> {
        if self.validated_up_front() {
            return Box::new(0..self.points);
        }
        // A refined sweep beyond the limit: its base grid, then one point per value.
        let base = match &self.refine {
            Some(r) if r.base.iter().product::<usize>() <= MAX_POINTS => {
                refine::base_points(self, r)
            }
            _ => Vec::new(),
        };
        // The stride of axis j in the point number (last axis fastest).
        let strides: Vec<usize> = (0..self.axes.len())
            .map(|j| {
                self.axes[j + 1..]
                    .iter()
                    .map(|a| a.values.len())
                    .product::<usize>()
            })
            .collect();
        Box::new(
            base.into_iter().chain(
                self.axes
                    .iter()
                    .zip(strides)
                    .flat_map(|(a, stride)| (0..a.values.len()).map(move |i| i * stride)),
            ),
        )
    }

    /// The number of the point at axis `indices` (last axis fastest); the inverse of
    /// [`Sweep::indices`].
    #[must_use]
    pub fn point(&self, indices: &[usize]) -> usize {
        indices
            .iter()
            .zip(&self.axes)
            .fold(0, |p, (&i, a)| p * a.values.len() + i)
    }

    /// The level of point `p`: 0 for every point of a sweep without `[refine]`, else
    /// [`refine::Refine::level`].
    #[must_use]
    pub fn level(&self, p: usize) -> usize {
        self.refine
            .as_ref()
            .map_or(0, |r| r.level(&self.indices(p)))
    }

    /// The axis indices of point `p` (last axis fastest).
    #[must_use]
    pub fn indices(&self, p: usize) -> Vec<usize> {
        let mut rest = p;
        let mut out = vec![0; self.axes.len()];
        for (slot, axis) in out.iter_mut().zip(&self.axes).rev() {
            let n = axis.values.len();
            *slot = rest % n;
            rest /= n;
        }
        out
    }

    /// The axis values of point `p`.
    #[must_use]
    pub fn values(&self, p: usize) -> Vec<toml::Value> {
        self.indices(p)
            .iter()
            .zip(&self.axes)
            .map(|(&i, a)| a.values[i].clone())
            .collect()
    }

    /// `key = value, …` of point `p`.
    #[must_use]
    pub fn describe(&self, p: usize) -> String {
        self.axes
            .iter()
            .zip(self.values(p))
            .map(|(a, v)| format!("{} = {}", a.key, value_text(&v)))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The resolved scene of point `p`.
    ///
    /// # Errors
    /// The scene's error (naming the key).
    pub fn scene(&self, p: usize) -> Result<ResolvedScene, SceneError> {
        let mut table = self.base.clone();
        for (axis, v) in self.axes.iter().zip(self.values(p)) {
            insert(&mut table, &axis.key, v);
        }
        Scene::resolve_table(table, &[] as &[&str])
    }

    /// The points of shard `index`/`count` (index mod count = `index`), without listing the
    /// others.
    pub fn shard(&self, index: usize, count: usize) -> impl Iterator<Item = usize> + use<> {
        (index..self.points).step_by(count.max(1))
    }

    /// Number of points of shard `index`/`count`.
    #[must_use]
    pub fn shard_len(&self, index: usize, count: usize) -> usize {
        shard_len(self.points, index, count)
    }

    /// What identifies this sweep apart from the build: a hash (16 hex digits) of the base
    /// scene with `[set]`, the axes, the thresholds and `[refine]`.
    #[must_use]
    pub fn definition(&self) -> String {
        // Without [refine] the text is what it was before refinement existed, so the
        // directories of earlier sweeps stay current.
        let text = match &self.refine {
            None => serde_json::to_string(&(&self.base, &self.axes, &self.thresholds)),
            Some(r) => serde_json::to_string(&(&self.base, &self.axes, &self.thresholds, r)),
        }
        .unwrap_or_default();
        format!("{:016x}", fnv1a64(FNV1A64_INIT, text.as_bytes()))
    }

    /// What identifies this sweep's results: everything that decides a point's outcome, the
    /// sweep ([`Sweep::definition`]) and the build of the numerics
    /// ([`stickslip_run::build_id::BUILD_ID`]), as `DEFINITION-BUILD`.
    #[must_use]
    pub fn fingerprint(&self) -> String {
        fingerprint(&self.definition(), stickslip_run::build_id::BUILD_ID)
    }
}

/// The fingerprint of a sweep `definition` computed by `build`.
#[must_use]
pub fn fingerprint(definition: &str, build: &str) -> String {
    format!("{definition}-{build}")
}

/// The definition and the build of a fingerprint (`None` if it has no `-`).
#[must_use]
pub fn split_fingerprint(fingerprint: &str) -> Option<(&str, &str)> {
    fingerprint.split_once('-')
}

/// Number of points of shard `index`/`count` among `points`.
#[must_use]
pub fn shard_len(points: usize, index: usize, count: usize) -> usize {
    if index >= points || count == 0 {
        0
    } else {
        (points - index).div_ceil(count)
    }
}

/// The number of points of `axes`, in overflow-safe arithmetic: at most [`MAX_POINTS`], or
/// [`HARD_MAX_POINTS`] with `allow_large`.
///
/// # Errors
/// Too many points, naming the count per axis.
pub fn point_count(axes: &[Axis], allow_large: bool) -> Result<usize, SweepError> {
    let counts: Vec<String> = axes.iter().map(|a| a.values.len().to_string()).collect();
    let product = axes
        .iter()
        .try_fold(1usize, |p, a| p.checked_mul(a.values.len()));
    let shown = |p: Option<usize>| {
        format!(
            "{} points ({})",
            p.map_or_else(|| "more than 2^64".to_string(), |p| p.to_string()),
            counts.join(" × ")
        )
    };
    match product {
        Some(p) if p <= MAX_POINTS => Ok(p),
        Some(p) if p <= HARD_MAX_POINTS && allow_large => Ok(p),
        p if allow_large => Err(SweepError::invalid(
            "axis",
            shown(p),
            &format!(
                "at most {HARD_MAX_POINTS} points (the limit of one sweep directory); split \
                 the sweep"
            ),
        )),
        p => Err(SweepError::invalid(
            "axis",
            shown(p),
            &format!(
                "at most {MAX_POINTS} points without --allow-large (allow_large=True in \
                 Python), at most {HARD_MAX_POINTS} with it"
            ),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::{log_point, log_spaced};

    #[test]
    fn listed_values_are_log_spaced_when_their_ratios_are_even() {
        assert!(log_spaced(&[0.3, 1.0, 3.0, 10.0]));
        assert!(log_spaced(&[10.0, 1.0, 100.0]));
        assert!(log_spaced(&[1e7, 1e8]));
        assert!(!log_spaced(&[1.0, 2.0, 3.0, 4.0]));
        assert!(!log_spaced(&[1.0, 2.0]));
        assert!(!log_spaced(&[-1.0, 1.0, 10.0]));
        assert!(!log_spaced(&[5.0]));
    }

    fn range(from: f64, to: f64, n: usize) -> Vec<f64> {
        (0..n)
            .map(|j| log_point(from, to, j as f64 / (n - 1) as f64))
            .collect()
    }

    #[test]
    fn log_ranges_hit_every_decade_exactly() {
        assert_eq!(range(1e7, 1e10, 4), vec![1e7, 1e8, 1e9, 1e10]);
        // Every power of ten between powers-of-ten ends, at several points per decade.
        for lo in -30_i32..30 {
            for span in 1..6 {
                for per_decade in [1, 2, 3, 4, 10] {
                    let from: f64 = format!("1e{lo}").parse().unwrap();
                    let to: f64 = format!("1e{}", lo + span).parse().unwrap();
                    let n = (span * per_decade + 1) as usize;
                    let v = range(from, to, n);
                    for k in 0..=span {
                        let exact: f64 = format!("1e{}", lo + k).parse().unwrap();
                        let j = (k * per_decade) as usize;
                        assert_eq!(v[j], exact, "1e{lo} … 1e{} ({n} points)", lo + span);
                    }
                }
            }
        }
    }

    #[test]
    fn whole_decades_from_either_end_and_other_points_unchanged() {
        // From a non-decade start: 3e-5 … 3e-1 hits 3e-4, 3e-3, 3e-2 as written.
        assert_eq!(range(3e-5, 3e-1, 5), vec![3e-5, 3e-4, 3e-3, 3e-2, 3e-1]);
        // Decades counted from the end: 2.5 … 2.5e3 in 7 points.
        let v = range(2.5, 2.5e3, 7);
        assert_eq!([v[0], v[2], v[4], v[6]], [2.5, 25.0, 250.0, 2500.0]);
        // Points between decades are the geometric ones.
        let mid = (1e7f64.ln() + 0.5 * (1e8f64.ln() - 1e7f64.ln())).exp();
        assert_eq!(range(1e7, 1e8, 3)[1], mid);
        assert!((mid / 10f64.powf(7.5) - 1.0).abs() < 1e-14);
    }
}
