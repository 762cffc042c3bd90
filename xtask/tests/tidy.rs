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
    let checkpoint = code("crates/stickslip-run/src/checkpoint.rs");
    assert!(
        !checkpoint.contains("crate::sink"),
        "checkpoint.rs must not depend on the sink that writes it (no module cycle)"
    );
}

#[test]
fn the_run_library_has_no_command_line_code() {
    let root = workspace_root();
    let manifest = std::fs::read_to_string(root.join("crates/stickslip-run/Cargo.toml")).unwrap();
    for dep in ["clap", "indicatif", "signal-hook", "pyo3"] {
        assert!(!manifest.contains(dep), "stickslip-run depends on {dep}");
    }
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
fn architecture_names_every_crate_and_run_library_module() {
    let root = workspace_root();
    let text = std::fs::read_to_string(root.join("ARCHITECTURE.md")).expect("ARCHITECTURE.md");
    let mut missing = Vec::new();
    for dir in [
        "crates/stickslip-core",
        "crates/stickslip-run",
        "crates/stickslip",
        "crates/stickslip-report",
        "crates/stickslip-convergence",
        "crates/stickslip-py",
        "validation/",
        "maps/",
        "benches/",
        "xtask/",
    ] {
        if !text.contains(dir) {
            missing.push(dir.to_string());
        }
    }
    let lib = std::fs::read_to_string(root.join("crates/stickslip-run/src/lib.rs")).unwrap();
    for line in lib.lines() {
        if let Some(m) = line
            .strip_prefix("pub mod ")
            .and_then(|m| m.strip_suffix(';'))
            && !text.contains(&format!("`{m}`"))
            && !text.contains(&format!("`{m}/`"))
        {
            missing.push(format!("stickslip-run module {m}"));
        }
    }
    assert!(
        missing.is_empty(),
        "ARCHITECTURE.md does not name: {missing:?}"
    );
}
