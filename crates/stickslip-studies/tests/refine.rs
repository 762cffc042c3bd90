//! Adaptive refinement of friction maps (`[refine]`): the point sets (subsets of the uniform
//! finest grid, on log and linear axes, one and two axes), numbering and determinism over jobs
//! and shards, an interrupted refined sweep rerun to the same map, agreement with the uniform
//! grid at the finest spacing, bad `[refine]` tables, and map.csv files without `level`.

use crate::common;
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use stickslip_run::cycles::StampRegime;
use stickslip_run::summary::Regime;
use stickslip_studies::sweep::exec::{self, Merge, SweepOptions};
use stickslip_studies::sweep::map::{MapRow, MapTable};
use stickslip_studies::sweep::record::PointStatus;
use stickslip_studies::sweep::refine::{self, agreement, geometry};
use stickslip_studies::sweep::{Sweep, file};

/// A sweep over the rigid drive (N = 20, short window) with `axes` and `refine` (TOML text).
fn sweep_text(axes: &str, refine: &str) -> String {
    format!(
        "name = \"refined\"\nscene = \"{}\"\n[set]\n\"contact.nodes\" = 20\n\
         \"time.max_events\" = 6\n\"time.max_open_event\" = 2e-5\n\"time.end\" = 1e-3\n\
         {axes}{refine}",
        common::scene("rigid").display()
    )
}

fn resolve(text: &str) -> Result<Sweep, stickslip_studies::sweep::SweepError> {
    let file = file::parse(text, "test.toml", true)?;
    Sweep::resolve(&file, Path::new("/nonexistent/test.toml"), false)
}

const VELOCITY_LOG: &str = "[[axis]]\nkey = \"drive.velocity\"\n\
                            range = { from = 0.01, to = 1.0, count = 3, scale = \"log\" }\n";
const A0_LINEAR: &str = "[[axis]]\nkey = \"temperature.A0\"\n\
                         range = { from = -3e5, to = 1.5e6, count = 3 }\n";

/// A row of regime `regime` (status ok) for point `p`.
fn row(p: usize, regime: Regime) -> MapRow {
    MapRow {
        point: p,
        values: Vec::new(),
        status: PointStatus::Ok,
        summary: stickslip_run::summary::RunSummary::without_numbers(regime),
        wall_s: 0.0,
        message: String::new(),
        level: 0,
        slip_interval_median: None,
        melting_interval_median: None,
    }
}

#[test]
fn the_finest_grid_is_the_uniform_grid_value_for_value() {
    for levels in 0..4 {
        let refined = resolve(&sweep_text(
            &format!("{VELOCITY_LOG}{A0_LINEAR}"),
            &format!("[refine]\nlevels = {levels}\n"),
        ))
        .unwrap();
        let m = 2 * (1 << levels) + 1;
        let uniform = resolve(&sweep_text(
            &format!("{VELOCITY_LOG}{A0_LINEAR}").replace("count = 3", &format!("count = {m}")),
            "",
        ))
        .unwrap();
        assert_eq!(refined.axes, uniform.axes, "levels = {levels}");
        assert_eq!(refined.points, m * m);
        let r = refined.refine.as_ref().unwrap();
        assert_eq!(r.base, vec![3, 3]);
        // The base points are the uniform grid's at every 2^levels-th place, level 0.
        let base = refine::base_points(&refined, r);
        assert_eq!(base.len(), 9);
        let step = 1 << levels;
        for &p in &base {
            let idx = refined.indices(p);
            assert!(idx.iter().all(|j| j % step == 0));
            assert_eq!(refined.level(p), 0);
        }
        // Distinct sweeps: the refine table is part of the definition.
        assert_ne!(refined.definition(), uniform.definition());
    }
    // Listed values: evenly between neighbours, geometrically on a log axis.
    let listed = resolve(&sweep_text(
        "[[axis]]\nkey = \"drive.velocity\"\nvalues = [0.01, 0.1, 1.0]\n",
        "[refine]\nlevels = 1\n",
    ))
    .unwrap();
    let v = listed.axes[0].numbers();
    assert_eq!(v.len(), 5);
    assert_eq!([v[0], v[2], v[4]], [0.01, 0.1, 1.0]);
    assert!((v[1] / 0.1f64.sqrt().powi(3) - 1.0).abs() < 1e-12, "{v:?}");
    let linear = resolve(&sweep_text(
        "[[axis]]\nkey = \"temperature.A0\"\nvalues = [1e5, 2e5, 3e5]\n",
        "[refine]\nlevels = 2\n",
    ))
    .unwrap();
    assert_eq!(
        linear.axes[0].numbers(),
        vec![1e5, 1.25e5, 1.5e5, 1.75e5, 2e5, 2.25e5, 2.5e5, 2.75e5, 3e5]
    );
    // Levels of points: the coarsest grid holding them.
    let r = linear.refine.as_ref().unwrap();
    let levels: Vec<usize> = (0..9).map(|p| linear.level(p)).collect();
    assert_eq!(levels, vec![0, 2, 1, 2, 0, 2, 1, 2, 0]);
    assert_eq!(r.stride(), 4);
}

/// The refined point set of `sweep` when the regime of every point is `truth(indices)`.
fn walk_with(sweep: &Sweep, truth: &dyn Fn(&[usize]) -> Regime) -> refine::Walk {
    let r = sweep.refine.as_ref().unwrap();
    refine::walk(sweep, r, |p| {
        Ok::<_, ()>(Some(row(p, truth(&sweep.indices(p)))))
    })
    .unwrap()
}

#[test]
fn split_cells_give_their_edge_midpoints_and_centre() {
    // One axis, 3 base values, 2 levels: a step between fine indices 4 and 5.
    let one = resolve(&sweep_text(A0_LINEAR, "[refine]\nlevels = 2\n")).unwrap();
    let step = |i: &[usize]| {
        if i[0] <= 4 {
            Regime::Sliding
        } else {
            Regime::StickSlip
        }
    };
    let w = walk_with(&one, &step);
    assert!(w.complete());
    assert_eq!(w.levels, vec![vec![0, 4, 8], vec![6], vec![5]]);
    // Nothing to split: the base grid only.
    let w = walk_with(&one, &|_| Regime::Smooth);
    assert_eq!(w.levels, vec![vec![0, 4, 8]]);
    // Two axes, a straight boundary x + y > c on a 3 × 3 base grid refined 3 times (17 × 17).
    let two = resolve(&sweep_text(
        &format!("{VELOCITY_LOG}{A0_LINEAR}"),
        "[refine]\nlevels = 3\n",
    ))
    .unwrap();
    let diagonal = |i: &[usize]| {
        if i[0] + i[1] > 13 {
            Regime::StickSlip
        } else {
            Regime::Partial
        }
    };
    let w = walk_with(&two, &diagonal);
    let points = w.points();
    assert!(points < two.points, "{points} of {}", two.points);
    // Every point is on the finest grid, once, and its level is that of its grid.
    let mut all: Vec<usize> = w.levels.concat();
    all.sort_unstable();
    all.dedup();
    assert_eq!(all.len(), points);
    for (k, level) in w.levels.iter().enumerate() {
        for &p in level {
            assert!(p < two.points);
            assert_eq!(two.level(p), k);
        }
    }
    // The cells assign every point of the uniform grid its true regime.
    let r = two.refine.as_ref().unwrap();
    let owners = geometry::owners(&two, r, &w.rows);
    let wrong = (0..two.points)
        .filter(|&p| {
            let owner = owners[p].unwrap();
            w.rows[&owner].summary.regime != diagonal(&two.indices(p))
        })
        .count();
    assert_eq!(wrong, 0);
    // The boundary: one segment per neighbouring pair across it.
    let rows: Vec<MapRow> = w.rows.values().cloned().collect();
    let segments = geometry::boundary(&two, r, &rows);
    let pairs = (0..17 * 17)
        .flat_map(|p| {
            let i = two.indices(p);
            [(1, 0), (0, 1)].into_iter().filter(move |&(dx, dy)| {
                i[0] + dx < 17 && i[1] + dy < 17 && {
                    let j = [i[0] + dx, i[1] + dy];
                    diagonal(&i) != diagonal(&j)
                }
            })
        })
        .count();
    assert_eq!(segments.len(), pairs);
    // Cells: each inside the map, coarse first; the same through map_geometry.
    let cells = geometry::cells(&two, r, &rows);
    let g = geometry::map_geometry(&two, &rows).unwrap();
    assert_eq!(
        (g.cells.len(), g.boundary.len()),
        (cells.len(), segments.len())
    );
    assert_eq!(cells.len(), points);
    assert!(cells.windows(2).all(|c| c[0].level <= c[1].level));
    println!(
        "diagonal boundary, 3 x 3 base, 3 levels: {points} points refined against {} uniform",
        two.points
    );
}

/// Runs `sweep` into `dir` with `options` (no interruption); the merge after its shard.
fn run(sweep: &Sweep, dir: &Path, options: &SweepOptions) -> exec::ShardReport {
    exec::prepare(sweep, dir, false).unwrap();
    let report = exec::run_shard(sweep, dir, options, None, &mut |_| {}).unwrap();
    exec::after_shard(dir, &sweep.fingerprint(), options.shard).unwrap();
    report
}

/// map.csv without the wall-clock column.
fn map_without_wall(dir: &Path) -> Vec<String> {
    let table = MapTable::read(dir).unwrap();
    let wall = table.header().iter().position(|h| h == "wall_s").unwrap();
    table
        .to_csv()
        .lines()
        .map(|l| {
            let mut c: Vec<&str> = l.split(',').collect();
            c.remove(wall);
            c.join(",")
        })
        .collect()
}

const TWO_AXES: &str = "[[axis]]\nkey = \"drive.velocity\"\n\
                        range = { from = 1e-3, to = 1e-2, count = 3, scale = \"log\" }\n\
                        [[axis]]\nkey = \"temperature.A0\"\n\
                        range = { from = -2e5, to = 1.4e6, count = 3 }\n";

#[test]
fn refined_maps_do_not_depend_on_jobs_shards_or_interruptions() {
    let tmp = tempfile::tempdir().unwrap();
    let sweep = resolve(&sweep_text(TWO_AXES, "[refine]\nlevels = 2\n")).unwrap();
    let one = tmp.path().join("one");
    let report = run(&sweep, &one, &SweepOptions::default());
    assert_eq!(report.waiting, None);
    let reference = map_without_wall(&one);
    let table = MapTable::read(&one).unwrap();
    assert!(table.rows.iter().any(|r| r.level == 2), "no level-2 point");
    assert!(table.rows.windows(2).all(|w| w[0].point < w[1].point));
    let two = tmp.path().join("two");
    run(
        &sweep,
        &two,
        &SweepOptions {
            jobs: 2,
            ..SweepOptions::default()
        },
    );
    assert_eq!(map_without_wall(&two), reference);
    // Three shards, run one after the other in rounds: a shard stops at a level whose other
    // points are missing, and the next round goes on from there.
    let sharded = tmp.path().join("sharded");
    let mut rounds = 0;
    while !sharded.join("map.csv").exists() {
        rounds += 1;
        assert!(rounds <= 4, "not complete after {rounds} rounds");
        for i in 0..3 {
            let report = run(
                &sweep,
                &sharded,
                &SweepOptions {
                    shard: (i, 3),
                    ..SweepOptions::default()
                },
            );
            if rounds == 1 && i == 0 {
                assert_eq!(report.waiting.map(|w| w.level), Some(0));
            }
        }
    }
    assert_eq!(map_without_wall(&sharded), reference);
    assert!(matches!(
        exec::merge(&sharded).unwrap(),
        Merge::Complete { .. }
    ));
    // Interrupted after some points (the flag a signal sets), at several instants, then rerun.
    for after in [2, 11, 20] {
        let dir = tmp.path().join(format!("interrupted{after}"));
        exec::prepare(&sweep, &dir, false).unwrap();
        let flag = AtomicBool::new(false);
        let report = exec::run_shard(
            &sweep,
            &dir,
            &SweepOptions::default(),
            Some(&flag),
            &mut |p| {
                if p.done >= after {
                    flag.store(true, Ordering::Relaxed);
                }
            },
        )
        .unwrap();
        assert!(report.interrupted, "after {after}");
        assert!(!dir.join("map.csv").exists());
        let read = exec::read_map(&dir).unwrap();
        assert!(!read.complete);
        let report = run(&sweep, &dir, &SweepOptions::default());
        assert!(report.skipped >= after, "{report:?}");
        assert_eq!(
            map_without_wall(&dir),
            reference,
            "interrupted after {after}"
        );
    }
    // A record lost from a middle level is recomputed, and the map is the same.
    let table = MapTable::read(&one).unwrap();
    let mid = table.rows.iter().find(|r| r.level == 1).unwrap().point;
    std::fs::remove_file(one.join("points").join(format!("{mid:07}.json"))).unwrap();
    for f in ["map.csv", "map.json"] {
        std::fs::remove_file(one.join(f)).unwrap();
    }
    let report = run(&sweep, &one, &SweepOptions::default());
    assert_eq!(report.ran, 1);
    assert_eq!(map_without_wall(&one), reference);
    // map.json carries the refine table.
    let json = stickslip_studies::sweep::map::MapJson::read(&one).unwrap();
    assert_eq!(json.sweep.refine.as_ref().map(|r| r.levels), Some(2));
}

#[test]
fn a_refined_map_agrees_with_the_uniform_grid_at_the_finest_spacing() {
    let tmp = tempfile::tempdir().unwrap();
    let options = SweepOptions {
        jobs: 2,
        ..SweepOptions::default()
    };
    // Two maps: a 2-axis one (velocity × A0) and a 1-axis one along A0.
    let one_axis = "[[axis]]\nkey = \"temperature.A0\"\n\
                    range = { from = -2e5, to = 1.4e6, count = 5 }\n";
    for (name, axes, levels, counts) in [
        ("two axes", TWO_AXES, 3, vec![3, 3]),
        ("one axis", one_axis, 3, vec![5]),
    ] {
        let refined =
            resolve(&sweep_text(axes, &format!("[refine]\nlevels = {levels}\n"))).unwrap();
        let mut uniform_axes = axes.to_string();
        for n in &counts {
            let m = (n - 1) * (1 << levels) + 1;
            uniform_axes =
                uniform_axes.replacen(&format!("count = {n} "), &format!("count = {m} "), 1);
            uniform_axes =
                uniform_axes.replacen(&format!("count = {n},"), &format!("count = {m},"), 1);
        }
        let uniform = resolve(&sweep_text(&uniform_axes, "")).unwrap();
        assert_eq!(refined.axes, uniform.axes, "{name}");
        let (rd, ud) = (
            tmp.path().join(format!("r{name}")),
            tmp.path().join(format!("u{name}")),
        );
        run(&refined, &rd, &options);
        run(&uniform, &ud, &options);
        let (r, u) = (MapTable::read(&rd).unwrap(), MapTable::read(&ud).unwrap());
        // Every refined point is the uniform grid's point of the same number, same results.
        let by_point: BTreeMap<usize, &MapRow> = u.rows.iter().map(|x| (x.point, x)).collect();
        for row in &r.rows {
            let other = by_point[&row.point];
            assert_eq!(row.values, other.values);
            assert_eq!(row.status, other.status);
            assert_eq!(row.summary, other.summary, "{name}: point {}", row.point);
        }
        // The refined map's cells against the uniform grid.
        let rows: BTreeMap<usize, MapRow> = r.rows.iter().map(|x| (x.point, x.clone())).collect();
        let owners = geometry::owners(&refined, refined.refine.as_ref().unwrap(), &rows);
        let differing = (0..uniform.points)
            .filter(|&p| {
                let owner = owners[p].unwrap();
                rows[&owner].summary.regime != by_point[&p].summary.regime
                    || (rows[&owner].status == PointStatus::Ok)
                        != (by_point[&p].status == PointStatus::Ok)
            })
            .count();
        println!(
            "{name}: refined {} points, uniform {}; {differing} uniform points in a cell of \
             another regime",
            r.rows.len(),
            u.rows.len()
        );
        assert!(r.rows.len() < u.rows.len(), "{name}");
        assert_eq!(differing, 0, "{name}");
        // The run library's comparison says the same, and sees a changed regime.
        let refine = refined.refine.as_ref().unwrap();
        let a = agreement::agreement(&refined, refine, &r.rows, &uniform, &u.rows);
        assert_eq!(a.compared, uniform.points, "{name}");
        assert_eq!(a.shared, r.rows.len(), "{name}");
        assert_eq!(a.inferred, uniform.points - r.rows.len(), "{name}");
        assert!(
            a.shared_differ.is_empty() && a.inferred_differ.is_empty(),
            "{name}"
        );
        assert_eq!(a.off_grid, 0, "{name}");
        let mut changed = u.rows.clone();
        let flip = |row: &mut MapRow| {
            row.summary.regime = if row.summary.regime == Regime::Smooth {
                Regime::StickSlip
            } else {
                Regime::Smooth
            };
        };
        let not_run = (0..uniform.points).find(|p| !rows.contains_key(p)).unwrap();
        flip(&mut changed[0]);
        flip(&mut changed[not_run]);
        let a = agreement::agreement(&refined, refine, &r.rows, &uniform, &changed);
        assert_eq!(a.shared_differ, vec![0], "{name}");
        assert_eq!(a.inferred_differ, vec![not_run], "{name}");
        // Every other value of the finest grid, as listed values, lies on it.
        let half = agreement::subgrid_values(&refined, 2, &[]);
        assert_eq!(
            half[0].len(),
            refined.axes[0].values.len().div_ceil(2),
            "{name}"
        );
    }
}

#[test]
fn bad_refine_tables_name_the_key() {
    let two = format!("{VELOCITY_LOG}{A0_LINEAR}");
    let cases: [(&str, &str, &str); 13] = [
        ("[refine]\nlevels = -1\n", "", "refine.levels"),
        ("[refine]\nlevels = 1.5\n", "", "refine.levels"),
        ("[refine]\nlevels = \"2\"\n", "", "refine.levels"),
        ("[refine]\non = \"regime\"\n", "", "refine.levels"),
        ("[refine]\nlevels = 2\non = \"speed\"\n", "", "refine.on"),
        ("[refine]\nlevels = 2\non = \"status\"\n", "", "refine.on"),
        (
            "[refine]\nlevels = 2\non = \"wall_s\"\nthreshold = 0.1\n",
            "",
            "refine.on",
        ),
        (
            "[refine]\nlevels = 2\non = \"recovery\"\n",
            "",
            "refine.threshold",
        ),
        (
            "[refine]\nlevels = 2\non = \"recovery\"\nthreshold = 0\n",
            "",
            "refine.threshold",
        ),
        (
            "[refine]\nlevels = 2\nthreshold = 0.1\n",
            "",
            "refine.threshold",
        ),
        ("[refine]\nlevels = 2\ndepth = 1\n", "", "refine.depth"),
        ("[refine]\nlevels = 30\n", "", "refine.levels"),
        ("[refine]\nlevels = 4000000000\n", "", "refine.levels"),
    ];
    for (refine, extra, key) in cases {
        let e = resolve(&sweep_text(&format!("{two}{extra}"), refine)).unwrap_err();
        assert_eq!(e.key(), Some(key), "{refine}: {e}");
    }
    // More than two axes, a word axis, an integer axis whose finest grid repeats values.
    let third = "[[axis]]\nkey = \"contact.film_thickness\"\nvalues = [8e-8, 1e-7]\n";
    let e = resolve(&sweep_text(
        &format!("{two}{third}"),
        "[refine]\nlevels = 1\n",
    ))
    .unwrap_err();
    assert_eq!(e.key(), Some("refine"), "{e}");
    let words = "[[axis]]\nkey = \"contact.model\"\nvalues = [\"radial\", \"homogeneous\"]\n";
    let e = resolve(&sweep_text(
        &format!("{VELOCITY_LOG}{words}"),
        "[refine]\nlevels = 1\n",
    ))
    .unwrap_err();
    assert_eq!(e.key(), Some("refine"), "{e}");
    assert!(e.to_string().contains("contact.model"), "{e}");
    let ints = "[[axis]]\nkey = \"lubricant.noise.seed\"\nvalues = [20, 22]\n";
    let e = resolve(&sweep_text(ints, "[refine]\nlevels = 2\n")).unwrap_err();
    assert_eq!(e.key(), Some("refine.levels"), "{e}");
    // One level gives 20, 21, 22: no complaint about refine (the scene may refuse the key).
    if let Err(e) = resolve(&sweep_text(ints, "[refine]\nlevels = 1\n")) {
        assert!(!e.key().unwrap_or("").starts_with("refine"), "{e}");
    }
    // A column with a threshold is fine; levels = 0 is the base grid.
    let ok = resolve(&sweep_text(
        &two,
        "[refine]\nlevels = 2\non = \"recovery\"\nthreshold = 0.1\n",
    ))
    .unwrap();
    assert_eq!(ok.refine.unwrap().threshold, Some(0.1));
    let zero = resolve(&sweep_text(&two, "[refine]\nlevels = 0\n")).unwrap();
    assert_eq!(zero.points, 9);
}

/// `text` without its last `n` columns.
fn cut_columns(text: &str, n: usize) -> String {
    text.lines()
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            c[..c.len() - n].join(",")
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn map_csv_without_level_or_steady_still_reads() {
    let table = MapTable {
        axes: vec!["drive.velocity".into()],
        rows: vec![{
            let mut r = row(4, Regime::StickSlip);
            r.values = vec!["1e-2".into()];
            r.level = 2;
            r.summary.n_slips = 3;
            r.summary.stamp_regime = Some(StampRegime::SteadySliding);
            r.slip_interval_median = Some(0.25);
            r.melting_interval_median = Some(4.5e-3);
            r.summary.energy_per_cycle = Some(1.25e-10);
            r
        }],
    };
    let text = table.to_csv();
    assert!(text.lines().next().unwrap().ends_with(
        ",steady,level,stamp_regime,n_slips,slip_interval_median,melting_interval_median,\
         energy_per_cycle"
    ));
    assert_eq!(MapTable::parse(&text).unwrap(), table);
    assert_eq!(
        MapTable::parse(&text).unwrap().rows[0].number("n_slips"),
        3.0
    );
    assert_eq!(
        MapTable::parse(&text).unwrap().rows[0].number("energy_per_cycle"),
        1.25e-10
    );
    // Without the energy (written before the energy books), then without the stamp's columns
    // (before slips), then without `level` (before refinement), and without `steady` either.
    let text = cut_columns(&text, 1);
    let before_energy = MapTable::parse(&text).unwrap();
    assert_eq!(before_energy.rows[0].summary.energy_per_cycle, None);
    assert_eq!(before_energy.rows[0].summary.n_slips, 3);
    let before_slips = MapTable::parse(&cut_columns(&text, 4)).unwrap();
    let r = &before_slips.rows[0];
    assert_eq!(
        (r.level, r.summary.n_slips, r.summary.stamp_regime),
        (2, 0, None)
    );
    assert_eq!(r.slip_interval_median, None);
    let text = cut_columns(&text, 4);
    for n in [1, 2] {
        let old = MapTable::parse(&cut_columns(&text, n)).unwrap();
        assert_eq!(old.rows[0].level, 0);
        assert_eq!(old.rows[0].summary.regime, Regime::StickSlip);
    }
}

#[test]
fn a_column_splits_by_its_relative_jump() {
    let sweep = resolve(&sweep_text(
        A0_LINEAR,
        "[refine]\nlevels = 1\non = \"recovery\"\nthreshold = 0.1\n",
    ))
    .unwrap();
    let r = sweep.refine.as_ref().unwrap();
    let with = |v: Option<f64>| {
        let mut x = row(0, Regime::Partial);
        x.summary.recovery = v;
        x
    };
    // |a − b| > threshold · max(|a|, |b|).
    assert!(r.differ(&with(Some(0.5)), &with(Some(0.56))));
    assert!(!r.differ(&with(Some(0.5)), &with(Some(0.54))));
    assert!(r.differ(&with(Some(-0.5)), &with(Some(0.5))));
    assert!(!r.differ(&with(Some(0.0)), &with(Some(0.0))));
    // A missing value differs from a number, not from another missing value.
    assert!(r.differ(&with(None), &with(Some(0.5))));
    assert!(!r.differ(&with(None), &with(None)));
    // Regimes alone do not split on a column; a failed point differs from an ok one.
    let mut other = with(Some(0.5));
    other.summary.regime = Regime::StickSlip;
    assert!(!r.differ(&with(Some(0.5)), &other));
    let mut failed = with(Some(0.5));
    failed.status = PointStatus::Failed;
    assert!(r.differ(&failed, &with(Some(0.5))));
    assert!(!r.differ(&failed, &failed.clone()));
    // On the regime, a failed point is a class of its own.
    let by_regime = resolve(&sweep_text(A0_LINEAR, "[refine]\nlevels = 1\n")).unwrap();
    let rr = by_regime.refine.as_ref().unwrap();
    assert!(rr.differ(&failed, &with(Some(0.5))));
    assert!(rr.differ(&with(Some(0.5)), &other));
}

/// The spot checks' choice (`[verify]`): an even sample in point order, and every point whose
/// nearest point along an axis (in a refined map, the nearest that ran) has another regime.
#[test]
fn spot_checks_sample_evenly_and_find_every_boundary_point() {
    use stickslip_studies::sweep::spot::{Reason, SpotChecks, select};
    // A 3 × 3 map: stick–slip in the first column of A0, partial elsewhere.
    let sweep = resolve(&sweep_text(&format!("{VELOCITY_LOG}{A0_LINEAR}"), "")).unwrap();
    let regime = |p: usize| {
        if p.is_multiple_of(3) {
            Regime::StickSlip
        } else {
            Regime::Partial
        }
    };
    let table = MapTable {
        axes: sweep.axes.iter().map(|a| a.key.clone()).collect(),
        rows: (0..9).map(|p| row(p, regime(p))).collect(),
    };
    let both = SpotChecks {
        sample: None,
        points: Some(3),
        boundaries: true,
    };
    let chosen = select(&sweep, &both, &table);
    // Boundary points: the first two columns (the third has partial neighbours only).
    let boundary: Vec<usize> = chosen
        .iter()
        .filter(|(_, r)| *r != Reason::Sample)
        .map(|(p, _)| *p)
        .collect();
    assert_eq!(boundary, vec![0, 1, 3, 4, 6, 7]);
    // The sample: the middles of three equal runs of the nine points.
    let sampled: Vec<usize> = chosen
        .iter()
        .filter(|(_, r)| *r != Reason::Boundary)
        .map(|(p, _)| *p)
        .collect();
    assert_eq!(sampled, vec![1, 4, 7]);
    // A refined map: only the base grid's corners ran (points 0, 2, 4 of a 5-value finest
    // axis): the nearest point that ran is two finest steps away.
    let refined = resolve(&sweep_text(VELOCITY_LOG, "[refine]\nlevels = 1\n")).unwrap();
    let table = MapTable {
        axes: refined.axes.iter().map(|a| a.key.clone()).collect(),
        rows: vec![
            row(0, Regime::StickSlip),
            row(2, Regime::StickSlip),
            row(4, Regime::Partial),
        ],
    };
    let only = SpotChecks {
        sample: None,
        points: None,
        boundaries: true,
    };
    let chosen: Vec<usize> = select(&refined, &only, &table)
        .into_iter()
        .map(|(p, _)| p)
        .collect();
    assert_eq!(chosen, vec![2, 4]);
}
