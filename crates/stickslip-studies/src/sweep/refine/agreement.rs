//! How a refined map agrees with a uniform sweep over points of its finest grid: the check
//! that refinement found every regime boundary a uniform grid shows.
//!
//! Each point of the uniform sweep is placed on the refined sweep's finest grid by its axis
//! values (exactly: write the uniform sweep's axes as `values` taken from the refined axes, see
//! [`subgrid_values`]). Where the refined map has that point, both ran the same scene and
//! must give the same regime; where it has not, the refined map's answer is the regime of
//! the point whose cell holds it ([`super::geometry::owners`]), and a difference means the
//! refinement missed a boundary (an island smaller than the base cells, say).

use super::super::Sweep;
use super::super::map::MapRow;
use super::{Refine, class, geometry};
use std::collections::BTreeMap;

/// The comparison of a refined map with a uniform sweep.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Agreement {
    /// Uniform points placed on the finest grid.
    pub compared: usize,
    /// Of those, points the refined map ran too.
    pub shared: usize,
    /// Shared points whose regimes differ (uniform point numbers).
    pub shared_differ: Vec<usize>,
    /// Points the refined map answers by the cell that holds them.
    pub inferred: usize,
    /// Inferred points whose regimes differ (uniform point numbers).
    pub inferred_differ: Vec<usize>,
    /// Uniform points whose values are not on the finest grid (or whose axes differ).
    pub off_grid: usize,
}

/// Compares the refined map (`sweep`, `refine`, `rows`) with a uniform sweep's rows.
#[must_use]
pub fn agreement(
    sweep: &Sweep,
    refine: &Refine,
    rows: &[MapRow],
    uniform: &Sweep,
    uniform_rows: &[MapRow],
) -> Agreement {
    let mut out = Agreement::default();
    let same_axes = uniform.axes.len() == sweep.axes.len()
        && uniform
            .axes
            .iter()
            .zip(&sweep.axes)
            .all(|(u, s)| u.key == s.key);
    if !same_axes {
        out.off_grid = uniform_rows.len();
        return out;
    }
    let fine: Vec<Vec<f64>> = sweep.axes.iter().map(super::super::Axis::numbers).collect();
    let coarse: Vec<Vec<f64>> = uniform
        .axes
        .iter()
        .map(super::super::Axis::numbers)
        .collect();
    let by_point: BTreeMap<usize, MapRow> = rows.iter().map(|r| (r.point, r.clone())).collect();
    let owners = geometry::owners(sweep, refine, &by_point);
    for u in uniform_rows {
        let placed: Option<Vec<usize>> = uniform
            .indices(u.point)
            .iter()
            .zip(coarse.iter().zip(&fine))
            .map(|(&j, (c, f))| f.iter().position(|&x| x == c[j]))
            .collect();
        let Some(idx) = placed else {
            out.off_grid += 1;
            continue;
        };
        out.compared += 1;
        let q = sweep.point(&idx);
        let theirs = if let Some(r) = by_point.get(&q) {
            out.shared += 1;
            Some((class(r), &mut out.shared_differ))
        } else if let Some(o) = owners[q].and_then(|o| by_point.get(&o)) {
            out.inferred += 1;
            Some((class(o), &mut out.inferred_differ))
        } else {
            None
        };
        if let Some((c, differ)) = theirs
            && c != class(u)
        {
            differ.push(u.point);
        }
    }
    out
}

/// Every `stride`-th value of each axis of the refined `sweep`'s finest grid, from
/// `window[k].0` to `window[k].1` (fine indices, inclusive; `None` for the whole axis), as the
/// numbers to write as a uniform sweep's `values` so that its points lie exactly on the
/// finest grid.
#[must_use]
pub fn subgrid_values(
    sweep: &Sweep,
    stride: usize,
    window: &[Option<(usize, usize)>],
) -> Vec<Vec<f64>> {
    sweep
        .axes
        .iter()
        .enumerate()
        .map(|(k, a)| {
            let v = a.numbers();
            let (lo, hi) = window
                .get(k)
                .copied()
                .flatten()
                .unwrap_or((0, v.len().saturating_sub(1)));
            (lo..=hi.min(v.len().saturating_sub(1)))
                .step_by(stride.max(1))
                .map(|j| v[j])
                .collect()
        })
        .collect()
}

/// The `[[axis]]` tables of a uniform sweep over [`subgrid_values`]: each refined axis's key
/// with its values listed, for a sweep file whose points lie exactly on the finest grid.
#[must_use]
pub fn subgrid_axes(
    sweep: &Sweep,
    stride: usize,
    window: &[Option<(usize, usize)>],
) -> Vec<toml::Table> {
    sweep
        .axes
        .iter()
        .zip(subgrid_values(sweep, stride, window))
        .map(|(a, v)| {
            let mut t = toml::Table::new();
            t.insert("key".into(), a.key.clone().into());
            t.insert(
                "values".into(),
                toml::Value::Array(v.into_iter().map(toml::Value::Float).collect()),
            );
            t
        })
        .collect()
}
