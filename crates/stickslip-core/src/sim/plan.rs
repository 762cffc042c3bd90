//! An adaptive run's accepted steps as a plan ([`PlannedStep`]), and the rule by which a step
//! that brings a melting onset is cut there, which the adaptive loop ([`super::adaptive`])
//! and a replay of its plan ([`super::replay`]) share.

use serde::{Deserialize, Serialize};

/// An onset located closer than this fraction of the step to its start is taken as is
/// (cutting the step there would leave a sliver).
const MIN_CUT_FRACTION: f64 = 1e-3;

/// Whether an accepted attempt of `h_s` that began with no event open (`was_open` false)
/// and located the first melting at `theta` of it is retaken to end at the melting (see
/// `adaptive::step`); `dt_min_s` the shortest step.
pub(super) fn cuts_to_onset(was_open: bool, theta: f64, h_s: f64, dt_min_s: f64) -> bool {
    !was_open && theta < 1.0 && theta > MIN_CUT_FRACTION && theta * h_s > dt_min_s
}

/// The length of the retake that ends just after an onset located at `theta` of an attempt of
/// `h_s` (the margin keeps the crossing inside it despite rounding).
pub(super) fn onset_retake_s(theta: f64, h_s: f64) -> f64 {
    theta * h_s * (1.0 + 1e-9)
}

/// How a recorded step is taken again.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum StepKind {
    /// Its length, cut at a first melting located inside it (the adaptive loop's rule).
    Free,
    /// An onset's cut: the attempt of the recorded length, retaken to end at the first
    /// melting it locates (taken whole when it locates none).
    Onset,
    /// Its length as is: a step the adaptive loop took while already cut to an onset.
    Held,
}

/// One accepted adaptive step as a replay takes it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PlannedStep {
    /// Length, s: the step's own, or for [`StepKind::Onset`] the attempt that was cut.
    pub h_s: f64,
    /// How it is taken.
    pub kind: StepKind,
    /// Whether it ended on its stop (a profile time or the end): a replay lands there too.
    pub landed: bool,
}

impl PlannedStep {
    /// A step cut at a first melting inside it, if any.
    pub(super) fn free(h_s: f64, landed: bool) -> Self {
        Self {
            h_s,
            kind: StepKind::Free,
            landed,
        }
    }

    /// The cut of the attempt of `attempt_s` at its onset.
    pub(super) fn onset(attempt_s: f64) -> Self {
        Self {
            h_s: attempt_s,
            kind: StepKind::Onset,
            landed: false,
        }
    }

    /// A step taken as is.
    pub(super) fn held(h_s: f64, landed: bool) -> Self {
        Self {
            h_s,
            kind: StepKind::Held,
            landed,
        }
    }
}
