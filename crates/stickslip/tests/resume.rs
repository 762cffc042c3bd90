//! Checkpoint and resume through the binary: a run killed with SIGKILL (several times, at
//! unplanned moments) and resumed ends with output bit-identical to an uninterrupted run,
//! as does one interrupted by SIGINT or SIGTERM (whose data so far are readable meanwhile),
//! gaussian noise included; a kill before the first checkpoint, a finished or failed run, and a
//! damaged checkpoint or partial output are refused with a message naming the directory, a
//! checkpoint of format 1 or of another build with exit 2 (the latter naming both builds, and
//! continued with `--allow-other-build`, which run.json records).

use crate::common;

use common::{bin, run, scene, signal, texts};
use std::borrow::Cow;
use std::path::{Path, PathBuf};
use std::process::{Child, Stdio};
use std::time::{Duration, Instant, SystemTime};
use stickslip_run::checkpoint::{BUILD_ID, Checkpoint};
use stickslip_run::schema::run_info::{BuildCrossing, RunInfo};

/// fig2 at N = 100 to 1 ms (four melting events, about 2 s in the dev profile, several times
/// the span of the kills below) with thermal noise, so the checkpoint must carry the noise
/// generators' positions.
const SHORT_NOISY: &[&str] = &[
    "--set",
    "contact.nodes=100",
    "--set",
    "time.end=1e-3",
    "--set",
    "output.profile_times=[3e-4, 1e-3]",
    "--set",
    "lubricant.noise.kind=gaussian",
    "--quiet",
];

const OUTPUTS: [&str; 4] = ["series.csv", "events.csv", "profiles.csv", "probes.csv"];

/// Longest wait for a file to appear or change.
const PATIENCE: Duration = Duration::from_secs(30);

fn run_args(out: &Path, extra: &[&str]) -> Vec<String> {
    let mut args: Vec<String> = vec![
        "run".into(),
        scene("fig2").display().to_string(),
        "--out".into(),
        out.display().to_string(),
    ];
    args.extend(extra.iter().map(|s| (*s).to_string()));
    args
}

fn spawn(args: &[String]) -> Child {
    bin()
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("the binary starts")
}

fn checkpoint(dir: &Path) -> PathBuf {
    dir.join("checkpoint.cbor")
}

/// Waits until `ready` holds; panics with `what` after [`PATIENCE`].
fn wait_until(what: &str, mut ready: impl FnMut() -> bool) {
    let start = Instant::now();
    while !ready() {
        assert!(start.elapsed() < PATIENCE, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// A delay of 0–250 ms that differs from call to call, so kills land at unplanned points of
/// the loop (between checkpoints, inside one, while rows are written).
fn unplanned_delay() -> Duration {
    let nanos = SystemTime::now()
        .duration_since(SystemTime::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    Duration::from_millis(u64::from(nanos % 251))
}

/// Sends SIGKILL (what `Child::kill` does on unix) and reaps the process; asserts it was still
/// running, i.e. the kill interrupted the run.
fn kill(mut child: Child, dir: &Path) {
    child.kill().unwrap();
    let status = child.wait().unwrap();
    assert!(
        !status.success(),
        "the run finished before it was killed; make the test scene longer"
    );
    assert!(
        checkpoint(dir).exists(),
        "a killed run keeps its checkpoint in {}",
        dir.display()
    );
}

/// run.json without its wall-clock line, the only one allowed to differ.
fn report_without_wall_time(dir: &Path) -> String {
    std::fs::read_to_string(dir.join("run.json"))
        .unwrap()
        .lines()
        .filter(|l| !l.contains("\"wall_seconds\""))
        .collect::<Vec<_>>()
        .join("\n")
}

fn assert_bit_identical(reference: &Path, resumed: &Path) {
    for f in OUTPUTS {
        let (a, b) = (
            std::fs::read(reference.join(f)).unwrap(),
            std::fs::read(resumed.join(f)).unwrap(),
        );
        assert!(
            a == b,
            "{f} of the resumed run differs from the uninterrupted one ({} against {} bytes)",
            b.len(),
            a.len()
        );
    }
    assert_eq!(
        report_without_wall_time(reference),
        report_without_wall_time(resumed),
        "run.json differs beyond wall_seconds"
    );
}

fn leftovers(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.') || n.starts_with("checkpoint"))
        .collect()
}

/// A killed run with a checkpoint in `dir` (checkpoints every 50 ms).
fn killed_run(dir: &Path) {
    let child = spawn(&run_args(
        dir,
        &[SHORT_NOISY, &["--checkpoint-every", "0.05"]].concat(),
    ));
    wait_until("the first checkpoint", || checkpoint(dir).exists());
    kill(child, dir);
}

#[test]
fn killed_run_resumes_bit_identical_to_an_uninterrupted_one() {
    let tmp = tempfile::tempdir().unwrap();
    let (reference, dir) = (tmp.path().join("reference"), tmp.path().join("killed"));
    // The reference runs meanwhile, without checkpoints: they must not change the output.
    let mut uninterrupted = spawn(&run_args(
        &reference,
        &[SHORT_NOISY, &["--checkpoint-every", "0"]].concat(),
    ));

    // Killed during `run`, then twice during `resume`, each time after a fresh checkpoint.
    let mut child = spawn(&run_args(
        &dir,
        &[SHORT_NOISY, &["--checkpoint-every", "0.05"]].concat(),
    ));
    wait_until("the first checkpoint", || checkpoint(&dir).exists());
    for _ in 0..2 {
        std::thread::sleep(unplanned_delay());
        kill(child, &dir);
        let seen = std::fs::read(checkpoint(&dir)).unwrap();
        child = spawn(&[
            "resume".to_string(),
            dir.display().to_string(),
            "--quiet".to_string(),
        ]);
        wait_until("a checkpoint of the resumed run", || {
            std::fs::read(checkpoint(&dir)).is_ok_and(|now| now != seen)
        });
    }
    std::thread::sleep(unplanned_delay());
    kill(child, &dir);
    // As if the kill had come while the run committed its output: the renamed file is used.
    std::fs::rename(dir.join(".probes.csv.tmp"), dir.join("probes.csv")).unwrap();

    let out = run(&["resume", &dir.display().to_string(), "--quiet"]);
    let (stdout, stderr) = texts(&out);
    assert_eq!(out.status.code(), Some(0), "stderr: {stderr}");
    assert!(stdout.contains("steps to t = 1e-3 s"), "{stdout}");

    assert!(uninterrupted.wait().unwrap().success());
    assert_bit_identical(&reference, &dir);
    assert!(
        leftovers(&dir).is_empty(),
        "left behind: {:?}",
        leftovers(&dir)
    );
}

#[test]
fn kill_before_the_first_checkpoint_leaves_nothing_to_resume() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("early");
    let child = spawn(&run_args(
        &dir,
        &[SHORT_NOISY, &["--checkpoint-every", "1000"]].concat(),
    ));
    wait_until("the partial series", || {
        dir.join(".series.csv.tmp").exists()
    });
    let mut child = child;
    child.kill().unwrap();
    assert!(!child.wait().unwrap().success());

    let dir_text = dir.display().to_string();
    let out = run(&["resume", &dir_text]);
    let (_, stderr) = texts(&out);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.starts_with(&format!("error: no checkpoint in {dir_text} ")),
        "{stderr}"
    );
    assert!(stderr.contains("before its first checkpoint"), "{stderr}");
}

#[test]
fn resuming_an_ended_run_changes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("done");
    let short = [
        "--set",
        "contact.nodes=20",
        "--set",
        "time.end=1e-5",
        "--set",
        "output.profile_times=[1e-5]",
        "--quiet",
    ];
    assert_eq!(
        run(&run_args(&dir, &short)
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>())
        .status
        .code(),
        Some(0)
    );
    assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));
    let before: Vec<Vec<u8>> = OUTPUTS
        .iter()
        .map(|f| std::fs::read(dir.join(f)).unwrap())
        .collect();

    let dir_text = dir.display().to_string();
    let out = run(&["resume", &dir_text]);
    let (stdout, stderr) = texts(&out);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    assert!(
        stdout.contains(&format!(
            "nothing to resume: the run in {dir_text} has already ended"
        )) && stdout.contains("\"ok\""),
        "{stdout}"
    );
    for (f, bytes) in OUTPUTS.iter().zip(&before) {
        assert_eq!(&std::fs::read(dir.join(f)).unwrap(), bytes, "{f} changed");
    }

    // A run that failed numerically has ended too; resume repeats its exit status 3.
    let failed = tmp.path().join("failed");
    let blowup = [
        "--set",
        "contact.nodes=40",
        "--set",
        "time.scheme=literal",
        "--set",
        "lubricant.gamma=1e5",
        "--set",
        "lubricant.noise.kind=off",
        "--set",
        "time.end=1e-4",
        "--set",
        "output.profile_times=[0.0]",
        "--quiet",
    ];
    let args = run_args(&failed, &blowup);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    assert_eq!(run(&args).status.code(), Some(3));
    let out = run(&["resume", &failed.display().to_string()]);
    let (_, stderr) = texts(&out);
    assert_eq!(out.status.code(), Some(3), "{stderr}");
    assert!(
        stderr.contains("nothing to resume") && stderr.contains("numerical failure"),
        "{stderr}"
    );
}

/// Copies the files of `from` into a new directory `to`.
fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
    }
}

/// Every file of `dir` with its bytes.
fn snapshot(dir: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .map(|entries| {
            entries
                .flatten()
                .filter(|e| e.path().is_file())
                .map(|e| {
                    (
                        e.file_name().to_string_lossy().into_owned(),
                        std::fs::read(e.path()).unwrap_or_default(),
                    )
                })
                .collect()
        })
        .unwrap_or_default()
}

/// `resume dir` exits 2 saying `expected`, and leaves every file of `dir` as it was.
fn assert_refused(dir: &Path, expected: &str) {
    let before = snapshot(dir);
    let out = run(&["resume", &dir.display().to_string(), "--quiet"]);
    let (_, stderr) = texts(&out);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    let after = snapshot(dir);
    assert_eq!(
        before.keys().collect::<Vec<_>>(),
        after.keys().collect::<Vec<_>>(),
        "a refused resume changed the files of {}",
        dir.display()
    );
    for (name, bytes) in &before {
        assert!(after[name] == *bytes, "a refused resume changed {name}");
    }
    assert!(stderr.starts_with("error: "), "{stderr}");
    assert!(
        stderr.contains(expected),
        "expected {expected:?} in: {stderr}"
    );
}

#[test]
fn damaged_checkpoint_or_partial_output_exits_2() {
    let tmp = tempfile::tempdir().unwrap();
    let killed = tmp.path().join("killed");
    killed_run(&killed);
    let bytes = std::fs::read(checkpoint(&killed)).unwrap();
    let corrupt = format!(
        "corrupt checkpoint {}",
        checkpoint(&tmp.path().join("flipped")).display()
    );

    let flipped = tmp.path().join("flipped");
    copy_dir(&killed, &flipped);
    let mut b = bytes.clone();
    let mid = b.len() / 2;
    b[mid] ^= 0x01;
    std::fs::write(checkpoint(&flipped), &b).unwrap();
    assert_refused(&flipped, &corrupt);
    assert_refused(&flipped, "checksum");

    let cut = tmp.path().join("cut");
    copy_dir(&killed, &cut);
    std::fs::write(checkpoint(&cut), &bytes[..bytes.len() - 100]).unwrap();
    assert_refused(&cut, "truncated");

    // Format 1, written before checkpoints were bound to the build: refused as such.
    let old = tmp.path().join("old");
    copy_dir(&killed, &old);
    let mut b = b"stickslip checkpoint 1\n".to_vec();
    b.extend_from_slice(&bytes[b.len()..]);
    std::fs::write(checkpoint(&old), &b).unwrap();
    assert_refused(
        &old,
        &format!(
            "{} is a checkpoint of format 1, and this build resumes format 3 only",
            checkpoint(&old).display()
        ),
    );

    let garbage = tmp.path().join("garbage");
    std::fs::create_dir_all(&garbage).unwrap();
    std::fs::write(checkpoint(&garbage), b"{\"not\": \"a checkpoint\"}").unwrap();
    assert_refused(&garbage, "not a stickslip checkpoint");

    // An intact checkpoint whose partial output lost bytes it recorded.
    let shortened = tmp.path().join("shortened");
    copy_dir(&killed, &shortened);
    std::fs::write(shortened.join(".series.csv.tmp"), b"t,X\n").unwrap();
    assert_refused(&shortened, "partial output cannot be continued");
    std::fs::remove_file(shortened.join(".series.csv.tmp")).unwrap();
    assert_refused(&shortened, "neither");

    // One stream's partial output lost: the others are kept, and what was there still loads.
    let lost = tmp.path().join("lost");
    copy_dir(&killed, &lost);
    let series_rows = |dir: &Path| {
        stickslip_run::sink::read::read_run(dir)
            .map(|r| r.output.series.len())
            .unwrap_or(0)
    };
    let rows = series_rows(&lost);
    assert!(rows > 0);
    std::fs::remove_file(lost.join(".probes.csv.tmp")).unwrap();
    assert_refused(&lost, "partial output cannot be continued");
    assert!(lost.join(".series.csv.tmp").exists());
    assert_eq!(series_rows(&lost), rows);

    // A checkpoint that is not a regular file, or longer than its header says, is refused
    // before its payload is read.
    let device = tmp.path().join("device");
    copy_dir(&killed, &device);
    std::fs::remove_file(checkpoint(&device)).unwrap();
    std::os::unix::fs::symlink("/dev/zero", checkpoint(&device)).unwrap();
    assert_refused(&device, "not a regular file");
    let long = tmp.path().join("long");
    copy_dir(&killed, &long);
    let f = std::fs::OpenOptions::new()
        .append(true)
        .open(checkpoint(&long))
        .unwrap();
    f.set_len(bytes.len() as u64 + (1 << 30)).unwrap();
    assert_refused(&long, "truncated or extended");
}

/// The status in `dir`'s run.json, if it can be read.
fn status(dir: &Path) -> Option<String> {
    stickslip_run::schema::run_info::RunInfo::read(dir)
        .ok()
        .map(|i| i.status.name().to_string())
}

#[test]
fn sigint_and_sigterm_checkpoint_exit_130_and_resume_bit_identical() {
    let tmp = tempfile::tempdir().unwrap();
    let reference = tmp.path().join("reference");
    let out = run(&run_args(&reference, SHORT_NOISY)
        .iter()
        .map(String::as_str)
        .collect::<Vec<_>>());
    assert!(out.status.success(), "{}", texts(&out).1);
    for sig in ["INT", "TERM"] {
        let dir = tmp.path().join(sig);
        // No periodic checkpoints: the one in the directory must come from the signal.
        let child = bin()
            .args(run_args(
                &dir,
                &[SHORT_NOISY, &["--checkpoint-every", "0"]].concat(),
            ))
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        wait_until("run.json with status running", || {
            status(&dir).as_deref() == Some("running")
        });
        std::thread::sleep(Duration::from_millis(100) + unplanned_delay());
        signal(&child, sig);
        let output = child.wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(130), "SIG{sig}: {stderr}");
        assert!(
            stderr.contains(&format!("resume with: stickslip resume {}", dir.display())),
            "SIG{sig}: {stderr}"
        );
        assert_eq!(status(&dir).as_deref(), Some("interrupted"), "SIG{sig}");
        assert!(checkpoint(&dir).exists(), "SIG{sig}: no checkpoint");
        // The data so far are under the documented names, for any reader.
        for f in ["series.csv", "profiles.csv", "probes.csv"] {
            let (part, whole) = (
                std::fs::read(dir.join(f)).unwrap(),
                std::fs::read(reference.join(f)).unwrap(),
            );
            assert!(whole.starts_with(&part), "SIG{sig}: {f} is not a prefix");
        }
        assert!(dir.join("events.csv").is_file(), "SIG{sig}: no events.csv");
        let resumed = run(&["resume", dir.to_str().unwrap(), "--quiet"]);
        assert!(resumed.status.success(), "{}", texts(&resumed).1);
        assert_bit_identical(&reference, &dir);
        assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));
    }
}

#[test]
fn an_earlier_run_is_refused_without_force_and_never_looks_current() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("out");
    let small = [
        "--set",
        "contact.nodes=10",
        "--set",
        "time.end=1e-5",
        "--set",
        "output.profile_times=[1e-5]",
        "--quiet",
    ];
    let first = run(&run_args(&dir, &small)
        .iter()
        .map(String::as_str)
        .collect::<Vec<_>>());
    assert!(first.status.success(), "{}", texts(&first).1);
    let before: Vec<Vec<u8>> = ["run.json", "series.csv", "events.csv"]
        .iter()
        .map(|f| std::fs::read(dir.join(f)).unwrap())
        .collect();
    let again = run(&run_args(&dir, &small)
        .iter()
        .map(String::as_str)
        .collect::<Vec<_>>());
    let stderr = texts(&again).1;
    assert_eq!(again.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains(&dir.display().to_string()) && stderr.contains("--force"),
        "{stderr}"
    );
    let after: Vec<Vec<u8>> = ["run.json", "series.csv", "events.csv"]
        .iter()
        .map(|f| std::fs::read(dir.join(f)).unwrap())
        .collect();
    assert_eq!(before, after, "a refused run touched the directory");

    // With --force a long run replaces the earlier results before its first step: killed
    // mid-way, the directory holds its run.json (running) and no finished-looking CSVs.
    let child = spawn(&run_args(&dir, &[SHORT_NOISY, &["--force"]].concat()));
    wait_until("run.json with status running", || {
        status(&dir).as_deref() == Some("running")
    });
    let mut child = child;
    child.kill().unwrap();
    child.wait().unwrap();
    assert_eq!(status(&dir).as_deref(), Some("running"));
    for f in ["series.csv", "events.csv", "profiles.csv", "probes.csv"] {
        assert!(!dir.join(f).exists(), "stale {f} beside a newer run");
    }
}

#[test]
fn another_builds_checkpoint_is_refused_unless_allowed_and_then_recorded() {
    let tmp = tempfile::tempdir().unwrap();
    let (reference, dir) = (tmp.path().join("reference"), tmp.path().join("killed"));
    let mut uninterrupted = spawn(&run_args(
        &reference,
        &[SHORT_NOISY, &["--checkpoint-every", "0"]].concat(),
    ));
    killed_run(&dir);
    // The checkpoint as another build would have written it.
    let other = "0123456789abcdef";
    let mut c = Checkpoint::decode(&std::fs::read(checkpoint(&dir)).unwrap()).unwrap();
    assert_eq!(
        c.build, BUILD_ID,
        "a run writes its own build into the checkpoint"
    );
    c.build = Cow::Borrowed(other);
    std::fs::write(checkpoint(&dir), c.encode().unwrap()).unwrap();
    let before = std::fs::read(checkpoint(&dir)).unwrap();

    let dir_text = dir.display().to_string();
    let out = run(&["resume", &dir_text, "--quiet"]);
    let (_, stderr) = texts(&out);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert_eq!(
        stderr,
        format!(
            "error: {} was written by build {other} and this is build {BUILD_ID}: its numbers \
             would differ; rerun, or resume with --allow-other-build to continue anyway\n",
            checkpoint(&dir).display()
        )
    );
    assert_eq!(
        std::fs::read(checkpoint(&dir)).unwrap(),
        before,
        "refused, yet touched"
    );
    assert_eq!(status(&dir).as_deref(), Some("running"));

    // Allowed: it goes on (killed once more after a checkpoint of its own, then resumed
    // without the flag, as that checkpoint is this build's) and run.json keeps the record.
    let child = spawn(&[
        "resume".to_string(),
        dir_text.clone(),
        "--quiet".to_string(),
        "--allow-other-build".to_string(),
        "--checkpoint-every".to_string(),
        "0.05".to_string(),
    ]);
    wait_until("a checkpoint of the resumed run", || {
        std::fs::read(checkpoint(&dir)).is_ok_and(|now| now != before)
    });
    kill(child, &dir);
    let out = run(&["resume", &dir_text, "--quiet"]);
    assert_eq!(out.status.code(), Some(0), "{}", texts(&out).1);
    let crossing = BuildCrossing {
        checkpoint_build: other.to_string(),
        build: BUILD_ID.to_string(),
    };
    let info = RunInfo::read(&dir).unwrap();
    assert_eq!(info.status.name(), "ok");
    assert_eq!(info.resumed_across_builds, vec![crossing]);
    let text = std::fs::read_to_string(dir.join("run.json")).unwrap();
    assert!(
        text.contains(&format!(
            "\"resumed_across_builds\": [\n    {{\n      \"checkpoint_build\": \"{other}\",\n      \
             \"build\": \"{BUILD_ID}\"\n    }}\n  ]"
        )),
        "{text}"
    );
    // Here the "other" build is this one in disguise, so the numbers are an uninterrupted
    // run's; run.json differs by the record alone.
    assert!(uninterrupted.wait().unwrap().success());
    for f in OUTPUTS {
        assert!(
            std::fs::read(reference.join(f)).unwrap() == std::fs::read(dir.join(f)).unwrap(),
            "{f} differs"
        );
    }
    let mut reread = RunInfo::read(&dir).unwrap();
    reread.resumed_across_builds.clear();
    reread.wall_seconds = 0.0;
    let mut uninterrupted_info = RunInfo::read(&reference).unwrap();
    uninterrupted_info.wall_seconds = 0.0;
    assert_eq!(reread, uninterrupted_info);
    assert!(!report_without_wall_time(&reference).contains("resumed_across_builds"));
}
