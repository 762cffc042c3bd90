//! The names of the files and folders that the commands writing a directory put there, kept
//! apart from the code that writes them so that any part may recognise another command's
//! results (the run's sink refuses a sweep's, a fit's or verify's directory) without importing that command.

/// A sweep's directory (`stickslip sweep`, the maps).
pub mod sweep {
    /// File name of the resolved sweep in its directory.
    pub const SWEEP_FILE: &str = "sweep.json";
    /// File name of the sweep's table.
    pub const CSV_FILE: &str = "map.csv";
    /// File name of the sweep as resolved with the table.
    pub const JSON_FILE: &str = "map.json";
    /// The spot checks' records under the sweep directory.
    pub const CHECKS_DIR: &str = "checks";
    /// Directory of the shard tables in a sweep directory.
    pub const SHARDS_DIR: &str = "shards";
    /// Subdirectories of a sweep directory a fresh start removes.
    pub const SWEEP_DIRS: [&str; 4] = ["points", "runs", SHARDS_DIR, CHECKS_DIR];
}

/// A fit's directory (`stickslip fit`).
pub mod fit {
    /// The fit's result (`fit.json`).
    pub const REPORT_FILE: &str = "fit.json";
    /// The scene with the fitted values.
    pub const FITTED_SCENE: &str = "fitted.toml";
}

/// `stickslip verify`'s directory.
pub mod verify {
    /// The refinements and their estimates.
    pub const VERIFY_FILE: &str = "verify.json";
    /// The settings for a target error (`--target`).
    pub const TARGET_FILE: &str = "target.json";
    /// The scene at those settings (`--target`).
    pub const RESOLUTION_FILE: &str = "resolution.toml";
}
