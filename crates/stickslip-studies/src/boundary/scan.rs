//! `boundary --scan N`: every regime change along one key, each bisected and given an error.
//!
//! A first scan runs N values over the bracket (log-spaced when both ends are positive, else
//! evenly spaced), `jobs` at a time. Every pair of neighbouring scan points with different
//! regimes holds at least one change; each such pair is bisected to `rtol` (as
//! [`super::find`] does), and its final end pair is run again at a refined resolution along
//! each axis `verify` refines ([`crate::verify::refinements`]: 2N, and a tenth of the tolerance
//! or half the fixed step):
//!
//! - when the refined pair still differs in regime, the change stays inside the bracket: it
//!   moved by less than the bracket;
//! - when both ends now share a regime, the change left the bracket: it is followed outwards
//!   (steps doubling from the bracket's width, within the scan's range) until the regime
//!   changes, bisected there at the refined resolution, and the move is the distance between
//!   the two values; a change not found again within the range is *lost* (infinite error).
//!
//! Points whose stamp-scale regime stays undecided (see [`super`]) are no side of a change:
//! each stretch of them between decided points is listed as an [`UndecidedSpan`], as is a
//! bisection that meets one, and a warning says so; a scan with undecided stretches only ends
//! in [`BoundaryError::Undecided`].
//!
//! A change's error is the bracket's half-width plus the larger of the moves. A change whose
//! bisection met a third regime, two changes closer than the scan's spacing and a lost change
//! are warnings: more changes may hide between the scan's points.

use super::{
    Bisected, BoundaryError, Label, MAX_RUNS, Probe, Scale, Stage, bisect, check_range, midpoint,
    regime_at,
};
use crate::verify::{Axis, refinements};
use serde::Serialize;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use stickslip_run::scene::ResolvedScene;
use stickslip_run::summary::RegimeThresholds;

/// Points of the first scan when none are asked for: 8 intervals, a factor 10^(1/4) apart on
/// a decade.
pub const DEFAULT_SCAN: usize = 9;

/// Most points of a scan.
pub const MAX_SCAN: usize = 10_000;

/// Keys that set the time stepping: a change along one of them is not rerun at a finer
/// tolerance (the rerun would set the key back).
const TIME_STEPPING_KEYS: [&str; 2] = ["time.tolerance", "time.dt"];

/// How a scan runs.
#[derive(Debug, Clone, Copy)]
pub struct ScanOptions<'a> {
    /// Points of the first scan (≥ 2; the bracket's ends included).
    pub points: usize,
    /// Runs at a time (scan points, and changes bisected side by side).
    pub jobs: usize,
    /// The regime followed: the film's or the stamp's.
    pub scale: Scale,
    /// Where the runs are kept as they end, and found again by a rerun ([`super::cache`]).
    pub cache: Option<&'a super::cache::ProbeCache>,
}

impl Default for ScanOptions<'_> {
    fn default() -> Self {
        Self {
            points: DEFAULT_SCAN,
            jobs: 2,
            scale: Scale::Film,
            cache: None,
        }
    }
}

/// A change's move at a refined resolution.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Shift {
    /// The refinement (`Space`: 2N; `Time`: tolerance/10 or Δt/2).
    pub stage: Stage,
    /// The change's value at that resolution (the unrefined value when it stayed inside the
    /// bracket); none when it was not found again within the scan's range.
    pub value: Option<f64>,
    /// How far it moved, in the key's unit (0 inside the bracket, infinite when lost).
    pub moved: f64,
    /// Runs this check took.
    pub runs: usize,
}

/// One regime change.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Change {
    /// The critical value: the midpoint of the final bracket.
    pub value: f64,
    /// The last value with the lower side's regime.
    pub below: Probe,
    /// The first value with another regime.
    pub above: Probe,
    /// Half the final bracket's width, in the key's unit.
    pub bracket: f64,
    /// The moves at refined resolutions (none when no refinement applies).
    pub shifts: Vec<Shift>,
    /// The error of `value`: `bracket` plus the largest move (infinite when lost).
    pub error: f64,
    /// A regime met inside the scan interval that is neither side's: another change nearby.
    pub third: Option<Label>,
    /// Runs for this change (its bisection's midpoints and its refined reruns).
    pub runs: usize,
    /// False for a change an interrupt cut short: its bracket is as far as the bisection got,
    /// and its refined reruns are those that ended.
    pub complete: bool,
}

/// A stretch of the range where the regime stayed undecided (the stamp's `transient` over
/// [`super::UNDECIDED_DOUBLINGS`] doublings of the window): a change may lie inside, between
/// the decided regimes at its ends, but it is not located and has no error.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UndecidedSpan {
    /// The last decided value below (or the range's first point, when undecided).
    pub below: Probe,
    /// The first decided value above (or the range's last point, when undecided).
    pub above: Probe,
    /// The undecided values met inside.
    pub undecided: Vec<f64>,
}

/// What a scan found.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Scan {
    /// The key searched.
    pub key: String,
    /// The lower end of the range.
    pub lo: f64,
    /// The upper end.
    pub hi: f64,
    /// The scan's points with their regimes, in increasing value.
    pub points: Vec<Probe>,
    /// Every change found, in increasing value.
    pub changes: Vec<Change>,
    /// Every stretch whose regime stayed undecided, in increasing value: listed, never
    /// counted as a change.
    pub undecided: Vec<UndecidedSpan>,
    /// What the scan cannot vouch for (changes closer than its spacing, a third regime inside
    /// a bisection, a change lost at a refined resolution, a refinement not made).
    pub warnings: Vec<String>,
    /// Runs in all.
    pub runs: usize,
    /// Points geometric (both ends > 0) or arithmetic.
    pub geometric: bool,
    /// The scan's spacing: the ratio of neighbouring points (geometric), or their difference.
    pub spacing: f64,
    /// The relative tolerance of the bisections.
    pub rtol: f64,
}

/// The scan's values from `a` to `b`, ends exact.
fn scan_values(a: f64, b: f64, n: usize, geometric: bool) -> Vec<f64> {
    (0..n)
        .map(|i| {
            let f = i as f64 / (n - 1) as f64;
            if i == 0 {
                a
            } else if i == n - 1 {
                b
            } else if geometric {
                a * (b / a).powf(f)
            } else {
                a + (b - a) * f
            }
        })
        .collect()
}

/// The shared context of one scan's runs.
struct Ctx<'a> {
    key: &'a str,
    lo: f64,
    hi: f64,
    rtol: f64,
    geometric: bool,
    thresholds: RegimeThresholds,
    scale: Scale,
    interrupt: Option<&'a AtomicBool>,
    cache: Option<&'a super::cache::ProbeCache>,
    on_probe: &'a (dyn Fn(&Probe) + Sync),
    runs: AtomicUsize,
}

impl Ctx<'_> {
    /// The regime of `scene` at `value` (`None`: interrupted), reported as `stage`.
    fn regime(
        &self,
        scene: &ResolvedScene,
        value: f64,
        stage: Stage,
    ) -> Result<Option<Label>, BoundaryError> {
        let r = regime_at(
            scene,
            self.key,
            value,
            (self.scale, self.thresholds),
            (self.interrupt, self.cache),
        )?;
        if let Some(regime) = r {
            self.runs.fetch_add(1, Ordering::Relaxed);
            (self.on_probe)(&Probe {
                value,
                regime,
                stage,
            });
        }
        Ok(r)
    }

    fn interrupted(&self) -> BoundaryError {
        BoundaryError::Interrupted {
            runs: self.runs.load(Ordering::Relaxed),
            lo: self.lo,
            hi: self.hi,
        }
    }

    /// Bisects `[a, b]` on `scene`, runs counted in `runs`; `Err` of the bracket so far when
    /// interrupted.
    fn bisect_on(
        &self,
        scene: &ResolvedScene,
        stage: Stage,
        a: (f64, Label),
        b: (f64, Label),
    ) -> Result<Result<Bisected, Bisected>, BoundaryError> {
        let mut regime = |v: f64| self.regime(scene, v, stage);
        bisect(a, b, self.rtol, self.geometric, MAX_RUNS, &mut regime)
    }

    /// Where the change bisected to `found` (lower regime `ra`) lies at the refined
    /// resolution `scene` (see the module docs).
    fn shift(
        &self,
        scene: &ResolvedScene,
        stage: Stage,
        found: &Bisected,
        ra: Label,
        value: f64,
    ) -> Result<Shift, BoundaryError> {
        // This change's runs (others may run meanwhile on other threads).
        let count = std::cell::Cell::new(0);
        let runs = |_: &Self| count.get();
        let at = |v: f64| -> Result<Label, BoundaryError> {
            count.set(count.get() + 1);
            self.regime(scene, v, stage)?
                .ok_or_else(|| self.interrupted())
        };
        let (ra2, rb2) = (at(found.a)?, at(found.b)?);
        if ra2 != rb2 {
            return Ok(Shift {
                stage,
                value: Some(value),
                moved: 0.0,
                runs: runs(self),
            });
        }
        // Both ends share a regime now: the change moved up when that is the lower side's
        // (or a third one), down when it is the upper side's.
        let up = ra2 == ra || ra2 != found.rb;
        let width = if self.geometric {
            (found.b / found.a).ln()
        } else {
            found.b - found.a
        };
        let (mut inner, mut step) = (if up { found.b } else { found.a }, width);
        loop {
            let sign = if up { 1.0 } else { -1.0 };
            let outer = if self.geometric {
                inner * (sign * step).exp()
            } else {
                inner + sign * step
            }
            .clamp(self.lo, self.hi);
            if outer == inner {
                return Ok(Shift {
                    stage,
                    value: None,
                    moved: f64::INFINITY,
                    runs: runs(self),
                });
            }
            let r = at(outer)?;
            if r != ra2 {
                let (lower, upper) = if up {
                    ((inner, ra2), (outer, r))
                } else {
                    ((outer, r), (inner, ra2))
                };
                let again = self
                    .bisect_on(scene, stage, lower, upper)?
                    .map_err(|_| self.interrupted())?;
                count.set(count.get() + again.runs);
                let v = midpoint(again.a, again.b, self.geometric);
                return Ok(Shift {
                    stage,
                    value: Some(v),
                    moved: (v - value).abs(),
                    runs: runs(self),
                });
            }
            inner = outer;
            step *= 2.0;
        }
    }
}

/// Scans `key` over `[lo, hi]` on `base`, then bisects and checks every change found (see
/// the module docs). `on_probe` sees every run as it ends (from the worker threads); `tick`
/// is called on this thread about five times a second while runs go on.
///
/// # Errors
/// A bad key, range, tolerance or scan size; a run that fails ([`BoundaryError::Failed`]:
/// its regime is unknown, so is every change next to it); Ctrl-C; no change among the
/// scan's points ([`BoundaryError::SameRegime`]).
#[allow(clippy::too_many_arguments)]
pub fn scan(
    base: &ResolvedScene,
    key: &str,
    (lo, hi): (f64, f64),
    rtol: f64,
    options: ScanOptions<'_>,
    thresholds: RegimeThresholds,
    interrupt: Option<&AtomicBool>,
    on_probe: &(dyn Fn(&Probe) + Sync),
    tick: &mut dyn FnMut(),
) -> Result<Scan, BoundaryError> {
    check_range(key, lo, hi, rtol)?;
    if !(2..=MAX_SCAN).contains(&options.points) {
        return Err(BoundaryError::Invalid {
            name: "--scan",
            value: options.points.to_string(),
            allowed: format!("2 … {MAX_SCAN} points (the range's ends included)"),
        });
    }
    let (a, b) = (lo.min(hi), lo.max(hi));
    let geometric = a > 0.0;
    let ctx = Ctx {
        key,
        lo: a,
        hi: b,
        rtol,
        geometric,
        thresholds,
        scale: options.scale,
        interrupt,
        cache: options.cache,
        on_probe,
        runs: AtomicUsize::new(0),
    };
    let values = scan_values(a, b, options.points, geometric);
    let regimes = crate::pool::map(
        values.len(),
        options.jobs,
        &|i| ctx.regime(base, values[i], Stage::Scan),
        tick,
    );
    let mut points = Vec::with_capacity(values.len());
    let mut cut = false;
    for (value, r) in values.iter().zip(regimes) {
        let Some(regime) = r? else {
            cut = true;
            continue;
        };
        points.push(Probe {
            value: *value,
            regime,
            stage: Stage::Scan,
        });
    }
    let spacing = if geometric {
        values[1] / values[0]
    } else {
        values[1] - values[0]
    };
    let result = |points: Vec<Probe>, changes, undecided, warnings| Scan {
        key: key.to_string(),
        lo: a,
        hi: b,
        points,
        runs: ctx.runs.load(Ordering::Relaxed),
        changes,
        undecided,
        warnings,
        geometric,
        spacing,
        rtol,
    };
    if cut {
        // Interrupted in the first scan: the changes between the points that ended, each
        // bracketed by them and not bisected.
        let (pairs, undecided) = split_pairs(&points);
        let changes = pairs
            .iter()
            .map(|&i| unbisected(points[i - 1], points[i]))
            .collect();
        return Err(BoundaryError::ScanInterrupted {
            runs: ctx.runs.load(Ordering::Relaxed),
            partial: Box::new(result(points, changes, undecided, Vec::new())),
        });
    }
    let (pairs, mut undecided) = split_pairs(&points);
    if pairs.is_empty() && undecided.is_empty() {
        return Err(BoundaryError::SameRegime {
            key: key.to_string(),
            lo: a,
            hi: b,
            regime: points[0].regime.name(),
            scanned: points.len() - 2,
        });
    }
    let mut warnings = Vec::new();
    let refined: Vec<(Stage, ResolvedScene)> = if TIME_STEPPING_KEYS.contains(&key) {
        warnings.push(format!(
            "{key} sets the time stepping: the changes are rerun at 2N only"
        ));
        refined_scenes(base, &mut warnings)
            .into_iter()
            .filter(|(s, _)| *s == Stage::Space)
            .collect()
    } else {
        refined_scenes(base, &mut warnings)
    };
    let change = |k: usize| -> Result<Result<Change, UndecidedSpan>, BoundaryError> {
        let (lower, upper) = (points[pairs[k] - 1], points[pairs[k]]);
        let (found, mut complete) = match ctx.bisect_on(
            base,
            Stage::Bisect,
            (lower.value, lower.regime),
            (upper.value, upper.regime),
        )? {
            Ok(found) => (found, true),
            Err(cut) => (cut, false),
        };
        // The bisection's last bracket: the span left undecided, or the change's.
        let below = Probe {
            value: found.a,
            regime: lower.regime,
            stage: Stage::Bisect,
        };
        let above = Probe {
            value: found.b,
            regime: found.rb,
            stage: Stage::Bisect,
        };
        if let Some(at) = found.undecided {
            return Ok(Err(UndecidedSpan {
                below,
                above,
                undecided: vec![at],
            }));
        }
        let value = midpoint(found.a, found.b, geometric);
        let mut shifts = Vec::new();
        for (stage, scene) in refined.iter().filter(|_| complete) {
            match ctx.shift(scene, *stage, &found, lower.regime, value) {
                Ok(s) => shifts.push(s),
                Err(BoundaryError::Interrupted { .. }) => {
                    complete = false;
                    break;
                }
                Err(e) => return Err(e),
            }
        }
        let bracket = 0.5 * (found.b - found.a);
        let error = bracket + shifts.iter().map(|s| s.moved).fold(0.0, f64::max);
        let runs = found.runs + shifts.iter().map(|s| s.runs).sum::<usize>();
        Ok(Ok(Change {
            value,
            below,
            above,
            bracket,
            shifts,
            error,
            third: found.third,
            runs,
            complete,
        }))
    };
    let found = crate::pool::map(pairs.len(), options.jobs, &change, tick);
    let mut changes = Vec::with_capacity(found.len());
    for c in found {
        match c? {
            Ok(c) => changes.push(c),
            Err(span) => undecided.push(span),
        }
    }
    undecided.sort_by(|x, y| x.below.value.total_cmp(&y.below.value));
    if changes.iter().any(|c| !c.complete) {
        return Err(BoundaryError::ScanInterrupted {
            runs: ctx.runs.load(Ordering::Relaxed),
            partial: Box::new(result(points, changes, undecided, warnings)),
        });
    }
    if changes.is_empty() {
        let span = &undecided[0];
        return Err(BoundaryError::Undecided {
            key: key.to_string(),
            at: span.undecided[0],
            lo: span.below.value,
            hi: span.above.value,
            factor: 1 << super::UNDECIDED_DOUBLINGS,
        });
    }
    for span in &undecided {
        warnings.push(format!(
            "{key}: between {:.4e} ({}) and {:.4e} ({}) the stamp-scale regime stays undecided \
             (transient) at {} value(s) even over {}× the window: a change there is not located \
             (a longer time.end or time.travel decides)",
            span.below.value,
            span.below.regime.said(),
            span.above.value,
            span.above.regime.said(),
            span.undecided.len(),
            1 << super::UNDECIDED_DOUBLINGS
        ));
    }
    warnings.extend(scan_warnings(&changes, geometric, &values, key));
    Ok(result(points, changes, undecided, warnings))
}

/// A change bracketed by two scan points and not bisected (an interrupted scan's).
fn unbisected(below: Probe, above: Probe) -> Change {
    let bracket = 0.5 * (above.value - below.value);
    Change {
        value: 0.5 * (below.value + above.value),
        below,
        above,
        bracket,
        shifts: Vec::new(),
        error: bracket,
        third: None,
        runs: 0,
        complete: false,
    }
}

/// The scan's neighbouring pairs whose regimes differ, both decided (the index of the upper
/// point), and the stretches of undecided points between decided ones (each listed once, with
/// the decided points around it, or the range's end when it reaches one).
fn split_pairs(points: &[Probe]) -> (Vec<usize>, Vec<UndecidedSpan>) {
    let mut pairs = Vec::new();
    let mut spans = Vec::new();
    let mut i = 0;
    while i < points.len() {
        if points[i].regime.decided() {
            if i > 0 && points[i - 1].regime.decided() && points[i - 1].regime != points[i].regime {
                pairs.push(i);
            }
            i += 1;
            continue;
        }
        let start = i;
        while i < points.len() && !points[i].regime.decided() {
            i += 1;
        }
        spans.push(UndecidedSpan {
            below: points[start.saturating_sub(1)],
            above: points[i.min(points.len() - 1)],
            undecided: points[start..i].iter().map(|p| p.value).collect(),
        });
    }
    (pairs, spans)
}

/// The refined scenes a change is rerun on, as stages; a refinement that does not resolve is
/// left out with a warning.
fn refined_scenes(base: &ResolvedScene, warnings: &mut Vec<String>) -> Vec<(Stage, ResolvedScene)> {
    match refinements(base) {
        Ok(r) => r
            .into_iter()
            .map(|(axis, s)| {
                let stage = match axis {
                    Axis::Space => Stage::Space,
                    Axis::Time => Stage::Time,
                };
                (stage, s)
            })
            .collect(),
        Err(e) => {
            warnings.push(format!(
                "the changes' errors count the bracket only: no refined rerun ({e})"
            ));
            Vec::new()
        }
    }
}

/// Warnings about what the scan may have missed.
fn scan_warnings(changes: &[Change], geometric: bool, values: &[f64], key: &str) -> Vec<String> {
    let mut out = Vec::new();
    let spacing = if geometric {
        (values[1] / values[0]).ln()
    } else {
        values[1] - values[0]
    };
    let apart = |x: f64, y: f64| if geometric { (y / x).ln() } else { y - x };
    for w in changes.windows(2) {
        if apart(w[0].value, w[1].value) < spacing {
            out.push(format!(
                "{key}: the changes at {:.4e} and {:.4e} are closer than the scan's spacing: more \
                 changes may lie between its points (a larger --scan finds them)",
                w[0].value, w[1].value
            ));
        }
    }
    for c in changes {
        if let Some(r) = c.third {
            out.push(format!(
                "{key}: between {:.4e} and {:.4e} the bisection met a third regime ({}): another \
                 change lies next to the one at {:.4e} (a larger --scan separates them)",
                c.below.value,
                c.above.value,
                r.name(),
                c.value
            ));
        }
        for s in &c.shifts {
            if s.value.is_none() {
                out.push(format!(
                    "{key}: the change at {:.4e} ({} → {}) is not found at {}: it is not \
                     resolved (infinite error)",
                    c.value,
                    c.below.regime.name(),
                    c.above.regime.name(),
                    s.stage.name()
                ));
            }
        }
    }
    out
}
