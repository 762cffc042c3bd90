//! The table of scene keys: unit, default, allowed range, usual range and meaning of each.
//!
//! One table serves three jobs: scene resolution checks single-key ranges against it (the
//! error text is the table's), `stickslip keys` prints it, and `docs/reference.md` is
//! generated from it (a tidy test keeps that file current and checks that the table, the
//! scene file's serde structs and the resolved defaults agree). Rules between keys (`time.dt
//! <= time.end`) are checked in code; the table's text states them.

use crate::scene::SceneError;
use crate::scene::error::human;

/// The type of a key's value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ValueType {
    /// A number (float or integer in the file).
    Real,
    /// An integer.
    Integer,
    /// A string.
    Text,
    /// One word of a fixed list.
    Choice(&'static [&'static str]),
    /// An array of numbers.
    RealList,
}

/// What is allowed, checked where it depends on the key alone.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Range {
    /// Any finite number.
    Finite,
    /// Finite and > 0.
    Positive,
    /// Finite and ≥ 0.
    NonNegative,
    /// Finite and > lo.
    Above(f64),
    /// lo ≤ x ≤ hi.
    Closed(f64, f64),
    /// lo < x < hi.
    Open(f64, f64),
    /// lo < x ≤ hi.
    OpenClosed(f64, f64),
    /// An integer in lo ..= hi.
    Integers(i64, i64),
    /// A word of the key's [`ValueType::Choice`] list.
    Word,
    /// A non-empty string.
    NonEmpty,
    /// Set by rules between keys, stated in the key's `rule` and checked in code.
    ByRule,
}

impl Range {
    /// Whether `v` is allowed (rules between keys aside).
    #[must_use]
    pub fn contains(&self, v: f64) -> bool {
        match *self {
            Self::Finite | Self::ByRule => v.is_finite(),
            Self::Positive => v.is_finite() && v > 0.0,
            Self::NonNegative => v.is_finite() && v >= 0.0,
            Self::Above(lo) => v.is_finite() && v > lo,
            Self::Closed(lo, hi) => v.is_finite() && (lo..=hi).contains(&v),
            Self::Open(lo, hi) => v.is_finite() && v > lo && v < hi,
            Self::OpenClosed(lo, hi) => v.is_finite() && v > lo && v <= hi,
            Self::Integers(lo, hi) => v.fract() == 0.0 && v >= lo as f64 && v <= hi as f64,
            Self::Word | Self::NonEmpty => true,
        }
    }

    /// The range in words, `var` naming the value in two-sided bounds, `unit` after numbers.
    #[must_use]
    pub fn describe(&self, var: &str, unit: &str) -> String {
        let u = if unit.is_empty() || unit == "–" {
            String::new()
        } else {
            format!(" {unit}")
        };
        match *self {
            Self::Finite | Self::ByRule => format!("finite{u}"),
            Self::Positive => format!("finite and > 0{u}"),
            Self::NonNegative => format!("finite and >= 0{u}"),
            Self::Above(lo) => format!("finite and > {}{u}", human(lo)),
            Self::Closed(lo, hi) if lo > 0.0 => {
                format!("finite and within [{lo:e}, {hi:e}]{u} (so > 0)")
            }
            Self::Closed(lo, hi) => format!("finite and within [{lo:e}, {hi:e}]{u}"),
            Self::Open(lo, hi) => format!("finite, > {} and < {}{u}", human(lo), human(hi)),
            Self::OpenClosed(lo, hi) => format!("{} < {var} <= {}{u}", human(lo), human(hi)),
            Self::Integers(lo, hi) => format!("an integer in {lo} ..= {hi}"),
            Self::Word => "one of the listed words".to_string(),
            Self::NonEmpty => "a non-empty string".to_string(),
        }
    }
}

/// A key's default, as documented.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DefaultValue {
    /// The key must be given.
    Required,
    /// This value (as written in a scene).
    Value(&'static str),
    /// Computed from other keys, as described.
    Derived(&'static str),
    /// No value: the feature is off.
    Off(&'static str),
}

impl DefaultValue {
    /// The default in words.
    #[must_use]
    pub fn describe(&self) -> String {
        match self {
            Self::Required => "required".to_string(),
            Self::Value(v) => (*v).to_string(),
            Self::Derived(d) | Self::Off(d) => (*d).to_string(),
        }
    }
}

/// One scene key.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Key {
    /// Full path, `section.key`.
    pub path: &'static str,
    /// Type of its value.
    pub value: ValueType,
    /// SI unit (`–` for dimensionless).
    pub unit: &'static str,
    /// Default.
    pub default: DefaultValue,
    /// Allowed values of the key alone.
    pub range: Range,
    /// Rules between keys, in words (empty if none).
    pub rule: &'static str,
    /// Usual range (absolute value): a value outside draws a warning, not an error.
    pub usual: Option<(f64, f64)>,
    /// One line of meaning.
    pub meaning: &'static str,
}

impl Key {
    /// Allowed values in words: the range, then the rules between keys.
    #[must_use]
    pub fn allowed(&self) -> String {
        let base = match self.value {
            ValueType::Choice(words) => format!(
                "one of {}",
                words
                    .iter()
                    .map(|w| format!("{w:?}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            ValueType::RealList => format!("an array of numbers in {}", self.unit),
            _ => self.range.describe(self.short_name(), self.unit),
        };
        if self.rule.is_empty() {
            base
        } else if self.range == Range::ByRule {
            self.rule.to_string()
        } else {
            format!("{base}; {}", self.rule)
        }
    }

    /// The last part of the path (`nu1` of `contact.nu1`), without trailing digits.
    #[must_use]
    pub fn short_name(&self) -> &'static str {
        let last = self.path.rsplit('.').next().unwrap_or(self.path);
        last.trim_end_matches(|c: char| c.is_ascii_digit())
    }

    /// Checks `v` against the key's own range.
    ///
    /// # Errors
    /// [`SceneError::Invalid`] with the table's wording.
    pub fn check(&self, v: f64) -> Result<f64, SceneError> {
        if self.range.contains(v) {
            Ok(v)
        } else {
            Err(SceneError::invalid(self.path, human(v), self.allowed()))
        }
    }

    /// Whether `v` lies outside the usual range (a likely unit slip).
    #[must_use]
    pub fn unusual(&self, v: f64) -> bool {
        self.usual
            .is_some_and(|(lo, hi)| v != 0.0 && !(lo..=hi).contains(&v.abs()))
    }
}

/// The key at `path`.
///
/// # Panics
/// If there is no such key: paths in code are fixed strings, checked by the tests.
#[must_use]
#[track_caller]
pub fn key(path: &str) -> &'static Key {
    KEYS.iter()
        .find(|k| k.path == path)
        .unwrap_or_else(|| panic!("no scene key {path}"))
}

/// Checks `v` against the range of the key at `path`.
///
/// # Errors
/// As [`Key::check`].
pub fn check(path: &str, v: f64) -> Result<f64, SceneError> {
    key(path).check(v)
}

/// The allowed words of a choice key.
#[must_use]
pub fn words(path: &str) -> &'static [&'static str] {
    match key(path).value {
        ValueType::Choice(w) => w,
        _ => &[],
    }
}

const fn k(
    path: &'static str,
    value: ValueType,
    unit: &'static str,
    default: DefaultValue,
    range: Range,
    meaning: &'static str,
) -> Key {
    Key {
        path,
        value,
        unit,
        default,
        range,
        rule: "",
        usual: None,
        meaning,
    }
}

const fn usual(mut key: Key, lo: f64, hi: f64) -> Key {
    key.usual = Some((lo, hi));
    key
}

const fn rule(mut key: Key, text: &'static str) -> Key {
    key.rule = text;
    key
}

use DefaultValue::{Derived, Off, Required, Value};
use ValueType::{Choice, Integer, Real, RealList, Text};

/// Largest number of nodes (the dense operators take 8·N² bytes each).
pub const MAX_NODES: i64 = stickslip_core::config::MAX_NODES as i64;
/// Largest number of steps a scene may ask for (time.end / time.dt).
pub const MAX_STEPS: f64 = 1e12;

/// Every scene key, in the order of the reference.
pub const KEYS: &[Key] = &[
    k(
        "name",
        Text,
        "–",
        Required,
        Range::NonEmpty,
        "name of the scene (messages, run.json)",
    ),
    usual(
        k(
            "lubricant.tau_max",
            Real,
            "Pa",
            Required,
            Range::Positive,
            "τmax: largest shear stress of the stationary stress–strain curve (Eq. 6)",
        ),
        1e3,
        1e10,
    ),
    usual(
        k(
            "lubricant.eps_max",
            Real,
            "–",
            Required,
            Range::Positive,
            "εmax: strain at which the stationary stress peaks (Eq. 6)",
        ),
        1e-3,
        1e2,
    ),
    usual(
        k(
            "lubricant.a",
            Real,
            "Pa",
            Required,
            Range::Positive,
            "a: coupling of order parameter and strain in the free energy (Eq. 1)",
        ),
        1e2,
        1e12,
    ),
    usual(
        k(
            "lubricant.gamma",
            Real,
            "1/(Pa·s)",
            Required,
            Range::Positive,
            "γ: kinetic coefficient of the film (Eq. 8)",
        ),
        1e-6,
        1e6,
    ),
    usual(
        k(
            "lubricant.melt_threshold",
            Real,
            "–",
            Value("0.01"),
            Range::Positive,
            "φ below which a node counts as melted; u0 is held at 0 there",
        ),
        1e-6,
        0.5,
    ),
    usual(
        rule(
            k(
                "lubricant.cubic",
                Real,
                "Pa",
                Value("0"),
                Range::NonNegative,
                "b3: cubic term −(b3/3)·φ³ of a first-order film's free energy; 0 is the paper's second-order film",
            ),
            "not with lubricant.eps_melt",
        ),
        1e2,
        1e12,
    ),
    usual(
        rule(
            k(
                "lubricant.eps_melt",
                Real,
                "–",
                Off("none (use lubricant.cubic)"),
                Range::ByRule,
                "ε₊: melting strain of a first-order film instead of b3; b3 = 2·√(a·b·(ε₊² − εc²)) with εc at the initial temperature, converted once (the resolved scene gives b3 as lubricant.cubic)",
            ),
            "finite and > eps_c = √(A0·b)/a at the initial temperature (0 when A0 <= 0); not with lubricant.cubic",
        ),
        1e-3,
        1e2,
    ),
    k(
        "lubricant.noise.kind",
        Choice(&["gaussian", "floor", "off"]),
        "–",
        Value("floor"),
        Range::Word,
        "thermal noise ξ(t) of Eq. 8: gaussian, a deterministic floor φ >= floor, or none",
    ),
    rule(
        k(
            "lubricant.noise.sigma",
            Real,
            "s^-1/2",
            Value("1 (kind = \"gaussian\")"),
            Range::NonNegative,
            "noise amplitude: ξ ~ N(0, σ²·Δt) per node and step",
        ),
        "only with kind = \"gaussian\"",
    ),
    rule(
        k(
            "lubricant.noise.floor",
            Real,
            "–",
            Value("1e-6 (kind = \"floor\")"),
            Range::ByRule,
            "deterministic floor of φ (no random numbers, bit-reproducible runs)",
        ),
        "finite, >= 0 and below lubricant.melt_threshold; only with kind = \"floor\"",
    ),
    rule(
        k(
            "lubricant.noise.seed",
            Integer,
            "–",
            Value("1 (kind = \"gaussian\")"),
            Range::Integers(0, i64::MAX),
            "seed of the per-node ChaCha8 noise streams",
        ),
        "only with kind = \"gaussian\"",
    ),
    k(
        "temperature.law",
        Choice(&["constant", "relaxation"]),
        "–",
        Value("constant"),
        Range::Word,
        "A constant, or A(t) = A0·exp(−t/t_relax) (Eq. 18)",
    ),
    usual(
        rule(
            k(
                "temperature.A0",
                Real,
                "Pa",
                Derived("1.5·tau_max/eps_max (law = \"constant\")"),
                Range::Finite,
                "A (constant) or A0 (relaxation): the temperature coefficient; A <= 0 melts the film (a first-order film may start as a metastable solid)",
            ),
            "required with law = \"relaxation\"",
        ),
        1e2,
        1e10,
    ),
    rule(
        k(
            "temperature.t_relax",
            Real,
            "s",
            Off("required with law = \"relaxation\""),
            Range::Positive,
            "t̃: relaxation time of A(t) (Eq. 18)",
        ),
        "only with law = \"relaxation\"",
    ),
    usual(
        k(
            "contact.radius",
            Real,
            "m",
            Required,
            Range::Closed(
                stickslip_core::config::LENGTH_RANGE_M.0,
                stickslip_core::config::LENGTH_RANGE_M.1,
            ),
            "a0: radius of the flat-ended stamp",
        ),
        1e-9,
        1e-2,
    ),
    usual(
        k(
            "contact.film_thickness",
            Real,
            "m",
            Required,
            Range::Closed(
                stickslip_core::config::LENGTH_RANGE_M.0,
                stickslip_core::config::LENGTH_RANGE_M.1,
            ),
            "h0: lubricant film thickness",
        ),
        1e-10,
        1e-5,
    ),
    usual(
        rule(
            k(
                "contact.g_eff",
                Real,
                "Pa",
                Required,
                Range::Closed(
                    stickslip_core::config::MODULUS_RANGE_PA.0,
                    stickslip_core::config::MODULUS_RANGE_PA.1,
                ),
                "G*: effective shear modulus of the contact (Eq. 9)",
            ),
            "either g_eff or all of g1, nu1, g2, nu2",
        ),
        1e5,
        1e12,
    ),
    usual(
        rule(
            k(
                "contact.g1",
                Real,
                "Pa",
                Off("none (use g_eff)"),
                Range::Positive,
                "G1: shear modulus of the stamp (Eq. 9)",
            ),
            "with nu1, g2, nu2 instead of g_eff",
        ),
        1e5,
        1e12,
    ),
    rule(
        k(
            "contact.nu1",
            Real,
            "–",
            Off("none (use g_eff)"),
            Range::OpenClosed(-1.0, 0.5),
            "ν1: Poisson ratio of the stamp (Eq. 9)",
        ),
        "with g1, g2, nu2 instead of g_eff",
    ),
    usual(
        rule(
            k(
                "contact.g2",
                Real,
                "Pa",
                Off("none (use g_eff)"),
                Range::Positive,
                "G2: shear modulus of the substrate (Eq. 9)",
            ),
            "with g1, nu1, nu2 instead of g_eff",
        ),
        1e5,
        1e12,
    ),
    rule(
        k(
            "contact.nu2",
            Real,
            "–",
            Off("none (use g_eff)"),
            Range::OpenClosed(-1.0, 0.5),
            "ν2: Poisson ratio of the substrate (Eq. 9)",
        ),
        "with g1, nu1, g2 instead of g_eff",
    ),
    rule(
        k(
            "contact.nodes",
            Integer,
            "–",
            Value("2000"),
            Range::Integers(1, MAX_NODES),
            "N: radial nodes r_i = i·a0/N (1 for the homogeneous model)",
        ),
        ">= 2 with time.scheme = \"literal\"",
    ),
    k(
        "contact.model",
        Choice(&["radial", "homogeneous"]),
        "–",
        Value("radial"),
        Range::Word,
        "radial MDR contact, or one homogeneous node (flat punch, uniform stress)",
    ),
    k(
        "contact.substrate",
        Choice(&["elastic", "rigid"]),
        "–",
        Value("elastic"),
        Range::Word,
        "elastic substrate (MDR, Eq. 13–15) or rigid (u3D = 0, no operator applied)",
    ),
    k(
        "drive.kind",
        Choice(&["spring", "rigid"]),
        "–",
        Value("spring"),
        Range::Word,
        "stamp pulled through a spring (Eq. 10) or by a rigid coupler X = V0·t",
    ),
    usual(
        rule(
            k(
                "drive.stiffness",
                Real,
                "N/m",
                Off("required with kind = \"spring\""),
                Range::Positive,
                "K: spring stiffness",
            ),
            "only with kind = \"spring\"",
        ),
        1e-3,
        1e9,
    ),
    usual(
        rule(
            k(
                "drive.mass",
                Real,
                "kg",
                Off("required with kind = \"spring\""),
                Range::Positive,
                "m: stamp mass",
            ),
            "only with kind = \"spring\"",
        ),
        1e-9,
        1e3,
    ),
    usual(
        k(
            "drive.velocity",
            Real,
            "m/s",
            Required,
            Range::Finite,
            "V0: velocity of the spring's free end (or of the rigid coupler)",
        ),
        1e-9,
        1e2,
    ),
    k(
        "drive.integrator",
        Choice(&["split", "verlet", "rk4"]),
        "–",
        Value("split"),
        Range::Word,
        "integrator of the spring drive: split (the spring's motion exact, the friction force as Verlet half kicks; symplectic), velocity Verlet, or RK4 (friction held over the step)",
    ),
    usual(
        k(
            "time.end",
            Real,
            "s",
            Required,
            Range::Positive,
            "end of the simulated interval",
        ),
        1e-12,
        10.0,
    ),
    rule(
        k(
            "time.dt",
            Real,
            "s",
            Value("1e-8"),
            Range::ByRule,
            "time step: the fixed step, or the first step tried when adaptive",
        ),
        "finite, > 0 and <= time.end (and >= time.end / 1e12: at most 1e12 steps)",
    ),
    k(
        "time.scheme",
        Choice(&["accurate", "literal"]),
        "–",
        Value("accurate"),
        Range::Word,
        "accurate (product integration, exact Landau step, coupling solved) or the paper's literal scheme",
    ),
    rule(
        k(
            "time.stepping",
            Choice(&["adaptive", "fixed"]),
            "–",
            Derived("adaptive for the accurate scheme without gaussian noise, else fixed"),
            Range::Word,
            "error-controlled steps (local error estimated from each step, PI controller) or fixed steps of time.dt",
        ),
        "\"fixed\" with the literal scheme or gaussian noise",
    ),
    rule(
        k(
            "time.tolerance",
            Real,
            "–",
            Value("5e-5 (adaptive)"),
            Range::Open(0.0, 1.0),
            "allowed local error per step, relative to scales that follow the state: φ to max(φ, melt threshold), the strain to εc(t) (ε₊(t) for a first-order film), X to max(|X|, 1e-3·h0), V to max(|V|, 1e-6·V0)",
        ),
        "only with stepping = \"adaptive\"",
    ),
    rule(
        k(
            "time.dt_max",
            Real,
            "s",
            Derived("time.end (adaptive: no cap)"),
            Range::Positive,
            "longest adaptive step (not needed for accuracy: the error control sets the step)",
        ),
        "<= time.end; only with stepping = \"adaptive\"",
    ),
    rule(
        k(
            "time.dt_min",
            Real,
            "s",
            Derived("1e-6·min(time.dt, time.dt_max) (adaptive)"),
            Range::Positive,
            "shortest adaptive step, accepted whatever its error (counted as forced)",
        ),
        "<= min(time.dt, time.dt_max); only with stepping = \"adaptive\"",
    ),
    k(
        "time.max_events",
        Integer,
        "–",
        Off("none (run to time.end)"),
        Range::Integers(1, i64::MAX),
        "stop once this many melting events have ended (the film recovered); time.end still bounds the run",
    ),
    k(
        "time.max_open_event",
        Real,
        "s",
        Off("none (run to time.end)"),
        Range::Positive,
        "stop once an event has stayed open this long (the film has not recovered; a sweep point's regime is clear)",
    ),
    k(
        "time.until",
        Choice(&["end", "periodic"]),
        "–",
        Value("end"),
        Range::Word,
        "end: run to time.end; periodic: stop at the end of the event after which the last time.steady_cycles cycles repeat (period, stamp advance and peak force within time.steady_rtol), or at time.end; run.json's summary says `steady` either way",
    ),
    k(
        "time.steady_cycles",
        Integer,
        "–",
        Value("3"),
        Range::Integers(1, 1000),
        "cycles (onset to onset) that must repeat for a run to count as steady",
    ),
    k(
        "time.steady_rtol",
        Real,
        "–",
        Value("1e-3"),
        Range::Open(0.0, 1.0),
        "relative tolerance of that repetition (each of the cycles against the last one)",
    ),
    rule(
        k(
            "output.profile_times",
            RealList,
            "s",
            Derived("[time.end]"),
            Range::ByRule,
            "times at which φ, ε, τ, u0, u3D are written against r (profiles.csv)",
        ),
        "each within [0, time.end]",
    ),
    rule(
        k(
            "output.probe_radii",
            RealList,
            "m",
            Value("[]"),
            Range::ByRule,
            "radii at which φ(t) and the last melting time are written (probes.csv)",
        ),
        "each within [0, contact.radius)",
    ),
    k(
        "output.event_merge_gap",
        Real,
        "s",
        Value("0"),
        Range::NonNegative,
        "a melting that begins less than this after the previous event ended continues it (0 = never)",
    ),
    k(
        "output.event_recovery",
        Real,
        "–",
        Value("2"),
        Range::Above(1.0),
        "an event ends when every node is back above this multiple of melt_threshold (capped at halfway to √(A/a))",
    ),
    k(
        "output.series_interval",
        Real,
        "s",
        Value("1e-7"),
        Range::Positive,
        "interval between rows of series.csv and probes.csv (rows at the first step at or after each mark)",
    ),
    k(
        "numerics.coupling_tol",
        Real,
        "–",
        Derived("time.tolerance / 100 (adaptive), 1e-10 (fixed)"),
        Range::Open(0.0, 1.0),
        "relative residual to which the accurate scheme solves the elastic coupling",
    ),
    k(
        "numerics.runaway_stress_factor",
        Real,
        "–",
        Value("10"),
        Range::Above(1.0),
        "a step fails when |τ| exceeds this multiple of tau_max (for a first-order film: of its stationary curve's peak, when larger)",
    ),
    k(
        "numerics.operator",
        Choice(&["auto", "fast", "dense"]),
        "–",
        Value("auto"),
        Range::Word,
        "MDR transforms: fast (hierarchical low-rank, O(N)), dense (O(N²)); auto = fast for accurate, dense for literal",
    ),
];

/// Warnings for values outside their key's usual range (likely unit slips), from the scene
/// as resolved (`table`: the resolved scene as a TOML table).
#[must_use]
pub fn unusual_values(table: &toml::Table) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for key in KEYS.iter().filter(|k| k.usual.is_some()) {
        let path: Vec<String> = key.path.split('.').map(str::to_string).collect();
        let Some(v) = crate::scene::error::lookup(table, &path).and_then(|v| match v {
            toml::Value::Float(f) => Some(*f),
            toml::Value::Integer(i) => Some(*i as f64),
            _ => None,
        }) else {
            continue;
        };
        if key.unusual(v)
            && let Some((lo, hi)) = key.usual
        {
            out.push((
                key.path.to_string(),
                format!(
                    "{} = {} {} is outside the usual range [{lo:e}, {hi:e}] {} for this model \
                     (a unit slip?); running anyway",
                    key.path,
                    human(v),
                    key.unit,
                    key.unit
                ),
            ));
        }
    }
    out
}

/// The scene keys as a Markdown section (one table per section of the scene file).
#[must_use]
pub fn markdown() -> String {
    let mut out = String::from(
        "## Scene keys\n\nAll quantities SI. Unknown keys are an error naming the key and its \
         section. A value outside its *usual* range draws a warning (a likely unit slip), not \
         an error.\n",
    );
    let mut section = "";
    for key in KEYS {
        let sec = key.path.rsplit_once('.').map_or("(top level)", |(s, _)| s);
        if sec != section {
            section = sec;
            out.push_str(&format!(
                "\n### `{}`\n\n| key | unit | default | allowed | usual | meaning |\n|---|---|---|---|---|---|\n",
                if sec == "(top level)" { sec.to_string() } else { format!("[{sec}]") }
            ));
        }
        let usual = key
            .usual
            .map_or_else(String::new, |(lo, hi)| format!("[{lo:e}, {hi:e}]"));
        out.push_str(&format!(
            "| `{}` | {} | {} | {} | {} | {} |\n",
            key.path,
            key.unit,
            key.default.describe().replace('|', "\\|"),
            key.allowed().replace('|', "\\|"),
            usual,
            key.meaning.replace('|', "\\|")
        ));
    }
    out
}

/// The table as aligned text (`stickslip keys`).
#[must_use]
pub fn table_text() -> String {
    let mut out = String::new();
    for key in KEYS {
        out.push_str(&format!(
            "{}  [{}]  default: {}\n    allowed: {}\n    {}\n",
            key.path,
            key.unit,
            key.default.describe(),
            key.allowed(),
            key.meaning
        ));
        if let Some((lo, hi)) = key.usual {
            out.push_str(&format!(
                "    usual: [{lo:e}, {hi:e}] {} (outside: a warning)\n",
                key.unit
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_are_unique_and_sorted_by_section() {
        let mut seen = std::collections::HashSet::new();
        for k in KEYS {
            assert!(seen.insert(k.path), "{} twice", k.path);
        }
    }

    #[test]
    fn ranges_say_what_they_check() {
        let r = key("contact.radius");
        assert!(r.check(2e-5).is_ok());
        let e = r.check(1e16).unwrap_err().to_string();
        assert!(e.contains("contact.radius = 1e16"), "{e}");
        assert!(e.contains("[1e-15, 1e15] m"), "{e}");
        assert!(key("contact.radius").unusual(20.0));
        assert!(!key("contact.radius").unusual(2e-5));
        assert!(key("time.tolerance").check(1.0).is_err());
        assert!(key("contact.nu1").check(0.5).is_ok());
        assert!(key("contact.nu1").check(-1.0).is_err());
    }
}
