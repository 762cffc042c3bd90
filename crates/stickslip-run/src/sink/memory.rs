//! A sink that keeps a run's output in memory, as the same types that read the files.

use crate::driver::{RunStart, Sink, Snapshot};
use crate::outcome::RunOutcome;
use crate::schema::RunOutput;
use crate::schema::events::Events;
use crate::schema::probes::Probes;
use crate::schema::profiles::Profiles;
use crate::schema::run_info::RunInfo;
use crate::schema::series::Series;
use crate::schema::slips::Slips;
use std::io;
use stickslip_core::sim::{Observables, SimState};

/// Keeps series, events, profiles, probes and run.json's contents in memory.
#[derive(Debug, Clone, Default)]
pub struct MemorySink {
    series: Series,
    probes: Probes,
    profiles: Profiles,
    events: Events,
    slips: Slips,
    info: Option<RunInfo>,
}

impl MemorySink {
    /// An empty sink.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Everything recorded, as [`RunOutput`]; `None` if the run never began.
    #[must_use]
    pub fn into_output(self) -> Option<RunOutput> {
        Some(RunOutput {
            info: self.info?,
            series: self.series,
            events: self.events,
            slips: self.slips,
            profiles: self.profiles,
            probes: self.probes,
        })
    }
}

impl Sink for MemorySink {
    fn begin(&mut self, start: &RunStart<'_>) -> io::Result<()> {
        self.probes = Probes::new(&start.scene.output.probe_radii_m);
        self.info = Some(RunInfo::starting(
            start.scene,
            start.preflight,
            start.warnings.to_vec(),
        ));
        Ok(())
    }

    fn series_row(&mut self, observables: &Observables, probes: &[f64]) -> io::Result<()> {
        self.series.push(observables);
        self.probes.push(probes);
        Ok(())
    }

    fn profile(&mut self, t_s: f64, radii_m: &[f64], state: &SimState) -> io::Result<()> {
        self.profiles.push(t_s, radii_m, state);
        Ok(())
    }

    fn end(&mut self, outcome: &RunOutcome, _snapshot: &Snapshot<'_>) -> io::Result<()> {
        self.events = Events(outcome.events.clone());
        self.slips = Slips(outcome.slips.clone());
        if let Some(info) = &mut self.info {
            info.finish(outcome);
        }
        Ok(())
    }
}
