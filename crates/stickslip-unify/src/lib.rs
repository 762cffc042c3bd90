//! Build plumbing without code: the manifest pins the features of shared dependencies so that
//! every cargo command of the workspace reuses one set of compiled artifacts (see
//! `Cargo.toml` for why).
