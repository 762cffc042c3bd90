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
        if let Ok(style) = ProgressStyle::with_template(
            "{elapsed_precise} [{wide_bar}] {percent}%  {msg}, eta {eta}",
        ) {
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
        self.bar
            .set_message(format!("t = {:.4e} s, {} events", p.t_s, p.events));
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
