//! Helpers shared by the integration tests: running the binary and reading its CSV output.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The `stickslip` binary built for these tests.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_stickslip"))
}

/// Path of a scene in validation/scenes.
pub fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../validation/scenes")
        .join(format!("{name}.toml"))
}

/// Runs the binary with `args`.
pub fn run(args: &[&str]) -> Output {
    bin().args(args).output().expect("the binary runs")
}

/// Sends `signal` (e.g. "INT") to `child`; panics when `kill` fails.
pub fn signal(child: &Child, signal: &str) {
    let ok = Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .expect("kill runs")
        .success();
    assert!(ok, "kill -{signal} failed");
}

/// Runs the binary with `args`, sends `sig` (e.g. "INT") once `ready()` holds or after
/// `timeout`, and returns its output: an interrupt at a chosen point of a long command.
pub fn run_signalled(
    args: &[String],
    sig: &str,
    ready: impl Fn() -> bool,
    timeout: Duration,
) -> Output {
    let child = bin()
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary starts");
    let started = Instant::now();
    while !ready() && started.elapsed() < timeout {
        std::thread::sleep(Duration::from_millis(5));
    }
    signal(&child, sig);
    child.wait_with_output().expect("the binary ends")
}

/// Stdout and stderr of `out` as text.
pub fn texts(out: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A CSV output file, read with the run library's parser (empty fields as NaN).
pub struct Csv {
    /// Column names.
    pub header: Vec<String>,
    /// Rows.
    pub rows: Vec<Vec<f64>>,
}

impl Csv {
    /// Reads and parses `path`; panics with the parser's message.
    pub fn read(path: &Path) -> Self {
        let text = std::fs::read_to_string(path)
            .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
        let csv = stickslip_run::schema::csv::NumericCsv::parse(&text, &path.display().to_string())
            .unwrap_or_else(|e| panic!("{e}"));
        Self {
            header: csv.header,
            rows: csv.rows,
        }
    }

    /// The column called `name`.
    pub fn col(&self, name: &str) -> Vec<f64> {
        let i = self
            .header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name} in {:?}", self.header));
        self.rows.iter().map(|r| r[i]).collect()
    }
}
