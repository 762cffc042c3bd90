//! Where a run's rows go: [`memory::MemorySink`] keeps them as the output types of
//! [`crate::schema`], [`dir::DirSink`] streams them into an output directory (atomically, with
//! checkpoints and run.json's status from the start), [`crate::driver::NullSink`] keeps
//! nothing. [`read`] reads an output directory back in any state (ended, interrupted, killed).

pub mod dir;
pub mod lock;
pub mod memory;
pub mod read;

pub use crate::driver::{NullSink, Sink};
