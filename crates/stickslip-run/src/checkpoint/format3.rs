//! Format 3 of the checkpoint's payload: its own types, mapped field by field to and from the
//! state they save. The mappings destructure every state type exhaustively, so a field added
//! to one does not compile until it is saved here (a change of the layout is a new format, its
//! own module and a new number in the header); no field has a default, so a file that lacks
//! one is refused.

use super::{Checkpoint, StreamPositions};
use crate::driver::DriverState;
use crate::scene::ResolvedScene;
use crate::schema::run_info::BuildCrossing;
use serde::{Deserialize, Serialize};
use std::borrow::Cow;
use stickslip_core::drive::DriveState;
use stickslip_core::noise::NoiseState;
use stickslip_core::preflight::Preflight;
use stickslip_core::sim::events::EventTracker;
use stickslip_core::sim::{
    ControllerMemory, EventBook, PhysicalState, SimState, StepCounters, StepperMemory,
};

/// The whole payload.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Payload<'a> {
    build: Cow<'a, str>,
    checkpoint_every_s: f64,
    scene: Cow<'a, ResolvedScene>,
    preflight: Cow<'a, Preflight>,
    driver: Cow<'a, DriverState>,
    sim: Sim,
    streams: StreamPositions,
    resumed_across_builds: Cow<'a, [BuildCrossing]>,
}

/// [`SimState`].
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Sim {
    physical: Physical,
    stepper: Stepper,
    controller: Controller,
    counters: Counters,
    events: Events,
}

/// [`PhysicalState`], the stamp's kinematics and the noise generators' positions spelt out.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Physical {
    t_s: f64,
    x_m: f64,
    v_m_per_s: f64,
    phi: Vec<f64>,
    u0_m: Vec<f64>,
    u3d_m: Vec<f64>,
    eps: Vec<f64>,
    tau_pa: Vec<f64>,
    force_n: f64,
    noise_seed: u64,
    noise_word_pos: Vec<u64>,
}

/// [`StepperMemory`].
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Stepper {
    u3d_prev_m: Vec<f64>,
    u3d_prev2_m: Vec<f64>,
    last_dt_s: f64,
    prev_dt_s: f64,
    accel_change_prev_m_per_s2: f64,
    /// +0 without viscosity, and then not written: such a checkpoint's bytes are as before the
    /// field existed (−0 is written, to keep its bit).
    #[serde(default, skip_serializing_if = "is_positive_zero")]
    mean_v_m_per_s: f64,
    /// As `mean_v_m_per_s`.
    #[serde(default, skip_serializing_if = "is_positive_zero")]
    viscous_v_m_per_s: f64,
    /// Empty without viscosity, and then not written.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    viscous_rate_prev_m_per_s: Vec<f64>,
}

#[allow(clippy::trivially_copy_pass_by_ref)] // serde's skip_serializing_if passes a reference
fn is_positive_zero(v: &f64) -> bool {
    v.to_bits() == 0
}

/// [`ControllerMemory`].
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Controller {
    next_dt_s: f64,
    err_prev: f64,
    rejected_last: bool,
}

/// [`StepCounters`].
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Counters {
    step: u64,
    accepted_steps: u64,
    rejected_steps: u64,
    forced_steps: u64,
    onset_retakes: u64,
    coupling_iterations: u64,
}

/// [`EventBook`]; the tracker, whose fields are its own, in its serde form.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Events {
    tracker: EventTracker,
    melted_in_step: Vec<bool>,
    last_melt_s: Vec<f64>,
    swept: Vec<bool>,
}

impl<'a> From<&'a Checkpoint<'_>> for Payload<'a> {
    fn from(c: &'a Checkpoint<'_>) -> Self {
        Self {
            build: Cow::Borrowed(&c.build),
            checkpoint_every_s: c.checkpoint_every_s,
            scene: Cow::Borrowed(&c.scene),
            preflight: Cow::Borrowed(&c.preflight),
            driver: Cow::Borrowed(&c.driver),
            sim: Sim::from(&*c.sim),
            streams: c.streams,
            resumed_across_builds: Cow::Borrowed(&c.resumed_across_builds),
        }
    }
}

impl From<Payload<'static>> for Checkpoint<'static> {
    fn from(p: Payload<'static>) -> Self {
        let Payload {
            build,
            checkpoint_every_s,
            scene,
            preflight,
            driver,
            sim,
            streams,
            resumed_across_builds,
        } = p;
        Self {
            build,
            checkpoint_every_s,
            scene,
            preflight,
            driver,
            sim: Cow::Owned(SimState::from(sim)),
            streams,
            resumed_across_builds,
        }
    }
}

impl From<&SimState> for Sim {
    fn from(s: &SimState) -> Self {
        let SimState {
            physical:
                PhysicalState {
                    drive:
                        DriveState {
                            t_s,
                            x_m,
                            v_m_per_s,
                        },
                    phi,
                    u0_m,
                    u3d_m,
                    eps,
                    tau_pa,
                    force_n,
                    noise: NoiseState { seed, word_pos },
                },
            stepper:
                StepperMemory {
                    u3d_prev_m,
                    u3d_prev2_m,
                    last_dt_s,
                    prev_dt_s,
                    accel_change_prev_m_per_s2,
                    mean_v_m_per_s,
                    viscous_v_m_per_s,
                    viscous_rate_prev_m_per_s,
                },
            controller:
                ControllerMemory {
                    next_dt_s,
                    err_prev,
                    rejected_last,
                },
            counters:
                StepCounters {
                    step,
                    accepted_steps,
                    rejected_steps,
                    forced_steps,
                    onset_retakes,
                    coupling_iterations,
                },
            events:
                EventBook {
                    tracker,
                    melted_in_step,
                    last_melt_s,
                    swept,
                },
        } = s;
        Self {
            physical: Physical {
                t_s: *t_s,
                x_m: *x_m,
                v_m_per_s: *v_m_per_s,
                phi: phi.clone(),
                u0_m: u0_m.clone(),
                u3d_m: u3d_m.clone(),
                eps: eps.clone(),
                tau_pa: tau_pa.clone(),
                force_n: *force_n,
                noise_seed: *seed,
                noise_word_pos: word_pos.clone(),
            },
            stepper: Stepper {
                u3d_prev_m: u3d_prev_m.clone(),
                u3d_prev2_m: u3d_prev2_m.clone(),
                last_dt_s: *last_dt_s,
                prev_dt_s: *prev_dt_s,
                accel_change_prev_m_per_s2: *accel_change_prev_m_per_s2,
                mean_v_m_per_s: *mean_v_m_per_s,
                viscous_v_m_per_s: *viscous_v_m_per_s,
                viscous_rate_prev_m_per_s: viscous_rate_prev_m_per_s.clone(),
            },
            controller: Controller {
                next_dt_s: *next_dt_s,
                err_prev: *err_prev,
                rejected_last: *rejected_last,
            },
            counters: Counters {
                step: *step,
                accepted_steps: *accepted_steps,
                rejected_steps: *rejected_steps,
                forced_steps: *forced_steps,
                onset_retakes: *onset_retakes,
                coupling_iterations: *coupling_iterations,
            },
            events: Events {
                tracker: tracker.clone(),
                melted_in_step: melted_in_step.clone(),
                last_melt_s: last_melt_s.clone(),
                swept: swept.clone(),
            },
        }
    }
}

impl From<Sim> for SimState {
    fn from(s: Sim) -> Self {
        let Sim {
            physical: p,
            stepper: st,
            controller: c,
            counters: n,
            events: e,
        } = s;
        Self {
            physical: PhysicalState {
                drive: DriveState {
                    t_s: p.t_s,
                    x_m: p.x_m,
                    v_m_per_s: p.v_m_per_s,
                },
                phi: p.phi,
                u0_m: p.u0_m,
                u3d_m: p.u3d_m,
                eps: p.eps,
                tau_pa: p.tau_pa,
                force_n: p.force_n,
                noise: NoiseState {
                    seed: p.noise_seed,
                    word_pos: p.noise_word_pos,
                },
            },
            stepper: StepperMemory {
                u3d_prev_m: st.u3d_prev_m,
                u3d_prev2_m: st.u3d_prev2_m,
                last_dt_s: st.last_dt_s,
                prev_dt_s: st.prev_dt_s,
                accel_change_prev_m_per_s2: st.accel_change_prev_m_per_s2,
                mean_v_m_per_s: st.mean_v_m_per_s,
                viscous_v_m_per_s: st.viscous_v_m_per_s,
                viscous_rate_prev_m_per_s: st.viscous_rate_prev_m_per_s,
            },
            controller: ControllerMemory {
                next_dt_s: c.next_dt_s,
                err_prev: c.err_prev,
                rejected_last: c.rejected_last,
            },
            counters: StepCounters {
                step: n.step,
                accepted_steps: n.accepted_steps,
                rejected_steps: n.rejected_steps,
                forced_steps: n.forced_steps,
                onset_retakes: n.onset_retakes,
                coupling_iterations: n.coupling_iterations,
            },
            events: EventBook {
                tracker: e.tracker,
                melted_in_step: e.melted_in_step,
                last_melt_s: e.last_melt_s,
                swept: e.swept,
            },
        }
    }
}
