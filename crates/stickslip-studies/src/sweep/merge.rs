//! The merge of a sweep's points into map.csv and map.json, at a cost of O(P) for a whole job
//! array, not O(T·P).
//!
//! A shard that ran all its points writes its table, `DIR/shards/I-of-N.BUILD.json`: the
//! fingerprint, the shard and one row per point of the shard ([`write_table`]). The merge after
//! a shard ([`after_shard`]) lists `shards/` (one directory read) and merges only when the
//! tables of a complete set of shards, 0 … N−1 of one N by this build, are there: it reads
//! those N tables, P rows in all, and writes the map. Of the T tasks of an array only the last
//! ones to finish see a complete set, so the array reads about T listings and a few times P
//! rows, where every task reading every record cost T·P/2 file reads. Several tasks may merge
//! at the same moment: they write the same map through the atomic writer, each under a
//! temporary name of its own.
//!
//! `sweep merge` ([`merge`]) uses a complete set of tables when there is one and otherwise
//! reads every record (P reads), checking each against the sweep: a record of another sweep is
//! refused, one of another build counts as missing. [`merge_wait`] waits for the sweep to be
//! complete first (a merge started with the array, or a dependent Slurm job). [`read_map`]
//! reads the table for a reader, complete or partial, and writes nothing.
//!
//! A refined sweep writes no shard tables: its shards read every level's records anyway (the
//! next level's points follow from them), and the one that finds every level complete writes
//! the map; [`merge`] and [`read_map`] walk its levels through the records.

use super::Sweep;
use super::lock::{SweepLock, SweepRunError, io_err, load_lock};
use super::map::{CSV_FILE, JSON_FILE, MapJson, MapRow, MapTable};
use super::record::{Found, PointRecord, listed};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};
use std::io;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use stickslip_run::atomic::write_atomic;
use stickslip_run::summary::Regime;

pub use stickslip_run::layout::sweep::SHARDS_DIR;

/// `DIR/shards/I-of-N.BUILD.json`: the rows of one shard that ran to its end.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShardTable {
    /// The sweep's fingerprint.
    pub fingerprint: String,
    /// Shard I of N.
    pub shard: (usize, usize),
    /// One row per point of the shard, in point order.
    pub rows: Vec<MapRow>,
}

/// File name of the table of shard `index`/`count` by `build`.
#[must_use]
pub fn table_name(index: usize, count: usize, build: &str) -> String {
    format!("{index}-of-{count}.{build}.json")
}

/// Shard (I, N) and build of a table's file name.
fn parse_table_name(name: &str) -> Option<(usize, usize, &str)> {
    let stem = name.strip_suffix(".json")?;
    let (shard, build) = stem.split_once('.')?;
    let (i, n) = shard.split_once("-of-")?;
    Some((i.parse().ok()?, n.parse().ok()?, build))
}

/// Writes the table of shard `shard` of `sweep` from its `records` (in point order); removes
/// that shard's tables of other builds.
///
/// # Errors
/// I/O errors.
pub fn write_table(
    dir: &Path,
    sweep: &Sweep,
    fingerprint: &str,
    shard: (usize, usize),
    records: &[PointRecord],
) -> Result<(), SweepRunError> {
    let (index, count) = shard;
    let build = super::split_fingerprint(fingerprint).map_or("", |(_, b)| b);
    let table = ShardTable {
        fingerprint: fingerprint.to_string(),
        shard,
        rows: records.iter().map(MapRow::of).collect(),
    };
    debug_assert_eq!(table.rows.len(), sweep.shard_len(index, count));
    let shards = dir.join(SHARDS_DIR);
    std::fs::create_dir_all(&shards).map_err(io_err(dir))?;
    let text = serde_json::to_string(&table).map_err(|e| io_err(dir)(io::Error::other(e)))?;
    write_atomic(&shards, &table_name(index, count, build), text.as_bytes())
        .map_err(io_err(dir))?;
    for name in table_names(dir).map_err(io_err(dir))? {
        if let Some((i, n, b)) = parse_table_name(&name)
            && (i, n) == shard
            && b != build
        {
            let _ = std::fs::remove_file(shards.join(&name));
        }
    }
    Ok(())
}

fn table_names(dir: &Path) -> io::Result<Vec<String>> {
    match std::fs::read_dir(dir.join(SHARDS_DIR)) {
        Ok(entries) => entries
            .map(|e| e.map(|e| e.file_name().to_string_lossy().into_owned()))
            .filter(|n| n.as_ref().map_or(true, |n| !n.starts_with('.')))
            .collect(),
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(Vec::new()),
        Err(e) => Err(e),
    }
}

/// Shard counts N whose tables 0 … N−1 by `build` are all there (names only), and for each
/// N, the indices present.
fn table_sets(dir: &Path, build: &str) -> io::Result<BTreeMap<usize, BTreeSet<usize>>> {
    let mut sets: BTreeMap<usize, BTreeSet<usize>> = BTreeMap::new();
    for name in table_names(dir)? {
        if let Some((i, n, b)) = parse_table_name(&name)
            && b == build
            && i < n
        {
            sets.entry(n).or_default().insert(i);
        }
    }
    Ok(sets)
}

/// How much a merge read.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MergeCost {
    /// Shard tables read.
    pub tables_read: usize,
    /// Point records read.
    pub records_read: usize,
    /// Wall-clock seconds of the merge.
    pub seconds: f64,
}

/// The result of a merge.
#[derive(Debug, Clone, PartialEq)]
pub enum Merge {
    /// Every point has its row: map.csv and map.json are written.
    Complete {
        /// The table.
        table: MapTable,
        /// Points per status.
        statuses: BTreeMap<String, usize>,
        /// Points per regime (status ok).
        regimes: BTreeMap<Regime, usize>,
        /// What the merge read.
        cost: MergeCost,
    },
    /// Points without a current record (shards still running or interrupted, or records of
    /// another build).
    Incomplete {
        /// How many.
        missing: usize,
        /// Of how many.
        points: usize,
        /// Of the missing, those whose record another build computed (known only when the
        /// records were read).
        other_build: usize,
        /// What the merge read.
        cost: MergeCost,
    },
}

/// The rows of the complete set of `count` tables, or `None` when one is unreadable or not
/// this sweep's and this build's (a table being rewritten, or a shard count of an earlier run
/// of the same build whose tables were partly replaced).
fn rows_from_tables(
    dir: &Path,
    lock: &SweepLock,
    count: usize,
    cost: &mut MergeCost,
) -> Result<Option<Vec<MapRow>>, SweepRunError> {
    let sweep = &lock.sweep;
    let build = super::split_fingerprint(&lock.fingerprint).map_or("", |(_, b)| b);
    let mut per_shard: Vec<Vec<MapRow>> = Vec::with_capacity(count);
    for index in 0..count {
        let path = dir.join(SHARDS_DIR).join(table_name(index, count, build));
        cost.tables_read += 1;
        let Ok(bytes) = stickslip_run::bounded::read(&path, stickslip_run::bounded::SHARD_TABLE)
        else {
            return Ok(None);
        };
        let Ok(table) = serde_json::from_slice::<ShardTable>(&bytes) else {
            return Ok(None);
        };
        if table.fingerprint != lock.fingerprint {
            let definition = super::split_fingerprint(&lock.fingerprint).map_or("", |(d, _)| d);
            if !table.fingerprint.starts_with(definition) {
                return Err(SweepRunError::Foreign {
                    path,
                    why: format!(
                        "its fingerprint {} is not this sweep's {}",
                        table.fingerprint, lock.fingerprint
                    ),
                });
            }
            return Ok(None);
        }
        if table.shard != (index, count) {
            return Ok(None);
        }
        let expected = sweep.shard_len(index, count);
        if table.rows.len() != expected {
            return Ok(None);
        }
        for (k, row) in table.rows.iter().enumerate() {
            let p = index + k * count;
            let values: Vec<String> = sweep.values(p).iter().map(super::value_text).collect();
            if row.point != p || row.values != values {
                return Err(SweepRunError::Foreign {
                    path,
                    why: format!(
                        "its row {k} is point {} ({}), this sweep's point {p} is ({})",
                        row.point,
                        row.values.join(", "),
                        values.join(", ")
                    ),
                });
            }
        }
        per_shard.push(table.rows);
    }
    // Interleave: point p is row p / N of shard p mod N.
    let mut iters: Vec<std::vec::IntoIter<MapRow>> =
        per_shard.into_iter().map(Vec::into_iter).collect();
    let rows = (0..sweep.points)
        .map(|p| iters[p % count].next())
        .collect::<Option<Vec<MapRow>>>();
    Ok(rows)
}

/// Writes map.csv and map.json of `sweep` from `rows`; the [`Merge::Complete`].
pub(super) fn write_map(
    dir: &Path,
    sweep: &Sweep,
    rows: Vec<MapRow>,
    mut cost: MergeCost,
    started: Instant,
) -> Result<Merge, SweepRunError> {
    let table = MapTable {
        axes: sweep.axes.iter().map(|a| a.key.clone()).collect(),
        rows,
    };
    write_atomic(dir, CSV_FILE, table.to_csv().as_bytes()).map_err(io_err(dir))?;
    let json = MapJson::new(sweep, table.clone());
    let mut text =
        serde_json::to_string_pretty(&json).map_err(|e| io_err(dir)(io::Error::other(e)))?;
    text.push('\n');
    write_atomic(dir, JSON_FILE, text.as_bytes()).map_err(io_err(dir))?;
    let mut statuses = BTreeMap::new();
    for r in &table.rows {
        *statuses.entry(r.status.name().to_string()).or_insert(0) += 1;
    }
    cost.seconds = started.elapsed().as_secs_f64();
    Ok(Merge::Complete {
        regimes: table.regime_counts(),
        statuses,
        table,
        cost,
    })
}

/// Merges from a complete set of shard tables, preferring `prefer` shards; `Ok(None)` when
/// there is none. `missing` then counts the points of the shards of `prefer` without a table.
fn merge_tables(
    dir: &Path,
    lock: &SweepLock,
    prefer: Option<usize>,
    cost: &mut MergeCost,
    started: Instant,
) -> Result<Result<Merge, usize>, SweepRunError> {
    if lock.sweep.refine.is_some() {
        // A refined sweep's shards write no tables: the shard that finds every level complete
        // writes the map (super::exec::run_shard), else the merge reads the records.
        return Ok(Err(1));
    }
    let build = super::split_fingerprint(&lock.fingerprint).map_or("", |(_, b)| b);
    let sets = table_sets(dir, build).map_err(io_err(dir))?;
    let mut complete: Vec<usize> = sets
        .iter()
        .filter(|(n, present)| present.len() == **n)
        .map(|(n, _)| *n)
        .collect();
    if let Some(n) = prefer
        && let Some(pos) = complete.iter().position(|&c| c == n)
    {
        complete.swap(0, pos);
    }
    for n in complete {
        if let Some(rows) = rows_from_tables(dir, lock, n, cost)? {
            return write_map(dir, &lock.sweep, rows, *cost, started).map(Ok);
        }
    }
    let points = lock.sweep.points;
    let missing = match prefer {
        Some(n) => {
            let present = sets.get(&n);
            (0..n)
                .filter(|i| present.is_none_or(|p| !p.contains(i)))
                .map(|i| super::shard_len(points, i, n))
                .sum()
        }
        None => points,
    };
    Ok(Err(missing))
}

/// The merge after shard `shard` of the sweep of `fingerprint` ran to its end: from the
/// tables of a complete set of shards (see the module docs), without reading any record.
///
/// # Errors
/// [`SweepRunError::TakenOver`] when the directory holds another sweep now; a table of
/// another sweep; I/O errors.
pub fn after_shard(
    dir: &Path,
    fingerprint: &str,
    shard: (usize, usize),
) -> Result<Merge, SweepRunError> {
    let started = Instant::now();
    let lock = load_lock(dir)?;
    if lock.fingerprint != fingerprint {
        return Err(SweepRunError::TakenOver {
            dir: dir.display().to_string(),
        });
    }
    let mut cost = MergeCost::default();
    match merge_tables(dir, &lock, Some(shard.1), &mut cost, started)? {
        Ok(m) => Ok(m),
        Err(missing) => {
            cost.seconds = started.elapsed().as_secs_f64();
            Ok(Merge::Incomplete {
                missing,
                points: lock.sweep.points,
                other_build: 0,
                cost,
            })
        }
    }
}

/// Merges the sweep in `dir` into map.csv and map.json when every point has a current row:
/// from a complete set of shard tables, else from the records (each checked).
///
/// # Errors
/// No sweep in `dir`; [`SweepRunError::Foreign`] for a record or table of another sweep; I/O
/// errors (a damaged record counts as missing).
pub fn merge(dir: &Path) -> Result<Merge, SweepRunError> {
    merge_once(dir, true)
}

fn merge_once(dir: &Path, read_records: bool) -> Result<Merge, SweepRunError> {
    let started = Instant::now();
    let lock = load_lock(dir)?;
    let mut cost = MergeCost::default();
    if let Ok(m) = merge_tables(dir, &lock, None, &mut cost, started)? {
        return Ok(m);
    }
    let sweep = &lock.sweep;
    if let Some(refine) = &sweep.refine {
        return merge_refined(dir, &lock, refine, cost, started);
    }
    if !read_records {
        let have = listed(dir).map_err(io_err(dir))?.len();
        if have < sweep.points {
            cost.seconds = started.elapsed().as_secs_f64();
            return Ok(Merge::Incomplete {
                missing: sweep.points - have,
                points: sweep.points,
                other_build: 0,
                cost,
            });
        }
    }
    let mut rows = Vec::with_capacity(sweep.points);
    let (mut missing, mut other_build) = (0, 0);
    for p in 0..sweep.points {
        cost.records_read += 1;
        match PointRecord::find(dir, p, &sweep.values(p), &lock.fingerprint).map_err(io_err(dir))? {
            Found::Current(r) => rows.push(MapRow::of(&r)),
            Found::OtherBuild { .. } => {
                missing += 1;
                other_build += 1;
            }
            Found::Missing | Found::Damaged => missing += 1,
            Found::OtherSweep { why } => {
                return Err(SweepRunError::Foreign {
                    path: PointRecord::path(dir, p),
                    why,
                });
            }
        }
    }
    if missing > 0 {
        cost.seconds = started.elapsed().as_secs_f64();
        return Ok(Merge::Incomplete {
            missing,
            points: sweep.points,
            other_build,
            cost,
        });
    }
    write_map(dir, sweep, rows, cost, started)
}

/// A current record's row (`None` for a missing, damaged or other build's record).
fn current_row(
    dir: &Path,
    sweep: &Sweep,
    fingerprint: &str,
    p: usize,
    other_build: &mut usize,
) -> Result<Option<MapRow>, SweepRunError> {
    match PointRecord::find(dir, p, &sweep.values(p), fingerprint).map_err(io_err(dir))? {
        Found::Current(r) => Ok(Some(MapRow::of(&r))),
        Found::OtherBuild { .. } => {
            *other_build += 1;
            Ok(None)
        }
        Found::Missing | Found::Damaged => Ok(None),
        Found::OtherSweep { why } => Err(SweepRunError::Foreign {
            path: PointRecord::path(dir, p),
            why,
        }),
    }
}

/// The merge of a refined sweep from its records: level by level, as far as they go.
fn merge_refined(
    dir: &Path,
    lock: &SweepLock,
    refine: &super::refine::Refine,
    mut cost: MergeCost,
    started: Instant,
) -> Result<Merge, SweepRunError> {
    let sweep = &lock.sweep;
    let mut other_build = 0;
    let walk = super::refine::walk(sweep, refine, |p| {
        cost.records_read += 1;
        current_row(dir, sweep, &lock.fingerprint, p, &mut other_build)
    })?;
    if !walk.complete() {
        cost.seconds = started.elapsed().as_secs_f64();
        return Ok(Merge::Incomplete {
            missing: walk.missing.len(),
            points: walk.points(),
            other_build,
            cost,
        });
    }
    write_map(dir, sweep, walk.rows.into_values().collect(), cost, started)
}

/// As [`merge`], waiting up to `timeout` for the directory to hold a sweep and for its points
/// to be complete (a merge started with the shards, or a dependent job): polls the shard
/// tables and the listing of `points/` five times a second, and reads the records only when
/// every point has one.
///
/// # Errors
/// As [`merge`]; [`SweepRunError::Missing`] when no sweep appeared within `timeout`.
pub fn merge_wait(dir: &Path, timeout: Duration) -> Result<Merge, SweepRunError> {
    let started = Instant::now();
    let mut pause = Duration::from_millis(200);
    loop {
        let late = started.elapsed() >= timeout;
        match load_lock(dir) {
            Err(e @ SweepRunError::Missing { .. }) => {
                if late {
                    return Err(e);
                }
            }
            Err(e) => return Err(e),
            Ok(_) => match merge_once(dir, late)? {
                Merge::Incomplete { cost, .. } if !late => {
                    // Records were read and some are not current (another build's, being
                    // recomputed): look again less often, so the waiting stays cheap.
                    if cost.records_read > 0 {
                        pause = pause.max(Duration::from_secs_f64(10.0 * cost.seconds));
                    }
                }
                m => return Ok(m),
            },
        }
        let left = timeout.saturating_sub(started.elapsed());
        std::thread::sleep(pause.min(left.max(Duration::from_millis(10))));
    }
}

/// The table of a sweep directory as a reader finds it ([`read_map`]).
#[derive(Debug, Clone, PartialEq)]
pub struct MapRead {
    /// The sweep (from sweep.json).
    pub sweep: Sweep,
    /// The rows there are, in point order.
    pub table: MapTable,
    /// Every point has its row.
    pub complete: bool,
    /// The points of the map: the sweep's, or a refined sweep's so far (the levels reached).
    pub points: usize,
}

/// Reads the table of the sweep in `dir` without writing anything: map.csv when it is there;
/// else, for a sweep still running, interrupted, or whose shards ran elsewhere, the rows of
/// the points whose record is this sweep's (the fingerprint in sweep.json), in point order.
/// Records of another build or damaged ones count as missing, as in [`merge`].
///
/// # Errors
/// No sweep in `dir` ([`SweepRunError::Missing`]); a map.csv that does not parse; a record of
/// another sweep ([`SweepRunError::Foreign`]); I/O errors.
pub fn read_map(dir: &Path) -> Result<MapRead, SweepRunError> {
    let lock = load_lock(dir)?;
    let sweep = lock.sweep;
    if dir.join(CSV_FILE).is_file() {
        let table = MapTable::read(dir).map_err(|e| io_err(dir)(io::Error::other(e)))?;
        let points = match &sweep.refine {
            Some(refine) => {
                let rows: BTreeMap<usize, &MapRow> =
                    table.rows.iter().map(|r| (r.point, r)).collect();
                super::refine::walk(&sweep, refine, |p| {
                    Ok::<_, SweepRunError>(rows.get(&p).map(|r| (*r).clone()))
                })?
                .points()
            }
            None => sweep.points,
        };
        return Ok(MapRead {
            complete: table.rows.len() == points,
            points,
            table,
            sweep,
        });
    }
    if let Some(refine) = &sweep.refine {
        let mut other_build = 0;
        let walk = super::refine::walk(&sweep, refine, |p| {
            current_row(dir, &sweep, &lock.fingerprint, p, &mut other_build)
        })?;
        return Ok(MapRead {
            complete: walk.complete(),
            points: walk.points(),
            table: MapTable {
                axes: sweep.axes.iter().map(|a| a.key.clone()).collect(),
                rows: walk.rows.into_values().collect(),
            },
            sweep,
        });
    }
    let mut rows = Vec::new();
    for p in listed(dir).map_err(io_err(dir))? {
        if p >= sweep.points {
            continue;
        }
        match PointRecord::find(dir, p, &sweep.values(p), &lock.fingerprint).map_err(io_err(dir))? {
            Found::Current(r) => rows.push(MapRow::of(&r)),
            Found::OtherBuild { .. } | Found::Missing | Found::Damaged => {}
            Found::OtherSweep { why } => {
                return Err(SweepRunError::Foreign {
                    path: PointRecord::path(dir, p),
                    why,
                });
            }
        }
    }
    Ok(MapRead {
        complete: rows.len() == sweep.points,
        points: sweep.points,
        table: MapTable {
            axes: sweep.axes.iter().map(|a| a.key.clone()).collect(),
            rows,
        },
        sweep,
    })
}

/// Paths of the shard tables in `dir` (for tests and cleanup).
///
/// # Errors
/// If `shards/` exists but cannot be listed.
pub fn table_paths(dir: &Path) -> io::Result<Vec<PathBuf>> {
    Ok(table_names(dir)?
        .into_iter()
        .map(|n| dir.join(SHARDS_DIR).join(n))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_names_round_trip() {
        let name = table_name(3, 16, "0123456789abcdef");
        assert_eq!(name, "3-of-16.0123456789abcdef.json");
        assert_eq!(parse_table_name(&name), Some((3, 16, "0123456789abcdef")));
        assert_eq!(parse_table_name("3-of-16.json"), None);
        assert_eq!(parse_table_name(".3-of-16.b.json.1-2.tmp"), None);
    }
}
