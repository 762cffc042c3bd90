//! The stamp's half steps around the film's: the first half before the film step (giving the
//! stamp's advance), the second after the coupling solve with the new friction force. The split
//! integrator's flow carries the friction force linearised at the step's start,
//! F0 + k·(X − X0) with k the contact as a spring ([`crate::drive::SpringDrive::loaded_flow`]),
//! so its closing kick carries only F's departure from that; Verlet and RK4 kick with F (or,
//! with viscosity, with its part outside the drag the drive takes as a dashpot).

use super::Simulation;
use crate::drive::{Drive, Integrator};

impl Simulation {
    pub(super) fn drive_first_half(&mut self, dt_s: f64) -> f64 {
        let x0 = self.state.physical.drive.x_m;
        if let Some(v) = &self.viscous {
            let f = self.kick_force_n();
            let drag = v.flow_drag_n_s_per_m;
            self.viscous_drive_half(dt_s, f, drag, true);
            return self.state.physical.drive.x_m - x0;
        }
        let f = self.state.physical.force_n;
        let k = self.flow_stiffness_n_per_m;
        match (&self.config.drive, self.config.integrator) {
            (Drive::Spring(s), Integrator::Verlet) => {
                s.half_kick(&mut self.state.physical.drive, f, dt_s);
                s.drift(&mut self.state.physical.drive, dt_s);
            }
            (Drive::Spring(s), Integrator::Split) if k > 0.0 => {
                self.flow_anchor =
                    s.loaded_split_open(&mut self.state.physical.drive, dt_s, k, 0.0, f);
            }
            (Drive::Spring(s), Integrator::Split) => {
                s.friction_half_kick(&mut self.state.physical.drive, f, dt_s);
                s.spring_flow(&mut self.state.physical.drive, dt_s);
            }
            (d, integrator) => d.step(integrator, &mut self.state.physical.drive, dt_s, f),
        }
        self.state.physical.drive.x_m - x0
    }

    pub(super) fn drive_second_half(&mut self, dt_s: f64) {
        if let Some(v) = &self.viscous {
            let f = self.kick_force_n();
            let drag = v.flow_drag_n_s_per_m;
            self.viscous_drive_half(dt_s, f, drag, false);
            return;
        }
        match (&self.config.drive, self.config.integrator) {
            (Drive::Spring(s), Integrator::Verlet) => {
                s.closing_half_kick(
                    &mut self.state.physical.drive,
                    self.state.physical.force_n,
                    dt_s,
                );
            }
            (Drive::Spring(s), Integrator::Split) => {
                let f = self.state.physical.force_n;
                if self.flow_stiffness_n_per_m > 0.0 {
                    s.loaded_split_close(
                        &mut self.state.physical.drive,
                        dt_s,
                        &self.flow_anchor,
                        f,
                    );
                } else {
                    s.friction_half_kick(&mut self.state.physical.drive, f, dt_s);
                }
            }
            _ => {}
        }
    }

    /// A half of the stamp's step (the first when `first`) with the part c = `drag` of the
    /// film's viscous drag that the flow takes, the kicks carrying `kick_n` = F − c·Ẋ (Ẋ of the
    /// viscous stress; docs/model.md#viscosity): split, the drag inside the spring's exact
    /// flow; Verlet and RK4, the drag as a dashpot on the absolute velocity,
    /// −c·Ẋ = c·(V0 − Ẋ) − c·V0 (Verlet's closing kick implicit in it); the rigid drive as
    /// without viscosity.
    fn viscous_drive_half(&mut self, dt_s: f64, kick_n: f64, drag: f64, first: bool) {
        let state = &mut self.state.physical.drive;
        match (&self.config.drive, self.config.integrator) {
            (Drive::Spring(s), Integrator::Split) => {
                let k = self.flow_stiffness_n_per_m;
                if first && k > 0.0 {
                    // As without viscosity: the flow carries the kick force linearised at the
                    // step's start, and the opening kick is 0.
                    self.flow_anchor = s.loaded_split_open(state, dt_s, k, drag, kick_n);
                } else if first {
                    s.friction_half_kick(state, kick_n, dt_s);
                    s.spring_flow_with_drag(state, dt_s, drag);
                } else if k > 0.0 {
                    s.loaded_split_close(state, dt_s, &self.flow_anchor, kick_n);
                } else {
                    s.friction_half_kick(state, kick_n, dt_s);
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
}
