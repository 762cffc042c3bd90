//! Adaptive refinement of a friction map (`[refine]` of a sweep file): after the base grid,
//! every cell whose corner points differ is split, `levels` times.
//!
//! **Grid and numbering.** A refined sweep's axes hold the values of its *finest* grid: an axis
//! of n base values has (n − 1)·2^levels + 1, the base values at every 2^levels-th place and
//! between neighbours the finer ones — for a `range`, the same range with that count (so the
//! finest grid is the uniform sweep of that count, value for value); for listed values,
//! 2^levels − 1 values between each pair of neighbours, evenly spaced (geometrically on a log
//! axis, see [`super::Axis::log`]). Points are numbered in that grid (the last axis fastest),
//! so a point's number is the same at every level and whatever the jobs or shards, and a
//! refined map's points are a subset of the uniform finest grid. A point's level is the
//! coarsest grid it lies on ([`Refine::level`]): 0 for the base grid.
//!
//! **Cells and splits.** A cell of level k is an interval (one axis) or a rectangle (two
//! axes) between neighbouring points of the level-k grid (spacing 2^(levels−k) in fine
//! indices) whose corners all have results. It is split when two of its corners differ
//! ([`differ`]): by regime (`on = "regime"`; a failed or refused point is its own class, apart
//! from every regime), or by a numeric map.csv column (`on = COLUMN`: |a − b| > threshold ·
//! max(|a|, |b|), a missing value against a number differs, two missing values do not). A
//! split cell gives the points of the level-(k+1) grid on and inside it that are not its
//! corners: the midpoints of its edges and its centre. The points of level k+1 are those of
//! every split cell of level k ([`next_points`]); they depend only on the results of the
//! levels before, so a rerun, another number of jobs or another sharding finds the same ones.
//!
//! At most [`MAX_AXES`] axes, every one numeric; the finest grid counts against the
//! directory's limit of [`super::HARD_MAX_POINTS`] points.

pub mod agreement;
pub mod geometry;

use super::file::{AxisFile, RefineFile};
use super::map::{MapRow, SUMMARY_COLUMNS};
use super::record::PointStatus;
use super::{Axis, HARD_MAX_POINTS, Sweep, SweepError, log_point, value_text};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};
use stickslip_run::keys::{self, ValueType};

/// Most axes a refined sweep may have.
pub const MAX_AXES: usize = 2;

/// `on = "regime"`: cells split where the regime differs.
pub const ON_REGIME: &str = "regime";

/// The resolved `[refine]` table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Refine {
    /// Levels of refinement (0 = the base grid only).
    pub levels: u32,
    /// `"regime"` or a numeric column of map.csv.
    pub on: String,
    /// With `on` a column: the relative jump that splits a cell.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub threshold: Option<f64>,
    /// Number of base values of each axis (as written in the sweep file).
    pub base: Vec<usize>,
}

/// The columns `on` may name: the numeric results of map.csv (not `wall_s`, which is no
/// result and differs from run to run).
#[must_use]
pub fn columns() -> Vec<&'static str> {
    SUMMARY_COLUMNS
        .iter()
        .map(|c| c.name)
        .filter(|&n| n != "regime" && n != "wall_s")
        .collect()
}

fn invalid(key: &str, value: impl std::fmt::Display, allowed: &str) -> SweepError {
    SweepError::invalid(key, value, allowed)
}

impl Refine {
    /// Fine-grid steps between neighbouring base values: 2^levels.
    #[must_use]
    pub fn stride(&self) -> usize {
        1usize << self.levels
    }

    /// The level of the point at fine-grid `indices`: the coarsest level whose grid holds it
    /// (0: the base grid).
    #[must_use]
    pub fn level(&self, indices: &[usize]) -> usize {
        let levels = self.levels as usize;
        let coarsest = indices
            .iter()
            .map(|&j| {
                if j == 0 {
                    levels
                } else {
                    (j.trailing_zeros() as usize).min(levels)
                }
            })
            .min()
            .unwrap_or(levels);
        levels - coarsest
    }

    /// Whether the rows `a` and `b` differ in the sense that splits a cell (see the module
    /// docs).
    #[must_use]
    pub fn differ(&self, a: &MapRow, b: &MapRow) -> bool {
        differ(self, a, b)
    }
}

/// A row's class: its regime when ok, else its status (`failed`, `refused`).
fn class(r: &MapRow) -> &'static str {
    if r.status == PointStatus::Ok {
        r.summary.regime.name()
    } else {
        r.status.name()
    }
}

/// Whether two corner points differ so that their cell splits: by class (regime, or a failed
/// or refused status) with `on = "regime"`; with `on = COLUMN`, by class when either is not
/// ok, else by |a − b| > threshold·max(|a|, |b|) (a missing value differs from a number, two
/// missing values do not).
#[must_use]
pub fn differ(refine: &Refine, a: &MapRow, b: &MapRow) -> bool {
    if refine.on == ON_REGIME || a.status != PointStatus::Ok || b.status != PointStatus::Ok {
        return class(a) != class(b);
    }
    let (x, y) = (a.number(&refine.on), b.number(&refine.on));
    match (x.is_finite(), y.is_finite()) {
        (false, false) => false,
        (true, true) => (x - y).abs() > refine.threshold.unwrap_or(0.0) * x.abs().max(y.abs()),
        _ => true,
    }
}

/// Resolves `[refine]` for the base `axes` (written as `files`): the table and the axes of the
/// finest grid.
///
/// # Errors
/// A bad value, naming `refine.levels`, `refine.on`, `refine.threshold` or `refine`.
pub(super) fn resolve(
    file: &RefineFile,
    axes: &[Axis],
    files: &[AxisFile],
) -> Result<(Refine, Vec<Axis>), SweepError> {
    let levels = match file.levels {
        None => {
            return Err(invalid(
                "refine.levels",
                "none",
                "an integer >= 0 (0 = no refinement)",
            ));
        }
        Some(l) if l < 0 => return Err(invalid("refine.levels", l, "an integer >= 0")),
        Some(l) => l,
    };
    let on = file.on.clone().unwrap_or_else(|| ON_REGIME.to_string());
    if on != ON_REGIME && !columns().contains(&on.as_str()) {
        let known_other = ["point", "status", "message", "steady", "level", "wall_s"]
            .contains(&on.as_str())
            || axes.iter().any(|a| a.key == on);
        let what = if known_other {
            format!(
                "{on:?} is a map.csv column but not a numeric result; allowed: \"{ON_REGIME}\" \
                 or one of"
            )
        } else {
            format!("\"{ON_REGIME}\" or a numeric column of map.csv:")
        };
        return Err(invalid(
            "refine.on",
            format!("{on:?}"),
            &format!("{what} {}", columns().join(", ")),
        ));
    }
    let threshold = match (on == ON_REGIME, file.threshold) {
        (true, None) => None,
        (true, Some(t)) => {
            return Err(invalid(
                "refine.threshold",
                t,
                "no threshold with on = \"regime\" (cells split where the regime differs); \
                 a threshold goes with on = a numeric column",
            ));
        }
        (false, None) => {
            return Err(invalid(
                "refine.threshold",
                "none",
                &format!(
                    "a number > 0 with on = {on:?}: the relative jump |a - b| > threshold · \
                     max(|a|, |b|) that splits a cell"
                ),
            ));
        }
        (false, Some(t)) if !(t.is_finite() && t > 0.0) => {
            return Err(invalid("refine.threshold", t, "a finite number > 0"));
        }
        (false, Some(t)) => Some(t),
    };
    if axes.len() > MAX_AXES {
        return Err(invalid(
            "refine",
            format!("{} axes", axes.len()),
            &format!(
                "at most {MAX_AXES} axes in a refined sweep (a map of one or two numeric \
                 axes); fix the others with [set], or run one refined sweep per value"
            ),
        ));
    }
    for (i, a) in axes.iter().enumerate() {
        if !a.numbers().iter().all(|v| v.is_finite()) {
            return Err(invalid(
                "refine",
                format!("axis[{i}] ({})", a.key),
                &format!(
                    "numeric axes only: axis[{i}] ({}) takes words, which have no values \
                     between them",
                    a.key
                ),
            ));
        }
    }
    // The finest grid's size, without overflow: (n − 1)·2^levels + 1 per axis.
    let fine_count = |n: usize| -> Option<usize> {
        let levels = u32::try_from(levels).ok()?;
        let stride = 2usize.checked_pow(levels)?;
        (n - 1).checked_mul(stride)?.checked_add(1)
    };
    let counts: Option<Vec<usize>> = axes.iter().map(|a| fine_count(a.values.len())).collect();
    let total = counts
        .as_ref()
        .and_then(|c| c.iter().try_fold(1usize, |p, &m| p.checked_mul(m)));
    let base: Vec<usize> = axes.iter().map(|a| a.values.len()).collect();
    let most = (0..64u32)
        .take_while(|&l| {
            base.iter()
                .try_fold(1usize, |p, &n| {
                    let m = (n - 1)
                        .checked_mul(2usize.checked_pow(l)?)?
                        .checked_add(1)?;
                    p.checked_mul(m)
                })
                .is_some_and(|p| p <= HARD_MAX_POINTS)
        })
        .last()
        .unwrap_or(0);
    let (Some(counts), Some(total)) = (counts, total.filter(|&t| t <= HARD_MAX_POINTS)) else {
        return Err(invalid(
            "refine.levels",
            levels,
            &format!(
                "at most {most} levels for these axes: the finest grid ((n - 1)·2^levels + 1 \
                 values per axis) may have at most {HARD_MAX_POINTS} points (the limit of one \
                 sweep directory)"
            ),
        ));
    };
    let refine = Refine {
        levels: u32::try_from(levels).unwrap_or(0),
        on,
        threshold,
        base,
    };
    let fine = axes
        .iter()
        .zip(files)
        .zip(counts)
        .enumerate()
        .map(|(i, ((a, f), m))| fine_axis(i, a, f, m, &refine, most))
        .collect::<Result<Vec<_>, _>>()?;
    debug_assert_eq!(
        fine.iter().map(|a| a.values.len()).product::<usize>(),
        total
    );
    Ok((refine, fine))
}

/// The axis `a` (written as `f`) on the finest grid of `m` values.
fn fine_axis(
    i: usize,
    a: &Axis,
    f: &AxisFile,
    m: usize,
    refine: &Refine,
    most: u32,
) -> Result<Axis, SweepError> {
    let stride = refine.stride();
    let n = a.values.len();
    let integer = keys::KEYS
        .iter()
        .find(|k| k.path == a.key)
        .is_some_and(|k| k.value == ValueType::Integer);
    let make = |v: f64| {
        if integer {
            toml::Value::Integer(v.round() as i64)
        } else {
            toml::Value::Float(v)
        }
    };
    let values: Vec<toml::Value> = match &f.range {
        // The same range at the finest count: value for value the uniform sweep's.
        Some(r) if n >= 2 => {
            let log = r.scale.as_deref() == Some("log");
            (0..m)
                .map(|j| {
                    if j == m - 1 {
                        return make(r.to);
                    }
                    let t = j as f64 / (m - 1) as f64;
                    make(if log {
                        log_point(r.from, r.to, t)
                    } else {
                        r.from + t * (r.to - r.from)
                    })
                })
                .collect()
        }
        // Listed values: evenly between neighbours (geometrically on a log axis).
        _ => {
            let nums = a.numbers();
            let mut out = Vec::with_capacity(m);
            for (k, v) in a.values.iter().enumerate() {
                out.push(v.clone());
                if k + 1 < n {
                    let (lo, hi) = (nums[k], nums[k + 1]);
                    for s in 1..stride {
                        let t = s as f64 / stride as f64;
                        out.push(make(if a.log {
                            log_point(lo, hi, t)
                        } else {
                            lo + t * (hi - lo)
                        }));
                    }
                }
            }
            out
        }
    };
    // The base values stay where they are, exactly.
    for (k, v) in a.values.iter().enumerate() {
        if values.get(k * stride) != Some(v) {
            return Err(invalid(
                "refine.levels",
                refine.levels,
                &format!(
                    "a finest grid holding the base values: axis[{i}] ({}) value {} is not \
                     reproduced (please report this)",
                    a.key,
                    value_text(v)
                ),
            ));
        }
    }
    if let Some(dup) = super::first_duplicate(&values) {
        return Err(invalid(
            "refine.levels",
            refine.levels,
            &format!(
                "fewer levels: axis[{i}] ({}) takes integers, and its finest grid of {m} values \
                 gives {} twice (at most {most} levels for the sweep's size; fewer for this \
                 axis's spacing)",
                a.key,
                value_text(dup)
            ),
        ));
    }
    Ok(Axis {
        key: a.key.clone(),
        values,
        log: a.log,
    })
}

/// The points of the base grid (level 0), in point order.
#[must_use]
pub fn base_points(sweep: &Sweep, refine: &Refine) -> Vec<usize> {
    let stride = refine.stride();
    let mut out = Vec::new();
    let mut idx = vec![0usize; refine.base.len()];
    let total: usize = refine.base.iter().product();
    for _ in 0..total {
        let fine: Vec<usize> = idx.iter().map(|&i| i * stride).collect();
        out.push(sweep.point(&fine));
        // Next base index, last axis fastest.
        for d in (0..idx.len()).rev() {
            idx[d] += 1;
            if idx[d] < refine.base[d] {
                break;
            }
            idx[d] = 0;
        }
    }
    out
}

/// The points of level `level` (≥ 1), in point order: those of every split cell of level
/// `level − 1` whose corners all have rows in `known` (see the module docs).
#[must_use]
pub fn next_points(
    sweep: &Sweep,
    refine: &Refine,
    level: usize,
    known: &BTreeMap<usize, MapRow>,
) -> Vec<usize> {
    let levels = refine.levels as usize;
    if level == 0 || level > levels {
        return Vec::new();
    }
    let s = 1usize << (levels - level + 1);
    let h = s / 2;
    let m: Vec<usize> = sweep.axes.iter().map(|a| a.values.len()).collect();
    // Axes along which cells extend (a single-valued axis does not).
    let dims: Vec<usize> = (0..m.len()).filter(|&d| m[d] > 1).collect();
    let mut new = BTreeSet::new();
    for (&p, _) in known.iter() {
        let lower = sweep.indices(p);
        if dims
            .iter()
            .any(|&d| !lower[d].is_multiple_of(s) || lower[d] + s > m[d] - 1)
        {
            continue;
        }
        // The corners: offsets 0 or s along each dimension.
        let corners: Option<Vec<&MapRow>> = (0..1usize << dims.len())
            .map(|bits| {
                let mut idx = lower.clone();
                for (b, &d) in dims.iter().enumerate() {
                    if bits >> b & 1 == 1 {
                        idx[d] += s;
                    }
                }
                known.get(&sweep.point(&idx))
            })
            .collect();
        let Some(corners) = corners else { continue };
        let split = corners
            .iter()
            .enumerate()
            .any(|(i, a)| corners[i + 1..].iter().any(|b| differ(refine, a, b)));
        if !split {
            continue;
        }
        // Offsets 0, h or s along each dimension, at least one h: not a corner.
        for code in 0..3usize.pow(dims.len() as u32) {
            let mut idx = lower.clone();
            let mut rest = code;
            let mut has_mid = false;
            for &d in &dims {
                let o = rest % 3;
                rest /= 3;
                has_mid |= o == 1;
                idx[d] += o * h;
            }
            if has_mid {
                new.insert(sweep.point(&idx));
            }
        }
    }
    new.into_iter().collect()
}

/// The levels of a refined sweep as far as the results go ([`walk`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Walk {
    /// The points of each level reached (level 0 the base grid), each in point order.
    pub levels: Vec<Vec<usize>>,
    /// The rows found, by point.
    pub rows: BTreeMap<usize, MapRow>,
    /// Points of the last level reached without a row (empty when the map is complete).
    pub missing: Vec<usize>,
}

impl Walk {
    /// Every point of every level has its row: the refined map is complete.
    #[must_use]
    pub fn complete(&self) -> bool {
        self.missing.is_empty()
    }

    /// Number of points of the levels reached.
    #[must_use]
    pub fn points(&self) -> usize {
        self.levels.iter().map(Vec::len).sum()
    }
}

/// Walks the levels of the refined `sweep`: level 0, then each next level from the rows of
/// the ones before, as long as every point of a level has a row (`find(p)`, `None` for a
/// point without a finished result). Stops at the first level with points missing.
///
/// # Errors
/// `find`'s.
pub fn walk<E>(
    sweep: &Sweep,
    refine: &Refine,
    mut find: impl FnMut(usize) -> Result<Option<MapRow>, E>,
) -> Result<Walk, E> {
    let mut walk = Walk::default();
    let mut set = base_points(sweep, refine);
    let mut level = 0;
    loop {
        for &p in &set {
            match find(p)? {
                Some(row) => {
                    walk.rows.insert(p, row);
                }
                None => walk.missing.push(p),
            }
        }
        walk.levels.push(std::mem::take(&mut set));
        level += 1;
        if !walk.missing.is_empty() || level > refine.levels as usize {
            return Ok(walk);
        }
        set = next_points(sweep, refine, level, &walk.rows);
        if set.is_empty() {
            return Ok(walk);
        }
    }
}
