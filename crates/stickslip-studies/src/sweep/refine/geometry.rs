//! The geometry of a refined map, in axis values, for plots and checks: each point's cell
//! ([`cells`]), the point whose cell holds each point of the uniform finest grid
//! ([`owners`]), and the regime boundary as segments ([`boundary`]).
//!
//! A point of level k owns the cell of the level-k grid centred on it: half a level-k step
//! either way along each axis (2^(levels−k−1) fine steps; half a fine step at the finest
//! level), clipped to the map (half a fine step beyond the end values, as the cells of an
//! unrefined map). Finer cells lie over coarser ones: a point of the finest grid belongs to
//! the cell of the finest level whose nearest grid point has a result ([`owners`]), which is
//! also what the plot shows. A split cell's points are all computed, so only unsplit cells
//! (whose corners agree) are drawn large.

use super::super::Sweep;
use super::super::map::MapRow;
use super::{Refine, class};
use std::collections::BTreeMap;

/// One point's cell.
#[derive(Debug, Clone, PartialEq)]
pub struct CellRect {
    /// The point.
    pub point: usize,
    /// Its level.
    pub level: usize,
    /// Lower edge along each axis, in axis values.
    pub lo: Vec<f64>,
    /// Upper edge along each axis, in axis values.
    pub hi: Vec<f64>,
}

/// One piece of the regime boundary, in axis values: (x, y) to (x, y); with one axis, y runs
/// from 0 to 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// Start.
    pub from: (f64, f64),
    /// End.
    pub to: (f64, f64),
}

/// A refined map's geometry ([`map_geometry`]).
#[derive(Debug, Clone, PartialEq)]
pub struct MapGeometry {
    /// Every row's cell, coarse levels first ([`cells`]).
    pub cells: Vec<CellRect>,
    /// The regime boundary ([`boundary`]).
    pub boundary: Vec<Segment>,
}

/// The cells and the regime boundary of a refined map: `sweep` and `rows` as a finished
/// map.json holds them (`MapJson::sweep`, `MapJson::table.rows`), or as `read_map` returns
/// them; `None` for a sweep without `[refine]`.
#[must_use]
pub fn map_geometry(sweep: &Sweep, rows: &[MapRow]) -> Option<MapGeometry> {
    let refine = sweep.refine.as_ref()?;
    Some(MapGeometry {
        cells: cells(sweep, refine, rows),
        boundary: boundary(sweep, refine, rows),
    })
}

/// Finest grids larger than this get no boundary from [`boundary`] (it visits every point of
/// the finest grid).
pub const MAX_BOUNDARY_GRID: usize = 4_000_000;

/// The value at half-step position `t` of an axis with `values` (`t = 2j` is value j, odd `t`
/// the edge between two values: their midpoint, geometric on a log axis; −1 and 2m − 1 half a
/// step beyond the ends).
fn at_half(values: &[f64], log: bool, t: i64) -> f64 {
    let m = values.len();
    let mid = |a: f64, b: f64| if log { (a * b).sqrt() } else { 0.5 * (a + b) };
    let out_of = |a: f64, b: f64| if log { a * a / b } else { 2.0 * a - b };
    if m == 1 {
        let v = values[0];
        return match t.signum() {
            0 => v,
            s if log => {
                if s < 0 {
                    v / 1.5
                } else {
                    v * 1.5
                }
            }
            s => v + s as f64 * 0.5 * v.abs().max(1e-300),
        };
    }
    let last = 2 * (m as i64 - 1);
    if t <= -1 {
        return mid(out_of(values[0], values[1]), values[0]);
    }
    if t > last {
        return mid(values[m - 1], out_of(values[m - 1], values[m - 2]));
    }
    let j = (t / 2) as usize;
    if t % 2 == 0 {
        values[j]
    } else {
        mid(values[j], values[j + 1])
    }
}

/// The axes' values as numbers, and whether each is log.
fn numbers(sweep: &Sweep) -> Vec<(Vec<f64>, bool)> {
    sweep.axes.iter().map(|a| (a.numbers(), a.log)).collect()
}

/// The cell of every row of the refined `sweep`, coarse levels first (so finer cells are
/// drawn over them), then in point order.
#[must_use]
pub fn cells(sweep: &Sweep, refine: &Refine, rows: &[MapRow]) -> Vec<CellRect> {
    let points: Vec<usize> = rows.iter().map(|r| r.point).collect();
    cells_of(sweep, refine, &points)
}

/// As [`cells`], for point numbers (points not run yet, say).
#[must_use]
pub fn cells_of(sweep: &Sweep, refine: &Refine, points: &[usize]) -> Vec<CellRect> {
    let axes = numbers(sweep);
    let levels = refine.levels as usize;
    let mut out: Vec<CellRect> = points
        .iter()
        .map(|&point| {
            let idx = sweep.indices(point);
            let level = refine.level(&idx);
            // Half-width in half-steps of the finest grid: 2^(levels − level).
            let w = 1i64 << (levels - level);
            let (mut lo, mut hi) = (Vec::new(), Vec::new());
            for ((values, log), &j) in axes.iter().zip(&idx) {
                let last = 2 * (values.len() as i64 - 1) + 1;
                let c = 2 * j as i64;
                lo.push(at_half(values, *log, (c - w).max(-1)));
                hi.push(at_half(values, *log, (c + w).min(last)));
            }
            CellRect {
                point,
                level,
                lo,
                hi,
            }
        })
        .collect();
    out.sort_by_key(|c| (c.level, c.point));
    out
}

/// For every point of the uniform finest grid (in point order), the point of the refined map
/// whose cell holds it: the nearest grid point of the finest level that has a row (ties to the
/// lower index); `None` where not even the base point has a row (a partial map).
#[must_use]
pub fn owners(
    sweep: &Sweep,
    refine: &Refine,
    rows: &BTreeMap<usize, MapRow>,
) -> Vec<Option<usize>> {
    let levels = refine.levels as usize;
    (0..sweep.points)
        .map(|p| {
            let idx = sweep.indices(p);
            (0..=levels).rev().find_map(|k| {
                let s = 1usize << (levels - k);
                let nearest: Vec<usize> = idx
                    .iter()
                    .map(|&j| {
                        let below = j / s * s;
                        if j - below > s / 2 { below + s } else { below }
                    })
                    .collect();
                let q = sweep.point(&nearest);
                rows.contains_key(&q).then_some(q)
            })
        })
        .collect()
}

/// The regime boundary of a refined map: the edges between neighbouring points of the finest
/// grid whose owners ([`owners`]) differ in class (regime, or a failed or refused status), in
/// axis values (one axis: vertical lines from y = 0 to 1). Empty beyond
/// [`MAX_BOUNDARY_GRID`] points or for more than two axes.
#[must_use]
pub fn boundary(sweep: &Sweep, refine: &Refine, rows: &[MapRow]) -> Vec<Segment> {
    if sweep.points > MAX_BOUNDARY_GRID || sweep.axes.len() > 2 {
        return Vec::new();
    }
    let by_point: BTreeMap<usize, MapRow> = rows.iter().map(|r| (r.point, r.clone())).collect();
    let owner = owners(sweep, refine, &by_point);
    let cls: Vec<Option<&'static str>> = owner
        .iter()
        .map(|o| o.and_then(|q| by_point.get(&q)).map(class))
        .collect();
    let axes = numbers(sweep);
    let m: Vec<usize> = axes.iter().map(|(v, _)| v.len()).collect();
    let mut out = Vec::new();
    for p in 0..sweep.points {
        let idx = sweep.indices(p);
        for d in 0..idx.len() {
            if idx[d] + 1 >= m[d] {
                continue;
            }
            let mut next = idx.clone();
            next[d] += 1;
            let q = sweep.point(&next);
            let (Some(a), Some(b)) = (cls[p], cls[q]) else {
                continue;
            };
            if a == b {
                continue;
            }
            // The edge between fine cells j and j + 1 along d, across the other axis's cell.
            let (values, log) = &axes[d];
            let at = at_half(values, *log, 2 * idx[d] as i64 + 1);
            let (lo, hi) = if idx.len() == 2 {
                let o = 1 - d;
                let (ov, olog) = &axes[o];
                let c = 2 * idx[o] as i64;
                (at_half(ov, *olog, c - 1), at_half(ov, *olog, c + 1))
            } else {
                (0.0, 1.0)
            };
            out.push(if d == 0 {
                Segment {
                    from: (at, lo),
                    to: (at, hi),
                }
            } else {
                Segment {
                    from: (lo, at),
                    to: (hi, at),
                }
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::at_half;

    #[test]
    fn half_steps_are_values_and_midpoints() {
        let v = [1.0, 2.0, 3.0];
        assert_eq!(at_half(&v, false, 0), 1.0);
        assert_eq!(at_half(&v, false, 1), 1.5);
        assert_eq!(at_half(&v, false, 4), 3.0);
        assert_eq!(at_half(&v, false, -1), 0.5);
        assert_eq!(at_half(&v, false, 5), 3.5);
        let l = [1.0, 100.0];
        assert!((at_half(&l, true, 1) - 10.0).abs() < 1e-12);
        assert!((at_half(&l, true, -1) - 0.1).abs() < 1e-12);
    }
}
