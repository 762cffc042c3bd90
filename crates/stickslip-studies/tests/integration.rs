//! The package's integration tests as one test binary, one module per file (one link for
//! all, as in the other crates).

mod common;

mod fit;
mod onset_sigma;
mod refine;
