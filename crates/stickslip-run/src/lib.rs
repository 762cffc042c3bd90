//! stickslip-run: the one path from a scene to results.
//!
//! - [`scene`] and [`keys`]: scene files, `--set` overrides, defaults and validation from the
//!   key table, resolved into the core's typed configuration ([`scene::ResolvedScene`]);
//! - [`driver`]: the one time loop (fixed or adaptive steps; stop at `time.end`, after
//!   `time.max_events` events, at a failure or an interrupt) feeding a [`driver::Sink`];
//! - [`sink`]: results in memory ([`sink::memory::MemorySink`]) or in an output directory
//!   ([`sink::dir`]: atomic files, run.json status from the start, checkpoints, resume;
//!   [`sink::read`]: an output directory read back, ended, interrupted or killed);
//! - [`schema`]: one type per output file, writer and reader together;
//! - [`outcome`] and [`summary`]: what a run hands back, and its summary and regime
//!   (docs/model.md#regimes-and-friction-maps);
//! - [`check`]: what `stickslip check` reports (preflight, plausibility, a timed probe);
//! - [`atomic`] and [`checkpoint`]: the one atomic writer, the checkpoint file;
//! - [`build_id`]: the build identity of the numerics, which checkpoints (and the studies'
//!   records) carry;
//! - [`exit`]: the kinds of ending, as the command line's exit statuses.
//!
//! One run only: many runs asking one question (maps, boundaries, verify, fits) are the
//! studies crate above this one.
//!
//! Invariant: no command-line or terminal code here (no clap, no progress bars); errors say
//! which kind of ending they are as an [`exit::Exit`], the command line turns that into the
//! process's status; the physics comes from `stickslip-core`.

pub mod atomic;
pub mod bounded;
pub mod build_id;
pub mod check;
pub mod checkpoint;
pub mod cycles;
pub mod driver;
pub mod edge_layer;
pub mod exit;
pub mod keys;
pub mod layout;
pub mod outcome;
pub mod output_size;
pub mod scene;
pub mod schema;
pub mod sink;
pub mod slips;
pub mod stats;
pub mod steady;
pub mod summary;

pub use driver::{Control, Driver, Limit, NullSink, Sink, StepPlan, run};
pub use outcome::{RunOutcome, RunStatus, StopReason};
pub use scene::{ResolvedScene, Scene, SceneError};
pub use schema::RunOutput;
pub use sink::dir::{DirOptions, ResumeOptions, RunError, resume, run_to_dir};
pub use sink::memory::MemorySink;
pub use sink::read::read_run;

/// Runs `scene` in memory and returns everything it produced.
///
/// # Errors
/// [`driver::StartError`] when the run cannot start.
///
/// # Example
/// ```
/// use stickslip_run::{Control, Scene, StopReason, run_in_memory};
/// const SCENE: &str = r#"
/// name = "example"
/// [lubricant]
/// tau_max = 1e6
/// eps_max = 1
/// a = 1e6
/// gamma = 10
/// [contact]
/// radius = 2e-5
/// film_thickness = 1e-7
/// g_eff = 1e9
/// nodes = 20
/// [drive]
/// stiffness = 500
/// mass = 0.1
/// velocity = 1
/// [time]
/// end = 2e-4
/// [output]
/// profile_times = []
/// "#;
/// let scene = Scene::from_toml_str(SCENE, &[] as &[&str]).unwrap();
/// let (outcome, output) = run_in_memory(&scene, &mut Control::default()).unwrap();
/// assert_eq!(outcome.stop, StopReason::End);
/// // The series, as series.csv would hold it: the last row at time.end.
/// let t_s = &output.series.t_s;
/// assert!((t_s[t_s.len() - 1] - 2e-4).abs() < 1e-12);
/// ```
pub fn run_in_memory(
    scene: &ResolvedScene,
    control: &mut Control<'_>,
) -> Result<(RunOutcome, RunOutput), driver::StartError> {
    let mut sink = MemorySink::new();
    let outcome = run(scene, &mut sink, control)?;
    let output = sink.into_output().ok_or(driver::StartError::NeverBegan)?;
    Ok((outcome, output))
}
