//! Merged melting events: onset, first-melting radius, peak force, front arrival at the centre.
//!
//! An event begins when the number of melted nodes (φ < threshold) rises from zero. While a
//! melting front passes, nodes flicker around the threshold, so a rise that comes less than
//! `merge_gap_s` after the contact was last fully solid continues the current event.

use serde::{Deserialize, Serialize};

/// One merged melting event.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MeltingEvent {
    /// Event number, from 1.
    pub k: usize,
    /// Onset time, s: the melted count rose from zero (located inside the step by the
    /// accurate scheme, the step's end for the literal one).
    pub t_onset_s: f64,
    /// Radius of the outermost node melted at the onset, m.
    pub r_first_m: f64,
    /// Stamp position at the onset, m.
    pub x_onset_m: f64,
    /// Largest friction force since the previous event began (or since t = 0), N.
    pub f_peak_n: f64,
    /// Smallest radius melted during the event, m.
    pub r_min_m: f64,
    /// First time the innermost node (r = 0) was melted during the event, s.
    pub t_center_s: Option<f64>,
    /// Largest melted area fraction during the event.
    pub max_melted_fraction: f64,
    /// Last time the contact became fully solid again during the event, s.
    pub t_end_s: Option<f64>,
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
    /// Radius of the outermost melted node, m (meaningless when none is melted).
    pub outermost_melted_m: f64,
    /// Radius of the innermost melted node, m (meaningless when none is melted).
    pub innermost_melted_m: f64,
    /// Whether node 0 (the axis) is melted.
    pub center_melted: bool,
    /// Melted area fraction.
    pub melted_fraction: f64,
}

/// Detects and merges melting events step by step; its state is checkpointable.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EventTracker {
    merge_gap_s: f64,
    events: Vec<MeltingEvent>,
    melted_before: usize,
    last_solid_s: Option<f64>,
    f_max_since_onset_n: f64,
}

impl EventTracker {
    /// A tracker merging rises closer than `merge_gap_s` to the last return to fully solid.
    pub fn new(merge_gap_s: f64) -> Self {
        Self {
            merge_gap_s,
            events: Vec::new(),
            melted_before: 0,
            last_solid_s: None,
            f_max_since_onset_n: f64::NEG_INFINITY,
        }
    }

    /// Feeds one step.
    pub fn observe(&mut self, s: &StepSample) {
        self.f_max_since_onset_n = self.f_max_since_onset_n.max(s.f_n);
        if self.melted_before == 0 && s.melted_nodes > 0 {
            let continues = matches!(
                (self.events.last(), self.last_solid_s),
                (Some(_), Some(t_solid)) if s.t_s - t_solid < self.merge_gap_s
            );
            if !continues {
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
                });
                self.f_max_since_onset_n = s.f_n;
            }
        }
        if s.melted_nodes > 0
            && let Some(ev) = self.events.last_mut()
        {
            ev.r_min_m = ev.r_min_m.min(s.innermost_melted_m);
            ev.max_melted_fraction = ev.max_melted_fraction.max(s.melted_fraction);
            if s.center_melted && ev.t_center_s.is_none() {
                ev.t_center_s = Some(s.t_s);
            }
        }
        if self.melted_before > 0 && s.melted_nodes == 0 {
            self.last_solid_s = Some(s.t_s);
            if let Some(ev) = self.events.last_mut() {
                ev.t_end_s = Some(s.t_s);
            }
        }
        self.melted_before = s.melted_nodes;
    }

    /// Events so far.
    pub fn events(&self) -> &[MeltingEvent] {
        &self.events
    }
}
