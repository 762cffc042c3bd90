//! `stickslip check`: prints the resolved scene, derived and stability numbers, quasi-static
//! estimates, the cost estimate and the warnings, all from the run library's check report.

use std::process::ExitCode;
use stickslip_core::preflight::Severity;
use stickslip_run::ResolvedScene;
use stickslip_run::check::show;
use stickslip_run::exit::Exit;

/// Prints the check of `scene`; exit 0 (2 if the engine rejects it). A configuration that
/// `run` would refuse is valid here: the refusal is printed among the warnings.
pub fn print(scene: &ResolvedScene) -> ExitCode {
    let report = match stickslip_run::check::check(scene) {
        Ok(r) => r,
        Err(e) => return crate::fail(e, Exit::BadInput),
    };
    let p = &report.preflight;
    let d = &p.derived;
    let c = &scene.config;
    say!("# resolved scene (defaults filled in)");
    say_raw!("{}", scene.resolved.to_toml_string());
    say!();
    say!("# derived parameters");
    say!("b = {:e} Pa", d.b_pa);
    say!("A = {:e} Pa", d.a_coeff_pa);
    say!("eps_c = {}", d.eps_c);
    say!("phi0 = {}", d.phi0);
    if let Some(f) = &p.first_order {
        say!(
            "cubic = {:e} Pa (b3: first-order film; docs/model.md#the-first-order-film)",
            f.cubic_pa
        );
        say!(
            "eps_melt = {} (eps+: the solid branch ends, the film melts, phi drops from b3/(2b) = \
             {} to 0)",
            f.eps_melt,
            f.phi_melt
        );
        if f.eps_solidify > 0.0 {
            say!(
                "eps_solidify = {} (eps- = eps_c: a liquid film re-solidifies, phi jumps to b3/b = {})",
                f.eps_solidify,
                f.phi_solidify
            );
        } else {
            say!(
                "eps_solidify = 0 (A <= 0: the liquid is stable at every strain, a melted film never \
                 re-solidifies without noise)"
            );
        }
        say!(
            "hysteresis_width = {} (eps+^2 - eps-^2; b3^2/(4ab) = {} while A > 0, at any \
             temperature)",
            f.hysteresis_width,
            c.lubricant.hysteresis_width()
        );
        say!(
            "tau_melt = {:e} Pa (tau on the solid branch at eps+)",
            f.tau_melt_pa
        );
        if let Some(metastable) = f.metastable_solid {
            if metastable {
                say!(
                    "metastable_solid = true (A <= 0, but b3^2 >= -4b*A*b/a: the film starts \
                     solid at phi0, melts once at eps+ and does not re-solidify without noise)"
                );
            } else {
                say!(
                    "metastable_solid = false (A <= 0 and b3^2 < -4b*A*b/a: the film is liquid \
                     from the start, F = 0)"
                );
            }
        }
    }
    say!("omega = {} rad/s", d.omega_rad_per_s);
    if let stickslip_core::drive::Drive::Spring(spring) = &c.drive {
        say!(
            "damping_ratio = {} (zeta = c_d/(2*sqrt(K*m)) of drive.damping = {:e} N*s/m; 0: the \
             paper's undamped spring, 1: critical)",
            spring.damping_ratio(),
            spring.damping_n_s_per_m
        );
    }
    if let Some(v) = &p.viscous {
        say!(
            "viscous_drag = {:e} N*s/m (c_v = eta*pi*a0^2/h0 of lubricant.viscosity = {:e} Pa*s: \
             a liquid film's force per stamp velocity on a rigid substrate; docs/model.md#viscosity)",
            v.drag_n_s_per_m,
            v.viscosity_pa_s
        );
        say!(
            "viscous_time = {:e} s (eta*a0/(h0*G*): the substrate relaxes through the viscous film \
             on this scale; 0 on a rigid substrate)",
            v.time_s
        );
    }
    say!("g_eff = {:e} Pa", c.contact.g_eff_pa);
    say!("nodes = {}", c.simulated_nodes());
    if c.time.adaptive.is_some() {
        say!(
            "steps = {} (time.end/time.dt: what fixed steps of time.dt would take; adaptive \
             steps follow time.tolerance instead: see steps_estimate below)",
            scene.steps
        );
    } else {
        say!("steps = {} (time.end/time.dt)", scene.steps);
    }
    say!(
        "lagged_sweep_contraction = {:.4} (rho of the paper's lagged elastic sweep at t = 0; \
         the literal scheme needs < 1)",
        p.lagged_sweep_contraction
    );
    if let Some(e) = p.euler_number {
        if p.first_order.is_some() {
            say!(
                "euler_number = {e} (literal scheme: dt*gamma*phi0*(2*b*phi0 - b3), stable below 2)"
            );
        } else {
            say!("euler_number = {e} (literal scheme: gamma*dt*2*A*b/a, stable below 2)");
        }
    }
    say!();
    say!("# plausibility");
    if p.first_order.is_some() {
        say!(
            "melting_force = {:e} N (peak of the first-order film's stationary stress curve \
             *pi*a0^2: the largest friction force the film carries)",
            p.melting_force_n
        );
    } else {
        say!(
            "melting_force = {:e} N (tau_max*pi*a0^2: the largest friction force the film carries)",
            p.melting_force_n
        );
    }
    say!(
        "critical_displacement = {:e} m ({}*h0: stamp advance to the first melting)",
        p.critical_displacement_m,
        if p.first_order.is_some() {
            "eps_melt"
        } else {
            "eps_c"
        }
    );
    if let Some(period) = p.spring_period_s {
        say!(
            "spring_period = {period:e} s (2*pi/omega; time.end = {:e} s is {:.3} of it)",
            c.time.end_s,
            c.time.end_s / period
        );
    }
    if p.stamp_travel_m.is_finite() {
        say!(
            "stamp_travel = {:e} m (free stamp at time.end, no friction)",
            p.stamp_travel_m
        );
    } else {
        // Only a damping or speed at the edge of the doubles gets here (a dashpot of 1e308
        // N·s/m overflows the free motion's exponentials): say which input, not NaN.
        say!(
            "stamp_travel: not computable (the free stamp's motion overflows with drive.damping \
             = {} N·s/m and drive.velocity = {} m/s; a dashpot far beyond a critical damping \
             of 2*sqrt(K*m) is a likely slip)",
            stickslip_run::keys::human(match &c.drive {
                stickslip_core::drive::Drive::Spring(s) => s.damping_n_s_per_m,
                stickslip_core::drive::Drive::Rigid(_) => 0.0,
            }),
            stickslip_run::keys::human(c.drive.velocity_m_per_s())
        );
    }
    match (p.first_onset_estimate_s, p.contact_spring) {
        (Some(t), Some(k)) if t > 0.0 => say!(
            "first_onset_estimate = {t:e} s (the stamp on its drive against the contact as a \
             spring of {:.4e} N/m; the first node melts at X = {:.4e} m, F = {:.4e} N, where \
             the contact's static problem, each node's film on its equilibrium branch in series \
             with the substrate, loses its solution; later at high speed, where the film lags)",
            k.stiffness_n_per_m(),
            k.x_melt_m,
            k.f_melt_n
        ),
        (Some(t), _) => say!(
            "first_onset_estimate = {t:e} s (quasi-static: the free stamp reaches {}*h0; \
             later at high speed)",
            if p.first_order.is_some() {
                "eps_melt"
            } else {
                "eps_c"
            }
        ),
        (None, _) => {
            say!("first_onset_estimate = none (the drive never reaches the melting strain)")
        }
    }
    let r = &report.resolution;
    say!();
    say!("# resolution (the first event at N and 2N)");
    match (r.relative_change, &r.skipped) {
        (Some(c), _) => say!(
            "first event at N = {} and {}: onsets {} and {} s, peak forces {} and {} N; change \
             {:.2} %",
            r.nodes[0],
            r.nodes[1],
            show(r.first_onset_s[0]),
            show(r.first_onset_s[1]),
            show(r.f_peak_first_n[0]),
            show(r.f_peak_first_n[1]),
            100.0 * c
        ),
        (None, Some(why)) => say!("not compared: {why}"),
        (None, None) => say!("not compared"),
    }
    if let Some(e) = &report.edge {
        say!();
        say!("# edge layer (where the first melting starts)");
        say!(
            "rho = {:.4} (the substrate's share of the compliance, pi*a0*a*phi0^2/(2*G*h0)), \
             width = {:.4e} m (a0/(8*rho^2)), outermost node {:.4e} m from the edge ({:.3} widths); \
             N needed on this grid: {:.0} (graded: {:.0})",
            e.rho,
            e.width_m,
            e.outermost_gap_m,
            e.outermost_gap_m / e.width_m,
            e.nodes_needed,
            e.nodes_needed_graded
        );
    }
    let cost = &report.cost;
    say!();
    say!("# cost estimate");
    say!(
        "seconds_per_step = {:.3e} s (measured on {} steps of this scene)",
        cost.seconds_per_step,
        cost.probe_steps
    );
    say!("steps_estimate = {:.0} ({})", cost.steps, cost.basis);
    match cost.seconds {
        Some(s) => say!("seconds_estimate = {s:.3} s"),
        None => say!(
            "seconds_estimate = unknown (the first steps' pace alone implies {:.3e} s)",
            cost.probe_pace_seconds
        ),
    }
    let out = &report.output;
    say!();
    say!("# output (expected)");
    say!(
        "series_rows = {:.0}{} (series.csv{}), profile_rows = {:.0} (profiles.csv), bytes = \
         {:.3e} ({:.1} MB)",
        out.series_rows,
        if out.series_rows_max > 1.5 * out.series_rows_min {
            format!(
                " (between {:.0}, a row per step at the first steps' pace, and {:.0}, a row \
                 per step: a melting's steps cluster and share the interval's marks)",
                out.series_rows_min, out.series_rows_max
            )
        } else {
            String::new()
        },
        if out.probes > 0 {
            format!(" and probes.csv, {} probes", out.probes)
        } else {
            ", no probes.csv".to_string()
        },
        out.profile_rows,
        out.bytes,
        out.bytes / 1e6
    );
    if !report.warnings.is_empty() {
        say!();
        say!("# warnings");
        for f in &report.warnings {
            let tag = match f.severity {
                Severity::Note => "note",
                Severity::Warning => "warning",
                Severity::Refusal => "refused",
            };
            say!("{tag}: {} ({})", f.message, f.key);
        }
    }
    // The warnings are part of the report on stdout; printing them again on stderr (as `run`
    // does) showed each one twice.
    ExitCode::SUCCESS
}
