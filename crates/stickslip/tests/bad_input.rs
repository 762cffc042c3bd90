//! The bad-input battery: `stickslip run` as a careless user or a broken file system would call
//! it. A small fig2 scene with one key mutated — removed, or set to NaN, ±inf, a subnormal,
//! ±0, ±1e308, a negative, a huge integer, a string, a boolean, an array, a table or a date —
//! or an unknown key added, in cases drawn by proptest from a fixed seed; and the special files
//! of the bad-input campaign. Each run must end in 0, 2 (refused) or 3 (a numerical failure),
//! never a panic (101) or a signal; a refusal within seconds, writing nothing; a run that goes
//! on must stop on SIGTERM (130); and no process may grow past a memory bound.

use crate::common;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use std::path::Path;
use std::process::{Child, Stdio};
use std::time::{Duration, Instant};
use toml::Value;

/// Largest resident memory a run of the battery may reach, kB (its runs need about 10 MB).
const MAX_RSS_KB: u64 = 1 << 20;
/// A refusal comes before this; a run still going then is stopped with SIGTERM.
const REFUSE_WITHIN: Duration = Duration::from_secs(5);
/// A stopped run must have ended this long after SIGTERM.
const STOP_WITHIN: Duration = Duration::from_secs(10);

/// The resident-memory peak of `pid` so far, kB (`VmHWM`; 0 once it is gone).
fn peak_rss_kb(pid: u32) -> u64 {
    std::fs::read_to_string(format!("/proc/{pid}/status"))
        .ok()
        .and_then(|s| {
            s.lines()
                .find_map(|l| l.strip_prefix("VmHWM:"))
                .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        })
        .unwrap_or(0)
}

/// How a run of the battery ended.
#[derive(Debug)]
struct Ending {
    code: Option<i32>,
    stderr: String,
    peak_kb: u64,
    refused_after: Duration,
}

/// Waits for `child`, watching its memory; SIGTERM after [`REFUSE_WITHIN`].
fn watch(mut child: Child) -> Ending {
    let started = Instant::now();
    let mut peak_kb = 0;
    let mut stopped = None;
    let status = loop {
        peak_kb = peak_kb.max(peak_rss_kb(child.id()));
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if peak_kb > MAX_RSS_KB {
            child.kill().ok();
            break child.wait().expect("wait");
        }
        let elapsed = started.elapsed();
        if stopped.is_none() && elapsed > REFUSE_WITHIN {
            std::process::Command::new("kill")
                .args(["-TERM", &child.id().to_string()])
                .status()
                .ok();
            stopped = Some(elapsed);
        }
        if stopped.is_some_and(|s| elapsed > s + STOP_WITHIN) {
            child.kill().ok();
            break child.wait().expect("wait");
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let mut stderr = String::new();
    if let Some(mut e) = child.stderr.take() {
        std::io::Read::read_to_string(&mut e, &mut stderr).ok();
    }
    Ending {
        code: status.code(),
        stderr,
        peak_kb,
        refused_after: started.elapsed(),
    }
}

/// Runs `stickslip run scene --out dir` and checks the ending; `Err` says what was wrong.
fn run_and_check(scene: &Path, dir: &Path, what: &str) -> Result<Ending, String> {
    let child = common::bin()
        .args([
            "run",
            scene.to_str().unwrap(),
            "--out",
            dir.to_str().unwrap(),
            "--quiet",
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary starts");
    let e = watch(child);
    let fail = |why: &str| Err(format!("{what}: {why} (exit {:?}): {}", e.code, e.stderr));
    if e.peak_kb > MAX_RSS_KB {
        return fail(&format!("grew to {} kB", e.peak_kb));
    }
    match e.code {
        Some(0 | 3 | 130) => {}
        Some(2) => {
            if e.refused_after > REFUSE_WITHIN {
                return fail("refused only after the stop");
            }
            if dir.exists() {
                return fail("refused, yet wrote its output directory");
            }
            if !e.stderr.starts_with("error: ") || e.stderr.lines().count() != 1 {
                return fail("refused without a one-line error");
            }
        }
        _ => return fail("neither ran, refused, failed numerically nor stopped"),
    }
    Ok(e)
}

/// fig2, small: 20 nodes to 1e-5 s.
fn base() -> toml::Table {
    let mut t: toml::Table = std::fs::read_to_string(common::scene("fig2"))
        .unwrap()
        .parse()
        .unwrap();
    let contact = t["contact"].as_table_mut().unwrap();
    contact.insert("nodes".into(), Value::Integer(20));
    let time = t["time"].as_table_mut().unwrap();
    time.insert("end".into(), Value::Float(1e-5));
    t.insert("output".into(), Value::Table(toml::Table::new()));
    t
}

/// The values a careless user or a broken file gives a key.
fn bad_value() -> impl Strategy<Value = Option<Value>> {
    let date: toml::value::Datetime = "1979-05-27T07:32:00Z".parse().unwrap();
    prop_oneof![
        Just(None),
        Just(Some(Value::Float(f64::NAN))),
        Just(Some(Value::Float(f64::INFINITY))),
        Just(Some(Value::Float(f64::NEG_INFINITY))),
        Just(Some(Value::Float(1e-320))),
        Just(Some(Value::Float(-1e-320))),
        Just(Some(Value::Float(0.0))),
        Just(Some(Value::Float(-0.0))),
        Just(Some(Value::Float(1e308))),
        Just(Some(Value::Float(-1e308))),
        Just(Some(Value::Float(-1.0))),
        Just(Some(Value::Integer(i64::MAX))),
        Just(Some(Value::Integer(i64::MIN))),
        Just(Some(Value::Integer(0))),
        Just(Some(Value::String("1e-3".into()))),
        Just(Some(Value::String(String::new()))),
        Just(Some(Value::Boolean(true))),
        Just(Some(Value::Array(vec![
            Value::Float(1.0),
            Value::Float(f64::NAN)
        ]))),
        Just(Some(Value::Table(toml::Table::new()))),
        Just(Some(Value::Datetime(date))),
        (-400.0..400.0f64).prop_map(|e| Some(Value::Float(10f64.powf(e)))),
    ]
}

fn set(t: &mut toml::Table, path: &str, v: Option<Value>) {
    let mut parts: Vec<&str> = path.split('.').collect();
    let last = parts.pop().unwrap();
    let mut table = t;
    for p in parts {
        let entry = table
            .entry(p.to_string())
            .or_insert_with(|| Value::Table(toml::Table::new()));
        if !entry.is_table() {
            *entry = Value::Table(toml::Table::new());
        }
        table = entry.as_table_mut().unwrap();
    }
    match v {
        Some(v) => table.insert(last.to_string(), v),
        None => table.remove(last),
    };
}

#[test]
fn mutated_scenes_run_or_are_refused_quickly_writing_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let mut paths: Vec<String> = stickslip_run::keys::KEYS
        .iter()
        .map(|k| k.path.to_string())
        .collect();
    paths.extend(
        [
            "lubricant.taumax",
            "bogus",
            "time.end.x",
            "contact.radius.a",
        ]
        .map(String::from),
    );
    let config = Config {
        cases: 400,
        failure_persistence: None,
        ..Config::default()
    };
    let mut runner =
        TestRunner::new_with_rng(config, TestRng::deterministic_rng(RngAlgorithm::ChaCha));
    let n = std::cell::Cell::new(0usize);
    let exits = std::cell::RefCell::new(std::collections::BTreeMap::new());
    let strategy = (proptest::sample::select(paths), bad_value());
    let result = runner.run(&strategy, |(path, value)| {
        n.set(n.get() + 1);
        let n = n.get();
        let mut t = base();
        let shown = value
            .as_ref()
            .map_or("(removed)".to_string(), Value::to_string);
        set(&mut t, &path, value);
        let scene = tmp.path().join(format!("s{n}.toml"));
        std::fs::write(&scene, toml::to_string(&t).unwrap_or_default()).unwrap();
        let dir = tmp.path().join(format!("out{n}"));
        let e = run_and_check(&scene, &dir, &format!("{path} = {shown}"))
            .map_err(TestCaseError::fail)?;
        if !matches!(e.code, Some(0 | 2)) {
            eprintln!("  {path} = {shown}: exit {:?} {}", e.code, e.stderr.trim());
        }
        *exits.borrow_mut().entry(e.code).or_insert(0usize) += 1;
        Ok(())
    });
    let (n, exits) = (n.get(), exits.into_inner());
    eprintln!("bad-input battery: {n} mutated scenes, exits {exits:?}");
    if let Err(e) = result {
        panic!("{e}");
    }
    // The battery reaches both sides: scenes that run and scenes refused.
    assert!(exits.get(&Some(2)).copied().unwrap_or(0) >= 40, "{exits:?}");
    assert!(exits.get(&Some(0)).copied().unwrap_or(0) >= 10, "{exits:?}");
}

#[test]
fn special_files_are_refused_at_once_writing_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let sparse = tmp.path().join("sparse.toml");
    std::fs::File::create(&sparse)
        .unwrap()
        .set_len(3 << 30)
        .unwrap();
    let link = tmp.path().join("zero.toml");
    std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
    let not_utf8 = tmp.path().join("latin1.toml");
    std::fs::write(&not_utf8, b"name = \"caf\xe9\"\n").unwrap();
    let cases: [(&Path, &str); 5] = [
        (Path::new("/dev/zero"), "not a regular file"),
        (&link, "not a regular file"),
        (tmp.path(), "not a regular file"),
        (&sparse, "larger than allowed"),
        (&not_utf8, "not UTF-8"),
    ];
    for (i, (scene, says)) in cases.iter().enumerate() {
        let dir = tmp.path().join(format!("out{i}"));
        let e = run_and_check(scene, &dir, &scene.display().to_string()).unwrap();
        assert_eq!(e.code, Some(2), "{}: {}", scene.display(), e.stderr);
        assert!(e.stderr.contains(says), "{}: {}", scene.display(), e.stderr);
        assert!(
            e.peak_kb < 64 << 10,
            "{}: {} kB",
            scene.display(),
            e.peak_kb
        );
    }
}

/// Whether this process runs as root (mounting a small file system needs it).
fn is_root() -> bool {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find_map(|l| l.strip_prefix("Uid:"))
                .map(|v| v.split_whitespace().next() == Some("0"))
        })
        .unwrap_or(false)
}

#[test]
fn a_full_disk_ends_the_run_as_failed_with_an_io_reason() {
    if !is_root() {
        eprintln!("skipped: mounting a 256 kB file system needs root (CI runs as root)");
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let disk = tmp.path().join("disk");
    std::fs::create_dir(&disk).unwrap();
    let mounted = std::process::Command::new("mount")
        .args([
            "-t",
            "tmpfs",
            "-o",
            "size=256k",
            "tmpfs",
            disk.to_str().unwrap(),
        ])
        .status()
        .expect("mount runs");
    assert!(mounted.success(), "cannot mount a tmpfs as root");
    let dir = disk.join("out");
    // Rows every 1e-9 s of a 20-node fig2 in fixed steps to 2e-5 s: about 2 MB of series, far
    // over 256 kB.
    let out = common::run(&[
        "run",
        common::scene("fig2").to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
        "--quiet",
        "--set",
        "contact.nodes=20",
        "--set",
        "time.end=2e-5",
        "--set",
        "time.stepping=fixed",
        "--set",
        "time.dt=1e-9",
        "--set",
        "output.series_interval=1e-9",
        "--set",
        "output.profile_times=[2e-5]",
    ]);
    let read = stickslip_run::sink::read::read_run(&dir);
    std::process::Command::new("umount")
        .arg(&disk)
        .status()
        .ok();
    let stderr = common::texts(&out).1;
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("No space left on device"), "{stderr}");
    let read = read.expect("the run directory reads");
    let info = &read.output.info;
    assert_eq!(info.status.name(), "failed");
    assert_eq!(info.stop.as_deref(), Some("io"));
    let failure = info.failure.as_ref().expect("a failure record");
    assert_eq!(failure.quantity, "io");
    assert!(
        failure.message.contains("No space left on device"),
        "{}",
        failure.message
    );
    // The rows written before the disk filled are kept and read.
    assert!(
        read.output.series.len() > 100,
        "{} rows",
        read.output.series.len()
    );
}

#[test]
fn a_large_checkpoint_with_a_wrong_header_is_refused_from_its_header() {
    // A 1 GiB file (sparse) named like a checkpoint but not one: resume must refuse it from
    // its first bytes, not read it whole first.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("run");
    std::fs::create_dir(&dir).unwrap();
    let mut f = std::fs::File::create(dir.join("checkpoint.cbor")).unwrap();
    std::io::Write::write_all(&mut f, b"not a checkpoint at all\n").unwrap();
    f.set_len(1 << 30).unwrap();
    let child = common::bin()
        .args(["resume", dir.to_str().unwrap(), "--quiet"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary starts");
    let e = watch(child);
    assert_eq!(e.code, Some(2), "{}", e.stderr);
    assert!(e.stderr.contains("wrong header"), "{}", e.stderr);
    assert!(e.peak_kb < 64 << 10, "{} kB", e.peak_kb);
}
