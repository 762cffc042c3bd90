//! The progress bar on stderr: shown after about a second, only on a terminal, never with
//! `--quiet`; position in simulated time.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::time::{Duration, Instant};
use stickslip_run::driver::Progress;

/// Runs shorter than this show no progress bar.
const DELAY: Duration = Duration::from_secs(1);
/// Positions of the bar (permille of the simulated interval).
const SCALE: u64 = 1000;

/// A progress bar over simulated time.
#[derive(Debug)]
pub struct Bar {
    bar: ProgressBar,
    started: Instant,
    enabled: bool,
    shown: bool,
}

impl Bar {
    /// A bar, hidden when `quiet` or when stderr is not a terminal.
    pub fn new(quiet: bool) -> Self {
        let bar = ProgressBar::with_draw_target(Some(SCALE), ProgressDrawTarget::hidden());
        if let Ok(style) =
            ProgressStyle::with_template("{elapsed_precise} [{wide_bar}] {percent}%  {msg}")
        {
            bar.set_style(style);
        }
        Self {
            bar,
            started: Instant::now(),
            enabled: !quiet && std::io::stderr().is_terminal(),
            shown: false,
        }
    }

    /// Updates the bar; never asks to stop (signals do that).
    pub fn update(&mut self, p: &Progress) -> bool {
        if !self.enabled {
            return false;
        }
        let frac = (p.t_s / p.end_s).clamp(0.0, 1.0);
        self.bar.set_position((frac * SCALE as f64) as u64);
        let eta = eta_text(self.started.elapsed().as_secs_f64(), frac);
        self.bar.set_message(format!(
            "t = {:.4e} s, {} events, eta {eta}",
            p.t_s, p.events
        ));
        if !self.shown && self.started.elapsed() >= DELAY {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
            self.shown = true;
        }
        false
    }

    /// Clears the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// The time left at `fraction` done after `elapsed_s`, at the run's mean rate so far.
///
/// indicatif's own estimate follows the latest rate, which swings with the adaptive step
/// (slow through an event, fast between events): it read "1s" at 41 %, 79 % and 90 % of an
/// 11 s run. The mean rate over the whole run so far does not swing that way.
#[must_use]
pub fn eta_text(elapsed_s: f64, fraction: f64) -> String {
    if !(fraction > 0.0 && elapsed_s.is_finite()) {
        return "?".into();
    }
    let left = elapsed_s * (1.0 - fraction.min(1.0)) / fraction;
    duration_text(left)
}

/// A duration as people read it: "7 s", "3 min 05 s", "2 h 04 min".
#[must_use]
pub fn duration_text(seconds: f64) -> String {
    let s = seconds.max(0.0).round() as u64;
    if s < 60 {
        format!("{s} s")
    } else if s < 3600 {
        format!("{} min {:02} s", s / 60, s % 60)
    } else {
        format!("{} h {:02} min", s / 3600, (s % 3600) / 60)
    }
}

#[cfg(test)]
mod tests {
    use super::{duration_text, eta_text};

    #[test]
    fn eta_is_the_mean_rate_so_far() {
        // 4.5 s for 41 % of an 11 s run: 6.5 s left, not 1 s.
        assert_eq!(eta_text(4.5, 0.41), "6 s");
        assert_eq!(eta_text(8.7, 0.79), "2 s");
        assert_eq!(eta_text(10.0, 0.5), "10 s");
        assert_eq!(eta_text(1.0, 0.0), "?");
        assert_eq!(eta_text(100.0, 1.0), "0 s");
        assert_eq!(duration_text(185.0), "3 min 05 s");
        assert_eq!(duration_text(7440.0), "2 h 04 min");
    }
}
