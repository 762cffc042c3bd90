//! The entries of the registry, one per scene key, declared with the scene file's sections:
//! [`section!`] makes of each section's entries the serde struct of the section (a field per
//! key, documented from the entry) and a module of typed [`Key`] constants, so a key is defined
//! once. Entries whose range the engine checks take path, unit and range from the engine's
//! [`bounds`] (a compile-time check keeps the paths equal).
//!
//! The scene file as written is [`Scene`]: every key optional, unknown keys rejected
//! (`deny_unknown_fields`); which keys are required, their defaults and ranges are decided when
//! a scene is resolved (`crate::scene`), and the resolved scene is this same structure with
//! every default filled in, so it can be written to `run.json` and read back as a scene.

use super::words::{
    ContactModel, DriveKind, FilmStep, GridChoice, Integrator, NoiseKindName, OperatorChoice,
    Scheme, Stepping, Substrate, TemperatureLaw, Until,
};
use super::{AnyKey, Key, KeyDefault, Range};
use serde::{Deserialize, Serialize};
use stickslip_core::config::{NumericsConfig, bounds};

/// Byte-wise equality of two strings, usable in constants.
const fn same_path(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

impl<T: 'static> Key<T> {
    /// An entry with nothing but its path, meaning and version; the rest follows.
    const fn blank(path: &'static str, meaning: &'static str, since: &'static str) -> Self {
        Self {
            path,
            unit: "–",
            default: KeyDefault::Required,
            range: Range::Finite,
            rule: "",
            usual: None,
            meaning,
            since,
        }
    }

    /// As [`Key::blank`], with the unit and range of the engine's bound for the key.
    const fn bounded(
        b: bounds::Bound,
        path: &'static str,
        meaning: &'static str,
        since: &'static str,
    ) -> Self {
        assert!(same_path(b.path, path), "an engine bound of another key");
        Self {
            unit: b.unit,
            range: b.range,
            ..Self::blank(path, meaning, since)
        }
    }
}

impl<T: Copy + 'static> Key<T> {
    /// The default value of a key with a fixed default (`None` for derived, required and off
    /// defaults), usable in constants.
    #[must_use]
    pub const fn fixed_default(&self) -> Option<T> {
        match &self.default {
            KeyDefault::Value(v) => Some(**v),
            _ => None,
        }
    }
}

/// A section of the scene file: its serde struct and a module of its keys (see the module
/// docs). Each entry: `CONST field "name" [@ bound]: Type = "meaning" { other fields of Key }`.
macro_rules! section {
    (
        $(#[$sdoc:meta])*
        $Struct:ident in $module:ident, $section:literal {
            $(
                $CONST:ident $field:ident $name:literal $(@ $bound:path)? : $ty:ty = $meaning:literal
                    { $($k:ident : $v:expr),* $(,)? }
            )*
        }
        $( sections { $( $(#[$subdoc:meta])* $sub:ident : $SubTy:ty ),* $(,)? } )?
    ) => {
        $(#[$sdoc])*
        #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
        #[derive(std::default::Default)]
        #[serde(deny_unknown_fields)]
        pub struct $Struct {
            $(
                #[doc = concat!("`", $section, ".", $name, "`: ", $meaning, " (unit, default and range: [`", stringify!($module), "::", stringify!($CONST), "`]).")]
                #[serde(rename = $name, skip_serializing_if = "Option::is_none")]
                pub $field: Option<$ty>,
            )*
            $($(
                $(#[$subdoc])*
                #[serde(skip_serializing_if = "Option::is_none")]
                pub $sub: Option<$SubTy>,
            )*)?
        }

        #[doc = concat!("The keys of `[", $section, "]`.")]
        pub mod $module {
            #[allow(unused_imports)]
            use super::*;
            $(
                #[doc = concat!("`", $section, ".", $name, "`: ", $meaning)]
                pub const $CONST: Key<$ty> = Key {
                    $($k: $v,)*
                    ..section!(@base ($section, $name, $meaning) $($bound)?)
                };
            )*
            /// Every key of the section, in the reference's order.
            pub const ALL: &[&dyn AnyKey] = &[$(&$CONST),*];
        }
    };
    (@base ($section:literal, $name:literal, $meaning:literal)) => {
        Key::blank(concat!($section, ".", $name), $meaning, "0.1.0")
    };
    (@base ($section:literal, $name:literal, $meaning:literal) $bound:path) => {
        Key::bounded($bound, concat!($section, ".", $name), $meaning, "0.1.0")
    };
}

use KeyDefault::{Derived, Off, Value};

/// `name`: the scene's name.
pub const NAME: Key<String> = Key {
    range: Range::NonEmpty,
    ..Key::blank("name", "name of the scene (messages, run.json)", "0.1.0")
};

/// The top-level keys.
const TOP: &[&dyn AnyKey] = &[&NAME];

/// A whole scene file as written (keys: docs/reference.md). All quantities SI.
#[derive(Debug, Clone, std::default::Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// [`NAME`] (required).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// `[lubricant]` (required).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lubricant: Option<LubricantSection>,
    /// `[temperature]` (optional).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub temperature: Option<TemperatureSection>,
    /// `[contact]` (required).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact: Option<ContactSection>,
    /// `[drive]` (required).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drive: Option<DriveSection>,
    /// `[time]` (required).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time: Option<TimeSection>,
    /// `[output]` (optional).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub output: Option<OutputSection>,
    /// `[numerics]` (optional).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub numerics: Option<NumericsSection>,
}

section! {
    /// `[lubricant]`: the Landau film (Eq. 1–8).
    LubricantSection in lubricant, "lubricant" {
        TAU_MAX tau_max "tau_max" @ bounds::TAU_MAX: f64 =
            "τmax: largest shear stress of the stationary stress–strain curve (Eq. 6)"
            { usual: Some((1e3, 1e10)) }
        EPS_MAX eps_max "eps_max" @ bounds::EPS_MAX: f64 =
            "εmax: strain at which the stationary stress peaks (Eq. 6)"
            { usual: Some((1e-3, 1e2)) }
        A a "a" @ bounds::A: f64 =
            "a: coupling of order parameter and strain in the free energy (Eq. 1)"
            { usual: Some((1e2, 1e12)) }
        GAMMA gamma "gamma" @ bounds::GAMMA: f64 =
            "γ: kinetic coefficient of the film (Eq. 8)"
            { usual: Some((1e-6, 1e6)) }
        MELT_THRESHOLD melt_threshold "melt_threshold" @ bounds::MELT_THRESHOLD: f64 =
            "φ below which a node counts as melted; u0 is held at 0 there"
            { default: Value(&0.01), usual: Some((1e-6, 0.5)) }
        CUBIC cubic "cubic" @ bounds::CUBIC: f64 =
            "b3: cubic term −(b3/3)·φ³ of a first-order film's free energy; 0 is the paper's second-order film"
            { default: Value(&0.0), rule: "not with lubricant.eps_melt", usual: Some((1e2, 1e12)) }
        EPS_MELT eps_melt "eps_melt": f64 =
            "ε₊: melting strain of a first-order film instead of b3; b3 = 2·√(a·b·(ε₊² − εc²)) with εc at the initial temperature, converted once (the resolved scene gives b3 as lubricant.cubic)"
            {
                default: Off("none (use lubricant.cubic)"),
                range: Range::ByRule,
                rule: "finite and > eps_c = √(A0·b)/a at the initial temperature (0 when A0 <= 0); not with lubricant.cubic",
                usual: Some((1e-3, 1e2)),
            }
        VISCOSITY viscosity "viscosity" @ bounds::VISCOSITY: f64 =
            "η: Newtonian viscosity of the film, a stress η·(Ẋ − u̇3D)/h0 added to τ solid or liquid (Kelvin–Voigt while solid); 0 = the paper's film"
            {
                default: Value(&0.0),
                rule: "0 with time.scheme = \"literal\"",
                usual: Some((1e-4, 1e4)),
                since: "0.2.0",
            }
    }
    sections {
        /// `[lubricant.noise]` (optional; default: the floor).
        noise: NoiseSection,
    }
}

section! {
    /// `[lubricant.noise]`: thermal noise ξ(t) or its deterministic floor.
    NoiseSection in noise, "lubricant.noise" {
        KIND kind "kind": NoiseKindName =
            "thermal noise ξ(t) of Eq. 8: gaussian, a deterministic floor φ >= floor, or none"
            { default: Value(&NoiseKindName::Floor), range: Range::Word }
        SIGMA sigma "sigma" @ bounds::NOISE_SIGMA: f64 =
            "noise amplitude: ξ ~ N(0, σ²·Δt) per node and step"
            { default: Value(&1.0), rule: "only with kind = \"gaussian\"" }
        FLOOR floor "floor" @ bounds::NOISE_FLOOR: f64 =
            "deterministic floor of φ (no random numbers, bit-reproducible runs)"
            {
                default: Value(&1e-6),
                rule: "finite, >= 0 and below lubricant.melt_threshold; only with kind = \"floor\"",
            }
        SEED seed "seed": i64 =
            "seed of the per-node ChaCha8 noise streams"
            {
                default: Value(&1),
                range: Range::Integers(0, i64::MAX),
                rule: "only with kind = \"gaussian\"",
            }
    }
}

section! {
    /// `[temperature]`: the law of A(t) (Eq. 17, 18).
    TemperatureSection in temperature, "temperature" {
        LAW law "law": TemperatureLaw =
            "A constant, or A(t) = A0·exp(−t/t_relax) (Eq. 18)"
            { default: Value(&TemperatureLaw::Constant), range: Range::Word }
        A0 a0 "A0" @ bounds::TEMPERATURE_A0: f64 =
            "A (constant) or A0 (relaxation): the temperature coefficient; A <= 0 melts the film (a first-order film may start as a metastable solid)"
            {
                default: Derived {
                    doc: "1.5·tau_max/eps_max (law = \"constant\")",
                    of: |s| {
                        let l = s.lubricant.as_ref()?;
                        Some(1.5 * l.tau_max? / l.eps_max?)
                    },
                },
                rule: "required with law = \"relaxation\"",
                usual: Some((1e2, 1e10)),
            }
        T_RELAX t_relax "t_relax" @ bounds::T_RELAX: f64 =
            "t̃: relaxation time of A(t) (Eq. 18)"
            {
                default: Off("required with law = \"relaxation\""),
                rule: "only with law = \"relaxation\"",
            }
    }
}

section! {
    /// `[contact]`: stamp geometry and elasticity (Eq. 9–16).
    ContactSection in contact, "contact" {
        RADIUS radius "radius" @ bounds::RADIUS: f64 =
            "a0: radius of the flat-ended stamp"
            { usual: Some((1e-9, 1e-2)) }
        FILM_THICKNESS film_thickness "film_thickness" @ bounds::FILM_THICKNESS: f64 =
            "h0: lubricant film thickness"
            { usual: Some((1e-10, 1e-5)) }
        G_EFF g_eff "g_eff" @ bounds::G_EFF: f64 =
            "G*: effective shear modulus of the contact (Eq. 9)"
            { rule: "either g_eff or all of g1, nu1, g2, nu2", usual: Some((1e5, 1e12)) }
        G1 g1 "g1": f64 =
            "G1: shear modulus of the stamp (Eq. 9)"
            {
                unit: "Pa",
                default: Off("none (use g_eff)"),
                range: Range::Positive,
                rule: "with nu1, g2, nu2 instead of g_eff",
                usual: Some((1e5, 1e12)),
            }
        NU1 nu1 "nu1": f64 =
            "ν1: Poisson ratio of the stamp (Eq. 9)"
            {
                default: Off("none (use g_eff)"),
                range: Range::OpenClosed(-1.0, 0.5),
                rule: "with g1, g2, nu2 instead of g_eff",
            }
        G2 g2 "g2": f64 =
            "G2: shear modulus of the substrate (Eq. 9)"
            {
                unit: "Pa",
                default: Off("none (use g_eff)"),
                range: Range::Positive,
                rule: "with g1, nu1, nu2 instead of g_eff",
                usual: Some((1e5, 1e12)),
            }
        NU2 nu2 "nu2": f64 =
            "ν2: Poisson ratio of the substrate (Eq. 9)"
            {
                default: Off("none (use g_eff)"),
                range: Range::OpenClosed(-1.0, 0.5),
                rule: "with g1, nu1, g2 instead of g_eff",
            }
        NODES nodes "nodes" @ bounds::NODES: i64 =
            "N: radial nodes, spread by contact.grid (1 for the homogeneous model)"
            // 200: on the default graded grid the h0 = 1 nm contact's first onset is then within
            // 1e-4 relative and fig2's within 1e-9 s (reports/convergence.md, section 8), at a
            // tenth of the cost of the 2000 uniform nodes the default was before the grid.
            { default: Value(&200), rule: ">= 2 with time.scheme = \"literal\"" }
        GRID grid "grid": GridChoice =
            "how the N nodes are spread: uniform r_i = i·a0/N (the paper's grid), or graded toward the contact's edge, r_i = a0·(1 − (1 − i/N)^p) with p = contact.grading, which resolves the stress's edge layer where the first melting starts (docs/model.md, \"The radial grid\")"
            {
                default: Derived {
                    doc: "graded for the accurate scheme's radial contact of N >= 10 nodes (it verifies: reports/convergence.md, section 8); uniform for the literal scheme, the homogeneous model and fewer nodes, where a grading has nothing to spread",
                    of: |s| {
                        let scheme = s.time.as_ref()?.scheme?;
                        let contact = s.contact.as_ref()?;
                        let (model, nodes) = (contact.model?, contact.nodes?);
                        Some(if scheme == Scheme::Accurate
                            && model == ContactModel::Radial
                            && nodes >= GRADED_MIN_NODES
                        {
                            GridChoice::Graded
                        } else {
                            GridChoice::Uniform
                        })
                    },
                },
                range: Range::Word,
                rule: "\"uniform\" with time.scheme = \"literal\"",
                since: "0.2.0",
            }
        GRADING grading "grading" @ bounds::GRADING: f64 =
            "p: the graded grid's exponent; the outermost node sits a0·N^(−p) from the edge and the widest cell, at the axis, is p·a0/N"
            {
                default: Derived {
                    doc: "3, or 11.5/log10(N) where that is smaller (N > 6800, so that N^(−p) >= 3e-12)",
                    of: |s| Some(default_grading(s.contact.as_ref()?.nodes?)),
                },
                rule: "only with grid = \"graded\"; N^(−p) >= 1e-12",
                since: "0.2.0",
            }
        MODEL model "model": ContactModel =
            "radial MDR contact, or one homogeneous node (flat punch, uniform stress)"
            { default: Value(&ContactModel::Radial), range: Range::Word }
        SUBSTRATE substrate "substrate": Substrate =
            "elastic substrate (MDR, Eq. 13–15) or rigid (u3D = 0, no operator applied)"
            { default: Value(&Substrate::Elastic), range: Range::Word }
    }
}

section! {
    /// `[drive]`: how the stamp is pulled (Eq. 10).
    DriveSection in drive, "drive" {
        KIND kind "kind": DriveKind =
            "stamp pulled through a spring (Eq. 10) or by a rigid coupler X = V0·t"
            { default: Value(&DriveKind::Spring), range: Range::Word }
        STIFFNESS stiffness "stiffness" @ bounds::STIFFNESS: f64 =
            "K: spring stiffness"
            {
                default: Off("required with kind = \"spring\""),
                rule: "only with kind = \"spring\"",
                usual: Some((1e-3, 1e9)),
            }
        MASS mass "mass" @ bounds::MASS: f64 =
            "m: stamp mass"
            {
                default: Off("required with kind = \"spring\""),
                rule: "only with kind = \"spring\"",
                usual: Some((1e-9, 1e3)),
            }
        DAMPING damping "damping" @ bounds::DAMPING: f64 =
            "dashpot parallel to the spring (damps the stamp's ringing; 0 = the paper's model)"
            {
                default: Value(&0.0),
                rule: "only with kind = \"spring\"",
                since: "0.2.0",
            }
        VELOCITY velocity "velocity" @ bounds::VELOCITY: f64 =
            "V0: velocity of the spring's free end (or of the rigid coupler)"
            { usual: Some((1e-9, 1e2)) }
        INTEGRATOR integrator "integrator": Integrator =
            "integrator of the spring drive: split (the motion of the spring and, with the accurate scheme, of the contact as a linear spring exact, the rest of the friction force as Verlet half kicks; symplectic), velocity Verlet, or RK4 (friction held over the step)"
            { default: Value(&Integrator::Split), range: Range::Word }
    }
}

/// Whether the scene as resolved so far steps adaptively (the derived `time.stepping`, or
/// the one given).
pub(crate) fn adaptive(s: &Scene) -> Option<bool> {
    Some(s.time.as_ref()?.stepping? == Stepping::Adaptive)
}

section! {
    /// `[time]`: interval, step and scheme.
    TimeSection in time, "time" {
        END end "end" @ bounds::END: f64 =
            "end of the simulated interval"
            // Up to 1e3 s: a surface-force-apparatus experiment at µm/s sticks for seconds and
            // is watched for minutes.
            {
                usual: Some((1e-12, 1e3)),
                default: Derived {
                    doc: "time.travel / |drive.velocity| when time.travel is given; else required",
                    of: |s| {
                        let travel = s.time.as_ref()?.travel?;
                        let v = s.drive.as_ref()?.velocity?;
                        (v != 0.0).then(|| travel / v.abs())
                    },
                },
                rule: "with time.travel too, the earlier of the two ends the run (the resolved time.end is the earlier)",
            }
        TRAVEL travel "travel": f64 =
            "the drive's advance |V0|·t after which the run ends: one window in drive travel for every drive.velocity, so that maps and boundary searches along the velocity compare like with like (the natural window of stick-slip scales like 1/V0)"
            {
                unit: "m",
                default: Off("none (time.end ends the run)"),
                range: Range::Positive,
                usual: Some((1e-12, 1e-1)),
                rule: "needs drive.velocity != 0",
                since: "0.2.0",
            }
        DT dt "dt" @ bounds::DT: f64 =
            "time step: the fixed step, or the first step tried when adaptive"
            {
                default: Value(&1e-8),
                rule: "finite, > 0 and <= time.end (and >= time.end / 1e12: at most 1e12 steps)",
            }
        SCHEME scheme "scheme": Scheme =
            "accurate (product integration, exact Landau step, coupling solved) or the paper's literal scheme"
            { default: Value(&Scheme::Accurate), range: Range::Word }
        STEPPING stepping "stepping": Stepping =
            "error-controlled steps (local error estimated from each step, PI controller) or fixed steps of time.dt"
            {
                default: Derived {
                    doc: "adaptive for the accurate scheme without gaussian noise, else fixed",
                    of: |s| {
                        let scheme = s.time.as_ref()?.scheme?;
                        let kind = s.lubricant.as_ref()?.noise.as_ref()?.kind?;
                        Some(if scheme == Scheme::Accurate && kind != NoiseKindName::Gaussian {
                            Stepping::Adaptive
                        } else {
                            Stepping::Fixed
                        })
                    },
                },
                range: Range::Word,
                rule: "\"fixed\" with the literal scheme or gaussian noise",
            }
        TOLERANCE tolerance "tolerance" @ bounds::TOLERANCE: f64 =
            "allowed local error per step, relative to scales that follow the state: φ to max(φ, melt threshold, numerics.phi_error_floor·φ_s), the strain to εc(t) (ε₊(t) for a first-order film), X to max(|X|, 1e-3·h0), V to max(|V|, 0.1·ω·h0·εc), ω = √(K/m)"
            { default: Value(&5e-5), rule: "only with stepping = \"adaptive\"" }
        DT_MAX dt_max "dt_max" @ bounds::DT_MAX: f64 =
            "longest adaptive step (not needed for accuracy: the error control sets the step)"
            {
                default: Derived {
                    doc: "time.end (no cap)",
                    of: |s| s.time.as_ref()?.end,
                },
                rule: "<= time.end; only with stepping = \"adaptive\"",
            }
        DT_MIN dt_min "dt_min" @ bounds::DT_MIN: f64 =
            "shortest adaptive step, accepted whatever its error (counted as forced)"
            {
                default: Derived {
                    doc: "1e-6·min(time.dt, time.dt_max)",
                    of: |s| {
                        let t = s.time.as_ref()?;
                        Some(1e-6 * t.dt?.min(t.dt_max?))
                    },
                },
                rule: "<= min(time.dt, time.dt_max); only with stepping = \"adaptive\"",
            }
        MAX_EVENTS max_events "max_events": i64 =
            "stop once this many melting events have ended (the film recovered); time.end still bounds the run"
            { default: Off("none (run to time.end)"), range: Range::Integers(1, i64::MAX) }
        MAX_OPEN_EVENT max_open_event "max_open_event": f64 =
            "stop once an event has stayed open this long (the film has not recovered; a sweep point's regime is clear)"
            { unit: "s", default: Off("none (run to time.end)"), range: Range::Positive }
        UNTIL until "until": Until =
            "end: run to time.end; periodic: stop at the end of the event after which the last time.steady_cycles cycles repeat (period, stamp advance and peak force within time.steady_rtol), or at time.end; run.json's summary says `steady` either way"
            { default: Value(&Until::End), range: Range::Word }
        STEADY_CYCLES steady_cycles "steady_cycles": i64 =
            "cycles (onset to onset) that must repeat for a run to count as steady"
            { default: Value(&3), range: Range::Integers(1, 1000) }
        STEADY_RTOL steady_rtol "steady_rtol": f64 =
            "relative tolerance of that repetition (each of the cycles against the last one)"
            { default: Value(&1e-3), range: Range::Open(0.0, 1.0) }
    }
}

section! {
    /// `[output]`: what is recorded.
    OutputSection in output, "output" {
        PROFILE_TIMES profile_times "profile_times": Vec<f64> =
            "times at which φ, ε, τ, u0, u3D are written against r (profiles.csv)"
            {
                unit: "s",
                default: Derived {
                    doc: "[time.end]",
                    of: |s| Some(vec![s.time.as_ref()?.end?]),
                },
                range: Range::ByRule,
                rule: "each within [0, time.end]",
            }
        PROBE_RADII probe_radii "probe_radii": Vec<f64> =
            "radii at which φ(t) and the last melting time are written (probes.csv)"
            {
                unit: "m",
                default: Value(&Vec::new()),
                range: Range::ByRule,
                rule: "each within [0, contact.radius)",
            }
        EVENT_MERGE_GAP event_merge_gap "event_merge_gap" @ bounds::EVENT_MERGE_GAP: f64 =
            "a melting that begins less than this after the previous event ended continues it (0 = never)"
            { default: Value(&0.0) }
        EVENT_RECOVERY event_recovery "event_recovery" @ bounds::EVENT_RECOVERY: f64 =
            "an event ends when every node is back above this multiple of melt_threshold (capped at halfway to √(A/a))"
            { default: Value(&2.0) }
        SLIP_DROP slip_drop "slip_drop": f64 =
            "a slip of the stamp: the drive's force falls by more than this fraction of tau_max·π·radius² (slips.csv, the stamp-scale regime)"
            {
                default: Value(&0.05),
                range: Range::OpenClosed(0.0, 1.0),
                since: "0.2.0",
            }
        SERIES_INTERVAL series_interval "series_interval": f64 =
            "interval between rows of series.csv and probes.csv (rows at the first step at or after each mark)"
            {
                unit: "s",
                default: Value(&1e-7),
                range: Range::Positive,
                rule: ">= time.end / 1e12 (marks closer than that would not advance the time)",
            }
    }
}

/// `numerics.coupling_tol` with adaptive steps is `time.tolerance` divided by this: the
/// coupling is solved just below the step's own error.
pub const TOLERANCE_PER_COUPLING_TOL: f64 = 100.0;

section! {
    /// `[numerics]`: numerical controls.
    NumericsSection in numerics, "numerics" {
        COUPLING_TOL coupling_tol "coupling_tol" @ bounds::COUPLING_TOL: f64 =
            "relative residual to which the accurate scheme solves the elastic coupling (with adaptive steps a residual whose RMS over the nodes is below time.tolerance/10 of the melting displacement εc·h0 also passes: its strain is a tenth of what the step's error estimate accepts, and it enters that estimate)"
            {
                default: Derived {
                    doc: "time.tolerance / 100 (adaptive), 1e-10 (fixed)",
                    of: |s| {
                        Some(if adaptive(s)? {
                            s.time.as_ref()?.tolerance? / TOLERANCE_PER_COUPLING_TOL
                        } else {
                            NumericsConfig::DEFAULT.coupling_tol
                        })
                    },
                },
            }
        RUNAWAY_STRESS_FACTOR runaway_stress_factor "runaway_stress_factor" @ bounds::RUNAWAY_STRESS_FACTOR: f64 =
            "a step fails when |τ| exceeds this multiple of tau_max (for a first-order film: of its stationary curve's peak, when larger), times (φ/φ0)² at a node that noise ordered beyond the solid's φ0"
            { default: Value(&NumericsConfig::DEFAULT.runaway_stress_factor) }
        OPERATOR operator "operator": OperatorChoice =
            "MDR transforms: fast (hierarchical low-rank, O(N)), dense (O(N²)); auto = fast for accurate, dense for literal"
            { default: Value(&OperatorChoice::Auto), range: Range::Word }
        FILM_STEP film_step "film_step": FilmStep =
            "the accurate scheme's step of the second-order film: ramp (the exact frozen-strain step corrected to first order in the film coefficient's change along the step's strain ramp, in closed form) or frozen (the exact step under one effective strain, as before the correction; for comparison). The first-order film always takes the frozen one"
            { default: Value(&FilmStep::Ramp), range: Range::Word }
        PHI_ERROR_FLOOR phi_error_floor "phi_error_floor" @ bounds::PHI_ERROR_FLOOR: f64 =
            "adaptive steps: the smallest scale of a node's φ error, as a fraction of the solid film's φ at zero strain: φ's error is taken relative to max(φ, melt threshold, this·φ_s). 0 keeps it relative down to the melt threshold; 0.1 stops steps from resolving a molten or regrowing node's φ to relative accuracy where its stress is below a hundredth of a solid node's, and halves the steps of a thin film's slip of many meltings (reports/performance.md)"
            { default: Value(&0.0), rule: "only with time.stepping = \"adaptive\"" }
        EVENT_PHI_ERROR_FLOOR event_phi_error_floor "event_phi_error_floor" @ bounds::EVENT_PHI_ERROR_FLOOR: f64 =
            "adaptive steps: numerics.phi_error_floor for a step that starts while a melting event is open (a cascade of meltings), where the larger of the two applies; the steps from an event's end to the next onset, where the onset's error is made, keep numerics.phi_error_floor. 0 adds nothing; 0.1 halves the step evaluations of a thin film's slip of many meltings with its onsets unchanged (docs/model.md)"
            { default: Value(&0.0), rule: "only with time.stepping = \"adaptive\"" }
        EVENT_TOLERANCE_FACTOR event_tolerance_factor "event_tolerance_factor" @ bounds::EVENT_TOLERANCE_FACTOR: f64 =
            "adaptive steps: the factor time.tolerance is multiplied by for a step that starts while a melting event is open (a cascade of meltings), from 1 up; the steps from an event's end to the next onset, where the onset's error is made, keep time.tolerance. 1 keeps one tolerance throughout"
            { default: Value(&1.0), rule: "only with time.stepping = \"adaptive\"" }
    }
}

/// The accurate scheme's radial contact is graded by default from this many nodes on: below,
/// the outermost cell would span much of the radius (r_1 = 0.875·a0 at N = 2) and the two
/// forces F and F_1d part by 0.5 % (hard case 6), for no edge to resolve.
pub const GRADED_MIN_NODES: i64 = 10;

/// The graded grid's default exponent for N nodes: 3 (docs/model.md, "The radial grid": the
/// thin films' first onsets are 2–2.5 times closer to converged at N = 200 than with 2, at
/// no more steps), lowered above N ≈ 6800 so that the edge cell a0·N^(−p) stays ≥ 3e-12·a0,
/// clear of the grid's guard at 1e-12.
#[must_use]
pub fn default_grading(nodes: i64) -> f64 {
    let n = nodes.max(2) as f64;
    (3.0_f64).min(11.5 / n.log10())
}

/// The sections' keys, in the reference's order.
pub(super) const SECTIONS: &[&[&dyn AnyKey]] = &[
    TOP,
    lubricant::ALL,
    noise::ALL,
    temperature::ALL,
    contact::ALL,
    drive::ALL,
    time::ALL,
    output::ALL,
    numerics::ALL,
];

/// Largest number of nodes (the dense operators take 8·N² bytes each).
pub const MAX_NODES: i64 = stickslip_core::config::MAX_NODES as i64;
/// Largest number of steps a scene may ask for (time.end / time.dt).
pub const MAX_STEPS: f64 = 1e12;
