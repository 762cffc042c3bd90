//! V3: what the film's viscous stress and the drive's dashpot cost on the h0 = 1 nm contact
//! (`sfa.toml` as shipped: K = 5000 N/m, 0 → 0.11 s, two meltings), each against the same
//! scene without it. The effects change the physics (a viscous film melts over milliseconds
//! instead of microseconds), so the rows give the event counts beside the ratios, and the cost
//! of the approach to the first melting apart from the whole run.

use super::targets::verdict;
use super::{BenchSettings, Timed, timed_scene};
use serde::Serialize;
use std::fmt::Write as _;
use stickslip_report::fmt::{sig, tick};
use stickslip_run::Scene;
use stickslip_run::keys::{drive, lubricant, output, time};

/// The goal: each effect at most this times the scene without it.
pub const V3_RATIO_GOAL: f64 = 1.5;
/// The film's viscosity of the viscous run, Pa·s (the viscous map's middle).
pub const VISCOSITY_PA_S: f64 = 10.0;
/// The dashpot's damping ratio of the damped run.
pub const DAMPING_RATIO: f64 = 0.5;
/// The approach runs stop here, s: before the first melting of all three (about 0.102 s with
/// the dashpot, 0.107 s without).
pub const APPROACH_END_S: f64 = 0.1;

/// One effect against the scene without it.
#[derive(Debug, Clone, Default, Serialize)]
pub struct EffectCost {
    /// The whole run with the effect.
    pub run: Timed,
    /// The approach (to [`APPROACH_END_S`]) with the effect.
    pub approach: Timed,
    /// The key and value that switch it on (`--set` text).
    pub setting: String,
}

/// V3's measurements.
#[derive(Debug, Clone, Default, Serialize)]
pub struct EffectsBench {
    /// The scene without either effect, whole run.
    pub base: Timed,
    /// The same, approach only.
    pub base_approach: Timed,
    /// `lubricant.viscosity` = [`VISCOSITY_PA_S`].
    pub viscous: EffectCost,
    /// `drive.damping` at ζ = [`DAMPING_RATIO`].
    pub damped: EffectCost,
}

impl EffectsBench {
    /// Whole-run wall-time ratios (viscous, damped) over the base.
    #[must_use]
    pub fn ratios(&self) -> (f64, f64) {
        let base = self.base.wall_s;
        (
            self.viscous.run.wall_s / base,
            self.damped.run.wall_s / base,
        )
    }

    /// Whether both effects are within [`V3_RATIO_GOAL`].
    #[must_use]
    pub fn met(&self) -> bool {
        let (v, d) = self.ratios();
        v <= V3_RATIO_GOAL && d <= V3_RATIO_GOAL
    }
}

/// Runs V3.
///
/// # Errors
/// A scene that does not resolve, or a run that failed.
pub fn measure(s: &BenchSettings, progress: &dyn Fn(&str)) -> Result<EffectsBench, String> {
    let scene = s.scene.with_file_name("sfa.toml");
    let resolved = Scene::from_path(&scene, &[] as &[String])
        .map_err(|e| format!("{}: {e}", scene.display()))?;
    let (k, m) = match resolved.config.drive {
        stickslip_core::drive::Drive::Spring(sp) => (sp.stiffness_n_per_m, sp.mass_kg),
        stickslip_core::drive::Drive::Rigid(_) => {
            return Err("V3: sfa.toml's drive is not a spring".into());
        }
    };
    let damping = 2.0 * DAMPING_RATIO * (k * m).sqrt();
    let small = [output::PROFILE_TIMES.set(Vec::<f64>::new()).to_string()];
    let repeats = s.repeats.min(3);
    let run = |tag: &str, extra: &[String], approach: bool| {
        let mut sets: Vec<String> = small.to_vec();
        sets.extend_from_slice(extra);
        if approach {
            sets.push(time::END.set(APPROACH_END_S).to_string());
        }
        timed_scene(s, &scene, tag, &sets, 2, repeats, &[])
    };
    progress("V3: the h0 = 1 nm contact with a viscous film and with a dashpot");
    // The whole run and the approach with one effect switched on by `setting`.
    let effect = |name: &str, setting: String| -> Result<EffectCost, String> {
        let extra = std::slice::from_ref(&setting);
        Ok(EffectCost {
            run: run(&format!("v3_{name}"), extra, false)?,
            approach: run(&format!("v3_{name}_approach"), extra, true)?,
            setting,
        })
    };
    Ok(EffectsBench {
        base: run("v3_base", &[], false)?,
        base_approach: run("v3_base_approach", &[], true)?,
        viscous: effect(
            "viscous",
            lubricant::VISCOSITY.set(VISCOSITY_PA_S).to_string(),
        )?,
        damped: effect("damped", drive::DAMPING.set(damping).to_string())?,
    })
}

/// The V3 row of the targets table.
pub(super) fn targets_row(m: &mut String, b: &EffectsBench) {
    let (v, d) = b.ratios();
    let part = |name: &str, e: &EffectCost, ratio: f64| {
        format!(
            "{name} {}× ({} s, {} evaluations, {} meltings; to {} s: {}×)",
            sig(ratio, 3),
            sig(e.run.wall_s, 3),
            e.run.evaluations(),
            e.run.events,
            APPROACH_END_S,
            sig(e.approach.wall_s / b.base_approach.wall_s, 3),
        )
    };
    let _ = writeln!(
        m,
        "| V3 the h0 = 1 nm contact (sfa.toml, 0 → 0.11 s) with a viscous film (η = {} Pa·s) and \
         with a dashpot (ζ = {}), each against neither (whole process) | each ≤ {}× | {}; {}; \
         neither: {} s, {} evaluations, {} meltings | {} |",
        VISCOSITY_PA_S,
        DAMPING_RATIO,
        tick(V3_RATIO_GOAL),
        part("viscous", &b.viscous, v),
        part("damped", &b.damped, d),
        sig(b.base.wall_s, 3),
        b.base.evaluations(),
        b.base.events,
        verdict(b.met()),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_row_gives_each_ratio_and_its_verdict() {
        let b = EffectsBench {
            base: Timed::of(0.2, 1000, 2),
            base_approach: Timed::of(0.1, 500, 0),
            viscous: EffectCost {
                run: Timed::of(1.0, 9000, 1),
                approach: Timed::of(0.11, 520, 0),
                setting: "lubricant.viscosity=10".into(),
            },
            damped: EffectCost {
                run: Timed::of(0.25, 1200, 4),
                approach: Timed::of(0.09, 450, 0),
                setting: "drive.damping=22.36".into(),
            },
        };
        assert_eq!(b.ratios(), (5.0, 1.25));
        assert!(!b.met());
        let mut m = String::new();
        targets_row(&mut m, &b);
        assert!(
            m.contains("viscous 5.00× (1.00 s, 9000 evaluations, 1 meltings; to 0.1 s: 1.10×)"),
            "{m}"
        );
        assert!(m.contains("damped 1.25× (0.250 s"), "{m}");
        assert!(
            m.contains("(η = 10 Pa·s)") && m.contains("(ζ = 0.5)"),
            "{m}"
        );
        assert!(m.contains("**not met**"), "{m}");
    }
}
