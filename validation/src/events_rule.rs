//! Where the event rule changes an event list: every paper scene run with the default event
//! settings (events delimited by the film's recovery, no merge gap) and again with
//! `output.event_merge_gap = 1e-5` s, the old default value; the counts, whether the onsets
//! agree, and a sentence computed from that table for the report.

use crate::claims::Runs;
use crate::runner::{EVENT_RULE_RUNS, old_gap_partner};
use serde_json::{Value, json};
use std::fmt::Write as _;
use stickslip_report::fmt;

/// Two onsets closer than this are the same onset, s (both lists come from the same run up to
/// the event bookkeeping, so equal onsets are equal to rounding).
const SAME_ONSET_S: f64 = 1e-12;

/// One paper run with both event settings.
#[derive(Debug, Clone, PartialEq)]
pub struct RuleRow {
    /// Run with the default event settings.
    pub run: String,
    /// The same with the old merge gap.
    pub old_gap_run: String,
    /// Events with the default settings.
    pub default_events: usize,
    /// Events with the old merge gap.
    pub old_gap_events: usize,
    /// Onsets of the old-gap list found in the default list.
    pub old_onsets_found: usize,
    /// Same count and every onset equal.
    pub same_list: bool,
}

/// The comparison for every run of [`EVENT_RULE_RUNS`] whose two runs are available; the
/// names of those that are not, with why.
pub fn compare(runs: &Runs) -> (Vec<RuleRow>, Vec<String>) {
    let mut rows = Vec::new();
    let mut missing = Vec::new();
    for name in EVENT_RULE_RUNS {
        let partner = old_gap_partner(name);
        let (a, b) = match (runs.get(name), runs.get(&partner)) {
            (Ok(a), Ok(b)) => (a, b),
            (Err(e), _) | (_, Err(e)) => {
                missing.push(e);
                continue;
            }
        };
        let (da, ob) = (a.events.onsets_s(), b.events.onsets_s());
        let found = ob
            .iter()
            .filter(|t| da.iter().any(|d| (d - *t).abs() <= SAME_ONSET_S))
            .count();
        rows.push(RuleRow {
            run: name.to_string(),
            old_gap_run: partner,
            default_events: da.len(),
            old_gap_events: ob.len(),
            old_onsets_found: found,
            same_list: da.len() == ob.len() && found == ob.len(),
        });
    }
    (rows, missing)
}

/// The rows as JSON (for summary.json).
pub fn to_json(rows: &[RuleRow]) -> Value {
    Value::Array(
        rows.iter()
            .map(|r| {
                json!({ "run": r.run, "old_gap_run": r.old_gap_run,
                        "events_default": r.default_events, "events_old_gap": r.old_gap_events,
                        "old_onsets_in_default_list": r.old_onsets_found,
                        "same_list": r.same_list })
            })
            .collect(),
    )
}

/// The sentence that sums the table up.
pub fn sentence(rows: &[RuleRow]) -> String {
    let changed: Vec<&RuleRow> = rows.iter().filter(|r| !r.same_list).collect();
    let same: Vec<&str> = rows
        .iter()
        .filter(|r| r.same_list)
        .map(|r| r.run.as_str())
        .collect();
    let mut s = format!(
        "The event rule changes the event list of {} of the {} runs compared",
        changed.len(),
        rows.len()
    );
    if changed.is_empty() {
        s.push('.');
        return s;
    }
    let parts: Vec<String> = changed
        .iter()
        .map(|r| {
            let how = if r.old_onsets_found == r.old_gap_events
                && r.default_events > r.old_gap_events
            {
                let n = r.default_events - r.old_gap_events;
                format!(
                    "{} among the new ones: the old gap folded {n} melting{} into earlier events",
                    if r.old_gap_events == 1 {
                        "the one old onset is".to_string()
                    } else {
                        format!("all {} old onsets are", r.old_gap_events)
                    },
                    if n == 1 { "" } else { "s" }
                )
            } else {
                format!(
                    "{} of the {} old onsets are among the new ones",
                    r.old_onsets_found, r.old_gap_events
                )
            };
            format!(
                "`{}` ({} events by default against {}; {how})",
                r.run, r.default_events, r.old_gap_events
            )
        })
        .collect();
    let _ = write!(s, ": {}", parts.join("; "));
    if !same.is_empty() {
        let _ = write!(
            s,
            ". {} keep the same events, onset for onset",
            same.iter()
                .map(|n| format!("`{n}`"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    s.push('.');
    s
}

/// The Markdown table and its sentence.
pub fn markdown(rows: &[RuleRow], missing: &[String]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "| run | events, default settings | events, `event_merge_gap = 1e-5` s | old onsets in the \
         new list | same list |\n|---|---|---|---|---|"
    );
    for r in rows {
        let _ = writeln!(
            s,
            "| `{}` (vs `{}`) | {} | {} | {}/{} | {} |",
            r.run,
            r.old_gap_run,
            r.default_events,
            r.old_gap_events,
            r.old_onsets_found,
            r.old_gap_events,
            if r.same_list { "yes" } else { "**no**" }
        );
    }
    let _ = writeln!(s, "\n{}", sentence(rows));
    for m in missing {
        let _ = writeln!(s, "\nNot compared: {}", fmt::first_line(m));
    }
    s
}
