//! The sweep file's keys in one table, as the scene's keys are in theirs: the reference's
//! "Sweep file" rows are written from it, and its test holds it to the keys the reader
//! accepts (each section's fields, as the reader's own refusal of an unknown key lists them).

use super::MAX_POINTS;
use super::refine::{ON_REGIME, columns};
use stickslip_run::summary::RegimeThresholds;

/// Where a key of the sweep file is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Place {
    /// At the top level: `name = …`.
    Top,
    /// A table of its own at the top level: `[set]`.
    Table,
    /// Inside a table: `[regime] smooth_recovery = …`.
    In(&'static str),
    /// Inside each of an array of tables: `[[axis]] key = …`.
    InEach(&'static str),
}

/// One key of the sweep file.
#[derive(Debug, Clone)]
pub struct SweepKey {
    /// Where it is written.
    pub place: Place,
    /// Its name.
    pub name: &'static str,
    /// What it means, with its allowed values and default.
    pub meaning: String,
}

impl SweepKey {
    /// How the reference names it: `name`, `[set]`, `[regime] smooth_recovery`,
    /// `[[axis]] key`.
    #[must_use]
    pub fn label(&self) -> String {
        match self.place {
            Place::Top => self.name.to_string(),
            Place::Table => format!("[{}]", self.name),
            Place::In(table) => format!("[{table}] {}", self.name),
            Place::InEach(table) => format!("[[{table}]] {}", self.name),
        }
    }

    /// The table it sits in (`None` at the top level, where `[set]` is a key too).
    #[must_use]
    pub fn section(&self) -> Option<&'static str> {
        match self.place {
            Place::Top | Place::Table => None,
            Place::In(table) | Place::InEach(table) => Some(table),
        }
    }
}

/// A key and its meaning.
fn key(place: Place, name: &'static str, meaning: impl Into<String>) -> SweepKey {
    SweepKey {
        place,
        name,
        meaning: meaning.into(),
    }
}

/// Every key of the sweep file, in the reference's order.
#[must_use]
pub fn registry() -> Vec<SweepKey> {
    let t = RegimeThresholds::default();
    let on_columns = columns()
        .iter()
        .map(|c| format!("`{c}`"))
        .collect::<Vec<_>>()
        .join(", ");
    vec![
        key(Place::Top, "name", "name of the sweep (required)"),
        key(
            Place::Top,
            "scene",
            "the base scene file, relative to the sweep file (required)",
        ),
        key(
            Place::Table,
            "set",
            "`\"section.key\" = value` applied to every point, like `--set`",
        ),
        key(
            Place::InEach("axis"),
            "key",
            "a scene key (`section.key`, see Scene keys); one axis per key",
        ),
        key(
            Place::InEach("axis"),
            "values",
            "the axis values: numbers, or words for a choice key",
        ),
        key(
            Place::InEach("axis"),
            "range",
            format!(
                "instead of `values`: `{{ from, to, count, scale }}`, `scale` `\"linear\"` \
                 (default) or `\"log\"` (from and to > 0), 1 ≤ count ≤ {MAX_POINTS} (per axis, \
                 also with `--allow-large`), from ≠ to when count > 1"
            ),
        ),
        key(
            Place::In("regime"),
            "stick_slip_recovery",
            format!(
                "R at or above which two or more events are `stick_slip` (default {})",
                t.stick_slip_recovery
            ),
        ),
        key(
            Place::In("regime"),
            "smooth_recovery",
            format!(
                "R below which two or more events are `smooth` (default {}); in between: \
                 `partial`",
                t.smooth_recovery
            ),
        ),
        key(
            Place::In("regime"),
            "sliding_fraction",
            format!(
                "share of the time after the first onset with no solid node at or above which \
                 the run is `sliding` (default {})",
                t.sliding_fraction
            ),
        ),
        key(
            Place::In("refine"),
            "levels",
            "levels of adaptive refinement, an integer ≥ 0 (0 = none); see Refinement below",
        ),
        key(
            Place::In("refine"),
            "on",
            format!(
                "what splits a cell: `\"{ON_REGIME}\"` (default: corners of different regime) \
                 or a numeric map.csv column: {on_columns}"
            ),
        ),
        key(
            Place::In("refine"),
            "threshold",
            "with `on` a column (required then, and only then), > 0: a cell splits when two of \
             its corners' values a, b have \\|a − b\\| > threshold · max(\\|a\\|, \\|b\\|)",
        ),
        key(
            Place::In("verify"),
            "sample",
            "spot checks: a share of the map's points, 0 < sample ≤ 1, spread evenly in point \
             order, rerun at 2N and at a tenth of the tolerance; see Spot checks below",
        ),
        key(
            Place::In("verify"),
            "points",
            "or a number of points ≥ 1 (not both)",
        ),
        key(
            Place::In("verify"),
            "boundaries",
            "also every point next to a regime boundary (default true)",
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeSet;

    /// The fields the reader accepts in `section`, as its refusal of an unknown key lists
    /// them.
    fn accepted(section: Option<&str>) -> BTreeSet<String> {
        let head = "name = \"x\"\nscene = \"s.toml\"\n";
        let text = match section {
            None => format!("{head}no_such_key = 1\n"),
            Some("axis") => format!("{head}[[axis]]\nno_such_key = 1\n"),
            Some(table) => format!("{head}[{table}]\nno_such_key = 1\n"),
        };
        let err = toml::from_str::<super::super::file::SweepFile>(&text)
            .expect_err("an unknown key is refused");
        let message = err.message().to_string();
        let expected = message
            .split_once("expected ")
            .map_or("", |(_, rest)| rest)
            .trim_start_matches("one of ");
        expected
            .split(", ")
            .map(|f| f.trim().trim_matches('`').to_string())
            .filter(|f| !f.is_empty())
            .collect()
    }

    #[test]
    fn the_registry_holds_exactly_the_keys_the_reader_accepts() {
        let keys = registry();
        let sections: BTreeSet<Option<&str>> = keys.iter().map(SweepKey::section).collect();
        for section in sections {
            let mut listed: BTreeSet<String> = keys
                .iter()
                .filter(|k| k.section() == section)
                .map(|k| k.name.to_string())
                .collect();
            if section.is_none() {
                // The tables are keys of the top level too.
                listed.extend(keys.iter().filter_map(SweepKey::section).map(String::from));
            }
            let read = accepted(section);
            assert!(read.len() >= 2, "{section:?}: no field list in the refusal");
            assert_eq!(listed, read, "sweep file section {section:?}");
        }
    }

    #[test]
    fn labels_say_where_a_key_is_written() {
        let labels: Vec<String> = registry().iter().map(SweepKey::label).collect();
        for label in [
            "name",
            "[set]",
            "[[axis]] range",
            "[regime] smooth_recovery",
        ] {
            assert!(labels.iter().any(|l| l == label), "{label} in {labels:?}");
        }
    }
}
