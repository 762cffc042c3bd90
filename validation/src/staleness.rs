//! Reports older than the code they describe: each committed report's JSON records the commit it
//! was generated at; the sources that make its numbers are compared with that commit, and a
//! report whose sources changed since is listed (by `cargo xtask validate --check`), with the
//! files. A change may not alter the numbers (a comment, a refactor); the list says which
//! reports to regenerate to be sure.

use std::path::Path;
use stickslip_report::provenance::{Commit, changed_since};

/// The sources every report's numbers come through.
const ENGINE: [&str; 3] = [
    "crates/stickslip-core/src",
    "crates/stickslip-run/src",
    "crates/stickslip-report/src",
];

/// (report JSON in `reports/`, the pages it backs, the sources beyond [`ENGINE`] that make it).
pub const REPORTS: [(&str, &str, &[&str]); 6] = [
    (
        "summary.json",
        "index.md, hard-cases.md",
        &[
            "validation/src",
            "validation/scenes",
            "validation/hard",
            "crates/stickslip-studies/src",
        ],
    ),
    (
        "independent.json",
        "index.md (Independent implementation, MDR against 3D elasticity)",
        &[
            "validation/src/independent",
            "validation/independent",
            "validation/scenes",
        ],
    ),
    (
        "convergence.json",
        "convergence.md",
        &["crates/stickslip-convergence/src"],
    ),
    (
        "performance.json",
        "performance.md",
        &["crates/stickslip-convergence/src", "benches"],
    ),
    (
        "fit.json",
        "fit.md",
        &[
            "crates/stickslip-studies/src",
            "crates/stickslip-fit-study/src",
        ],
    ),
    (
        "build-timing.json",
        "performance.md (P4)",
        &["xtask/src", "Cargo.lock"],
    ),
];

/// One report's state.
#[derive(Debug, Clone, PartialEq)]
pub enum Age {
    /// Its sources are unchanged since its commit.
    Current,
    /// Its sources changed since its commit: these files.
    Older(Vec<String>),
    /// It records no commit, or git cannot compare: why.
    Unknown(String),
}

/// Every report's age against the working tree at `root`.
#[must_use]
pub fn ages(root: &Path) -> Vec<(&'static str, &'static str, Age)> {
    REPORTS
        .iter()
        .map(|(file, pages, extra)| {
            let path = root.join("reports").join(file);
            let commit = std::fs::read_to_string(&path)
                .map_err(|e| format!("{}: {e}", path.display()))
                .and_then(|t| {
                    serde_json::from_str::<serde_json::Value>(&t).map_err(|e| e.to_string())
                })
                .and_then(|v| match &v["commit"] {
                    // build-timing.json records the full hash as a string.
                    serde_json::Value::String(h) => Ok(Commit {
                        hash: h.clone(),
                        dirty: false,
                        date: None,
                        host: None,
                    }),
                    c => serde_json::from_value::<Commit>(c.clone())
                        .map_err(|_| "no commit recorded".to_string()),
                });
            let age = match commit {
                Err(e) => Age::Unknown(e),
                Ok(c) => {
                    let paths: Vec<&str> = ENGINE.iter().chain(extra.iter()).copied().collect();
                    match changed_since(root, &c, &paths) {
                        None => Age::Unknown(format!("git cannot compare with {}", c.hash)),
                        Some(files) if files.is_empty() => Age::Current,
                        Some(files) => Age::Older(files),
                    }
                }
            };
            (*file, *pages, age)
        })
        .collect()
}

/// The lines `validate --check` prints.
#[must_use]
pub fn lines(ages: &[(&str, &str, Age)]) -> Vec<String> {
    ages.iter()
        .map(|(file, pages, age)| match age {
            Age::Current => format!("reports/{file} ({pages}): current"),
            Age::Unknown(why) => format!("reports/{file} ({pages}): age unknown ({why})"),
            Age::Older(files) => format!(
                "reports/{file} ({pages}): OLDER than its code, {} file(s) changed since: {}{}",
                files.len(),
                files.iter().take(5).cloned().collect::<Vec<_>>().join(", "),
                if files.len() > 5 { ", …" } else { "" }
            ),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_report_with_a_commit_is_compared_with_its_sources() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let ages = ages(&root);
        assert_eq!(ages.len(), REPORTS.len());
        let mut compared = 0;
        for (file, _, age) in &ages {
            let path = root.join("reports").join(file);
            match age {
                Age::Current | Age::Older(_) => compared += 1,
                // Only a report that records no commit (or is absent) may have no age.
                Age::Unknown(why) => {
                    let text = std::fs::read_to_string(&path).unwrap_or_default();
                    let recorded = serde_json::from_str::<serde_json::Value>(&text)
                        .is_ok_and(|v| v["commit"].is_object() || v["commit"].is_string());
                    assert!(!recorded, "{file}: has a commit, yet: {why}");
                }
            }
        }
        assert!(compared >= 2, "{ages:?}");
        assert_eq!(lines(&ages).len(), REPORTS.len());
    }
}
