//! What the figure tests share: the committed report figures.

use std::path::{Path, PathBuf};

/// Every `reports/*.svg`, sorted; at least 30 of them (a test over none would pass).
pub fn report_figures() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../reports");
    let mut figures: Vec<_> = std::fs::read_dir(&dir)
        .expect("reports/")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "svg"))
        .collect();
    figures.sort();
    assert!(figures.len() > 30, "{} figures", figures.len());
    figures
}
