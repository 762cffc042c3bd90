//! The package's integration tests as one test binary, one module per file: a single link
//! and one copy of the dependencies' generic code instead of one per file (the test
//! command's compile time, P4 of reports/performance.md).

mod common;

mod checkpoint_instants;
mod dir_states;
mod drive_damping;
mod error_norm;
mod event_tolerance;
mod events;
mod first_order;
mod grid;
mod keys;
mod onset_estimate;
mod output_rows;
mod replay;
mod scene_fuzz;
mod scene_resolution;
mod schema;
mod sim;
mod slips;
mod steady;
mod viscosity;
