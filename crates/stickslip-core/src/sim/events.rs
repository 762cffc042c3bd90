//! Melting events, one per melt–recover cycle of the film, and the statistics of each cycle.
//!
//! ## The rule
//! An event **begins** when a node melts (φ < threshold, or melting located inside the step)
//! while no event is open. It stays open until the film has **recovered**: every node is back
//! at or above the recovery level
//!
//! φ_rec(t) = min(k·threshold, ½·(threshold + φ_eq(t))),  φ_eq(t) = √(A(t)/a)
//!
//! (φ_eq the unstrained solid film: for the first-order film its solid branch φ₊(0) at A(t)),
//!
//! k = `events.recovery_factor` (scene key `output.event_recovery`, default 2). That time is
//! the event's `t_end`. A melting that begins less than `merge_gap_s` after the previous event
//! ended continues that event (scene key `output.event_merge_gap`, default 0: off).
//!
//! ## Why a hysteresis and not a time gap
//! While a melting front passes, nodes cross the threshold one after another, and in the
//! accurate scheme each melting is instantaneous (a node touches the threshold and regrows
//! within the step), so the number of melted nodes drops to zero between two nodes of the
//! same front; with gaussian noise a node next to the front can also dip below the threshold
//! a few ns early. None of these returns the *film* above φ_rec, so none ends the event. A
//! fixed time gap, the earlier rule, merged whole cycles once the stick–slip period was
//! shorter than the gap (the rigid drive at 0.1–1 m/s has periods of 2.2–0.3 µs). The
//! hysteresis has no time scale: it separates cycles at any period as long as the film
//! regrows above φ_rec between them; k = 2 keeps cycles apart down to a recovery of a few
//! percent of φ_eq, where the regime rules (docs/model.md#regimes-and-friction-maps) call
//! the regime `smooth`.
//!
//! ## Cycle statistics
//! Each event also carries what happened from its onset to the next onset (or to the end of
//! the run): the largest area-weighted ⟨φ⟩ relative to φ_eq(t) (`recovery`) and the time-mean
//! friction force (`f_mean_n`), integrated over every step, not over sampled rows. The
//! tracker also counts the time during which no node was solid after the first onset, for
//! the `sliding` regime.

use super::energy::{EnergyBooks, EnergyFlows, StoredEnergy};
use serde::{Deserialize, Serialize};

pub use crate::config::EventConfig;

/// One melting event and the cycle that follows it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MeltingEvent {
    /// Event number, from 1.
    pub k: usize,
    /// Onset time, s: the first node melted (located inside the step by the accurate scheme,
    /// the step's end for the literal one).
    pub t_onset_s: f64,
    /// Radius of the outermost node melted at the onset, m.
    pub r_first_m: f64,
    /// Stamp position at the onset, m.
    pub x_onset_m: f64,
    /// Largest friction force since the previous event began (or since t = 0), N.
    pub f_peak_n: f64,
    /// Smallest radius melted during the event, m.
    pub r_min_m: f64,
    /// First time the innermost node (r = 0) melted during the event, s (located inside the
    /// step by the accurate scheme).
    pub t_center_s: Option<f64>,
    /// Largest area fraction below the melting threshold at one instant during the event.
    /// The accurate scheme melts a node and lets it regrow at once, so there this tends to 0
    /// as Δt → 0; [`MeltingEvent::melted_area`] is the extent of the melting.
    pub max_melted_fraction: f64,
    /// When the film had recovered (every node at or above the recovery level), s; `None`
    /// while the event is open.
    pub t_end_s: Option<f64>,
    /// Largest area-weighted ⟨φ⟩/φ_eq(t) from this onset to the next one (or the end of the
    /// run): 1 when the film re-solidifies fully between events.
    pub recovery: f64,
    /// Time-mean friction force from this onset to the next one (or the end of the run), N.
    pub f_mean_n: f64,
    /// Area fraction of the contact that melted at least once during the event (1 when the
    /// front reached the axis): converges as Δt → 0, unlike the instantaneous fraction.
    pub melted_area: f64,
    /// The energy books from this onset to the next one (or the end of the run); `None` for a
    /// run resumed from a checkpoint written before the books existed.
    #[serde(default)]
    pub energy: Option<CycleEnergy>,
}

/// The energy books over one cycle, from an onset (located inside its step, the books
/// interpolated linearly there) to the next onset or the end of the run, J.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct CycleEnergy {
    /// The flows over the cycle (drive, temperature, noise, and each sink).
    pub flows: EnergyFlows,
    /// The change of the stored energy over the cycle, J.
    pub stored_change_j: f64,
    /// in − sinks − stored change over the cycle, J (see [`super::energy`]).
    pub residual_j: f64,
}

impl CycleEnergy {
    /// The cycle from the books `start` to `end` (each: flows since t = 0, stored energy).
    #[must_use]
    pub fn between(start: &(EnergyFlows, StoredEnergy), end: &(EnergyFlows, StoredEnergy)) -> Self {
        let flows = end.0.plus_scaled(&start.0, -1.0);
        Self {
            flows,
            stored_change_j: end.1.total_j() - start.1.total_j(),
            residual_j: super::energy::residual_j(&flows, &start.1, &end.1),
        }
    }

    /// Every sink together over the cycle, J.
    #[must_use]
    pub fn dissipated_j(&self) -> f64 {
        self.flows.dissipated_j()
    }
}

/// What the tracker needs from one step.
#[derive(Debug, Clone, Copy)]
pub struct StepSample {
    /// Time, s.
    pub t_s: f64,
    /// When, within the step that ends at `t_s`, the first node fell below the threshold, s
    /// (located on the node's exact path where the scheme knows it, else `t_s`).
    pub first_melt_s: f64,
    /// Stamp velocity, m/s: places X at `first_melt_s`.
    pub v_m_per_s: f64,
    /// Stamp position, m.
    pub x_m: f64,
    /// Friction force, N.
    pub f_n: f64,
    /// Number of melted nodes.
    pub melted_nodes: usize,
    /// Number of nodes melted or below the recovery level.
    pub unrecovered_nodes: usize,
    /// Number of solid nodes (φ ≥ threshold and not melted during the step).
    pub solid_nodes: usize,
    /// Radius of the outermost melted node, m (meaningless when none is melted).
    pub outermost_melted_m: f64,
    /// Radius of the innermost melted node, m (meaningless when none is melted).
    pub innermost_melted_m: f64,
    /// Whether node 0 (the axis) is melted.
    pub center_melted: bool,
    /// When node 0 melted, s (located where the scheme knows it, else `t_s`).
    pub center_melt_s: f64,
    /// When, within the step, the last node rose through the recovery level, s (located
    /// where the scheme knows it, else `t_s`).
    pub recovered_s: f64,
    /// Area fraction below the melting threshold now.
    pub melted_fraction: f64,
    /// Area fraction that melted at least once since the open event began.
    pub swept_fraction: f64,
    /// Area-weighted mean of φ.
    pub phi_mean: f64,
    /// The unstrained solid film φ_eq now: √(A(t)/a) (0 when A ≤ 0), or the first-order film's
    /// φ₊(0) (0 when no solid branch exists).
    pub phi_eq: f64,
    /// The energy books' flows over the step (zero for the initial state), J.
    pub energy_step: EnergyFlows,
    /// The energy stored at `t_s`, J.
    pub stored: StoredEnergy,
}

/// Running sums of the open cycle (from the last onset on).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
struct CycleSums {
    /// ∫F dt since the onset, N·s.
    force_integral_ns: f64,
    /// Time since the onset, s.
    duration_s: f64,
    /// Largest ⟨φ⟩/φ_eq since the onset.
    recovery: f64,
}

/// Detects events step by step; its state is checkpointable (its serde form is part of the
/// checkpoint's, where every field must be present).
#[derive(Debug, PartialEq, Serialize, Deserialize)]
pub struct EventTracker {
    config: EventConfig,
    events: Vec<MeltingEvent>,
    open: bool,
    last_end_s: Option<f64>,
    f_max_since_onset_n: f64,
    /// Time and force of the previous step (for the trapezoidal ∫F dt).
    last_t_s: f64,
    last_f_n: f64,
    cycle: CycleSums,
    /// Time after the first onset during which no node was solid, s.
    no_solid_s: f64,
    /// Time and force of the step before the previous one (t_end is located no earlier).
    prev_t_s: f64,
    prev_f_n: f64,
    /// The energy books since t = 0; `None` when resumed from a checkpoint without them.
    #[serde(default)]
    books: Option<EnergyBooks>,
    /// The books at the open cycle's onset (flows since t = 0, stored energy).
    #[serde(default)]
    cycle_books: Option<(EnergyFlows, StoredEnergy)>,
}

/// Field by field, so that `clone_from` reuses the event list's buffer (see `SimState`).
impl Clone for EventTracker {
    fn clone(&self) -> Self {
        let Self {
            config,
            events,
            open,
            last_end_s,
            f_max_since_onset_n,
            last_t_s,
            last_f_n,
            cycle,
            no_solid_s,
            prev_t_s,
            prev_f_n,
            books,
            cycle_books,
        } = self;
        Self {
            config: *config,
            events: events.clone(),
            open: *open,
            last_end_s: *last_end_s,
            f_max_since_onset_n: *f_max_since_onset_n,
            last_t_s: *last_t_s,
            last_f_n: *last_f_n,
            cycle: *cycle,
            no_solid_s: *no_solid_s,
            prev_t_s: *prev_t_s,
            prev_f_n: *prev_f_n,
            books: *books,
            cycle_books: *cycle_books,
        }
    }

    fn clone_from(&mut self, source: &Self) {
        let Self {
            config,
            events,
            open,
            last_end_s,
            f_max_since_onset_n,
            last_t_s,
            last_f_n,
            cycle,
            no_solid_s,
            prev_t_s,
            prev_f_n,
            books,
            cycle_books,
        } = source;
        self.config = *config;
        self.events.clone_from(events);
        self.open = *open;
        self.last_end_s = *last_end_s;
        self.f_max_since_onset_n = *f_max_since_onset_n;
        self.last_t_s = *last_t_s;
        self.last_f_n = *last_f_n;
        self.cycle = *cycle;
        self.no_solid_s = *no_solid_s;
        self.prev_t_s = *prev_t_s;
        self.prev_f_n = *prev_f_n;
        self.books = *books;
        self.cycle_books = *cycle_books;
    }
}

impl EventTracker {
    /// A tracker with the given rules.
    #[must_use]
    pub fn new(config: EventConfig) -> Self {
        Self {
            config,
            events: Vec::new(),
            open: false,
            last_end_s: None,
            f_max_since_onset_n: f64::NEG_INFINITY,
            last_t_s: 0.0,
            last_f_n: 0.0,
            cycle: CycleSums::default(),
            no_solid_s: 0.0,
            prev_t_s: f64::NAN,
            prev_f_n: f64::NAN,
            books: None,
            cycle_books: None,
        }
    }

    /// The rules.
    #[must_use]
    pub fn config(&self) -> EventConfig {
        self.config
    }

    /// Feeds one step (or the initial state, with `t_s` = 0).
    pub fn observe(&mut self, s: &StepSample) {
        let dt = s.t_s - self.last_t_s;
        let books_before = self.books;
        match &mut self.books {
            Some(b) if dt > 0.0 => {
                b.flows = b.flows.plus_scaled(&s.energy_step, 1.0);
                b.stored = s.stored;
            }
            Some(_) => {}
            None if s.t_s == 0.0 && self.last_t_s == 0.0 && self.events.is_empty() => {
                self.books = Some(EnergyBooks {
                    flows: EnergyFlows::default(),
                    stored: s.stored,
                    stored_initial: s.stored,
                });
            }
            None => {}
        }
        if !self.events.is_empty() && dt > 0.0 {
            self.cycle.force_integral_ns += 0.5 * (self.last_f_n + s.f_n) * dt;
            self.cycle.duration_s += dt;
            if s.solid_nodes == 0 {
                self.no_solid_s += dt;
            }
        }
        self.prev_t_s = self.last_t_s;
        self.prev_f_n = self.last_f_n;
        self.last_t_s = s.t_s;
        self.last_f_n = s.f_n;
        self.f_max_since_onset_n = self.f_max_since_onset_n.max(s.f_n);
        if !self.open && s.melted_nodes > 0 {
            self.open = true;
            let continues = matches!(
                (self.events.last(), self.last_end_s),
                (Some(_), Some(t_end)) if s.t_s - t_end < self.config.merge_gap_s
            );
            if continues {
                if let Some(ev) = self.events.last_mut() {
                    ev.t_end_s = None;
                }
            } else {
                // The books at the onset, interpolated inside its step.
                let at_onset = books_before.map(|b| {
                    let w = if dt > 0.0 {
                        ((s.first_melt_s - (s.t_s - dt)) / dt).clamp(0.0, 1.0)
                    } else {
                        1.0
                    };
                    (
                        b.flows.plus_scaled(&s.energy_step, w),
                        b.stored.lerp(&s.stored, w),
                    )
                });
                // The step up to here belongs to the cycle that this onset closes.
                self.write_cycle(at_onset);
                self.cycle_books = at_onset;
                self.events.push(MeltingEvent {
                    k: self.events.len() + 1,
                    t_onset_s: s.first_melt_s,
                    r_first_m: s.outermost_melted_m,
                    x_onset_m: s.x_m - (s.t_s - s.first_melt_s) * s.v_m_per_s,
                    f_peak_n: self.f_max_since_onset_n,
                    r_min_m: s.innermost_melted_m,
                    t_center_s: None,
                    max_melted_fraction: 0.0,
                    t_end_s: None,
                    recovery: 0.0,
                    f_mean_n: 0.0,
                    melted_area: 0.0,
                    energy: None,
                });
                self.f_max_since_onset_n = s.f_n;
                self.cycle = CycleSums::default();
            }
        }
        if !self.events.is_empty() && s.phi_eq > 0.0 {
            self.cycle.recovery = self.cycle.recovery.max(s.phi_mean / s.phi_eq);
        }
        if s.melted_nodes > 0
            && let Some(ev) = self.events.last_mut()
        {
            ev.r_min_m = ev.r_min_m.min(s.innermost_melted_m);
            ev.max_melted_fraction = ev.max_melted_fraction.max(s.melted_fraction);
            ev.melted_area = ev.melted_area.max(s.swept_fraction);
            if s.center_melted && ev.t_center_s.is_none() {
                ev.t_center_s = Some(s.center_melt_s);
            }
        }
        if self.open && s.unrecovered_nodes == 0 {
            self.open = false;
            // The located recovery, never before the previous sample.
            let t_end = s.recovered_s.clamp(self.prev_t_s.min(s.t_s), s.t_s);
            let t_end = if t_end.is_finite() { t_end } else { s.t_s };
            self.last_end_s = Some(t_end);
            if let Some(ev) = self.events.last_mut() {
                ev.t_end_s = Some(t_end);
            }
        }
        self.write_cycle(self.books.map(|b| (b.flows, b.stored)));
    }

    /// Copies the open cycle's statistics into the last event, its energy books up to
    /// `books_end`.
    fn write_cycle(&mut self, books_end: Option<(EnergyFlows, StoredEnergy)>) {
        let cycle = self.cycle;
        let energy = match (&self.cycle_books, &books_end) {
            (Some(start), Some(end)) => Some(CycleEnergy::between(start, end)),
            _ => None,
        };
        if let Some(ev) = self.events.last_mut() {
            ev.energy = energy;
            ev.recovery = cycle.recovery;
            ev.f_mean_n = if cycle.duration_s > 0.0 {
                cycle.force_integral_ns / cycle.duration_s
            } else {
                self.last_f_n
            };
        }
    }

    /// Events so far (the last one's cycle statistics run to the current step).
    #[must_use]
    pub fn events(&self) -> &[MeltingEvent] {
        &self.events
    }

    /// Events that have ended (the film recovered after them).
    #[must_use]
    pub fn ended(&self) -> usize {
        self.events.len() - usize::from(self.open)
    }

    /// Whether an event is open now.
    #[must_use]
    pub fn is_open(&self) -> bool {
        self.open
    }

    /// The energy books since t = 0 (`None` when resumed from a checkpoint without them).
    #[must_use]
    pub fn books(&self) -> Option<&EnergyBooks> {
        self.books.as_ref()
    }

    /// Time after the first onset during which no node was solid, s.
    #[must_use]
    pub fn no_solid_time_s(&self) -> f64 {
        self.no_solid_s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(t_s: f64, melted: usize, unrecovered: usize) -> StepSample {
        StepSample {
            t_s,
            first_melt_s: t_s,
            v_m_per_s: 1.0,
            x_m: t_s,
            f_n: 1.0,
            melted_nodes: melted,
            unrecovered_nodes: unrecovered,
            solid_nodes: 10 - melted,
            outermost_melted_m: 1.0,
            innermost_melted_m: 0.5,
            center_melted: false,
            center_melt_s: t_s,
            recovered_s: t_s,
            melted_fraction: melted as f64 / 10.0,
            swept_fraction: melted as f64 / 10.0,
            phi_mean: 1.0,
            phi_eq: 1.0,
            energy_step: EnergyFlows::default(),
            stored: StoredEnergy::default(),
        }
    }

    #[test]
    fn a_cycles_energy_runs_from_its_onset_located_inside_its_step() {
        let mut tr = EventTracker::new(EventConfig::default());
        tr.observe(&sample(0.0, 0, 0));
        // Each step of 1 s brings 1 J of drive work and 0.25 J of Landau dissipation, and
        // stores the rest (stored = 0.75·t).
        let step = EnergyFlows {
            drive_work_j: 1.0,
            landau_j: 0.25,
            ..EnergyFlows::default()
        };
        for (t, melted) in [(1.0, 0), (2.0, 1), (3.0, 0), (4.0, 0)] {
            let mut s = sample(t, melted, melted);
            s.energy_step = step;
            s.stored.spring_j = 0.75 * t;
            if melted > 0 {
                s.first_melt_s = 1.5;
            }
            tr.observe(&s);
        }
        let e = tr.events()[0].energy.expect("books from t = 0");
        // From the located onset at 1.5 s to 4 s.
        assert!((e.flows.drive_work_j - 2.5).abs() < 1e-12, "{e:?}");
        assert!((e.dissipated_j() - 0.625).abs() < 1e-12, "{e:?}");
        assert!((e.stored_change_j - 1.875).abs() < 1e-12, "{e:?}");
        assert!(e.residual_j.abs() < 1e-12, "{e:?}");
        let books = tr.books().expect("books");
        assert!((books.flows.drive_work_j - 4.0).abs() < 1e-12);
        assert!(books.residual_j().abs() < 1e-12);
    }

    #[test]
    fn a_tracker_restored_without_books_reports_none() {
        // A checkpoint written before the books existed: no initial state is observed.
        let mut tr = EventTracker::new(EventConfig::default());
        tr.last_t_s = 1.0;
        tr.observe(&sample(2.0, 1, 1));
        assert!(tr.books().is_none());
        assert!(tr.events()[0].energy.is_none());
    }

    #[test]
    fn flicker_inside_an_unrecovered_film_is_one_event() {
        let mut tr = EventTracker::new(EventConfig::default());
        for (t, m, u) in [
            (0.0, 0, 0),
            (1.0, 2, 3),
            (2.0, 0, 3),
            (3.0, 1, 2),
            (4.0, 0, 0),
        ] {
            tr.observe(&sample(t, m, u));
        }
        assert_eq!(tr.events().len(), 1);
        assert_eq!(tr.events()[0].t_end_s, Some(4.0));
        assert_eq!(tr.ended(), 1);
    }

    #[test]
    fn a_recovered_film_starts_a_new_event_unless_within_the_merge_gap() {
        for (gap, expected) in [(0.0, 2), (0.5, 2), (2.0, 1)] {
            let mut tr = EventTracker::new(EventConfig {
                merge_gap_s: gap,
                recovery_factor: 2.0,
            });
            for (t, m, u) in [
                (0.0, 0, 0),
                (1.0, 1, 1),
                (2.0, 0, 0),
                (3.0, 1, 1),
                (4.0, 0, 1),
            ] {
                tr.observe(&sample(t, m, u));
            }
            assert_eq!(tr.events().len(), expected, "gap {gap}");
            assert_eq!(tr.ended(), expected - 1, "gap {gap}");
            assert!(tr.is_open());
        }
    }

    #[test]
    fn recovery_level_stays_between_threshold_and_equilibrium() {
        let c = EventConfig::default();
        assert_eq!(c.recovery_phi(0.01, 1.2), 0.02);
        assert_eq!(c.recovery_phi(0.01, 0.02), 0.015);
        assert_eq!(c.recovery_phi(0.01, 0.005), 0.02);
    }

    #[test]
    fn cycle_mean_force_is_the_trapezoidal_time_mean() {
        let mut tr = EventTracker::new(EventConfig::default());
        let mut s = sample(0.0, 0, 0);
        tr.observe(&s);
        s = sample(1.0, 1, 1);
        s.f_n = 2.0;
        tr.observe(&s);
        s = sample(3.0, 0, 0);
        s.f_n = 4.0;
        tr.observe(&s);
        assert_eq!(tr.events()[0].f_mean_n, 3.0);
    }
}
