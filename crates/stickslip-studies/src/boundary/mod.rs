//! The critical value of one scene key: where the regime changes between two of its values,
//! found by bisection (`stickslip boundary`, Python's `stickslip.boundary`).
//!
//! Both ends are run first; they must differ in regime. Each further run halves the bracket:
//! at its geometric midpoint when both ends are positive (a relative tolerance halves the
//! same number of times whatever the scale), else at its arithmetic one. The bracket closes
//! when (hi − lo) ≤ rtol·max(|lo|, |hi|); the value reported is its midpoint, so it is within
//! rtol/2 of every value of the bracket. A midpoint whose regime is neither end's (a third
//! regime in between) counts as the upper side, and the answer says which regime lies above.
//! Every run is the driver's, as in a sweep: the scene with `KEY=value` and nothing written.
//!
//! **Undecided runs.** On the stamp's scale `transient` means the window was too short to
//! decide (a longer run decides). Such a run is repeated over a doubled window (`time.end`,
//! and `time.travel` when the scene gives it), up to [`UNDECIDED_DOUBLINGS`] times; a value
//! still undecided then is no regime: it is never a side of a change. A search whose end or
//! midpoint stays undecided stops with [`BoundaryError::Undecided`], naming the bracket that
//! holds the change; a scan lists such stretches apart from its changes.
//!
//! [`scan`] scans the bracket first and finds every change between its points, each bisected
//! and given an error (the bracket and the change's move at a refined resolution).

pub mod cache;
pub mod scan;

use serde::Serialize;
use std::sync::atomic::AtomicBool;
use stickslip_run::cycles::StampRegime;
use stickslip_run::driver::{Control, NullSink, StartError};
use stickslip_run::keys::{self, KEYS, ValueType};
use stickslip_run::scene::{ResolvedScene, SceneError};
use stickslip_run::summary::{Regime, RegimeThresholds};

/// Most runs a search may take (the ends included): 60 halvings shrink any bracket of finite
/// doubles below a relative 1e-15.
pub const MAX_RUNS: usize = 64;

/// Times a run whose stamp-scale regime is undecided (`transient`: the window too short to
/// tell) is run again over a doubled window (`time.end`, and `time.travel` when given) before
/// its value counts as undecided: up to 2^3 = 8 times the scene's window.
pub const UNDECIDED_DOUBLINGS: u32 = 3;

/// One run of the search.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Probe {
    /// The key's value, in its unit.
    pub value: f64,
    /// The regime there.
    pub regime: Label,
    /// Which part of the search made the run.
    pub stage: Stage,
}

/// Which regime a search follows: the film's (`regime`, the default) or the stamp's
/// (`stamp_regime`: where slips stop recurring).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Scale {
    /// The film-scale regime of the summary.
    #[default]
    Film,
    /// The stamp-scale regime (docs/model.md#two-scales-meltings-and-slips).
    Stamp,
}

impl Scale {
    /// The scale's name (`film`, `stamp`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Film => "film",
            Self::Stamp => "stamp",
        }
    }

    /// The scale called `name`.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        [Self::Film, Self::Stamp]
            .into_iter()
            .find(|s| s.name() == name)
    }
}

/// A regime on either scale, as a search compares them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Label {
    /// A film-scale regime.
    Film(Regime),
    /// A stamp-scale regime.
    Stamp(StampRegime),
}

impl Label {
    /// The regime's name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Film(r) => r.name(),
            Self::Stamp(r) => r.name(),
        }
    }

    /// Whether the run decided a regime: the stamp's `transient` says the window was too short
    /// to tell (a longer run decides), so a search treats it as no regime, never as a side of
    /// a change.
    #[must_use]
    pub fn decided(self) -> bool {
        self != Self::Stamp(StampRegime::Transient)
    }

    /// The regime's name, with "(undecided)" after one that is not decided.
    #[must_use]
    pub fn said(self) -> String {
        if self.decided() {
            self.name().to_string()
        } else {
            format!("{} (undecided)", self.name())
        }
    }
}

impl Serialize for Label {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

/// The part of a search a run belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stage {
    /// A point of the first scan (the bracket's ends without a scan).
    Scan,
    /// A midpoint of a bisection at the scene's resolution.
    Bisect,
    /// A run at twice the nodes (checking a change).
    Space,
    /// A run at a tenth of the tolerance, or half the fixed step (checking a change).
    Time,
}

impl Stage {
    /// The stage's name in the output.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Scan => "scan",
            Self::Bisect => "bisect",
            Self::Space => "2N",
            Self::Time => "tolerance/10",
        }
    }
}

/// The result of a search.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Boundary {
    /// The key searched.
    pub key: String,
    /// The critical value: the midpoint of the final bracket.
    pub value: f64,
    /// The last value with the lower end's regime.
    pub below: Probe,
    /// The first value with another regime.
    pub above: Probe,
    /// Runs taken, the two ends included.
    pub runs: usize,
    /// Every run, in order.
    pub probes: Vec<Probe>,
    /// Midpoints geometric (both ends > 0) or arithmetic.
    pub geometric: bool,
    /// The relative tolerance asked for.
    pub rtol: f64,
}

/// Why a search could not be made.
#[derive(Debug, thiserror::Error)]
pub enum BoundaryError {
    /// The key is not a real-valued scene key.
    #[error("--key {key}: {why}; allowed: a scene key that takes a number (stickslip keys)")]
    Key {
        /// The key given.
        key: String,
        /// What is wrong with it.
        why: String,
    },
    /// A bad bracket or tolerance.
    #[error("{name} = {value}: out of range; allowed: {allowed}")]
    Invalid {
        /// The option.
        name: &'static str,
        /// Its value.
        value: String,
        /// The allowed range.
        allowed: String,
    },
    /// A value the scene refuses.
    #[error("{0}")]
    Scene(#[from] SceneError),
    /// The engine refused the configuration.
    #[error("{0}")]
    Start(#[from] StartError),
    /// Both ends have the same regime: nothing to bracket.
    #[error(
        "{key} = {} and {} both give the regime {regime}{}: no change to bracket; \
         allowed: ends with different regimes (widen the range, or map it with a sweep first)",
        stickslip_run::keys::human(*lo),
        stickslip_run::keys::human(*hi),
        between(*scanned)
    )]
    SameRegime {
        /// The key.
        key: String,
        /// Lower end.
        lo: f64,
        /// Upper end.
        hi: f64,
        /// Their regime.
        regime: &'static str,
        /// Points run between them (a scan's), all of that regime too.
        scanned: usize,
    },
    /// A run failed numerically: its regime is unknown.
    #[error(
        "{key} = {}: the run failed ({message}); the search stops there",
        stickslip_run::keys::human(*value)
    )]
    Failed {
        /// The key.
        key: String,
        /// Where.
        value: f64,
        /// The failure.
        message: String,
    },
    /// A run of the search stayed undecided (the stamp's `transient`) over
    /// [`UNDECIDED_DOUBLINGS`] doublings of its window: the change is bracketed, not located.
    #[error(
        "{key} = {}: the stamp-scale regime is undecided (transient) even over {factor}× the \
         scene's window; the change lies between {} and {} but cannot be narrowed there; \
         allowed: a longer time.end or time.travel, or --scan to list the decided changes",
        stickslip_run::keys::human(*at),
        stickslip_run::keys::human(*lo),
        stickslip_run::keys::human(*hi)
    )]
    Undecided {
        /// The key.
        key: String,
        /// Where the regime stayed undecided.
        at: f64,
        /// Lower side of the bracket.
        lo: f64,
        /// Upper side.
        hi: f64,
        /// The longest window tried, as a multiple of the scene's.
        factor: u32,
    },
    /// A scan interrupted (Ctrl-C, SIGTERM): what it had found by then — the scan's points
    /// that ended, every change bisected so far and the bracket each cut-short bisection had
    /// reached (marked incomplete).
    #[error("interrupted after {runs} runs{}", found_so_far(partial))]
    ScanInterrupted {
        /// Runs that ended.
        runs: usize,
        /// The scan as far as it got.
        partial: Box<scan::Scan>,
    },
    /// Interrupted (Ctrl-C); the bracket so far.
    #[error(
        "interrupted after {runs} runs; the boundary lies between {} and {}",
        stickslip_run::keys::human(*lo),
        stickslip_run::keys::human(*hi)
    )]
    Interrupted {
        /// Runs taken.
        runs: usize,
        /// Lower side of the bracket.
        lo: f64,
        /// Upper side.
        hi: f64,
    },
}

/// What an interrupted scan had found, in words.
fn found_so_far(partial: &scan::Scan) -> String {
    if partial.changes.is_empty() {
        return format!(
            "; {} of the scan's points had ended, no change bracketed yet",
            partial.points.len()
        );
    }
    let brackets: Vec<String> = partial
        .changes
        .iter()
        .map(|c| {
            format!(
                "{} → {} in [{:e}, {:e}]{}",
                c.below.regime.name(),
                c.above.regime.name(),
                c.below.value,
                c.above.value,
                if c.complete { "" } else { " (cut short)" }
            )
        })
        .collect();
    format!("; the changes so far: {}", brackets.join("; "))
}

/// The scan points between the ends, in words.
fn between(scanned: usize) -> String {
    match scanned {
        0 => String::new(),
        1 => " (as does the scan point between them)".into(),
        n => format!(" (as do the {n} scan points between them)"),
    }
}

/// Checks the key: a scene key taking a real number.
fn check_key(key: &str) -> Result<(), BoundaryError> {
    let bad = |why: &str| BoundaryError::Key {
        key: key.to_string(),
        why: why.to_string(),
    };
    match KEYS.iter().find(|k| k.path == key) {
        None => Err(bad("no such scene key")),
        Some(k) if k.value == ValueType::Real => Ok(()),
        Some(_) => Err(bad("it does not take a real number")),
    }
}

/// The regime on `scale` of `base` with `key = value`, or None when interrupted.
fn regime_at(
    base: &ResolvedScene,
    key: &str,
    value: f64,
    (scale, thresholds): (Scale, RegimeThresholds),
    (interrupt, cache): (Option<&AtomicBool>, Option<&cache::ProbeCache>),
) -> Result<Option<Label>, BoundaryError> {
    let fingerprint =
        cache.map(|_| cache::ProbeCache::fingerprint(base, key, value, (scale, thresholds)));
    if let (Some(c), Some(f)) = (cache, &fingerprint)
        && let Some(label) = c.get(f, scale)
    {
        return Ok(Some(label));
    }
    let label = regime_run(base, key, value, (scale, thresholds), interrupt)?;
    if let (Some(c), Some(f), Some(l)) = (cache, fingerprint, label) {
        c.put(f, l);
    }
    Ok(label)
}

/// The regime of one value: its run, lengthened while undecided (see the module docs).
fn regime_run(
    base: &ResolvedScene,
    key: &str,
    value: f64,
    (scale, thresholds): (Scale, RegimeThresholds),
    interrupt: Option<&AtomicBool>,
) -> Result<Option<Label>, BoundaryError> {
    let mut label = None;
    for doubling in 0..=UNDECIDED_DOUBLINGS {
        // The window first, the key last: a search along a window key keeps its value.
        let mut overrides = window_overrides(base, f64::from(1u32 << doubling));
        overrides.push(format!("{key}={value:e}"));
        let scene = base.with_overrides(&overrides)?;
        let mut control = Control {
            interrupt,
            thresholds,
            ..Control::default()
        };
        let outcome = stickslip_run::driver::run(&scene, &mut NullSink, &mut control)?;
        if outcome.stop == stickslip_run::outcome::StopReason::Interrupted {
            return Ok(None);
        }
        if let Some(f) = &outcome.failure {
            return Err(BoundaryError::Failed {
                key: key.to_string(),
                value,
                message: f.to_string(),
            });
        }
        let l = match scale {
            Scale::Film => Label::Film(outcome.summary.regime),
            Scale::Stamp => {
                Label::Stamp(outcome.summary.stamp_regime.unwrap_or(StampRegime::Creep))
            }
        };
        label = Some(l);
        if l.decided() {
            break;
        }
    }
    Ok(label)
}

/// The overrides that lengthen `base`'s window `factor` times (none for 1): `time.end`, and
/// `time.travel` when the scene gives it.
fn window_overrides(base: &ResolvedScene, factor: f64) -> Vec<String> {
    if factor == 1.0 {
        return Vec::new();
    }
    let time = base.resolved.time.as_ref();
    let mut out = vec![
        keys::time::END
            .set(factor * base.config.time.end_s)
            .to_string(),
    ];
    if let Some(travel) = time.and_then(|t| t.travel) {
        out.push(keys::time::TRAVEL.set(factor * travel).to_string());
    }
    out
}

/// Checks the bracket's ends and the tolerance.
fn check_range(key: &str, lo: f64, hi: f64, rtol: f64) -> Result<(), BoundaryError> {
    check_key(key)?;
    for (name, v) in [("--from", lo), ("--to", hi)] {
        if !v.is_finite() {
            return Err(BoundaryError::Invalid {
                name,
                value: stickslip_run::keys::human(v),
                allowed: "a finite number".into(),
            });
        }
    }
    if lo == hi {
        return Err(BoundaryError::Invalid {
            name: "--to",
            value: format!("{hi:e}"),
            allowed: format!("a value other than --from = {lo:e}"),
        });
    }
    if !(rtol > 0.0 && rtol <= 0.5) {
        return Err(BoundaryError::Invalid {
            name: "--rtol",
            value: stickslip_run::keys::human(rtol),
            allowed: "0 < rtol <= 0.5".into(),
        });
    }
    Ok(())
}

/// The midpoint of `[a, b]`: geometric or arithmetic.
fn midpoint(a: f64, b: f64, geometric: bool) -> f64 {
    if geometric {
        (a * b).sqrt()
    } else {
        0.5 * (a + b)
    }
}

/// A bisected bracket: `a` has the lower side's regime, `b` another.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Bisected {
    a: f64,
    b: f64,
    /// The regime at `b`.
    rb: Label,
    /// Midpoints run.
    runs: usize,
    /// A regime met inside that is neither end's (a second change nearby).
    third: Option<Label>,
    /// A midpoint whose regime stayed undecided: the bisection stopped there, with `[a, b]`
    /// holding it.
    undecided: Option<f64>,
}

/// Bisects `[a, b]` (regimes `ra` ≠ `rb`) until (b − a) ≤ rtol·max(|a|, |b|); `regime` runs
/// one value (`None`: interrupted; the bisection then gives back its bracket so far, as
/// `Err` of a [`Bisected`]).
fn bisect(
    (mut a, ra): (f64, Label),
    (mut b, mut rb): (f64, Label),
    rtol: f64,
    geometric: bool,
    max_runs: usize,
    regime: &mut dyn FnMut(f64) -> Result<Option<Label>, BoundaryError>,
) -> Result<Result<Bisected, Bisected>, BoundaryError> {
    let (rb0, mut runs, mut third) = (rb, 0, None);
    while b - a > rtol * a.abs().max(b.abs()) && runs < max_runs {
        let mid = midpoint(a, b, geometric);
        // Rounding can leave no double strictly inside the bracket.
        if !(mid > a && mid < b) {
            break;
        }
        let Some(r) = regime(mid)? else {
            return Ok(Err(Bisected {
                a,
                b,
                rb,
                runs,
                third,
                undecided: None,
            }));
        };
        runs += 1;
        if !r.decided() {
            return Ok(Ok(Bisected {
                a,
                b,
                rb,
                runs,
                third,
                undecided: Some(mid),
            }));
        }
        if r != ra && r != rb0 {
            third.get_or_insert(r);
        }
        if r == ra {
            a = mid;
        } else {
            b = mid;
            rb = r;
        }
    }
    Ok(Ok(Bisected {
        a,
        b,
        rb,
        runs,
        third,
        undecided: None,
    }))
}

/// Brackets the regime change of `base` along `key` between `lo` and `hi` and bisects it to
/// the relative tolerance `rtol`; `on_probe` sees every run as it ends.
///
/// # Errors
/// See [`BoundaryError`].
pub fn find(
    base: &ResolvedScene,
    key: &str,
    (lo, hi): (f64, f64),
    rtol: f64,
    thresholds: RegimeThresholds,
    interrupt: Option<&AtomicBool>,
    on_probe: &mut dyn FnMut(&Probe),
) -> Result<Boundary, BoundaryError> {
    check_range(key, lo, hi, rtol)?;
    let (a, b) = (lo.min(hi), lo.max(hi));
    let geometric = a > 0.0;
    let mut probes = Vec::new();
    let mut probe = |value: f64, stage: Stage| -> Result<Option<Label>, BoundaryError> {
        let r = regime_at(
            base,
            key,
            value,
            (Scale::Film, thresholds),
            (interrupt, None),
        )?;
        if let Some(regime) = r {
            let p = Probe {
                value,
                regime,
                stage,
            };
            on_probe(&p);
            probes.push(p);
        }
        Ok(r)
    };
    let interrupted =
        |runs: usize, a: f64, b: f64| BoundaryError::Interrupted { runs, lo: a, hi: b };
    let Some(ra) = probe(a, Stage::Scan)? else {
        return Err(interrupted(0, a, b));
    };
    let Some(rb) = probe(b, Stage::Scan)? else {
        return Err(interrupted(1, a, b));
    };
    let undecided = |at: f64, lo: f64, hi: f64| BoundaryError::Undecided {
        key: key.to_string(),
        at,
        lo,
        hi,
        factor: 1 << UNDECIDED_DOUBLINGS,
    };
    if !ra.decided() {
        return Err(undecided(a, a, b));
    }
    if !rb.decided() {
        return Err(undecided(b, a, b));
    }
    if ra == rb {
        return Err(BoundaryError::SameRegime {
            key: key.to_string(),
            lo: a,
            hi: b,
            regime: ra.name(),
            scanned: 0,
        });
    }
    let mut mid = |v: f64| probe(v, Stage::Bisect);
    let found = bisect((a, ra), (b, rb), rtol, geometric, MAX_RUNS - 2, &mut mid)?;
    let found = match found {
        Ok(found) => found,
        Err(cut) => return Err(interrupted(probes.len(), cut.a, cut.b)),
    };
    if let Some(at) = found.undecided {
        return Err(undecided(at, found.a, found.b));
    }
    Ok(Boundary {
        key: key.to_string(),
        value: midpoint(found.a, found.b, geometric),
        below: Probe {
            value: found.a,
            regime: ra,
            stage: Stage::Bisect,
        },
        above: Probe {
            value: found.b,
            regime: found.rb,
            stage: Stage::Bisect,
        },
        runs: probes.len(),
        probes,
        geometric,
        rtol,
    })
}
