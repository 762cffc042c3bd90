//! Regimes of the steady state: the rigid drive's speeds run with `time.until = "periodic"` in
//! a window and in one twice as long.
//!
//! A regime read at the end of a fixed window can be an artefact of the window: a run whose
//! cycles are still changing (a transient after the start, a recovery that keeps falling)
//! may read `partial` after 300 events and `smooth` later. With `time.until = "periodic"` a
//! run stops once its last `time.steady_cycles` cycles repeat (period, stamp advance per
//! cycle and peak force within `time.steady_rtol`) and its summary says `steady`; the regime
//! is then that of the steady cycle, and a longer window must give the same one.

use crate::{Check, Map, Section};
use stickslip_report::fmt::sig;
use stickslip_report::map::panels;

const V: &str = stickslip_run::keys::drive::VELOCITY.path;
const END: &str = stickslip_run::keys::time::END.path;

/// The steady map's section.
///
/// # Errors
/// If the map lacks its axes.
pub fn section(map: &Map) -> Result<Section, String> {
    let rows = &map.json.table.rows;
    let ends = map.values(END);
    let (short, long) = match ends.as_slice() {
        [a, b] => (a.min(*b), a.max(*b)),
        _ => return Err(format!("{END}: two windows expected, got {}", ends.len())),
    };
    let speeds = map.values(V);
    let mut pairs = Vec::new();
    for &v in &speeds {
        let at = |end: f64| {
            rows.iter()
                .find(|r| map.axis(r, V) == v && map.axis(r, END) == end)
        };
        if let (Some(a), Some(b)) = (at(short), at(long)) {
            pairs.push((v, a, b));
        }
    }
    let steady_short = pairs.iter().filter(|(_, a, _)| a.summary.steady).count();
    let same = pairs
        .iter()
        .filter(|(_, a, b)| !a.summary.steady || a.summary.regime == b.summary.regime)
        .count();
    let still_steady = pairs
        .iter()
        .filter(|(_, a, b)| !a.summary.steady || b.summary.steady)
        .count();
    let checks = vec![
        Check {
            claim: format!(
                "a regime taken on the steady cycle does not change when the window doubles \
                 ({} s → {} s), and the longer run is steady too",
                sig(short, 2),
                sig(long, 2)
            ),
            measured: format!(
                "{same} of {} speeds keep their regime, {still_steady} stay steady; steady in \
                 the shorter window at {steady_short} of {} speeds",
                pairs.len(),
                pairs.len()
            ),
            pass: !pairs.is_empty() && same == pairs.len() && still_steady == pairs.len(),
        },
        Check {
            claim: format!(
                "every speed reaches its steady cycle within {} s",
                sig(short, 2)
            ),
            measured: format!("{steady_short} of {} speeds", pairs.len()),
            pass: steady_short == pairs.len(),
        },
    ];
    let figure = panels(&map.json, "n_events")?;
    let scene = map.unswept_scene()?;
    let table: String = pairs
        .iter()
        .map(|(v, a, b)| {
            format!(
                "| {} | {} ({}, {} events) | {} ({}, {} events) |\n",
                sig(*v, 3),
                a.summary.regime.name(),
                if a.summary.steady { "steady" } else { "window" },
                a.summary.n_events,
                b.summary.regime.name(),
                if b.summary.steady { "steady" } else { "window" },
                b.summary.n_events,
            )
        })
        .collect();
    let text = format!(
        "The base scene is `{}` at N = {} nodes with `time.until = \"periodic\"`: a run stops \
         once its last {} cycles repeat within {} (period, stamp advance and peak force), or \
         at time.end. Each of {} speeds ({} … {} m/s, log) runs in a window of {} s and of {} \
         s; map.csv's `steady` column says whether the steady cycle was reached.\n\n\
         | V0 [m/s] | regime, {} s | regime, {} s |\n|---|---|---|\n{table}",
        map.scene_file(),
        scene.config.contact.nodes,
        scene.steady.cycles,
        sig(scene.steady.rtol, 2),
        speeds.len(),
        sig(speeds[0], 2),
        sig(speeds[speeds.len() - 1], 2),
        sig(short, 2),
        sig(long, 2),
        sig(short, 2),
        sig(long, 2),
    );
    Ok(Section {
        title: "Rigid drive: regimes of the steady state".into(),
        text,
        figure: ("maps_rigid_steady.svg".into(), figure),
        checks,
    })
}
