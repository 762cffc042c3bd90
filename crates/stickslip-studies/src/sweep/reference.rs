//! The sweeps part of `docs/reference.md`: the sweep file's keys, the table's columns and the
//! regime rules, written from the definitions they describe (the thresholds' defaults, the
//! summary columns, the point limit), so the reference cannot drift from the code.

use super::map::{ENERGY_COLUMN, LEVEL_COLUMN, STAMP_COLUMNS, SUMMARY_COLUMNS};
use super::record::PointStatus;
use super::refine::{MAX_AXES, ON_REGIME};
use super::{HARD_MAX_POINTS, MAX_POINTS};
use stickslip_run::layout::sweep::{CHECKS_DIR, CSV_FILE, JSON_FILE};
use stickslip_run::summary::{Regime, RegimeThresholds};

/// `### Refinement`: the `[refine]` table's rules.
fn refinement() -> String {
    format!(
        "\n### Refinement\n\n\
         ```toml\n[refine]\nlevels = 4              # integer ≥ 0; 0 = no refinement\n\
         on = \"{ON_REGIME}\"           # or the name of a numeric map.csv column …\n\
         threshold = 0.1         # … with a relative jump that splits a cell\n```\n\n\
         A refined sweep runs its base grid, then `levels` times splits every cell whose \
         corners differ and runs the new points. An axis of n values has (n − 1)·2^levels + 1 \
         on the finest grid: a `range` is the same range with that count (the finest grid is \
         the uniform sweep of that count, value for value); listed values get 2^levels − 1 \
         values between neighbours, evenly spaced, geometrically where the axis is \
         log-spaced. Points are numbered in the finest grid (the last axis fastest), so a \
         point's number is the same at every level and for any jobs or shards, and map.csv \
         (rows in point order) holds a subset of the uniform finest grid's points. A cell of \
         level k is the interval (one axis) or rectangle (two axes) between neighbouring \
         points of the level-k grid (2^(levels−k) finest steps apart) whose corners all ran; \
         it splits when two corners differ — in regime (a failed or refused point is a class \
         of its own), or with `on` a column in that column's value by more than `threshold` \
         (relative, as above; a missing value differs from a number, two missing values do \
         not; failed or refused points compare by status) — and gives the finer grid's points \
         on its edges' midpoints and its centre. The next level's points depend only on the \
         results of the levels before: a rerun after a kill skips every finished point and \
         finds the same points. At most {MAX_AXES} axes, all numeric (a word axis, or a third \
         axis, exits 2 naming `refine`); an integer key's axis whose finest grid would repeat \
         a value, or levels whose finest grid passes {HARD_MAX_POINTS} points, exit 2 naming \
         `refine.levels`. The limit of {MAX_POINTS} points without `--allow-large` counts \
         the base grid.\n\n\
         With `--shard I/N`, a shard runs every N-th point of each level (in point order, from \
         the I-th), and stops with exit 0 at a level whose other points are not finished yet \
         (it says which); a rerun goes on. `sweep slurm --submit` submits the script once per \
         level and once for the base grid, each array after the previous one ended well \
         (`--dependency=afterok`), then `sweep merge` as a job after the last one (the shard \
         that finds every level complete writes the map, but tasks ending together may each \
         miss the others' points). A shard reads the records of every level it passes \
         (about N·P reads for an array of N tasks) and writes no shard table. `sweep plot` draws \
         each point's cell at its level's size (half a level-k step either way, finer cells \
         over coarser) and the regime boundary as a line.\n"
    )
}

/// `### Spot checks`: the `[verify]` table's rules.
fn spot_checks() -> String {
    format!(
        "\n### Spot checks\n\n\
         ```toml\n[verify]\nsample = 0.1            # a share of the points (or: points = 30)\n\
         boundaries = true       # and every point next to a regime boundary (default)\n```\n\n\
         Once the map is complete, `sweep run` (and `sweep merge`) rerun the checked points at \
         twice the nodes (radial contacts) and at a tenth of `time.tolerance` (half \
         `time.dt` with fixed steps): the first refinement along each axis that `stickslip \
         verify` makes. The sample is spread evenly over the points that ran `ok`, in point \
         order; a boundary point is one whose nearest neighbour along an axis (in a refined \
         map, the nearest point that ran) has another regime, a failed or refused neighbour \
         counting as a class of its own. Each check is a record `{dir}/<point>.json` (its \
         reruns' summaries, whether the regime changed, the largest relative change of \
         `t_first_onset`, `period_last`, `f_peak_first`, `f_peak_last` or `f_mean`), written \
         atomically with the sweep's fingerprint: a rerun skips the checks done by this build, \
         and Ctrl-C keeps the finished ones (exit 130). {json} then gains `spot_checks`: the \
         settings, the counts (checked, sampled, at boundaries, changed), the largest change \
         with its column and point, and every check. `[verify]` is not part of the sweep's \
         definition: adding it to a finished sweep runs only the checks. A changed regime is a \
         warning, not an exit status: the map's regime at that point is not converged. `sweep \
         plot` rings the checked points whose regime changed.\n",
        dir = CHECKS_DIR,
        json = JSON_FILE,
    )
}

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
    for key in super::file_keys::registry() {
        out.push_str(&format!("| `{}` | {} |\n", key.label(), key.meaning));
    }
    out.push_str(&format!(
        "\nMore than {MAX_POINTS} points need `--allow-large` (`allow_large=True` in Python); \
         no sweep may have more than {HARD_MAX_POINTS}. Beyond {MAX_POINTS} points each axis \
         value is validated at once and each point's scene when the point runs: a combination \
         of values the scene refuses is a `refused` row.\n"
    ));
    out.push_str(&refinement());
    out.push_str(&spot_checks());
    out.push_str(
        "\n### Sweep directory\n\n\
         | file | what |\n|---|---|\n\
         | `sweep.json` | the sweep as resolved, its fingerprint (a hash of the base scene with \
         `[set]`, the axes, the thresholds and `[refine]`, and the build identity of the \
         numerics) and the build |\n\
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
    out.push_str(&format!(
        "| `{LEVEL_COLUMN}` | – | the point's level in a refined sweep: 0 for the base grid (and \
         every point of a sweep without `[refine]`), k for the points of cells split k times (a \
         map.csv without this column reads as 0) |\n"
    ));
    for c in STAMP_COLUMNS.iter().chain(std::iter::once(&ENERGY_COLUMN)) {
        out.push_str(&format!("| `{}` | {} | {} |\n", c.name, c.unit, c.meaning));
    }

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
