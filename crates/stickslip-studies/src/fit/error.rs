//! Why a fit could not be made, each with the kind of ending it is ([`Exit`]): bad input names
//! the field, the value and what is allowed; a fit none of whose runs succeeded is a numerical
//! failure.

use stickslip_run::exit::Exit;
use stickslip_run::scene::SceneError;

/// Why a fit could not be made.
#[derive(Debug, thiserror::Error)]
pub enum FitError {
    /// A bad field of the input: a parameter, a bound, a trace column or value, an option.
    #[error("{field} = {value} is invalid; allowed: {allowed}")]
    Input {
        /// What is wrong (`--param`, `trace t`, `--noise`, …).
        field: String,
        /// Its value, as given.
        value: String,
        /// What is allowed.
        allowed: String,
    },
    /// The trace file cannot be read.
    #[error("cannot read the trace {path}: {message}")]
    Read {
        /// The file.
        path: String,
        /// Why.
        message: String,
    },
    /// The scene with a parameter's value does not resolve.
    #[error("{0}")]
    Scene(#[from] Box<SceneError>),
    /// Interrupted before any run ended.
    #[error("interrupted after {evaluations} runs, before any run of the fit had ended")]
    Interrupted {
        /// Runs started.
        evaluations: usize,
    },
    /// No forward run of the optimiser succeeded.
    #[error(
        "no run of the optimiser succeeded ({evaluations} runs, every one failed or was \
         refused; the first: {first})"
    )]
    NoRun {
        /// Runs tried.
        evaluations: usize,
        /// The first failure, in words.
        first: String,
    },
}

impl FitError {
    /// A bad input field.
    pub fn input(
        field: impl Into<String>,
        value: impl Into<String>,
        allowed: impl Into<String>,
    ) -> Self {
        Self::Input {
            field: field.into(),
            value: value.into(),
            allowed: allowed.into(),
        }
    }

    /// The kind of ending: bad input, or a numerical failure when no run succeeded.
    #[must_use]
    pub fn exit(&self) -> Exit {
        match self {
            Self::NoRun { .. } => Exit::Numerical,
            Self::Interrupted { .. } => Exit::Interrupted,
            Self::Input { .. } | Self::Read { .. } | Self::Scene(_) => Exit::BadInput,
        }
    }
}
