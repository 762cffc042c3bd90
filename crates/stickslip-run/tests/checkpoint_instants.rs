//! A run resumed from a checkpoint taken at any iteration ends exactly as the uninterrupted
//! run: same stop reason, same final state, same rows. Every iteration's checkpoint is tried,
//! on runs that stop after `time.max_events` events and after an event stays open for
//! `time.max_open_event`, so a kill right after the stop condition is among them (a checkpoint
//! saved before the stop checks resumed one step further than the uninterrupted run).

use crate::common;

use stickslip_core::sim::{Observables, SimState};
use stickslip_run::driver::{Control, Driver, DriverState, RunStart, Sink, Snapshot};
use stickslip_run::{ResolvedScene, RunOutcome, Scene, StopReason};

/// What a run records, and the checkpoints a checkpointing sink would have saved.
#[derive(Default)]
struct Recorder {
    /// Per series row: t and F, as bits.
    rows: Vec<(u64, u64)>,
    /// Per profile: t, as bits.
    profiles: Vec<u64>,
    /// Every checkpoint the run offered: the states and how many rows had been recorded.
    checkpoints: Vec<(SimState, DriverState, usize, usize)>,
    /// The loop index at the end.
    final_loop: u64,
}

impl Sink for Recorder {
    fn begin(&mut self, _start: &RunStart<'_>) -> std::io::Result<()> {
        Ok(())
    }
    fn series_row(&mut self, o: &Observables, _probes: &[f64]) -> std::io::Result<()> {
        self.rows.push((o.t_s.to_bits(), o.f_n.to_bits()));
        Ok(())
    }
    fn profile(&mut self, t_s: f64, _r: &[f64], _s: &SimState) -> std::io::Result<()> {
        self.profiles.push(t_s.to_bits());
        Ok(())
    }
    fn after_iteration(&mut self, s: &Snapshot<'_>) -> std::io::Result<()> {
        self.checkpoints.push((
            s.sim.clone(),
            s.driver.clone(),
            self.rows.len(),
            self.profiles.len(),
        ));
        Ok(())
    }
    fn end(&mut self, _o: &RunOutcome, s: &Snapshot<'_>) -> std::io::Result<()> {
        self.final_loop = s.driver.loop_index;
        Ok(())
    }
}

/// The rigid drive at N = 10 with `extra` overrides.
fn rigid(extra: &[&str]) -> ResolvedScene {
    let mut sets = vec!["contact.nodes=10", "output.profile_times=[0.0, 1e-3]"];
    sets.extend_from_slice(extra);
    Scene::from_path(&common::scene("rigid"), &sets).unwrap()
}

/// Runs `scene` whole, then resumes it from every checkpoint it offered and compares.
fn resumes_identically_from_every_checkpoint(scene: &ResolvedScene, stop: StopReason) {
    let mut whole = Recorder::default();
    let driver = Driver::start(scene, &mut whole).unwrap();
    let reference = driver
        .run_to_end(&mut whole, &mut Control::default())
        .unwrap();
    assert_eq!(
        reference.stop, stop,
        "the test scene stops for another reason"
    );
    let n = whole.checkpoints.len();
    assert!(
        (50..5000).contains(&n),
        "{n} iterations: the test wants a short run"
    );
    let mut mismatches = Vec::new();
    for (k, (sim, state, rows, profiles)) in whole.checkpoints.iter().enumerate() {
        let mut rest = Recorder {
            rows: whole.rows[..*rows].to_vec(),
            profiles: whole.profiles[..*profiles].to_vec(),
            checkpoints: Vec::new(),
            final_loop: 0,
        };
        let resumed = Driver::restore(
            scene,
            reference.preflight.clone(),
            sim.clone(),
            state.clone(),
        )
        .unwrap()
        .run_to_end(&mut rest, &mut Control::default())
        .unwrap();
        let same = resumed.stop == reference.stop
            && resumed.t_final_s.to_bits() == reference.t_final_s.to_bits()
            && resumed.counts == reference.counts
            && resumed.events == reference.events
            && resumed.summary == reference.summary
            && rest.rows == whole.rows
            && rest.profiles == whole.profiles;
        if !same {
            mismatches.push(format!(
                "checkpoint {k} (iteration {}): stop {:?} at t = {:e} after {} steps, \
                 uninterrupted {:?} at t = {:e} after {} steps",
                state.loop_index,
                resumed.stop,
                resumed.t_final_s,
                resumed.counts.steps,
                reference.stop,
                reference.t_final_s,
                reference.counts.steps
            ));
        }
    }
    assert!(
        mismatches.is_empty(),
        "{} of {n} checkpoints resume differently:\n{}",
        mismatches.len(),
        mismatches[..mismatches.len().min(5)].join("\n")
    );
    // The run stopped in the iteration after the last checkpoint: that checkpoint is what a
    // kill right after the stop condition leaves behind, and it was tried above.
    assert_eq!(whole.checkpoints[n - 1].1.loop_index + 1, whole.final_loop);
}

#[test]
fn resuming_after_max_events_stop_is_identical_from_every_checkpoint() {
    for stepping in ["adaptive", "fixed"] {
        let scene = rigid(&[
            "drive.velocity=0.1",
            "time.max_events=2",
            "time.dt=2e-8",
            &format!("time.stepping={stepping}"),
        ]);
        resumes_identically_from_every_checkpoint(&scene, StopReason::MaxEvents);
    }
}

#[test]
fn resuming_after_an_open_event_stop_is_identical_from_every_checkpoint() {
    // At 10 m/s the film melts 54 ns after the start and never recovers.
    let scene = rigid(&[
        "drive.velocity=10.0",
        "time.max_open_event=2e-7",
        "time.dt=2e-9",
        "time.stepping=fixed",
    ]);
    resumes_identically_from_every_checkpoint(&scene, StopReason::OpenEvent);
}
