//! An output directory reads back in every state. An interrupted run's data are under the
//! documented names (its series.csv a prefix of the uninterrupted run's) and resuming it gives
//! the uninterrupted run's bytes; a killed run (temporary files and a checkpoint only) reads as
//! of its checkpoint, and without one, its complete rows.

use crate::common;

use std::path::Path;
use stickslip_run::driver::{Control, Progress};
use stickslip_run::schema::run_info::RunInfo;
use stickslip_run::sink::read::{Source, read_run};
use stickslip_run::{DirOptions, ResolvedScene, RunStatus, Scene, StopReason};

const OUTPUTS: [&str; 4] = ["series.csv", "events.csv", "profiles.csv", "probes.csv"];

/// fig2 at N = 50 to 7e-4 s: one melting event, a few hundred adaptive steps, profiles and
/// probes.
fn scene() -> ResolvedScene {
    Scene::from_path(
        &common::scene("fig2"),
        &[
            "contact.nodes=50",
            "time.end=7e-4",
            "output.profile_times=[2e-4, 7e-4]",
            "output.probe_radii=[2e-6, 1e-5]",
        ],
    )
    .unwrap()
}

fn no_checkpoints() -> DirOptions {
    DirOptions {
        force: false,
        checkpoint_every_s: 0.0,
    }
}

/// `scene` run into `dir`, interrupted after 150 adaptive steps.
fn interrupted_after_150_steps(
    scene: &ResolvedScene,
    dir: &Path,
    options: &DirOptions,
) -> stickslip_run::RunOutcome {
    let mut polls = 0;
    let mut poll = |_: &Progress| {
        polls += 1;
        polls >= 150
    };
    let mut control = Control {
        poll: Some(&mut poll),
        ..Control::default()
    };
    stickslip_run::run_to_dir(scene, dir, options, &mut control).unwrap()
}

fn read(dir: &Path, f: &str) -> Vec<u8> {
    std::fs::read(dir.join(f)).unwrap_or_else(|e| panic!("{}: {e}", dir.join(f).display()))
}

/// run.json without its wall-clock line.
fn run_json_without_wall_time(dir: &Path) -> String {
    String::from_utf8(read(dir, "run.json"))
        .unwrap()
        .lines()
        .filter(|l| !l.contains("\"wall_seconds\""))
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn interrupted_data_are_readable_and_the_resumed_run_is_bit_identical() {
    let tmp = tempfile::tempdir().unwrap();
    let (reference, dir) = (tmp.path().join("reference"), tmp.path().join("interrupted"));
    let scene = scene();
    let whole = stickslip_run::run_to_dir(
        &scene,
        &reference,
        &no_checkpoints(),
        &mut Control::default(),
    )
    .unwrap();
    assert_eq!(whole.stop, StopReason::End);

    // Interrupted after 150 adaptive steps, about half the run, inside the first event.
    let stopped = interrupted_after_150_steps(&scene, &dir, &no_checkpoints());
    assert_eq!(stopped.stop, StopReason::Interrupted);
    assert!(stopped.t_final_s < whole.t_final_s);

    // Every file under its documented name, the streams as prefixes of the whole run's.
    for f in ["series.csv", "profiles.csv", "probes.csv"] {
        let (part, all) = (read(&dir, f), read(&reference, f));
        assert!(
            all.starts_with(&part),
            "{f} is not a prefix of the whole run's"
        );
        assert!(part.ends_with(b"\n"), "{f} ends inside a row");
    }
    let series = read(&dir, "series.csv");
    assert!(series.len() < read(&reference, "series.csv").len());
    let info = RunInfo::read(&dir).unwrap();
    assert_eq!(info.status, RunStatus::Interrupted);
    let rows = series.iter().filter(|&&b| b == b'\n').count() - 1;
    assert_eq!(rows as u64, info.series_rows);
    let got = read_run(&dir).unwrap();
    assert_eq!(got.source, Source::Files);
    assert_eq!(got.output.series.len(), rows);
    assert_eq!(got.output.events.len(), stopped.events.len());
    assert!(dir.join(".series.csv.tmp").exists() && dir.join("checkpoint.cbor").exists());

    // As a hard kill would leave it: no published copies, run.json still `running`, and a
    // row cut off after the checkpoint. The reader stops at the checkpoint.
    let killed = tmp.path().join("killed");
    std::fs::create_dir_all(&killed).unwrap();
    for e in std::fs::read_dir(&dir).unwrap() {
        let e = e.unwrap();
        let name = e.file_name().to_string_lossy().into_owned();
        if !OUTPUTS.contains(&name.as_str()) {
            std::fs::copy(e.path(), killed.join(&name)).unwrap();
        }
    }
    let mut running = info.clone();
    running.status = RunStatus::Running;
    running.stop = None;
    running.summary = None;
    running.write(&killed).unwrap();
    let mut tmp_series = read(&killed, ".series.csv.tmp");
    tmp_series.extend_from_slice(b"9.9e-4,1e-9");
    std::fs::write(killed.join(".series.csv.tmp"), &tmp_series).unwrap();
    let at_checkpoint = read_run(&killed).unwrap();
    assert_eq!(at_checkpoint.source, Source::Checkpoint);
    let (a, b) = (&at_checkpoint.output, &got.output);
    assert_eq!(a.info.status, RunStatus::Running);
    assert_eq!(
        (&a.series, &a.probes, &a.profiles),
        (&b.series, &b.probes, &b.profiles)
    );
    assert_eq!(a.events, b.events);
    assert_eq!(a.info.summary, b.info.summary);
    assert_eq!(a.info.steps, b.info.steps);

    // Killed before any checkpoint: the complete rows, as many series as probe rows.
    std::fs::remove_file(killed.join("checkpoint.cbor")).unwrap();
    let early = read_run(&killed).unwrap();
    assert_eq!(early.source, Source::Temporaries);
    assert_eq!(early.output.series, b.series);
    assert_eq!(early.output.probes.len(), b.series.len());
    assert!(early.output.events.is_empty());

    // Resumed: every output file as the uninterrupted run's, byte for byte.
    let (_, outcome) = stickslip_run::resume(
        &dir,
        &stickslip_run::ResumeOptions::default(),
        &mut Control::default(),
    )
    .unwrap();
    assert_eq!(outcome.stop, StopReason::End);
    for f in OUTPUTS {
        assert!(
            read(&dir, f) == read(&reference, f),
            "{f} of the resumed run differs from the uninterrupted one"
        );
    }
    assert_eq!(
        run_json_without_wall_time(&dir),
        run_json_without_wall_time(&reference)
    );
    let leftovers: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.') || n.starts_with("checkpoint"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
    assert_eq!(
        read_run(&dir).unwrap().output.series.len(),
        whole.series_rows as usize
    );
}

#[test]
fn a_directory_without_a_run_is_named() {
    let tmp = tempfile::tempdir().unwrap();
    let e = read_run(&tmp.path().join("nothing"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("not a run directory (no such directory)"), "{e}");
    let e = read_run(tmp.path()).unwrap_err().to_string();
    assert!(e.contains("no run.json"), "{e}");
}

#[test]
fn a_directory_another_process_writes_is_refused_and_left_as_it_was() {
    // The lock is the kernel's (flock), held per open file: a second open in this process
    // conflicts as a second process's would.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("busy");
    let scene = scene();
    let options = DirOptions {
        force: false,
        checkpoint_every_s: 1e-9,
    };
    let stopped = interrupted_after_150_steps(&scene, &dir, &options);
    assert_eq!(stopped.stop, StopReason::Interrupted);
    let before = read(&dir, "run.json");
    let held = stickslip_run::sink::lock::DirLock::acquire(&dir).unwrap();
    let resumed = stickslip_run::resume(
        &dir,
        &stickslip_run::ResumeOptions::default(),
        &mut Control::default(),
    );
    let e = resumed.expect_err("a second writer is refused");
    assert!(
        matches!(e, stickslip_run::RunError::Busy { .. })
            && e.to_string().contains("nothing was changed"),
        "{e}"
    );
    let forced = stickslip_run::run_to_dir(
        &scene,
        &dir,
        &DirOptions {
            force: true,
            checkpoint_every_s: 0.0,
        },
        &mut Control::default(),
    );
    assert!(matches!(forced, Err(stickslip_run::RunError::Busy { .. })));
    assert_eq!(read(&dir, "run.json"), before);
    // Released: the resume finishes the run.
    drop(held);
    let (_, done) = stickslip_run::resume(
        &dir,
        &stickslip_run::ResumeOptions::default(),
        &mut Control::default(),
    )
    .unwrap();
    assert_eq!(done.stop, StopReason::End);
}

#[test]
fn a_directory_of_another_commands_results_is_refused_even_with_force() {
    let tmp = tempfile::tempdir().unwrap();
    for (file, what) in [
        ("verify.json", "stickslip verify"),
        ("fit.json", "stickslip fit"),
        ("sweep.json", "a sweep"),
    ] {
        let dir = tmp.path().join(file);
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join(file), b"{}").unwrap();
        for force in [false, true] {
            let e = stickslip_run::run_to_dir(
                &scene(),
                &dir,
                &DirOptions {
                    force,
                    checkpoint_every_s: 0.0,
                },
                &mut Control::default(),
            )
            .expect_err("refused");
            let text = e.to_string();
            assert!(
                matches!(e, stickslip_run::RunError::Foreign { .. })
                    && text.contains(what)
                    && text.contains(file),
                "{text}"
            );
        }
        // Nothing was written beside the other results.
        let names: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert_eq!(names.len(), 1, "{file}");
    }
}
