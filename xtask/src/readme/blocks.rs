//! The generated blocks' texts, each from the committed reports it names: the JSON read as
//! [`serde_json::Value`] (the convergence and performance studies' types live in a crate xtask
//! does not build) or typed where xtask already depends on the writer (build-timing.json,
//! fit.json), markdown tables copied or quoted cell by cell; numbers formatted as the reports
//! format them.

use serde_json::Value;
use std::fmt::Write as _;
use std::path::Path;
use stickslip_report::build_timing::BuildTiming;
use stickslip_report::fmt::sig;

/// A report file's text.
fn read(root: &Path, file: &str) -> Result<String, String> {
    std::fs::read_to_string(root.join(file)).map_err(|e| format!("{file}: {e}"))
}

/// A JSON report.
struct Doc {
    /// Its path under the root, for messages.
    file: &'static str,
    /// Its contents.
    value: Value,
}

impl Doc {
    fn read(root: &Path, file: &'static str) -> Result<Self, String> {
        let text = read(root, file)?;
        let value = serde_json::from_str(&text).map_err(|e| format!("{file}: {e}"))?;
        Ok(Self { file, value })
    }

    fn root(&self) -> Node<'_> {
        Node {
            file: self.file,
            path: String::new(),
            v: &self.value,
        }
    }
}

/// A value in a JSON report with its path, so that a missing field names the file and the
/// field.
#[derive(Clone)]
struct Node<'a> {
    file: &'a str,
    path: String,
    v: &'a Value,
}

impl<'a> Node<'a> {
    fn missing(&self, what: &str) -> String {
        format!("{}: no {what} at `{}`", self.file, self.path)
    }

    fn at(&self, key: &str) -> Result<Node<'a>, String> {
        let path = if self.path.is_empty() {
            key.to_string()
        } else {
            format!("{}.{key}", self.path)
        };
        match self.v.get(key) {
            Some(v) => Ok(Node {
                file: self.file,
                path,
                v,
            }),
            None => Err(format!("{}: no field `{path}`", self.file)),
        }
    }

    fn f64(&self, key: &str) -> Result<f64, String> {
        let n = self.at(key)?;
        n.v.as_f64().ok_or_else(|| n.missing("number"))
    }

    /// A number or `null`.
    fn opt_f64(&self, key: &str) -> Result<Option<f64>, String> {
        let n = self.at(key)?;
        if n.v.is_null() {
            Ok(None)
        } else {
            n.v.as_f64().map(Some).ok_or_else(|| n.missing("number"))
        }
    }

    fn u64(&self, key: &str) -> Result<u64, String> {
        let n = self.at(key)?;
        n.v.as_u64().ok_or_else(|| n.missing("whole number"))
    }

    fn str(&self, key: &str) -> Result<&'a str, String> {
        let n = self.at(key)?;
        n.v.as_str().ok_or_else(|| n.missing("string"))
    }

    fn list(&self, key: &str) -> Result<Vec<Node<'a>>, String> {
        let n = self.at(key)?;
        let items = n.v.as_array().ok_or_else(|| n.missing("list"))?;
        Ok(items
            .iter()
            .enumerate()
            .map(|(i, v)| Node {
                file: self.file,
                path: format!("{}[{i}]", n.path),
                v,
            })
            .collect())
    }

    fn f64s(&self, key: &str) -> Result<Vec<f64>, String> {
        self.list(key)?
            .iter()
            .map(|n| n.v.as_f64().ok_or_else(|| n.missing("number")))
            .collect()
    }
}

/// `lo–hi` with `digits` significant digits, one value when both print the same (the
/// convergence report's ranges).
fn span(lo: f64, hi: f64, digits: usize) -> String {
    let (a, b) = (
        sig(rounded(lo, digits), digits),
        sig(rounded(hi, digits), digits),
    );
    if a == b { a } else { format!("{a}–{b}") }
}

/// `x` rounded to `digits` significant digits (so that 0.9985 at two prints as 1.0, not 1.00).
fn rounded(x: f64, digits: usize) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let scale = 10f64.powi(i32::try_from(digits).unwrap_or(3) - 1 - x.abs().log10().floor() as i32);
    (x * scale).round() / scale
}

/// An order as the convergence report prints it: two decimals, `–` for none.
fn p2(p: Option<f64>) -> String {
    p.map_or_else(|| "–".into(), |p| format!("{p:.2}"))
}

/// `n level` or `n levels`.
fn levels(n: usize) -> String {
    format!("{n} level{}", if n == 1 { "" } else { "s" })
}

/// The default `time.tolerance` (docs/reference.md), whose row the README quotes.
const DEFAULT_TOLERANCE: f64 = 5e-5;
/// The default graded grid's exponent (`contact.grid = "graded"`).
const DEFAULT_GRID_POWER: f64 = 3.0;

fn same(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * b.abs()
}

/// "The two commands": a fresh clone's validate and test command.
pub(super) fn build_timing(root: &Path) -> Result<String, String> {
    let t = BuildTiming::read(&root.join("reports"))?
        .ok_or("reports/build-timing.json: not measured (run `cargo xtask build-timing`)")?;
    let failed = |ok: bool| if ok { "" } else { ", FAILED" };
    let stages = t
        .test_stages
        .iter()
        .map(|s| {
            format!(
                "{} {} s{}",
                s.name,
                sig(s.seconds, 3),
                if s.ok { "" } else { " FAILED" }
            )
        })
        .collect::<Vec<_>>()
        .join(", ");
    Ok(format!(
        "Measured on a fresh clone of `{}` here ({} CPUs; the cargo registry {}; \
         `reports/build-timing.json`, from `cargo xtask build-timing`): `cargo xtask validate` \
         took {} s{}, the test command after it {} s{} = {}× validate ({stages}).",
        &t.commit[..t.commit.len().min(10)],
        t.cpus,
        if t.registry_warm {
            "already held the dependencies' sources"
        } else {
            "empty: downloads included"
        },
        sig(t.validate_s, 3),
        failed(t.validate_ok),
        sig(t.test_s, 3),
        failed(t.test_ok),
        sig(t.test_s / t.validate_s, 2),
    ))
}

/// The claims' verdicts in summary.json.
pub(super) fn claims(root: &Path) -> Result<String, String> {
    let doc = Doc::read(root, "reports/summary.json")?;
    let claims = doc.root().at("claims")?;
    let map = claims
        .v
        .as_object()
        .ok_or_else(|| claims.missing("object of claims"))?;
    let mut failing = Vec::new();
    for key in map.keys() {
        let c = claims.at(key)?;
        let pass = c.at("pass")?;
        if !pass
            .v
            .as_bool()
            .ok_or_else(|| pass.missing("true or false"))?
        {
            failing.push(key.clone());
        }
    }
    // C2 before C10.
    let number = |k: &String| {
        k.trim_start_matches('C')
            .split(|c: char| !c.is_ascii_digit())
            .next()
            .and_then(|d| d.parse::<u32>().ok())
            .unwrap_or(u32::MAX)
    };
    failing.sort_by_key(number);
    let n = map.len();
    Ok(if failing.is_empty() {
        format!(
            "In the committed `reports/summary.json`, {n} of {n} claims pass (`index.md` gives \
             each one's criterion and measured value)."
        )
    } else {
        format!(
            "In the committed `reports/summary.json`, {} of {n} claims pass; {} fail{} (`index.md` \
             gives each one's criterion and measured value).",
            n - failing.len(),
            failing.join(", "),
            if failing.len() == 1 { "s" } else { "" }
        )
    })
}

/// The convergence study's wall time.
pub(super) fn convergence_time(root: &Path) -> Result<String, String> {
    let doc = Doc::read(root, "reports/convergence.json")?;
    let r = doc.root();
    let total = r.f64("total_wall_s")?;
    let machine = r.str("machine")?;
    let profile = r.str("build_profile")?;
    let grid = match r.at("grid") {
        Ok(g) if !g.v.is_null() => Some(g.f64("wall_s")?),
        _ => None,
    };
    let mut s = format!(
        "The committed convergence study took {} s ({} min) here ({machine}, {profile} build; \
         `total_wall_s` of `reports/convergence.json`)",
        sig(total, 3),
        sig(total / 60.0, 2)
    );
    match grid {
        // A spatial study longer than the whole was run on its own and merged.
        Some(g) if g > total => {
            let _ = write!(
                s,
                "; its section 8, the spatial study, {} s, run on its own (`--grid-only`)",
                sig(g, 3)
            );
        }
        Some(g) => {
            let _ = write!(
                s,
                ", of which section 8, the spatial study, {} s",
                sig(g, 3)
            );
        }
        None => {}
    }
    s.push('.');
    Ok(s)
}

/// The headline numbers: the literal scheme's onsets, the default stepping's error and cost
/// at N = 200, the N = 200 solution against N = 2000's.
pub(super) fn headline(root: &Path) -> Result<String, String> {
    let doc = Doc::read(root, "reports/convergence.json")?;
    let r = doc.root();
    let settings = r.at("settings")?;
    let dt = settings.f64("sim_nodes_dt_s")?;
    let reference = r.at("work_precision")?.at("reference")?.f64s("onsets_s")?;
    // The literal runs refining N at the study's Δt: each onset against the reference's.
    let mut gaps = Vec::new();
    let mut nodes = Vec::new();
    for run in r.list("runs")? {
        if run.str("role")? != "N" || run.str("scheme")? != "literal" {
            continue;
        }
        if !run.at("failure")?.v.is_null() || !same(run.f64("dt_s")?, dt) {
            continue;
        }
        nodes.push(run.u64("nodes")?);
        for (ev, t_ref) in run.list("events")?.iter().zip(&reference) {
            gaps.push(ev.f64("onset_s")? - t_ref);
        }
    }
    if gaps.is_empty() {
        return Err("reports/convergence.json: no literal run refining N with events".into());
    }
    nodes.sort_unstable();
    let lo = gaps.iter().map(|g| g.abs()).fold(f64::INFINITY, f64::min);
    let hi = gaps.iter().map(|g| g.abs()).fold(0.0, f64::max);
    let direction = if gaps.iter().all(|g| *g < 0.0) {
        "before"
    } else if gaps.iter().all(|g| *g > 0.0) {
        "after"
    } else {
        "away from"
    };
    // The default tolerance at N = 200 against its same-N reference.
    let tol = r.at("tolerance")?;
    let point = tol
        .list("points")?
        .into_iter()
        .find(|p| {
            p.u64("nodes").is_ok_and(|n| n == 200)
                && p.f64("tolerance").is_ok_and(|t| same(t, DEFAULT_TOLERANCE))
        })
        .ok_or_else(|| {
            format!(
                "reports/convergence.json: no `tolerance.points[]` at N = 200 and tolerance \
                 {DEFAULT_TOLERANCE:e}"
            )
        })?;
    let max_onset = point.at("errors")?.f64("max_onset_s")?;
    let wall = point.f64("wall_s")?;
    let repeats = tol.at("settings")?.u64("repeats")?;
    let spatial = tol
        .list("spatial")?
        .into_iter()
        .find(|s| s.u64("nodes").is_ok_and(|n| n == 200))
        .ok_or("reports/convergence.json: no `tolerance.spatial[]` at N = 200")?;
    let finer = spatial.u64("finer_nodes")?;
    let spatial_onset = spatial.at("errors")?.f64("max_onset_s")?;
    Ok(format!(
        "Headline numbers (from `reports/convergence.json`): the literal scheme converges to a \
         different answer — its melting starts at the axis, because its back sum leaves \
         u3D(0) = 0 — and at Δt = {dt:e} s its onsets lie {} µs {direction} the reference's at \
         every N of the study ({}; convergence.md §4). The accurate scheme with its default \
         adaptive steps (tolerance {DEFAULT_TOLERANCE:e}) puts the fig2 onsets at N = 200 within \
         {} ns of a same-N converged reference, in {} s of simulation (median of {repeats}, \
         convergence.md §5; P3 under Performance times the whole process); the N = 200 \
         solution's onsets are themselves within {} ns of N = {finer}'s.",
        span(lo * 1e6, hi * 1e6, 2),
        nodes
            .iter()
            .map(u64::to_string)
            .collect::<Vec<_>>()
            .join(", "),
        sig(max_onset * 1e9, 3),
        sig(wall, 2),
        sig(spatial_onset * 1e9, 3),
    ))
}

/// The fit study's size and wall time.
pub(super) fn fit(root: &Path) -> Result<String, String> {
    let file = "reports/fit.json";
    let study = stickslip_fit_study::record::Study::parse(&read(root, file)?)
        .map_err(|e| format!("{file}: {e}"))?;
    // As fit.md prints it.
    let wall = if study.wall_s < 120.0 {
        format!("{:.1} s", study.wall_s)
    } else {
        format!("{:.0} s ({:.1} min)", study.wall_s, study.wall_s / 60.0)
    };
    Ok(format!(
        "The committed study (`reports/fit.json`, {} size: {} seeds per coverage set, fig2 at \
         N = {} and the SFA contact at N = {}) took {wall} on {} cores.",
        if study.sizes.quick {
            "smoke (`--quick`)"
        } else {
            "full"
        },
        study.sizes.seeds,
        study.sizes.fig2_nodes,
        study.sizes.sfa_nodes,
        study.host.cores,
    ))
}

/// How long `cargo xtask bench` took.
pub(super) fn bench_time(root: &Path) -> Result<String, String> {
    let doc = Doc::read(root, "reports/performance.json")?;
    let r = doc.root();
    let total = r.f64("total_s")?;
    Ok(format!(
        "The committed `cargo xtask bench` took {} s ({} min) here ({}; `total_s` of \
         `reports/performance.json`).",
        sig(total, 3),
        sig(total / 60.0, 2),
        r.str("machine")?
    ))
}

/// performance.md's summary table: its header line and every table line after it.
pub(super) fn performance(root: &Path) -> Result<String, String> {
    let file = "reports/performance.md";
    let report = read(root, file)?;
    table(&report).ok_or_else(|| format!("{file}: no summary table (`{HEADER}`)"))
}

/// The summary table's header in performance.md.
const HEADER: &str = "| target | goal | measured | verdict |";

/// performance.md's summary table.
fn table(report: &str) -> Option<String> {
    let lines: Vec<&str> = report.lines().collect();
    let start = lines.iter().position(|l| l.starts_with(HEADER))?;
    let rows: Vec<&str> = lines[start..]
        .iter()
        .take_while(|l| l.starts_with('|'))
        .copied()
        .collect();
    Some(rows.join("\n"))
}

/// The graded grid against the uniform one on the h0 = 1 nm contact (convergence.md §8).
pub(super) fn grid(root: &Path) -> Result<String, String> {
    let doc = Doc::read(root, "reports/convergence.json")?;
    let g = doc.root().at("grid")?;
    let scene = "sfa";
    let reference = g
        .list("references")?
        .into_iter()
        .find(|r| {
            r.str("scene").is_ok_and(|s| s == scene)
                && r.str("observable").is_ok_and(|o| o == "t_onset")
        })
        .ok_or("reports/convergence.json: no `grid.references[]` of sfa's t_onset")?
        .f64("value")?;
    let sequence = |graded: bool| -> Result<Vec<(u64, f64)>, String> {
        let seq = g
            .list("sequences")?
            .into_iter()
            .find(|q| {
                let grid_ok = q.at("grid").is_ok_and(|k| {
                    if graded {
                        k.v.pointer("/graded/power")
                            .and_then(Value::as_f64)
                            .is_some_and(|p| same(p, DEFAULT_GRID_POWER))
                    } else {
                        k.v.as_str() == Some("uniform")
                    }
                });
                grid_ok
                    && q.str("scene").is_ok_and(|s| s == scene)
                    && q.str("observable").is_ok_and(|o| o == "t_onset")
            })
            .ok_or_else(|| {
                format!(
                    "reports/convergence.json: no `grid.sequences[]` of sfa's t_onset on the {} \
                     grid",
                    if graded { "graded (p = 3)" } else { "uniform" }
                )
            })?;
        let nodes = seq.list("nodes")?;
        let values = seq.f64s("values")?;
        nodes
            .iter()
            .zip(values)
            .map(|(n, v)| {
                n.v.as_u64()
                    .map(|n| (n, (v - reference).abs()))
                    .ok_or_else(|| n.missing("whole number"))
            })
            .collect()
    };
    let graded = sequence(true)?;
    let uniform = sequence(false)?;
    let at = |s: &[(u64, f64)], n: u64| s.iter().find(|(m, _)| *m == n).map(|(_, e)| *e);
    let g200 = at(&graded, 200).ok_or("reports/convergence.json: no graded sfa run at N = 200")?;
    let u200 =
        at(&uniform, 200).ok_or("reports/convergence.json: no uniform sfa run at N = 200")?;
    // The error cells as §8's table prints them (sig 2, s).
    let as_close = uniform.iter().find(|(_, e)| *e <= g200);
    let (finest, finest_err) = *uniform.last().expect("a sequence has levels");
    let uniform_text = match as_close {
        Some((n, e)) => format!("needs N = {n} to come as close ({} s)", sig(*e, 2)),
        None => format!(
            "does not come as close even at N = {finest} ({} s)",
            sig(finest_err, 2)
        ),
    };
    Ok(format!(
        "On the h0 = 1 nm contact (`sfa`, convergence.md §8) the graded grid's first onset at \
         N = 200 lies {} s from the converged {} s; the paper's uniform grid is {} s off at N = \
         200 and {uniform_text}.",
        sig(g200, 2),
        sig(reference, 9),
        sig(u200, 2),
    ))
}

/// The weak order of noisy fixed steps (convergence.md §6).
pub(super) fn noise(root: &Path) -> Result<String, String> {
    let doc = Doc::read(root, "reports/convergence.json")?;
    let n = doc.root().at("noise")?;
    let settings = n.at("settings")?;
    let mean = n.at("mean")?;
    let slope = mean.opt_f64("slope")?;
    let points = usize::try_from(mean.u64("slope_points")?).unwrap_or(usize::MAX);
    let fit_p = mean.opt_f64("fit_p")?;
    // The noise's own part of the bias: weak error less the deterministic error, resolved
    // where it exceeds twice its standard error.
    let mut resolved = Vec::new();
    for e in mean.list("errors")? {
        if let Some(d) = e.opt_f64("deterministic_s")? {
            let part = e.f64("error_s")? - d;
            if part.abs() > 2.0 * e.f64("se_s")? {
                resolved.push((e.f64("dt_s")?, part.abs()));
            }
        }
    }
    let part = if resolved.len() >= 2 {
        format!(
            "resolved at {}, where its observed order is {}",
            levels(resolved.len()),
            p2(Some(stickslip_report::stats::log_log_slope(&resolved)))
        )
    } else {
        format!(
            "resolved at {}, too few for an order",
            levels(resolved.len())
        )
    };
    let order = match slope {
        Some(p) => format!(
            "falls like Δt^{} over the {} where it exceeds twice its standard error (a \
             weighted fit over every level: p = {})",
            p2(Some(p)),
            levels(points),
            p2(fit_p)
        ),
        None => "stays within twice its standard error at all but one level: no order can \
                 be read"
            .to_string(),
    };
    Ok(format!(
        "With gaussian noise and fixed steps (fig2 at N = {}, {} seeds; convergence.md §6) the \
         weak error of the mean first onset {order}; the noise's own part of that bias (the weak \
         error less the deterministic scheme's) is {part}.",
        settings.u64("nodes")?,
        settings.u64("seeds")?,
    ))
}

/// The rows of maps.md's "Checks" table: (map, what physics says, measured, verdict).
fn checks(maps: &str) -> Vec<[String; 4]> {
    maps.split("\n## Checks\n")
        .nth(1)
        .unwrap_or("")
        .lines()
        .skip_while(|l| !l.starts_with('|'))
        .take_while(|l| l.starts_with('|'))
        .skip(2)
        .filter_map(|l| {
            let cells: Vec<String> = l
                .trim()
                .trim_start_matches('|')
                .trim_end_matches('|')
                .split(" | ")
                .map(|c| c.trim().to_string())
                .collect();
            <[String; 4]>::try_from(cells).ok()
        })
        .collect()
}

/// The showcase maps and their measured checks (reports/maps.md).
pub(super) fn maps(root: &Path) -> Result<String, String> {
    let file = "reports/maps.md";
    let md = read(root, file)?;
    let rows = checks(&md);
    if rows.is_empty() {
        return Err(format!("{file}: no \"## Checks\" table"));
    }
    let measured = |map: &str, says: &str| -> Result<String, String> {
        let row = rows
            .iter()
            .find(|r| r[0] == map && r[1].starts_with(says))
            .ok_or_else(|| format!("{file}: no check of \"{map}\" that says \"{says} …\""))?;
        Ok(if row[3].contains("pass") {
            row[2].clone()
        } else {
            format!("{}; verdict {}", row[2], row[3])
        })
    };
    // "refined 4 times where …: 3379 points of the 241 × 193 uniform grid … (7.3 %)".
    let rigid = "Rigid drive: speed × temperature";
    let refined = md
        .split(&format!("\n## {rigid}\n"))
        .nth(1)
        .and_then(|s| {
            let from = s.find("refined ")?;
            let to = s[from..].find(", each drawn as")? + from;
            Some(&s[from..to])
        })
        .ok_or_else(|| {
            format!("{file}: no \"refined … , each drawn as\" in the section \"{rigid}\"")
        })?;
    let pass = rows.iter().filter(|r| r[3].contains("pass")).count();
    Ok(format!(
        "- the rigid drive's speed × temperature, {refined}; the critical speed on paper \
         against the map's — {}; the critical speed by `boundary` in every row; and a window of \
         the uniform grid at the finest spacing against the refined map — {};\n\
         - the spring's stiffness × speed; radial against homogeneous over film thickness × \
         modulus;\n\
         - two of the first-order film: radial against homogeneous beside the second-order \
         film's map, for the paper's contrast (the first-order film's radial–homogeneous onset \
         difference against the second-order film's) — {}; and its melting strain × speed under \
         the rigid drive: the advance per cycle on paper, the fold's delay, and a critical speed \
         that grows far more slowly than ε₊·h0;\n\
         - the rigid drive's regimes on the steady state (`time.until = \"periodic\"`) in a \
         window and in one twice as long — {};\n\
         - a viscous film's stiffness × viscosity, and the critical speed above which the \
         stamp's slips stop recurring — {}.\n\
         \n\
         {pass} of {} checks pass.",
        measured(rigid, "critical speed: R falls")?,
        measured(rigid, "refinement finds the boundaries")?,
        measured(
            "First-order film: radial against homogeneous",
            "the paper's contrast"
        )?,
        measured(
            "Rigid drive: regimes of the steady state",
            "a regime taken on the steady cycle"
        )?,
        measured(
            "Viscous film: stiffness × viscosity, and the critical speed",
            "with η = 10 Pa·s slips stop recurring"
        )?,
        rows.len(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_maps_checks_table_is_read_cell_by_cell() {
        let md = "# x\n\n## Checks\n\n| map | what physics says | measured | verdict |\n\
                  |---|---|---|---|\n| A | says this | 3 of 3 | **pass** |\n\
                  | B | that | 1 of 2 | **fail** |\n\n## Next\n";
        let rows = checks(md);
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0][2], "3 of 3");
        assert_eq!(rows[1][3], "**fail**");
    }
}
