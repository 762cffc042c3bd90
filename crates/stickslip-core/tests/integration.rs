//! The package's integration tests as one test binary, one module per file: a single link
//! and one copy of the dependencies' generic code instead of one per file (the test
//! command's compile time, P4 of reports/performance.md).

mod alloc_free;
mod drive;
mod energy_books;
mod hodlr;
mod hodlr_build;
mod hodlr_split;
mod landau;
mod landau_first_order;
mod mdr_entries;
mod mdr_pairs;
mod mdr_properties;
mod models;
mod noise;
mod preflight;
mod scenes;
mod sim_first_order;
mod sim_state;
mod transpose;
