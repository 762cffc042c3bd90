//! Which commit a report was generated at, when and where: every generated report says so in
//! its first paragraph, so that a number in it can be traced to the code that made it. The
//! generators record the [`Commit`] (hash, dirty, UTC date, host) in their raw JSON when they
//! run, and the pages render it from there (a `--render-only` keeps the commit of the study,
//! not the one that redrew it).

use serde::{Deserialize, Serialize};
use std::path::Path;
use std::process::Command;

/// A commit of the repository.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Commit {
    /// Its abbreviated hash (10 hex digits).
    pub hash: String,
    /// Whether the working tree had uncommitted changes to tracked files then.
    pub dirty: bool,
    /// The UTC date the report was generated (YYYY-MM-DD); none in records made before dates
    /// were recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub date: Option<String>,
    /// The host's name; none in records made before hosts were recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub host: Option<String>,
}

/// Today's UTC date as YYYY-MM-DD, from the system clock (civil-from-days, proleptic
/// Gregorian).
#[must_use]
pub fn utc_date() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    civil_date(i64::try_from(secs / 86_400).unwrap_or(0))
}

/// The date `days` after 1970-01-01 as YYYY-MM-DD.
#[must_use]
pub fn civil_date(days: i64) -> String {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}")
}

/// The host's name (`/etc/hostname`, else `$HOSTNAME`), if any.
#[must_use]
pub fn host_name() -> Option<String> {
    std::fs::read_to_string("/etc/hostname")
        .ok()
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .or_else(|| std::env::var("HOSTNAME").ok().filter(|s| !s.is_empty()))
}

impl Commit {
    /// The commit checked out in the repository at `root`; none outside a git checkout or
    /// without git.
    #[must_use]
    pub fn of(root: &Path) -> Option<Self> {
        let git = |args: &[&str]| {
            Command::new("git")
                .arg("-C")
                .arg(root)
                .args(args)
                .output()
                .ok()
                .filter(|o| o.status.success())
                .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        };
        let hash = git(&["rev-parse", "--short=10", "HEAD"])?;
        // The generated files themselves (reports/, README.md's generated blocks) do not make
        // the sources dirty: a report regenerated over an older one is the usual state.
        let dirty = git(&[
            "status",
            "--porcelain",
            "--untracked-files=no",
            "--",
            ".",
            ":(exclude)reports",
            ":(exclude)README.md",
        ])
        .is_some_and(|s| !s.is_empty());
        Some(Self {
            hash,
            dirty,
            date: Some(utc_date()),
            host: host_name(),
        })
    }

    /// The workspace's commit (this crate lives at `crates/stickslip-report`).
    #[must_use]
    pub fn of_workspace() -> Option<Self> {
        Self::of(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."))
    }
}

/// The files under `paths` (relative to the repository at `root`) that differ between
/// `commit` and the working tree; none when git cannot tell (no checkout, unknown commit).
#[must_use]
pub fn changed_since(root: &Path, commit: &Commit, paths: &[&str]) -> Option<Vec<String>> {
    let out = Command::new("git")
        .arg("-C")
        .arg(root)
        .args(["diff", "--name-only", &commit.hash, "--"])
        .args(paths)
        .output()
        .ok()
        .filter(|o| o.status.success())?;
    Some(
        String::from_utf8_lossy(&out.stdout)
            .lines()
            .map(str::to_string)
            .collect(),
    )
}

/// The sentence a report's first paragraph carries.
#[must_use]
pub fn sentence(commit: Option<&Commit>) -> String {
    let when = |c: &Commit| {
        let mut w = String::new();
        if let Some(d) = &c.date {
            w.push_str(&format!(" on {d}"));
        }
        if let Some(h) = &c.host {
            w.push_str(&format!(" (host `{h}`)"));
        }
        w
    };
    match commit {
        Some(c) if c.dirty => format!(
            "Generated at commit `{}`{} with uncommitted changes to tracked files (the numbers \
             are those of that commit plus the changes committed with this report).",
            c.hash,
            when(c)
        ),
        Some(c) => format!("Generated at commit `{}`{}.", c.hash, when(c)),
        None => "The generating commit was not recorded (a study made before commits were \
                 recorded, or outside a git checkout)."
            .to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_workspace_has_a_commit_and_the_sentence_names_it() {
        // CI clones the repository: there is a HEAD.
        let c = Commit::of_workspace().expect("a git checkout");
        assert_eq!(c.hash.len(), 10);
        assert!(c.hash.chars().all(|ch| ch.is_ascii_hexdigit()));
        assert!(sentence(Some(&c)).contains(&c.hash));
        assert!(sentence(None).contains("not recorded"));
        let dirty = Commit {
            dirty: true,
            ..c.clone()
        };
        assert!(sentence(Some(&dirty)).contains("uncommitted"));
        assert!(sentence(Some(&c)).contains(&utc_date()));
        // A record made before dates and hosts were kept still reads.
        let old: Commit = serde_json::from_str(r#"{"hash":"0123456789","dirty":false}"#).unwrap();
        assert_eq!((old.date, old.host), (None, None));
    }

    #[test]
    fn civil_dates_from_days() {
        assert_eq!(civil_date(0), "1970-01-01");
        assert_eq!(civil_date(11_016), "2000-02-29");
        assert_eq!(civil_date(20_453), "2025-12-31");
        assert_eq!(civil_date(-1), "1969-12-31");
    }
}
