//! The expected size of a run's output, for `check`: rows and bytes of series.csv, probes.csv
//! and profiles.csv, and the series interval that keeps the whole under a size.
//!
//! A series row is written at the first step at or after each mark `output.series_interval`
//! apart, so the rows are at most time.end/interval + 1 and at most the steps taken (adaptive
//! steps longer than the interval give one row each). Bytes per number are those of a typical
//! shortest round-trip `{:e}` value with its comma, measured on fig2's series.csv.

use crate::scene::ResolvedScene;
use serde::Serialize;

/// Bytes per number written, its comma included (fig2's series.csv: 17.0).
pub const BYTES_PER_NUMBER: f64 = 17.0;

/// Above this, `check` warns and names the series interval that keeps the output under it.
pub const LARGE_BYTES: f64 = 100e6;

/// Numbers per series.csv row.
const SERIES_NUMBERS: f64 = crate::schema::series::COLUMNS.len() as f64;

/// Numbers per profiles.csv row.
const PROFILE_NUMBERS: f64 = crate::schema::profiles::COLUMNS.len() as f64;

/// The expected output of a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OutputSize {
    /// Rows of series.csv (and of probes.csv when the scene has probes):
    /// [`OutputSize::series_rows_min`]. The writer writes a row at the first step at or after
    /// each mark: a melting's steps cluster in a front microseconds long and share marks, the
    /// stick's steps each reach one. 1.26× and 1.8× the rows written on fig2 at N = 200 and on
    /// the h0 = 1 nm contact at a 1 µs interval (tested within 3×), where a row per step is
    /// 2.6× and 7.6× high.
    pub series_rows: f64,
    /// A row per step at the pace of the run's first steps (the approach to the first
    /// melting, over check's probe: a count of steps set by the scene, so the same on any
    /// machine), at most one per mark: the stick phases' rows. Not a bound: a run's later
    /// sticks may be stepped faster or slower than its first.
    pub series_rows_min: f64,
    /// The most: a row per step, at most one per mark.
    pub series_rows_max: f64,
    /// Probe radii (0: no probes.csv).
    pub probes: usize,
    /// Rows of profiles.csv (a profile per profile time, a row per node).
    pub profile_rows: f64,
    /// All three files, bytes.
    pub bytes: f64,
    /// The series interval that keeps the whole under [`LARGE_BYTES`], s, when the output
    /// would be larger.
    pub interval_for_limit_s: Option<f64>,
}

/// The expected output of `scene` over `steps` steps, all at one pace.
#[must_use]
pub fn estimate(scene: &ResolvedScene, steps: f64) -> OutputSize {
    estimate_clustered(scene, steps, steps)
}

/// The expected output of `scene` over `steps` steps of which `approach_steps` come at the
/// pace of the run's first steps, the rest clustered in meltings (see [`OutputSize`]).
#[must_use]
pub fn estimate_clustered(scene: &ResolvedScene, steps: f64, approach_steps: f64) -> OutputSize {
    let (c, o) = (&scene.config, &scene.output);
    let end = c.time.end_s;
    let interval = o.series_interval_s;
    let marks = (end / interval).floor().max(0.0) + 1.0;
    let series_rows_max = marks.min(steps.max(1.0) + 1.0);
    let series_rows_min = marks.min(approach_steps.clamp(1.0, steps.max(1.0)).round() + 1.0);
    let series_rows = series_rows_min;
    let probes = o.probe_radii_m.len();
    let row_bytes = BYTES_PER_NUMBER
        * (SERIES_NUMBERS
            + if probes > 0 {
                1.0 + 2.0 * probes as f64
            } else {
                0.0
            });
    let profile_rows = (o.sorted_profile_times_s().len() * c.contact.nodes) as f64;
    let profile_bytes = profile_rows * PROFILE_NUMBERS * BYTES_PER_NUMBER;
    let bytes = series_rows * row_bytes + profile_bytes;
    let interval_for_limit_s = (bytes > LARGE_BYTES).then(|| {
        let rows = ((LARGE_BYTES - profile_bytes) / row_bytes).max(1.0);
        // Rounded up to two significant digits: a number to type, still under the limit.
        let x = end / rows;
        let unit = 10f64.powf(x.log10().floor() - 1.0);
        (x / unit).ceil() * unit
    });
    OutputSize {
        series_rows,
        series_rows_min,
        series_rows_max,
        probes,
        profile_rows,
        bytes,
        interval_for_limit_s,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    fn fig2(sets: &[&str]) -> ResolvedScene {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../validation/scenes/fig2.toml"
        );
        Scene::from_path(std::path::Path::new(path), sets).unwrap()
    }

    #[test]
    fn rows_follow_the_interval_or_the_steps_and_a_large_output_names_its_interval() {
        // fig2: 1.3 ms at 1e-7 s: 13 001 marks; with fewer steps than marks, a row per step.
        let s = fig2(&[]);
        let o = estimate(&s, 1e6);
        assert_eq!(o.series_rows, 13_001.0);
        assert_eq!(o.probes, 9);
        assert_eq!(o.profile_rows, 2000.0);
        assert!(o.interval_for_limit_s.is_none());
        assert_eq!(estimate(&s, 3000.0).series_rows, 3001.0);
        // 10 s at 1e-7 s with steps to match: 1e8 rows, far above 100 MB.
        let long = fig2(&["time.end=10", "output.profile_times=[10]"]);
        let o = estimate(&long, 1e9);
        assert!(o.bytes > 1e10, "{o:?}");
        let fit = o.interval_for_limit_s.unwrap();
        let at = fig2(&[
            "time.end=10",
            "output.profile_times=[10]",
            &format!("output.series_interval={fit:e}"),
        ]);
        let under = estimate(&at, 1e9);
        assert!(
            under.bytes <= LARGE_BYTES * 1.0001 && under.bytes > 0.9 * LARGE_BYTES,
            "{under:?}"
        );
    }
}
