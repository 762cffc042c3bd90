//! The spot checks taken one level further: every checked point whose regime changed at 2N
//! or at a tenth of the tolerance is run again at 4N (and a tenth of the tolerance), so that
//! the report can say whether the map's regime there was a resolution artefact that the
//! refinement settles (the 4N run agrees with the refined regime) or is still moving
//! (unconverged), and mark the map's verdicts accordingly.

use stickslip_run::keys::{contact, time};
use stickslip_run::{Control, NullSink};
use stickslip_studies::sweep::Sweep;
use stickslip_studies::sweep::map::MapJson;

/// How many times the map's nodes the deeper rerun takes.
pub const FACTOR: usize = 4;

/// One changed point followed to [`FACTOR`]·N.
#[derive(Debug, Clone, PartialEq)]
pub struct Deeper {
    /// Point number.
    pub point: usize,
    /// The regime at the map's N.
    pub at_n: String,
    /// The spot check's regimes (2N, then a tenth of the tolerance).
    pub checked: Vec<String>,
    /// The regime at [`FACTOR`]·N and a tenth of the tolerance, or why there is none.
    pub at_4n: Result<String, String>,
}

impl Deeper {
    /// The 4N run (at a tenth of the tolerance too) agrees with the refinement that changed
    /// the regime: the refined regime holds, and the map's regime there was a resolution
    /// artefact of its N or its tolerance. Otherwise (the 4N run back at the map's regime, or
    /// at a third) the point is unconverged.
    #[must_use]
    pub fn settled(&self) -> bool {
        self.at_4n
            .as_ref()
            .is_ok_and(|r| self.checked.iter().any(|c| c != &self.at_n && c == r))
    }
}

/// Reruns the changed spot checks of `json` at [`FACTOR`]·N and a tenth of the tolerance.
///
/// # Errors
/// If a point's scene does not resolve.
pub fn rerun(sweep: &Sweep, json: &MapJson) -> Result<Vec<Deeper>, String> {
    let Some(report) = &json.spot_checks else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for c in report.checks.iter().filter(|c| c.changed) {
        let scene = sweep.scene(c.point).map_err(|e| e.to_string())?;
        let mut sets = vec![
            contact::NODES
                .set((FACTOR * scene.config.contact.nodes) as i64)
                .to_string(),
        ];
        if let Some(a) = scene.config.time.adaptive {
            sets.push(time::TOLERANCE.set(0.1 * a.tolerance).to_string());
        }
        let at_4n = scene
            .with_overrides(&sets)
            .map_err(|e| e.to_string())
            .and_then(|s| {
                let mut control = Control {
                    thresholds: sweep.thresholds,
                    ..Control::default()
                };
                stickslip_run::driver::run(&s, &mut NullSink, &mut control)
                    .map(|o| o.summary.regime.name().to_string())
                    .map_err(|e| e.to_string())
            });
        out.push(Deeper {
            point: c.point,
            at_n: c.regime.clone(),
            checked: c
                .runs
                .iter()
                .map(|r| r.summary.regime.name().to_string())
                .collect(),
            at_4n,
        });
    }
    Ok(out)
}

/// The sentence for one map's changed points (empty when none changed).
#[must_use]
pub fn sentence(deeper: &[Deeper]) -> String {
    if deeper.is_empty() {
        return String::new();
    }
    let each: Vec<String> = deeper
        .iter()
        .map(|d| {
            let at_4n = match &d.at_4n {
                Ok(r) => r.clone(),
                Err(e) => format!("failed ({e})"),
            };
            format!(
                "point {}: {} at N, {} at 2N / tolerance/10, {at_4n} at {FACTOR}N — {}",
                d.point,
                d.at_n,
                d.checked.join(" / "),
                if d.settled() {
                    "the refined regime holds: the map's regime there is a resolution artefact"
                } else {
                    "still moving: unconverged"
                }
            )
        })
        .collect();
    each.join("; ")
}

/// The note a map's verdicts carry when a changed point is still moving at 4N.
#[must_use]
pub fn verdict_note(deeper: &[Deeper]) -> Option<String> {
    let moving: Vec<String> = deeper
        .iter()
        .filter(|d| !d.settled())
        .map(|d| d.point.to_string())
        .collect();
    (!moving.is_empty()).then(|| {
        format!(
            " (unconverged at point{} {}: see Spot checks)",
            if moving.len() == 1 { "" } else { "s" },
            moving.join(", ")
        )
    })
}
