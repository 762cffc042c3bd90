//! The claims' numerical uncertainty: every run a claim reads is repeated at twice the nodes
//! and at a tenth of the time tolerance (half the step where the steps are fixed), the claims
//! are evaluated again on each refined set, and each claim's margin carries the largest change
//! as its uncertainty. A margin within its uncertainty is a verdict within noise.

use crate::claims::{Claim, Runs};
use crate::runner::RunSpec;
use std::collections::BTreeMap;
use std::path::Path;
use stickslip_run::keys::time;

/// The runs the claims read (and fig3, which derives its overrides from fig2).
const CLAIM_RUNS: [&str; 8] = [
    "fig2",
    "fig3",
    "fig4",
    "rigid",
    "melt",
    "homogeneous",
    "fig2_first_order",
    "homogeneous_first_order",
];

/// The refinements: run-name suffix and what it refines.
pub const REFINEMENTS: [(&str, &str); 2] = [("@2N", "2N"), ("@t", "tolerance/10 (dt/2)")];

fn refined_names() -> Vec<String> {
    CLAIM_RUNS
        .iter()
        .map(ToString::to_string)
        .chain(
            crate::sizes::HYSTERESIS_A0_PA
                .iter()
                .map(|&a0| crate::sizes::hysteresis_run(a0)),
        )
        .collect()
}

/// The refined copies of the claims' runs among `base` (scene files in `scenes`).
#[must_use]
pub fn specs(base: &[RunSpec], scenes: &Path) -> Vec<RunSpec> {
    let names = refined_names();
    let mut out = Vec::new();
    for spec in base.iter().filter(|s| names.contains(&s.name)) {
        let scene = scenes.join(format!("{}.toml", spec.scene));
        let time_set = stickslip_run::Scene::from_path(&scene, &spec.overrides())
            .ok()
            .map(|r| match r.config.time.adaptive {
                Some(a) => time::TOLERANCE.set(0.1 * a.tolerance).to_string(),
                None => time::DT.set(0.5 * r.config.time.dt_s).to_string(),
            });
        for (suffix, what) in REFINEMENTS {
            let mut s = spec.clone();
            s.name = format!("{}{suffix}", spec.name);
            s.purpose = format!("the claims' numerical uncertainty: {} at {what}", spec.name);
            s.after = spec
                .after
                .as_ref()
                .map(|(dep, f)| (format!("{dep}{suffix}"), *f));
            match suffix {
                "@2N" => s.nodes *= 2,
                _ => match &time_set {
                    Some(t) => s.sets.push(t.clone()),
                    None => continue,
                },
            }
            out.push(s);
        }
    }
    out
}

/// `runs` with each claim run replaced by its refined copy of `suffix` (where it ran).
fn refined(runs: &Runs, suffix: &str) -> Runs {
    let mut map = runs.map.clone();
    for name in refined_names() {
        if let Some(r) = runs.map.get(&format!("{name}{suffix}")) {
            map.insert(name, r.clone());
        }
    }
    Runs { map }
}

/// One claim's margin uncertainty.
#[derive(Debug, Clone, PartialEq)]
pub struct MarginError {
    /// The largest |margin change| over the refinements (infinite when a refined margin is
    /// missing).
    pub error: f64,
    /// The refinements under which the verdict flips.
    pub flips: Vec<&'static str>,
}

impl MarginError {
    /// Whether the margin `m` lies within the uncertainty (or a refinement flips the verdict).
    #[must_use]
    pub fn within_noise(&self, m: f64) -> bool {
        !self.flips.is_empty() || self.error >= m.abs()
    }
}

/// Each claim's margin uncertainty, by id: the claims evaluated again on each refined run set.
#[must_use]
pub fn evaluate(runs: &Runs, claims: &[Claim]) -> BTreeMap<&'static str, MarginError> {
    let mut out: BTreeMap<&'static str, MarginError> = BTreeMap::new();
    for (suffix, what) in REFINEMENTS {
        let r = refined(runs, suffix);
        let mut again = crate::claims::evaluate(&r);
        again.extend(crate::claims_first_order::evaluate(&r));
        for c in claims {
            let entry = out.entry(c.id).or_insert(MarginError {
                error: 0.0,
                flips: Vec::new(),
            });
            let Some(other) = again.iter().find(|a| a.id == c.id) else {
                entry.error = f64::INFINITY;
                continue;
            };
            if other.pass != c.pass {
                entry.flips.push(what);
            }
            match (crate::margins::of(c), crate::margins::of(other)) {
                (Some(m0), Some(m1)) => {
                    entry.error = entry.error.max((m1.value - m0.value).abs());
                }
                (Some(_), None) => entry.error = f64::INFINITY,
                _ => {}
            }
        }
    }
    out
}
