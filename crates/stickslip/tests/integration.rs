//! The package's integration tests as one test binary, one module per file: a single link
//! and one copy of the dependencies' generic code instead of one per file (the test
//! command's compile time, P4 of reports/performance.md).

mod common;

mod bad_input;
mod bad_scenes;
mod boundary;
mod fit;
mod reference;
mod resume;
mod runs;
mod spot;
mod sweep;
mod sweep_safe;
mod verify;
