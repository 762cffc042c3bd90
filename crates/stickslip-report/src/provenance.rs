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
    /// without git. Its hash is that of the last commit that changed anything but the
    /// generated files (reports/, README.md): a commit that only regenerates reports makes
    /// no new code, so a report regenerated after it names the same commit, and
    /// `cargo xtask validate` run again leaves the tree as it was. HEAD's where the history
    /// cannot tell (a shallow clone).
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
        // The generated files themselves (reports/, README.md's generated blocks) are not
        // sources: neither a commit of them nor their uncommitted state changes the code.
        let sources = ["--", ".", ":(exclude)reports", ":(exclude)README.md"];
        let head = git(&["rev-parse", "--short=10", "HEAD"])?;
        let hash = git(&[
            &["log", "-1", "--format=%h", "--abbrev=10"][..],
            &sources[..],
        ]
        .concat())
        .filter(|h| h.len() == 10)
        .unwrap_or(head);
        let dirty = git(&[
            &["status", "--porcelain", "--untracked-files=no"][..],
            &sources[..],
        ]
        .concat())
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

/// Whether two versions of a generated file say the same but when and where they were made:
/// equal once each provenance's date and host are set aside (the markdown sentence's
/// ` on YYYY-MM-DD` and `` (host `h`)``, a JSON record's `"date"` and `"host"` inside its
/// `"commit"` object). The commit and its `dirty` flag count: a file from other code differs.
/// The one report writer keeps the file it would otherwise rewrite with only these changed.
#[must_use]
pub fn same_but_when(old: &str, new: &str) -> bool {
    fn normal(text: &str) -> Vec<String> {
        let mut in_commit = false;
        let mut out = Vec::new();
        for line in text.lines() {
            let t = line.trim_start();
            if t.starts_with("\"commit\": {") {
                in_commit = true;
            } else if in_commit && t.starts_with('}') {
                in_commit = false;
            } else if in_commit && (t.starts_with("\"date\":") || t.starts_with("\"host\":")) {
                continue;
            }
            let mut l = line.to_string();
            if let Some(at) = l.find("Generated at commit `") {
                let (head, tail) = l.split_at(at);
                let mut tail = tail.to_string();
                // ` on YYYY-MM-DD` right after the hash's closing backtick.
                if let Some(close) = tail["Generated at commit `".len()..].find('`') {
                    let after = "Generated at commit `".len() + close + 1;
                    if tail[after..].starts_with(" on ") && tail.len() >= after + 14 {
                        tail.replace_range(after..after + 14, "");
                    }
                }
                if let Some(h) = tail.find(" (host `")
                    && let Some(end) = tail[h + 8..].find("`)")
                {
                    tail.replace_range(h..h + 8 + end + 2, "");
                }
                l = format!("{head}{tail}");
            }
            out.push(l);
        }
        out
    }
    normal(old) == normal(new)
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
    fn files_differing_only_in_when_and_where_are_the_same() {
        let md = |date: &str, host: &str, hash: &str, n: u32| {
            format!(
                "# Report\n\nGenerated at commit `{hash}` on {date} (host `{host}`).\n\n{n} runs\n"
            )
        };
        let a = md("2026-12-08", "vm", "0123456789", 3);
        assert!(same_but_when(
            &a,
            &md("2026-12-09", "ci-box", "0123456789", 3)
        ));
        assert!(
            !same_but_when(&a, &md("2026-12-08", "vm", "abcdef0123", 3)),
            "other code"
        );
        assert!(
            !same_but_when(&a, &md("2026-12-08", "vm", "0123456789", 4)),
            "other numbers"
        );
        let dirty = a.replace(
            "(host `vm`).",
            "(host `vm`) with uncommitted changes to tracked files.",
        );
        assert_ne!(dirty, a);
        assert!(!same_but_when(&a, &dirty));
        let json = |date: &str, host: &str, x: f64| {
            format!(
                "{{\n  \"commit\": {{\n    \"hash\": \"0123456789\",\n    \"dirty\": false,\n    \
                 \"date\": \"{date}\",\n    \"host\": \"{host}\"\n  }},\n  \"host\": \"{host}\",\n  \
                 \"x\": {x}\n}}\n"
            )
        };
        assert!(same_but_when(
            &json("2026-12-08", "vm", 1.0),
            &json("2026-12-08", "vm", 1.0)
        ));
        assert!(!same_but_when(
            &json("2026-12-08", "vm", 1.0),
            &json("2026-12-08", "vm", 2.0)
        ));
        // A "host" outside the commit object is data, and counts.
        assert!(!same_but_when(
            &json("2026-12-08", "vm", 1.0),
            &json("2026-12-09", "ci", 1.0)
        ));
        let inside_only =
            json("2026-12-08", "vm", 1.0).replacen("\"host\": \"vm\"", "\"host\": \"ci\"", 1);
        assert!(same_but_when(&json("2026-12-08", "vm", 1.0), &inside_only));
    }

    #[test]
    fn civil_dates_from_days() {
        assert_eq!(civil_date(0), "1970-01-01");
        assert_eq!(civil_date(11_016), "2000-02-29");
        assert_eq!(civil_date(20_453), "2025-12-31");
        assert_eq!(civil_date(-1), "1969-12-31");
    }
}
