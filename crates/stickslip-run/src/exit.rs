//! The command line's exit statuses as a type: each error of the run library says which kind
//! of ending it is, and the command line turns that into the process's status. The reference's
//! sentence on exit statuses is written from [`Exit::ALL`].

/// How a command ended, as its exit status.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Exit {
    /// It did what was asked.
    Success,
    /// An I/O error while writing output.
    Io,
    /// Bad input: a bad scene, bad arguments, an output directory holding an earlier run
    /// without `--force`, or a checkpoint that cannot be resumed.
    BadInput,
    /// A numerical failure or a refused configuration.
    Numerical,
    /// A result with parts that failed: a sweep whose map is complete but has failed or
    /// refused points, or `verify` with a quantity not within its accuracy.
    FailedPoints,
    /// `sweep merge` while points are missing.
    Incomplete,
    /// Interrupted by SIGINT or SIGTERM.
    Interrupted,
}

impl Exit {
    /// Every status, in the order of their codes.
    pub const ALL: [Self; 7] = [
        Self::Success,
        Self::Io,
        Self::BadInput,
        Self::Numerical,
        Self::FailedPoints,
        Self::Incomplete,
        Self::Interrupted,
    ];

    /// The process's exit status.
    #[must_use]
    pub const fn code(self) -> u8 {
        match self {
            Self::Success => 0,
            Self::Io => 1,
            Self::BadInput => 2,
            Self::Numerical => 3,
            Self::FailedPoints => 4,
            Self::Incomplete => 5,
            Self::Interrupted => 130,
        }
    }

    /// What the status means, for the reference.
    #[must_use]
    pub const fn meaning(self) -> &'static str {
        match self {
            Self::Success => "success",
            Self::Io => "an I/O error while writing output",
            Self::BadInput => {
                "a bad scene, bad arguments, an output directory holding an earlier run \
                 without `--force`, or a checkpoint `resume` cannot continue (none, damaged, \
                 of an older format, or of another build without `--allow-other-build`)"
            }
            Self::Numerical => "a numerical failure or a refused configuration",
            Self::FailedPoints => {
                "a sweep whose map is complete but has failed or refused points (their rows \
                 say why), or `verify` with a quantity not within --rtol (its table says \
                 which)"
            }
            Self::Incomplete => "`sweep merge` while points are missing",
            Self::Interrupted => {
                "interrupted (SIGINT/SIGTERM: a run writes a checkpoint and `stickslip resume \
                 DIR` finishes it; a sweep keeps its finished points and a rerun skips them)"
            }
        }
    }

    /// The reference's sentence: every status with its meaning.
    #[must_use]
    pub fn reference() -> String {
        let parts: Vec<String> = Self::ALL
            .iter()
            .map(|e| format!("{} {}", e.code(), e.meaning()))
            .collect();
        format!("Exit status: {}.", parts.join("; "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_are_distinct_and_in_order() {
        let codes: Vec<u8> = Exit::ALL.iter().map(|e| e.code()).collect();
        assert!(codes.windows(2).all(|w| w[0] < w[1]), "{codes:?}");
        assert!(Exit::reference().starts_with("Exit status: 0 success; 1 an I/O error"));
    }
}
