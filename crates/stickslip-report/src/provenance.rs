//! Which commit a report was generated at: every generated report says so in its first
//! paragraph, so that a number in it can be traced to the code that made it. The generators
//! record the [`Commit`] in their raw JSON when they run, and the pages render it from there
//! (a `--render-only` keeps the commit of the study, not the one that redrew it).

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
        let dirty =
            git(&["status", "--porcelain", "--untracked-files=no"]).is_some_and(|s| !s.is_empty());
        Some(Self { hash, dirty })
    }

    /// The workspace's commit (this crate lives at `crates/stickslip-report`).
    #[must_use]
    pub fn of_workspace() -> Option<Self> {
        Self::of(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."))
    }
}

/// The sentence a report's first paragraph carries.
#[must_use]
pub fn sentence(commit: Option<&Commit>) -> String {
    match commit {
        Some(c) if c.dirty => format!(
            "Generated at commit `{}` with uncommitted changes to tracked files (the numbers \
             are those of that commit plus the changes committed with this report).",
            c.hash
        ),
        Some(c) => format!("Generated at commit `{}`.", c.hash),
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
        let dirty = Commit { dirty: true, ..c };
        assert!(sentence(Some(&dirty)).contains("uncommitted"));
    }
}
