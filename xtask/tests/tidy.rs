//! Repository rules checked as a plain test, so `cargo test --workspace` is the whole gate.

use std::path::{Path, PathBuf};

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives one level below the workspace root")
        .to_path_buf()
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let name = entry.file_name();
        let name = name.to_string_lossy();
        if name.starts_with('.') || name == "target" || name == "out" {
            continue;
        }
        if path.is_dir() {
            rust_files(&path, out);
        } else if name.ends_with(".rs") {
            out.push(path);
        }
    }
}

#[test]
fn every_rust_file_starts_with_a_module_doc_line() {
    let root = workspace_root();
    let mut files = Vec::new();
    rust_files(&root, &mut files);
    assert!(files.len() > 10, "found only {} .rs files", files.len());
    let offenders: Vec<String> = files
        .iter()
        .filter(|p| {
            let text = std::fs::read_to_string(p).unwrap_or_default();
            !text.starts_with("//!")
        })
        .map(|p| p.strip_prefix(&root).unwrap_or(p).display().to_string())
        .collect();
    assert!(
        offenders.is_empty(),
        "these files must start with a `//!` line saying what they hold:\n{}",
        offenders.join("\n")
    );
}

#[test]
fn ci_runs_exactly_the_readme_test_command() {
    let root = workspace_root();
    let readme = std::fs::read_to_string(root.join("README.md")).expect("README.md");
    let ci = std::fs::read_to_string(root.join(".ci/run")).expect(".ci/run");
    let command = "cargo xtask test";
    assert!(readme.contains(command), "README.md must show `{command}`");
    assert!(
        readme.contains("cargo xtask validate"),
        "README.md must show the main job"
    );
    assert!(
        ci.lines().any(|l| l.trim() == command),
        ".ci/run must run exactly `{command}`"
    );
}

/// Files under `dir` (relative to the root), their paths and texts.
fn sources(root: &Path, dir: &str) -> Vec<(String, String)> {
    let mut files = Vec::new();
    rust_files(&root.join(dir), &mut files);
    files
        .into_iter()
        .map(|p| {
            let rel = p.strip_prefix(root).unwrap_or(&p).display().to_string();
            (rel, std::fs::read_to_string(&p).unwrap_or_default())
        })
        .collect()
}

#[test]
fn the_core_does_no_file_io() {
    let root = workspace_root();
    let offenders: Vec<String> = sources(&root, "crates/stickslip-core/src")
        .into_iter()
        .filter(|(_, text)| text.contains("std::fs") || text.contains("File::"))
        .map(|(p, _)| p)
        .collect();
    assert!(
        offenders.is_empty(),
        "the core knows nothing of files (ARCHITECTURE.md): {offenders:?}"
    );
}

#[test]
fn nothing_outside_the_run_library_steps_a_simulation() {
    // Without a Simulation of its own nothing can step one: every consumer goes through the
    // run library's driver. The core itself (its own tests of one step) is the other owner.
    let root = workspace_root();
    let mut offenders = Vec::new();
    for dir in ["crates", "validation", "benches", "xtask", "examples"] {
        for (path, text) in sources(&root, dir) {
            let owner = path.starts_with("crates/stickslip-core/")
                || path.starts_with("crates/stickslip-run/src/")
                || path == "xtask/tests/tidy.rs";
            if !owner && (text.contains("Simulation::new(") || text.contains("step_adaptive(")) {
                offenders.push(path);
            }
        }
    }
    assert!(
        offenders.is_empty(),
        "these files build or step a Simulation themselves; use stickslip_run's driver: {offenders:?}"
    );
}

#[test]
fn the_driver_knows_no_files_and_checkpoints_know_no_sink() {
    let root = workspace_root();
    // Code only: doc comments may name what a module does not depend on.
    let code = |path: &str| -> String {
        std::fs::read_to_string(root.join(path))
            .unwrap()
            .lines()
            .filter(|l| !l.trim_start().starts_with("//"))
            .collect::<Vec<_>>()
            .join("\n")
    };
    let driver = code("crates/stickslip-run/src/driver.rs");
    for forbidden in [
        "std::fs",
        "crate::checkpoint",
        "crate::sink::dir",
        "crate::atomic",
    ] {
        assert!(!driver.contains(forbidden), "driver.rs uses {forbidden}");
    }
    for path in [
        "crates/stickslip-run/src/checkpoint.rs",
        "crates/stickslip-run/src/checkpoint/format3.rs",
    ] {
        assert!(
            !code(path).contains("crate::sink"),
            "{path} must not depend on the sink that writes it (no module cycle)"
        );
    }
}

#[test]
fn the_run_library_has_no_command_line_code() {
    let root = workspace_root();
    for krate in ["stickslip-run", "stickslip-studies"] {
        let manifest =
            std::fs::read_to_string(root.join(format!("crates/{krate}/Cargo.toml"))).unwrap();
        for dep in ["clap", "indicatif", "signal-hook", "pyo3"] {
            assert!(!manifest.contains(dep), "{krate} depends on {dep}");
        }
    }
}

#[test]
fn the_one_run_library_knows_no_study() {
    // One run below, the studies made of many runs above: the run library neither depends on
    // the studies (not even for its tests) nor names their code.
    let root = workspace_root();
    let manifest = std::fs::read_to_string(root.join("crates/stickslip-run/Cargo.toml")).unwrap();
    assert!(
        !manifest.contains("stickslip-studies"),
        "stickslip-run depends on the studies"
    );
    let naming: Vec<String> = sources(&root, "crates/stickslip-run")
        .into_iter()
        .filter(|(_, text)| text.contains("stickslip_studies"))
        .map(|(path, _)| path)
        .collect();
    assert!(
        naming.is_empty(),
        "these run-library files name the studies: {naming:?}"
    );
}

#[test]
fn no_source_file_is_far_over_a_thousand_lines() {
    let root = workspace_root();
    let mut offenders = Vec::new();
    for dir in ["crates", "validation", "benches", "xtask"] {
        for (path, text) in sources(&root, dir) {
            let lines = text.lines().count();
            if lines > 1100 && !path.contains("/tests/") {
                offenders.push(format!("{path} ({lines} lines)"));
            }
        }
    }
    assert!(
        offenders.is_empty(),
        "split by responsibility: {offenders:?}"
    );
}

#[test]
fn the_engine_files_stay_small() {
    // The time loop's modules (problem, steppers, the adaptive loop) each hold one thing; a
    // file far over 600 lines there is two things.
    let root = workspace_root();
    let offenders: Vec<String> = sources(&root, "crates/stickslip-core/src/sim")
        .into_iter()
        .filter(|(_, text)| text.lines().count() > 660)
        .map(|(p, text)| format!("{p} ({} lines)", text.lines().count()))
        .collect();
    assert!(
        offenders.is_empty(),
        "split by responsibility: {offenders:?}"
    );
}

/// The functions of `text` longer than `max` lines, as "name (lines)": a function starts at a
/// line `fn name` (after any visibility) and ends at the first line that is its indentation
/// followed by `}` (rustfmt's layout).
fn long_functions(text: &str, max: usize) -> Vec<String> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let trimmed = line.trim_start();
        let indent = &line[..line.len() - trimmed.len()];
        let signature = [
            "fn ",
            "pub fn ",
            "pub(crate) fn ",
            "pub(super) fn ",
            "const fn ",
        ]
        .iter()
        .find_map(|p| trimmed.strip_prefix(p));
        let Some(rest) = signature else { continue };
        let name: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        let close = format!("{indent}}}");
        if let Some(len) = lines[i + 1..].iter().position(|l| *l == close)
            && len + 2 > max
        {
            out.push(format!("{name} ({} lines)", len + 2));
        }
    }
    out
}

#[test]
fn no_core_function_is_over_120_lines() {
    let root = workspace_root();
    let mut offenders = Vec::new();
    for (path, text) in sources(&root, "crates/stickslip-core/src") {
        for f in long_functions(&text, 120) {
            offenders.push(format!("{path}: {f}"));
        }
    }
    assert!(
        offenders.is_empty(),
        "a core function over 120 lines does several things: {offenders:?}"
    );
}

#[test]
fn the_function_length_check_finds_a_long_function() {
    let body = "    let x = 1;\n".repeat(125);
    let text = format!("/// Doc.\npub fn long() {{\n{body}}}\n\nfn short() {{\n}}\n");
    assert_eq!(
        long_functions(&text, 120),
        vec!["long (127 lines)".to_string()]
    );
    assert!(long_functions(&text, 130).is_empty());
}

/// Whether `text` holds a string literal that starts `"section.key=` (lower-case words).
fn has_setting_literal(text: &str) -> bool {
    text.split('"').skip(1).step_by(2).any(|literal| {
        let Some((path, _)) = literal.split_once('=') else {
            return false;
        };
        let mut parts = path.split('.');
        let word = |w: Option<&str>| {
            w.is_some_and(|w| {
                !w.is_empty() && w.chars().all(|c| c.is_ascii_lowercase() || c == '_')
            })
        };
        word(parts.next()) && word(parts.next()) && parts.next().is_none()
    })
}

#[test]
fn settings_in_code_go_through_the_key_registry() {
    // Code sets a scene key with `Key::set` (typed, checked against the registry), not with
    // `"section.key=value"` text; tests may spell the command line's text.
    let root = workspace_root();
    let mut offenders = Vec::new();
    for dir in ["crates", "validation", "maps", "xtask/src"] {
        for (path, text) in sources(&root, dir) {
            if path.contains("/tests/") || path.contains("/benches/") {
                continue;
            }
            let code = text.split("#[cfg(test)]").next().unwrap_or("");
            for (i, line) in code.lines().enumerate() {
                let trimmed = line.trim_start();
                if !trimmed.starts_with("//") && has_setting_literal(line) {
                    offenders.push(format!("{path}:{}", i + 1));
                }
            }
        }
    }
    assert!(
        offenders.is_empty(),
        "set keys with Key::set: {offenders:?}"
    );
}

#[test]
fn the_setting_check_finds_a_setting_literal() {
    assert!(has_setting_literal(r#"let s = "contact.nodes=200";"#));
    assert!(has_setting_literal(r#"f("x", "drive.damping=1e-3")"#));
    assert!(!has_setting_literal(
        r#"let s = "contact.nodes"; let t = "a = b";"#
    ));
    assert!(!has_setting_literal(r#"let s = "{path}={value}";"#));
}

/// The modules a crate root or a `mod.rs` declares (`mod x;` or `pub mod x;`, tests aside).
fn declared_modules(file: &Path) -> Vec<String> {
    std::fs::read_to_string(file).map_or_else(|_| Vec::new(), |t| modules_in(&t))
}

/// The modules `text` declares.
fn modules_in(text: &str) -> Vec<String> {
    text.lines()
        .map(str::trim)
        .filter_map(|l| {
            let l = l.strip_prefix("pub ").unwrap_or(l);
            let l = l.strip_prefix("pub(crate) ").unwrap_or(l);
            l.strip_prefix("mod ")?
                .strip_suffix(';')
                .map(str::to_string)
        })
        .filter(|m| m != "tests")
        .collect()
}

#[test]
fn architecture_names_every_crate_and_module() {
    let root = workspace_root();
    let text = std::fs::read_to_string(root.join("ARCHITECTURE.md")).expect("ARCHITECTURE.md");
    let mut missing = Vec::new();
    // Every crate directory has its own section, headed by its path.
    let mut crates: Vec<String> = std::fs::read_dir(root.join("crates"))
        .expect("crates/")
        .flatten()
        .filter(|e| e.path().join("Cargo.toml").is_file())
        .map(|e| format!("crates/{}", e.file_name().to_string_lossy()))
        .collect();
    crates.sort();
    assert!(crates.len() >= 7, "{crates:?}");
    for dir in &crates {
        if !text.contains(&format!("### `{dir}`")) {
            missing.push(format!("a section headed `{dir}`"));
        }
    }
    for dir in ["validation/", "maps/", "benches/", "xtask/"] {
        if !text.contains(&format!("`{dir}`")) {
            missing.push(dir.to_string());
        }
    }
    // Every module of every crate (and one level of submodules) is named in backticks in the
    // crate's own section (`x`, `x.rs`, `x/` or `parent/x`).
    for dir in &crates {
        let heading = format!("### `{dir}`");
        let section = text.split_once(&heading).map_or("", |(_, rest)| {
            rest.split_once("\n### ").map_or(rest, |(own, _)| own)
        });
        let named = |names: &[String]| {
            names.iter().any(|n| {
                [format!("`{n}`"), format!("`{n}.rs`"), format!("`{n}/`")]
                    .iter()
                    .any(|form| section.contains(form.as_str()))
            })
        };
        let src = root.join(dir).join("src");
        for top in ["lib.rs", "main.rs"] {
            for m in declared_modules(&src.join(top)) {
                if !named(std::slice::from_ref(&m)) {
                    missing.push(format!("{dir}: {m}"));
                }
                for sub in declared_modules(&src.join(&m).join("mod.rs")) {
                    if !named(&[sub.clone(), format!("{m}/{sub}")]) {
                        missing.push(format!("{dir}: {m}/{sub}"));
                    }
                }
            }
        }
    }
    assert!(
        missing.is_empty(),
        "ARCHITECTURE.md does not name: {missing:#?}"
    );
}

#[test]
fn the_architecture_check_fails_on_an_unnamed_module() {
    let declared =
        modules_in("//! x\npub mod named;\nmod unnamed_one;\n#[cfg(test)]\nmod tests;\n");
    assert_eq!(declared, ["named", "unnamed_one"]);
    let architecture = "### `crates/x`\n`named` does this.";
    let unnamed: Vec<_> = declared
        .iter()
        .filter(|m| !architecture.contains(&format!("`{m}`")))
        .collect();
    assert_eq!(unnamed, ["unnamed_one"]);
}

/// The tracked files (`git ls-files`), relative to the root; without git (an unpacked archive)
/// every file below the root but `.git/` and `target/`.
fn tracked_files(root: &Path) -> Vec<String> {
    let listed = std::process::Command::new("git")
        .arg("-C")
        .arg(root)
        .args(["ls-files", "-z"])
        .output()
        .ok()
        .filter(|o| o.status.success() && !o.stdout.is_empty());
    if let Some(out) = listed {
        return String::from_utf8_lossy(&out.stdout)
            .split('\0')
            .filter(|p| !p.is_empty())
            .map(str::to_string)
            .collect();
    }
    fn walk(root: &Path, dir: &Path, out: &mut Vec<String>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            let name = entry.file_name();
            if name == ".git" || name == "target" {
                continue;
            }
            if path.is_dir() {
                walk(root, &path, out);
            } else if let Ok(rel) = path.strip_prefix(root) {
                out.push(rel.display().to_string());
            }
        }
    }
    let mut out = Vec::new();
    walk(root, root, &mut out);
    out
}

/// This file: it spells out what the checks below look for.
const THIS_FILE: &str = "xtask/tests/tidy.rs";

/// The tracked text files (other than this one) and their contents.
fn tracked_texts(root: &Path) -> Vec<(String, String)> {
    tracked_files(root)
        .into_iter()
        .filter(|p| p != THIS_FILE)
        .filter_map(|p| {
            let bytes = std::fs::read(root.join(&p)).ok()?;
            let text = String::from_utf8(bytes).ok()?;
            Some((p, text))
        })
        .collect()
}

/// Whether `text` holds `word` with no letter, digit or `_` on either side.
fn contains_word(text: &str, word: &str) -> bool {
    let part = |c: Option<char>| c.is_some_and(|c| c.is_alphanumeric() || c == '_');
    text.match_indices(word).any(|(i, _)| {
        !part(text[..i].chars().next_back()) && !part(text[i + word.len()..].chars().next())
    })
}

#[test]
fn no_tracked_file_cites_files_outside_the_repository() {
    // A clone has nothing beside the repository: the design notes the project started from
    // are not part of it. Pointers go to docs/model.md, docs/reference.md or the paper's
    // equation numbers. The needles are assembled so that this file does not hold them.
    let root = workspace_root();
    let spec = ["SP", "EC"].concat();
    let needles = [
        format!("{spec} §"),
        format!("{spec}.md"),
        ["INTER", "FACE.md"].concat(),
        ["..", "/shared"].concat(),
    ];
    let files = tracked_texts(&root);
    assert!(files.len() > 50, "found only {} tracked files", files.len());
    let mut offenders = Vec::new();
    for (path, text) in &files {
        for (n, line) in text.lines().enumerate() {
            // The bare word as a file name (in parentheses, or before a section number);
            // identifiers that merely contain it as one part of a longer name are not citations.
            if needles.iter().any(|needle| line.contains(needle.as_str()))
                || contains_word(line, &spec)
            {
                offenders.push(format!("{path}:{}: {}", n + 1, line.trim()));
            }
        }
    }
    assert!(
        offenders.is_empty(),
        "these lines cite files that are not in the repository; point at docs/model.md, \
         docs/reference.md or the paper's equation numbers instead:\n{}",
        offenders.join("\n")
    );
}

/// GitHub's anchor of a Markdown heading: lower case, punctuation dropped, spaces as hyphens.
fn heading_anchor(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || *c == ' ' || *c == '-' || *c == '_')
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

#[test]
fn links_into_the_documentation_name_existing_sections() {
    // "docs/model.md#the-drive" in a comment, a scene or a report must lead somewhere.
    let root = workspace_root();
    let files = tracked_texts(&root);
    let mut anchors: std::collections::BTreeMap<String, Vec<String>> = Default::default();
    for (path, text) in &files {
        if !path.ends_with(".md") {
            continue;
        }
        let name = path.rsplit('/').next().unwrap_or(path).to_string();
        let mut fenced = false;
        for line in text.lines() {
            if line.starts_with("```") {
                fenced = !fenced;
            } else if !fenced && line.starts_with('#') {
                let heading = line.trim_start_matches('#');
                anchors
                    .entry(name.clone())
                    .or_default()
                    .push(heading_anchor(heading));
            }
        }
    }
    let mut broken = Vec::new();
    for doc in ["model.md", "reference.md"] {
        let known = anchors.get(doc).cloned().unwrap_or_default();
        assert!(!known.is_empty(), "docs/{doc} has no headings");
        let link = format!("{doc}#");
        for (path, text) in &files {
            for (n, line) in text.lines().enumerate() {
                for (i, _) in line.match_indices(&link) {
                    let anchor: String = line[i + link.len()..]
                        .chars()
                        .take_while(|c| c.is_alphanumeric() || *c == '-' || *c == '_')
                        .collect();
                    if !known.contains(&anchor) {
                        broken.push(format!("{path}:{}: {doc}#{anchor}", n + 1));
                    }
                }
            }
        }
    }
    assert!(
        broken.is_empty(),
        "links to sections that do not exist:\n{}",
        broken.join("\n")
    );
}

/// The value of `key = "…"` on its own line in `text`, the first one after the line `section`.
fn toml_string(text: &str, section: &str, key: &str) -> Option<String> {
    text.lines()
        .skip_while(|l| l.trim() != section)
        .skip(1)
        .take_while(|l| !l.trim_start().starts_with('['))
        .find_map(|l| {
            let (k, v) = l.split_once('=')?;
            (k.trim() == key).then(|| v.trim().trim_matches('"').to_string())
        })
}

#[test]
fn licence_and_citation_agree_with_the_workspace() {
    let root = workspace_root();
    let read =
        |p: &str| std::fs::read_to_string(root.join(p)).unwrap_or_else(|e| panic!("{p}: {e}"));
    let manifest = read("Cargo.toml");
    let version = toml_string(&manifest, "[workspace.package]", "version").expect("version");
    let licence = toml_string(&manifest, "[workspace.package]", "license").expect("license");
    assert_eq!(licence, "MIT OR Apache-2.0");
    for file in ["LICENSE-MIT", "LICENSE-APACHE"] {
        assert!(root.join(file).is_file(), "{file} is missing");
    }
    // Every crate inherits the workspace's licence.
    let mut missing = Vec::new();
    for path in tracked_files(&root) {
        if path.ends_with("/Cargo.toml") {
            let text = read(&path);
            if text.contains("[package]")
                && toml_string(&text, "[package]", "license.workspace") != Some("true".to_string())
            {
                missing.push(path);
            }
        }
    }
    assert!(
        missing.is_empty(),
        "these crates do not set license.workspace = true: {missing:?}"
    );
    let pyproject = read("crates/stickslip-py/pyproject.toml");
    assert!(
        pyproject.contains(&licence),
        "crates/stickslip-py/pyproject.toml must declare {licence}"
    );
    let cff = read("CITATION.cff");
    let field = |key: &str| {
        cff.lines()
            .find_map(|l| l.strip_prefix(key))
            .map(|v| v.trim().trim_matches(['"', '\'']).to_string())
    };
    assert_eq!(
        field("version:").as_deref(),
        Some(version.as_str()),
        "CITATION.cff's version must be the workspace's"
    );
    // CFF takes SPDX identifiers, one per list item: the dual licence is the list of both.
    let cff_licences: Vec<&str> = cff
        .lines()
        .skip_while(|l| l.trim() != "license:")
        .skip(1)
        .map_while(|l| l.strip_prefix("  - "))
        .map(str::trim)
        .collect();
    let spdx: Vec<&str> = licence.split(" OR ").collect();
    assert_eq!(
        cff_licences, spdx,
        "CITATION.cff's license must list {spdx:?}"
    );
}

#[test]
fn the_committed_reports_prose_has_no_runs_of_spaces() {
    // A string continued over lines without its backslashes carries the next line's indent
    // into the report (it did, once, in the SFA section of reports/performance.md). Code
    // blocks, where columns are aligned on purpose, are left out.
    let root = workspace_root();
    let mut offenders = Vec::new();
    for entry in std::fs::read_dir(root.join("reports")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("md") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let mut in_code = false;
        for (i, line) in text.lines().enumerate() {
            if line.trim_start().starts_with("```") {
                in_code = !in_code;
                continue;
            }
            if !in_code && line.trim().contains("    ") {
                offenders.push(format!("{}:{}", path.display(), i + 1));
            }
        }
    }
    assert!(
        offenders.is_empty(),
        "runs of spaces in prose: {offenders:?}"
    );
}
