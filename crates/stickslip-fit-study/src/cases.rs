//! The study's fits: each a scene with known ("true") parameter values, the free parameters
//! with their bounds, the trace's window, sampling and noise, at the full size or the
//! `--quick` smoke size. The truth differs from the scene's own values (where the search also
//! starts), so every fit has to move.

use serde::{Deserialize, Serialize};
use stickslip_run::keys;

/// fig2's drive-spring scene at N = 100 and the h0 = 1 nm SFA contact, under
/// `validation/scenes/`.
pub const FIG2: &str = "fig2.toml";
/// The SFA contact's scene.
pub const SFA: &str = "sfa.toml";
/// The drive's dashpot of the damped contact, N·s/m: damping ratio ½ with the SFA scene's
/// K = 5000 N/m and m = 0.1 kg (c = 2ζ·√(K·m)).
pub const SFA_DAMPING: f64 = 22.360_679_774_997_898;

/// One synthetic fit problem.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Case {
    /// Short name (`A`, `B`, `sfa4`, `viscous`).
    pub id: String,
    /// What it is, in words.
    pub title: String,
    /// The scene file under `validation/scenes/`.
    pub scene: String,
    /// Overrides of the scene (`KEY=VALUE`): the known quantities of this case.
    pub settings: Vec<String>,
    /// The free parameters' keys and true values.
    pub truth: Vec<(String, f64)>,
    /// The free parameters as the fit takes them, `KEY=LO:HI`, in the order of `truth`.
    pub params: Vec<String>,
    /// How the trace's window is chosen.
    pub window: Window,
    /// The spacing of the samples, s.
    pub spacing_s: f64,
    /// The trace's last time, s (its samples are evenly spaced over (0, end]); set by
    /// [`Window::end_s`] from the true model's meltings unless fixed.
    pub end_s: f64,
    /// Samples of the trace: end / spacing.
    pub samples: usize,
    /// Standard deviation of the noise added to F, N.
    pub noise_n: f64,
}

impl Case {
    /// The truth as `KEY=VALUE` overrides.
    #[must_use]
    pub fn truth_settings(&self) -> Vec<String> {
        self.truth
            .iter()
            .map(|(k, v)| format!("{k}={v:e}"))
            .collect()
    }

    /// Sets the window's end (and the samples) to `end_s`.
    pub fn set_end(&mut self, end_s: f64) {
        self.end_s = end_s;
        self.samples = (end_s / self.spacing_s).round() as usize;
    }

    /// The case's contact.nodes as its settings give it ("?" when they do not).
    #[must_use]
    pub fn nodes(&self) -> String {
        stickslip_run::scene::overrides::value_in(keys::contact::NODES.path, &self.settings)
            .and_then(|v| v.as_integer())
            .map_or_else(|| "?".to_string(), |n| n.to_string())
    }

    /// The true value of `key`.
    #[must_use]
    pub fn true_value(&self, key: &str) -> Option<f64> {
        self.truth.iter().find(|(k, _)| k == key).map(|(_, v)| *v)
    }
}

/// How a case's window is chosen: fixed, or from the onsets of the true model's meltings (as
/// found by the fit's own event rule on the clean trace), so that a case holds the same
/// meltings at any N.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Window {
    /// Up to a fixed time, s.
    Fixed(f64),
    /// The first `count` meltings: up to half-way to the next onset, at most `after_s` past
    /// the last one.
    Meltings {
        /// Meltings in the window.
        count: usize,
        /// Largest time after the last one, s.
        after_s: f64,
        /// How far the true model is run to find them, s.
        horizon_s: f64,
    },
    /// The first slip of the stamp: the first meltings whose onsets follow each other within
    /// `gap_s`, and `after_s` past the last of them.
    FirstSlip {
        /// Largest interval between two meltings of one slip, s.
        gap_s: f64,
        /// Time after the slip's last melting, s.
        after_s: f64,
        /// How far the true model is run to find them, s.
        horizon_s: f64,
    },
}

impl Window {
    /// How far the true model must run to place the window, s.
    #[must_use]
    pub fn horizon_s(&self) -> f64 {
        match *self {
            Self::Fixed(end) => end,
            Self::Meltings { horizon_s, .. } | Self::FirstSlip { horizon_s, .. } => horizon_s,
        }
    }

    /// The window's end from the true model's melting onsets `onsets_s` (increasing).
    ///
    /// # Errors
    /// Fewer meltings than the window needs, in words.
    pub fn end_s(&self, onsets_s: &[f64]) -> Result<f64, String> {
        let short = |what: String| {
            format!(
                "the true model has {} melting(s) up to {} s, fewer than {what}",
                onsets_s.len(),
                self.horizon_s()
            )
        };
        match *self {
            Self::Fixed(end) => Ok(end),
            Self::Meltings { count, after_s, .. } => {
                let last = *onsets_s
                    .get(count.saturating_sub(1))
                    .filter(|_| count > 0)
                    .ok_or_else(|| short(format!("the {count} the window holds")))?;
                let next = onsets_s
                    .get(count)
                    .map_or(f64::INFINITY, |n| 0.5 * (last + n));
                Ok(next.min(last + after_s))
            }
            Self::FirstSlip { gap_s, after_s, .. } => {
                let first = onsets_s.first().ok_or_else(|| short("one".into()))?;
                let mut last = *first;
                for &t in &onsets_s[1..] {
                    if t - last > gap_s {
                        return Ok(last + after_s);
                    }
                    last = t;
                }
                Err(short("a whole slip (a gap after its meltings)".into()))
            }
        }
    }
}

/// The sizes of a study.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Sizes {
    /// The smoke size (`--quick`).
    pub quick: bool,
    /// Noise seeds per coverage set.
    pub seeds: usize,
    /// Seeds per level of the interval-width study.
    pub width_seeds: usize,
    /// Levels of the interval-width study (samples ×1, ×2, ×4, …).
    pub width_levels: usize,
    /// contact.nodes of fig2.
    pub fig2_nodes: usize,
    /// contact.nodes of the SFA contact.
    pub sfa_nodes: usize,
}

impl Sizes {
    /// The full study: 20 seeds per set, N = 100, four sampling levels of three seeds.
    #[must_use]
    pub fn full() -> Self {
        Self {
            quick: false,
            seeds: 20,
            width_seeds: 3,
            width_levels: 4,
            fig2_nodes: 100,
            sfa_nodes: 100,
        }
    }

    /// The smoke study: a few seeds at N = 30.
    #[must_use]
    pub fn quick() -> Self {
        Self {
            quick: true,
            seeds: 2,
            width_seeds: 1,
            width_levels: 2,
            fig2_nodes: 30,
            sfa_nodes: 30,
        }
    }
}

fn common(nodes: usize) -> Vec<String> {
    vec![
        keys::contact::NODES.set(nodes as i64).to_string(),
        keys::output::PROFILE_TIMES.set(Vec::new()).to_string(),
    ]
}

/// A case of `scene` with `settings`, the truth and its bounds, `window`, `spacing_s` and
/// `noise_n`.
fn case(
    (id, title, scene): (&str, &str, &str),
    settings: Vec<String>,
    free: &[(&str, f64, &str)],
    window: Window,
    spacing_s: f64,
    noise_n: f64,
) -> Case {
    let names: Vec<&str> = free
        .iter()
        .map(|(k, _, _)| k.rsplit('.').next().unwrap_or(k))
        .collect();
    let mut c = Case {
        id: id.into(),
        title: format!("{title}: {} free", names.join(", ")),
        scene: scene.into(),
        settings,
        truth: free
            .iter()
            .map(|(k, v, _)| ((*k).to_string(), *v))
            .collect(),
        params: free.iter().map(|(k, _, b)| format!("{k}={b}")).collect(),
        window,
        spacing_s,
        end_s: 0.0,
        samples: 0,
        noise_n,
    };
    if let Window::Fixed(end) = window {
        c.set_end(end);
    }
    c
}

/// `free`, or at the smoke size its first two (τmax and γ): a four-parameter fit of the SFA
/// contact takes many minutes even at N = 30.
fn smoke<'a>(sizes: &Sizes, free: &'a [(&'a str, f64, &'a str)]) -> &'a [(&'a str, f64, &'a str)] {
    if sizes.quick { &free[..2] } else { free }
}

/// τmax and γ, their truth and bounds.
const TAU_GAMMA: [(&str, f64, &str); 2] = [
    ("lubricant.tau_max", 1.15e6, "5e5:2e6"),
    ("lubricant.gamma", 8.0, "3:30"),
];

/// Set A: fig2 (1.3 ms, ten meltings at N = 100), τmax and γ free, sampled every 2 µs, noise
/// of 1e-5 N (about 1 % of the peaks).
#[must_use]
pub fn set_a(sizes: &Sizes) -> Case {
    let end_s = if sizes.quick { 1e-3 } else { 1.3e-3 };
    case(
        ("A", "fig2", FIG2),
        common(sizes.fig2_nodes),
        &TAU_GAMMA,
        Window::Fixed(end_s),
        2e-6,
        1e-5,
    )
}

/// Set B: the SFA contact (a0 = 20 µm, h0 = 1 nm, K = 5000 N/m, V0 = 1 µm/s) over the first
/// four meltings of its first slip, τmax and γ free, sampled every µs (a melting's drop takes
/// a few µs), noise of 5e-6 N (about 1 % of the peaks).
#[must_use]
pub fn set_b(sizes: &Sizes) -> Case {
    case(
        ("B", "the SFA contact", SFA),
        common(sizes.sfa_nodes),
        &TAU_GAMMA,
        Window::Meltings {
            count: 4,
            after_s: 3e-3,
            horizon_s: 0.2,
        },
        1e-6,
        5e-6,
    )
}

/// The cost target's fit: the SFA contact's first slip (every melting of the stamp's first
/// slip) with τmax, γ, h0 and G* free, sampled every µs with noise of 5e-6 N.
#[must_use]
pub fn first_slip(sizes: &Sizes) -> Case {
    case(
        ("first-slip", "the SFA contact's first slip", SFA),
        common(sizes.sfa_nodes),
        smoke(
            sizes,
            &[
                TAU_GAMMA[0],
                TAU_GAMMA[1],
                ("contact.film_thickness", 1.2e-9, "5e-10:2e-9"),
                ("contact.g_eff", 1.3e9, "3e8:3e9"),
            ],
        ),
        Window::FirstSlip {
            gap_s: 5e-3,
            after_s: 4e-3,
            horizon_s: 0.25,
        },
        1e-6,
        5e-6,
    )
}

/// The damped, viscous SFA contact: a dashpot of damping ratio ½ on the drive
/// ([`SFA_DAMPING`], known) and a film of viscosity η = 10 Pa·s (the search starts from the
/// scene's values and η = 3 Pa·s), τmax, γ, h0 and η free, over its first four meltings,
/// sampled every µs with noise of 5e-6 N.
#[must_use]
pub fn viscous(sizes: &Sizes) -> Case {
    let mut settings = common(sizes.sfa_nodes);
    settings.push(keys::drive::DAMPING.set(SFA_DAMPING).to_string());
    settings.push(keys::lubricant::VISCOSITY.set(3.0).to_string());
    case(
        ("viscous", "the damped, viscous SFA contact", SFA),
        settings,
        smoke(
            sizes,
            &[
                TAU_GAMMA[0],
                TAU_GAMMA[1],
                ("contact.film_thickness", 1.2e-9, "5e-10:2e-9"),
                ("lubricant.viscosity", 10.0, "1:100"),
            ],
        ),
        Window::Meltings {
            count: 4,
            after_s: 3e-3,
            horizon_s: 0.2,
        },
        1e-6,
        5e-6,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn windows_end_after_their_meltings() {
        let on = [1.0, 2.0, 2.5, 3.0, 10.0, 10.5];
        let w = Window::Meltings {
            count: 2,
            after_s: 1.0,
            horizon_s: 20.0,
        };
        assert_eq!(w.end_s(&on), Ok(2.25));
        let w = Window::Meltings {
            count: 6,
            after_s: 1.0,
            horizon_s: 20.0,
        };
        assert_eq!(w.end_s(&on), Ok(11.5));
        let slip = Window::FirstSlip {
            gap_s: 2.0,
            after_s: 0.5,
            horizon_s: 20.0,
        };
        assert_eq!(slip.end_s(&on), Ok(3.5));
        assert!(slip.end_s(&on[..4]).is_err());
        assert!(w.end_s(&on[..3]).unwrap_err().contains("3 melting(s)"));
        let mut c = set_a(&Sizes::full());
        assert_eq!(c.samples, 650);
        c.set_end(2e-3);
        assert_eq!(c.samples, 1000);
    }
}
