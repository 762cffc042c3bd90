//! `cargo xtask wheel`: the Python package as one abi3 wheel in `dist/`, for machines without
//! Rust; and its check (the `wheel` stage of `cargo xtask test`): the wheel installed into a
//! fresh virtual environment whose `PATH` has no cargo or rustc, running the README's example.
//!
//! 1. `maturin build --release --out dist` with the test venv's maturin (the extension is
//!    built into the workspace's `target/`, so after `cargo xtask python-test` only the wheel
//!    is packed);
//! 2. `python3 -m venv --clear target/wheel-venv`, then `pip install --only-binary :all:
//!    dist/stickslip-…whl[plot]` there with `PATH` stripped of every directory holding cargo
//!    or rustc (pip may download NumPy and matplotlib, never compile);
//! 3. `python examples/fig2.py --quick` from that venv, after checking that it finds no
//!    cargo, imports the installed package (not the sources) and that the wheel's `stickslip`
//!    command (its console script, asserted in entry_points.txt when the wheel is built) runs.

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::time::Instant;

const USAGE: &str = "\
cargo xtask wheel [--check]

  builds the abi3 wheel of the Python package into dist/ (maturin, release profile)
  --check   then installs it into a fresh venv without cargo on PATH (target/wheel-venv)
            and runs the README's example (examples/fig2.py --quick) with it";

fn status(what: &str, cmd: &mut Command) -> Result<(), String> {
    match cmd.status() {
        Ok(s) if s.success() => Ok(()),
        Ok(s) => Err(format!("{what} failed ({s})")),
        Err(e) => Err(format!("{what}: cannot start {:?}: {e}", cmd.get_program())),
    }
}

/// Exits non-zero unless the wheel (`argv[1]`) declares the `stickslip` console script, the
/// command line that `pip install` puts on `PATH`.
const ENTRY_POINT_PROBE: &str = "\
import configparser, sys, zipfile
with zipfile.ZipFile(sys.argv[1]) as z:
    names = [n for n in z.namelist() if n.endswith('.dist-info/entry_points.txt')]
    assert names, 'no entry_points.txt in ' + sys.argv[1]
    ep = configparser.ConfigParser(delimiters=('=',))
    ep.read_string(z.read(names[0]).decode())
got = ep.get('console_scripts', 'stickslip', fallback=None)
assert got == 'stickslip._cli:main', 'console_scripts stickslip = %r' % got
";

/// Builds the wheel into `root/dist` and checks that it declares the `stickslip` command;
/// its path.
///
/// # Errors
/// No venv with maturin could be made, maturin failed, or no wheel appeared.
pub fn build(root: &Path) -> Result<PathBuf, String> {
    let (python, _) = crate::python::venv(root, false)?;
    let dist = root.join("dist");
    let before = wheels(&dist);
    let t = Instant::now();
    status(
        "maturin build",
        Command::new(&python).current_dir(root).args([
            "-m",
            "maturin",
            "build",
            "--release",
            "--quiet",
            "--out",
            "dist",
            "-m",
            "crates/stickslip-py/Cargo.toml",
        ]),
    )?;
    let wheel = newest_wheel(&dist).ok_or("maturin wrote no wheel into dist/")?;
    status(
        "the wheel's console script (entry_points.txt declaring stickslip)",
        Command::new(&python)
            .arg("-c")
            .arg(ENTRY_POINT_PROBE)
            .arg(&wheel),
    )?;
    let size = std::fs::metadata(&wheel).map_or(0, |m| m.len());
    eprintln!(
        "wheel: {} ({:.1} MB) in {:.1} s{}",
        wheel.display(),
        size as f64 / 1e6,
        t.elapsed().as_secs_f64(),
        if before.contains(&wheel) {
            " (rewritten)"
        } else {
            ""
        }
    );
    Ok(wheel)
}

fn wheels(dist: &Path) -> Vec<PathBuf> {
    std::fs::read_dir(dist)
        .map(|d| {
            d.filter_map(Result::ok)
                .map(|e| e.path())
                .filter(|p| p.extension().is_some_and(|e| e == "whl"))
                .collect()
        })
        .unwrap_or_default()
}

/// The most recently written `stickslip-*.whl` in `dist`.
fn newest_wheel(dist: &Path) -> Option<PathBuf> {
    wheels(dist)
        .into_iter()
        .filter(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("stickslip-"))
        })
        .max_by_key(|p| std::fs::metadata(p).and_then(|m| m.modified()).ok())
}

/// `PATH` without the directories that hold `cargo` or `rustc`.
fn path_without_rust() -> std::ffi::OsString {
    let kept: Vec<PathBuf> = std::env::var_os("PATH")
        .map(|p| std::env::split_paths(&p).collect::<Vec<_>>())
        .unwrap_or_default()
        .into_iter()
        .filter(|d| !d.join("cargo").exists() && !d.join("rustc").exists())
        .collect();
    std::env::join_paths(kept).unwrap_or_default()
}

/// Installs `wheel` into a fresh venv without Rust on `PATH` and runs the README example;
/// (install seconds, example seconds).
///
/// # Errors
/// A step failed, or the venv could still find cargo.
pub fn check(root: &Path, wheel: &Path) -> Result<(f64, f64), String> {
    let dir = root.join("target").join("wheel-venv");
    let base = std::env::var("STICKSLIP_PYTHON").unwrap_or_else(|_| "python3".to_string());
    let path = path_without_rust();
    status(
        "creating the fresh venv target/wheel-venv",
        Command::new(&base)
            .env("PATH", &path)
            .args(["-m", "venv", "--clear"])
            .arg(&dir),
    )?;
    let python = dir.join("bin").join("python");
    let bin = dir.join("bin");
    let venv_path = {
        let mut p = vec![bin];
        p.extend(std::env::split_paths(&path));
        std::env::join_paths(p).unwrap_or_default()
    };
    let t = Instant::now();
    let requirement = format!("{}[plot]", wheel.display());
    status(
        "pip install of the wheel (binary packages only)",
        Command::new(&python)
            .env("PATH", &venv_path)
            .env_remove("CARGO")
            .args([
                "-m",
                "pip",
                "install",
                "-q",
                "--disable-pip-version-check",
                "--only-binary",
                ":all:",
            ])
            .arg(&requirement),
    )?;
    let install_s = t.elapsed().as_secs_f64();
    let out = root.join("target").join("wheel-example");
    // Run from target/ so the sources in crates/stickslip-py/python cannot shadow the wheel.
    let probe = "import shutil, stickslip, sys; \
                 assert shutil.which('cargo') is None and shutil.which('rustc') is None, 'cargo on PATH'; \
                 assert 'site-packages' in stickslip.__file__, stickslip.__file__; \
                 print('wheel-venv: stickslip from', stickslip.__file__)";
    status(
        "the wheel's import without Rust",
        Command::new(&python)
            .current_dir(root.join("target"))
            .env("PATH", &venv_path)
            .args(["-c", probe]),
    )?;
    // The command line the wheel installs, run without Rust anywhere on PATH.
    let command = dir.join("bin").join("stickslip");
    let version = Command::new(&command)
        .current_dir(root.join("target"))
        .env("PATH", &venv_path)
        .arg("--version")
        .output()
        .map_err(|e| {
            format!(
                "the wheel's stickslip command: cannot start {}: {e}",
                command.display()
            )
        })?;
    let text = String::from_utf8_lossy(&version.stdout);
    if !version.status.success() || !text.starts_with("stickslip ") {
        return Err(format!(
            "the wheel's stickslip command: `stickslip --version` gave {} {text:?} {:?}",
            version.status,
            String::from_utf8_lossy(&version.stderr)
        ));
    }
    eprintln!(
        "wheel-venv: {} --version: {}",
        command.display(),
        text.trim()
    );
    let t = Instant::now();
    status(
        "examples/fig2.py --quick with the wheel",
        Command::new(&python)
            .current_dir(root.join("target"))
            .env("PATH", &venv_path)
            .env("MPLBACKEND", "Agg")
            .arg(root.join("examples").join("fig2.py"))
            .args(["--quick", "--out"])
            .arg(&out),
    )?;
    let run_s = t.elapsed().as_secs_f64();
    for figure in ["fig2.png", "friction_map.png"] {
        if !out.join(figure).is_file() {
            return Err(format!(
                "the example wrote no {}",
                out.join(figure).display()
            ));
        }
    }
    eprintln!(
        "wheel: installed into a fresh venv without cargo in {install_s:.1} s; the README \
         example ran in {run_s:.1} s"
    );
    Ok((install_s, run_s))
}

/// `cargo xtask wheel [--check]`.
pub fn main(args: &[String], root: &Path) -> ExitCode {
    let mut check_it = false;
    for a in args {
        match a.as_str() {
            "--check" => check_it = true,
            "-h" | "--help" => {
                println!("{USAGE}");
                return ExitCode::SUCCESS;
            }
            other => {
                eprintln!("unknown option `{other}` for wheel\n\n{USAGE}");
                return ExitCode::from(2);
            }
        }
    }
    let result = build(root).and_then(|w| {
        if check_it {
            check(root, &w).map(|_| ())
        } else {
            Ok(())
        }
    });
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("wheel: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The `wheel` stage of `cargo xtask test`: build, then check.
///
/// # Errors
/// As [`build`] and [`check`].
pub fn stage(root: &Path) -> Result<(), String> {
    let wheel = build(root)?;
    check(root, &wheel).map(|_| ())
}
