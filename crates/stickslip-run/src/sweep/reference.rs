//! The sweeps part of `docs/reference.md`: the sweep file's keys, the table's columns and the
//! regime rules, written from the definitions they describe (the thresholds' defaults, the
//! summary columns, the point limit), so the reference cannot drift from the code.

use super::map::{CSV_FILE, JSON_FILE, SUMMARY_COLUMNS};
use super::record::PointStatus;
use super::{HARD_MAX_POINTS, MAX_POINTS};
use crate::summary::{Regime, RegimeThresholds};

/// Markdown: `## Sweeps` with the file, the table and the regimes.
#[must_use]
pub fn markdown() -> String {
    let t = RegimeThresholds::default();
    let mut out = String::from("## Sweeps\n\n");
    out.push_str(
        "A sweep file (TOML) runs one scene over the cartesian product of its axes, the last \
         axis fastest, points numbered 0 … P−1 (`stickslip sweep run`, `stickslip.sweep` from \
         Python). Every point is validated before the first one runs; a bad file exits 2 \
         naming the key, its line, the value and what is allowed. An axis must not give the \
         same point twice: repeated values, and an integer key's range whose values round to \
         the same integer, are refused.\n\n",
    );
    out.push_str("### Sweep file\n\n| key | meaning |\n|---|---|\n");
    let rows: [(&str, String); 9] = [
        ("name", "name of the sweep (required)".into()),
        (
            "scene",
            "the base scene file, relative to the sweep file (required)".into(),
        ),
        (
            "[set]",
            "`\"section.key\" = value` applied to every point, like `--set`".into(),
        ),
        (
            "[[axis]] key",
            "a scene key (`section.key`, see Scene keys); one axis per key".into(),
        ),
        (
            "[[axis]] values",
            "the axis values: numbers, or words for a choice key".into(),
        ),
        (
            "[[axis]] range",
            "instead of `values`: `{ from, to, count, scale }`, `scale` `\"linear\"` (default) \
             or `\"log\"` (from and to > 0), count ≥ 1"
                .into(),
        ),
        (
            "[regime] stick_slip_recovery",
            format!(
                "R at or above which two or more events are `stick_slip` (default {})",
                t.stick_slip_recovery
            ),
        ),
        (
            "[regime] smooth_recovery",
            format!(
                "R below which two or more events are `smooth` (default {}); in between: \
                 `partial`",
                t.smooth_recovery
            ),
        ),
        (
            "[regime] sliding_fraction",
            format!(
                "share of the time after the first onset with no solid node at or above which \
                 the run is `sliding` (default {})",
                t.sliding_fraction
            ),
        ),
    ];
    for (key, meaning) in rows {
        out.push_str(&format!("| `{key}` | {meaning} |\n"));
    }
    out.push_str(&format!(
        "\nMore than {MAX_POINTS} points need `--allow-large` (`allow_large=True` in Python); \
         no sweep may have more than {HARD_MAX_POINTS}. Beyond {MAX_POINTS} points each axis \
         value is validated at once and each point's scene when the point runs: a combination \
         of values the scene refuses is a `refused` row.\n"
    ));
    out.push_str(
        "\n### Sweep directory\n\n\
         | file | what |\n|---|---|\n\
         | `sweep.json` | the sweep as resolved, its fingerprint (a hash of the base scene with \
         `[set]`, the axes and the thresholds, and the build identity of the numerics) and \
         the build |\n\
         | `points/NNNNNNN.json` | one record per finished point: its values, summary, status \
         and the sweep's fingerprint |\n\
         | `shards/I-of-N.BUILD.json` | the rows of shard I/N once it ran to its end; the last \
         shard to finish merges the tables of a complete set |\n\
         | `map.csv`, `map.json` | the map, when every point has a row |\n\
         | `runs/NNNNNNN/` | with `--keep all`, each point's output files |\n\n\
         One sweep per directory: a record or table of another sweep is refused (exit 2, \
         naming it); records of the same sweep computed by another build are recomputed, and \
         `sweep run` says how many and why. `--force` starts afresh (also for the same \
         sweep). Shards, jobs and merges may run at once on one directory.\n",
    );

    out.push_str(&format!(
        "\n### `{CSV_FILE}`\n\nOne row per point, in point order; `{JSON_FILE}` holds the \
         sweep as resolved, the same table, the regime thresholds and the program version. \
         Results do not depend on `--jobs` or `--shard` (only `wall_s` differs).\n\n\
         | column | unit | meaning |\n|---|---|---|\n\
         | `point` | – | point number |\n\
         | `<axis key>` | the key's unit | one column per axis, named by its key |\n"
    ));
    let statuses: Vec<String> = [PointStatus::Ok, PointStatus::Failed, PointStatus::Refused]
        .iter()
        .map(|s| format!("`{}`", s.name()))
        .collect();
    out.push_str(&format!(
        "| `status` | – | {} (a failing point is a row, the sweep goes on) |\n",
        statuses.join(" \\| ")
    ));
    for c in SUMMARY_COLUMNS {
        out.push_str(&format!("| `{}` | {} | {} |\n", c.name, c.unit, c.meaning));
    }
    out.push_str("| `message` | – | the failure or refusal, in one line (empty when ok) |\n");
    out.push_str(
        "| `steady` | – | `true` when the point's last time.steady_cycles cycles repeat within \
         time.steady_rtol (its regime is the steady state's), else `false` (taken at the end of \
         its window; a map.csv without this column reads as `false`) |\n",
    );

    out.push_str(
        "\n### Regimes\n\nDecided in this order (R: the largest area-weighted ⟨φ⟩/√(A/a) (the \
         first-order film: ⟨φ⟩/φ₊(0)) over the last complete cycle, `recovery` above; the physics behind the rules: \
         [model.md](model.md#regimes-and-friction-maps)):\n\n| regime | rule |\n|---|---|\n",
    );
    for r in Regime::ALL {
        let rule = match r {
            Regime::Sliding => format!(
                "A(0) ≤ 0 (a first-order film: unless it starts as a metastable solid), or no \
                 node solid for at least {} of the time after the first onset",
                t.sliding_fraction
            ),
            Regime::NoMelting => "no event".to_string(),
            Regime::Transient => {
                "one event (one open event whose own recovery stays below the smooth threshold \
                 is `smooth`)"
                    .to_string()
            }
            Regime::StickSlip => format!("two or more events, R ≥ {}", t.stick_slip_recovery),
            Regime::Partial => format!(
                "two or more events, {} ≤ R < {}",
                t.smooth_recovery, t.stick_slip_recovery
            ),
            Regime::Smooth => format!("two or more events, R < {}", t.smooth_recovery),
        };
        out.push_str(&format!("| `{}` | {rule} |\n", r.name()));
    }
    out
}
