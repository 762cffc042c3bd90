//! The stamp's half steps around the film's: the first half before the film step (giving the
//! stamp's advance), the second after the coupling solve with the new friction force. The split
//! integrator's flow carries the friction force linearised at the step's start,
//! F0 + k·(X − X0) with k the contact as a spring ([`crate::drive::SpringDrive::loaded_flow`]),
//! so its closing kick carries only F's departure from that; Verlet and RK4 kick with F (or,
//! with viscosity, with its part outside the drag the drive takes as a dashpot).

use super::problem::Problem;
use crate::drive::{Drive, DriveState, FlowAnchor, Integrator};

/// The opening half of the stamp's step of `dt_s` with the kick force `kick_n` (F; with
/// viscosity, F less the drag `viscous_drag` the flow takes): the stamp's advance, m, and where
/// the split flow linearised the kick force (the closing half's anchor).
pub(super) fn open(
    problem: &Problem,
    drive: &mut DriveState,
    kick_n: f64,
    viscous_drag: Option<f64>,
    dt_s: f64,
) -> (f64, FlowAnchor) {
    let x0 = drive.x_m;
    let mut anchor = FlowAnchor::default();
    if let Some(drag) = viscous_drag {
        viscous_half(
            problem,
            drive,
            (dt_s, kick_n, drag),
            Half::Open(&mut anchor),
        );
        return (drive.x_m - x0, anchor);
    }
    let f = kick_n;
    let k = problem.flow_stiffness_n_per_m;
    match (&problem.config.drive, problem.config.integrator) {
        (Drive::Spring(s), Integrator::Verlet) => {
            s.half_kick(drive, f, dt_s);
            s.drift(drive, dt_s);
        }
        (Drive::Spring(s), Integrator::Split) if k > 0.0 => {
            anchor = s.loaded_split_open(drive, dt_s, k, 0.0, f);
        }
        (Drive::Spring(s), Integrator::Split) => {
            s.friction_half_kick(drive, f, dt_s);
            s.spring_flow(drive, dt_s);
        }
        (d, integrator) => d.step(integrator, drive, dt_s, f),
    }
    (drive.x_m - x0, anchor)
}

/// The closing half of the stamp's step (see [`open`]) with the kick force of the step's end.
pub(super) fn close(
    problem: &Problem,
    drive: &mut DriveState,
    kick_n: f64,
    viscous_drag: Option<f64>,
    (dt_s, anchor): (f64, &FlowAnchor),
) {
    if let Some(drag) = viscous_drag {
        viscous_half(problem, drive, (dt_s, kick_n, drag), Half::Close(anchor));
        return;
    }
    match (&problem.config.drive, problem.config.integrator) {
        (Drive::Spring(s), Integrator::Verlet) => {
            s.closing_half_kick(drive, kick_n, dt_s);
        }
        (Drive::Spring(s), Integrator::Split) => {
            if problem.flow_stiffness_n_per_m > 0.0 {
                s.loaded_split_close(drive, dt_s, anchor, kick_n);
            } else {
                s.friction_half_kick(drive, kick_n, dt_s);
            }
        }
        _ => {}
    }
}

/// Which half of the stamp's step: the opening one sets the split flow's anchor, the closing
/// one reads it.
enum Half<'a> {
    Open(&'a mut FlowAnchor),
    Close(&'a FlowAnchor),
}

/// A half of the stamp's step with the part c = `drag` of the
/// film's viscous drag that the flow takes, the kicks carrying `kick_n` = F − c·Ẋ (Ẋ of the
/// viscous stress; docs/model.md#viscosity): split, the drag inside the spring's exact
/// flow; Verlet and RK4, the drag as a dashpot on the absolute velocity,
/// −c·Ẋ = c·(V0 − Ẋ) − c·V0 (Verlet's closing kick implicit in it); the rigid drive as
/// without viscosity.
fn viscous_half(
    problem: &Problem,
    state: &mut DriveState,
    (dt_s, kick_n, drag): (f64, f64, f64),
    half: Half<'_>,
) {
    let first = matches!(half, Half::Open(_));
    match (&problem.config.drive, problem.config.integrator) {
        (Drive::Spring(s), Integrator::Split) => {
            let k = problem.flow_stiffness_n_per_m;
            match half {
                // As without viscosity: the flow carries the kick force linearised at the
                // step's start, and the opening kick is 0.
                Half::Open(anchor) if k > 0.0 => {
                    *anchor = s.loaded_split_open(state, dt_s, k, drag, kick_n);
                }
                Half::Open(_) => {
                    s.friction_half_kick(state, kick_n, dt_s);
                    s.spring_flow_with_drag(state, dt_s, drag);
                }
                Half::Close(anchor) if k > 0.0 => {
                    s.loaded_split_close(state, dt_s, anchor, kick_n);
                }
                Half::Close(_) => s.friction_half_kick(state, kick_n, dt_s),
            }
        }
        (Drive::Spring(s), Integrator::Verlet) => {
            let loaded = s.with_drag(drag);
            let f = kick_n + drag * s.velocity_m_per_s;
            if first {
                loaded.half_kick(state, f, dt_s);
                loaded.drift(state, dt_s);
            } else {
                loaded.closing_half_kick(state, f, dt_s);
            }
        }
        (Drive::Spring(s), Integrator::Rk4) => {
            if first {
                let f = kick_n + drag * s.velocity_m_per_s;
                s.with_drag(drag).rk4_step(state, dt_s, f);
            }
        }
        (d @ Drive::Rigid(_), integrator) => {
            if first {
                d.step(integrator, state, dt_s, kick_n);
            }
        }
    }
}
