//! README.md's measured numbers, generated from the committed reports.
//!
//! No measured number in README.md is typed by hand: each sits in a generated block,
//!
//! ```text
//! <!-- generated: NAME from reports/FILE -->
//! …
//! <!-- end generated -->
//! ```
//!
//! whose text [`BLOCKS`] writes from the files under `reports/` (read from disk, as committed).
//! `cargo xtask readme` rewrites every block, `--check` lists the blocks that differ; the
//! commands that write reports (validate, convergence, bench, fit-study, maps, build-timing)
//! call [`update`] at their end. The tests below regenerate every block from the committed
//! reports and fail, naming the block, where README.md differs.

mod blocks;

use std::fmt::Write as _;
use std::path::Path;
use std::process::ExitCode;

/// The first line of a block: `<!-- generated: NAME from SOURCES -->`.
const BEGIN: &str = "<!-- generated: ";
/// The rest of that line after the sources.
const BEGIN_END: &str = " -->";
/// The last line of a block.
const END: &str = "<!-- end generated -->";

/// One generated block of README.md.
pub struct Block {
    /// Its name in the marker.
    pub name: &'static str,
    /// The reports it reads, as the marker names them.
    pub sources: &'static str,
    /// Its text (without the marker lines) from the workspace root's `reports/`.
    pub render: fn(&Path) -> Result<String, String>,
}

/// Every generated block, in README order.
pub const BLOCKS: &[Block] = &[
    Block {
        name: "build-timing",
        sources: "reports/build-timing.json",
        render: blocks::build_timing,
    },
    Block {
        name: "claims",
        sources: "reports/summary.json",
        render: blocks::claims,
    },
    Block {
        name: "convergence-time",
        sources: "reports/convergence.json",
        render: blocks::convergence_time,
    },
    Block {
        name: "headline",
        sources: "reports/convergence.json",
        render: blocks::headline,
    },
    Block {
        name: "fit",
        sources: "reports/fit.json",
        render: blocks::fit,
    },
    Block {
        name: "bench-time",
        sources: "reports/performance.json",
        render: blocks::bench_time,
    },
    Block {
        name: "performance",
        sources: "reports/performance.md",
        render: blocks::performance,
    },
    Block {
        name: "grid",
        sources: "reports/convergence.json",
        render: blocks::grid,
    },
    Block {
        name: "noise",
        sources: "reports/convergence.json",
        render: blocks::noise,
    },
    Block {
        name: "maps",
        sources: "reports/maps.md",
        render: blocks::maps,
    },
];

/// The block named `name`.
fn block(name: &str) -> Option<&'static Block> {
    BLOCKS.iter().find(|b| b.name == name)
}

/// README's line width, to which generated prose is wrapped.
const WIDTH: usize = 95;

/// A block's text as README.md has it: rendered, then wrapped to [`WIDTH`].
///
/// # Errors
/// A report is missing, unreadable or lacks a field the block quotes.
pub fn generate(b: &Block, root: &Path) -> Result<String, String> {
    (b.render)(root).map(|t| wrap(t.trim_end_matches('\n'), WIDTH))
}

/// Whether a line starting with `word` would read as markdown other than a paragraph's
/// continuation (a list item, a heading, a quote, a table row, HTML).
fn opens_markup(word: &str) -> bool {
    matches!(word, "-" | "+" | "*")
        || word.starts_with(['#', '>', '|', '<'])
        || word
            .strip_suffix(['.', ')'])
            .is_some_and(|d| !d.is_empty() && d.chars().all(|c| c.is_ascii_digit()))
}

/// A line's words, with `a = b` and a number with its unit (`0.08 s`) kept together: the units
/// that follow a number in the blocks.
fn unbreakable(line: &str) -> Vec<String> {
    const UNITS: [&str; 9] = ["s", "ns", "µs", "ms", "min", "%", "m/s", "Pa", "N/m"];
    let mut words: Vec<String> = Vec::new();
    let mut glue_next = false;
    for word in line.split(' ') {
        let after_number = words
            .last()
            .is_some_and(|w| w.ends_with(|c: char| c.is_ascii_digit()));
        match words.last_mut() {
            Some(last)
                if glue_next
                    || word == "="
                    || (after_number
                        && UNITS.contains(&word.trim_end_matches([',', ';', ':', '.', ')']))) =>
            {
                last.push(' ');
                last.push_str(word);
            }
            _ => words.push(word.to_string()),
        }
        glue_next = word == "=";
    }
    words
}

/// Markdown prose wrapped to `width` characters: paragraphs at spaces, list items (`- `) with
/// their continuation lines indented by two; table rows and short lines as they are. A word
/// that would open markup at a line's start stays on the line before.
fn wrap(text: &str, width: usize) -> String {
    let mut out: Vec<String> = Vec::new();
    for line in text.lines() {
        if line.starts_with('|') || line.chars().count() <= width {
            out.push(line.to_string());
            continue;
        }
        let indent = if line.starts_with("- ") { "  " } else { "" };
        let mut current = String::new();
        for word in unbreakable(line) {
            let word = word.as_str();
            let fits = current.chars().count() + 1 + word.chars().count() <= width;
            if current.trim().is_empty() {
                current.push_str(word);
            } else if fits || opens_markup(word) {
                current.push(' ');
                current.push_str(word);
            } else {
                out.push(std::mem::replace(&mut current, format!("{indent}{word}")));
            }
        }
        out.push(current);
    }
    out.join("\n")
}

// ---------------------------------------------------------------------------------------
// README.md's blocks: finding, splicing.

/// A block as README.md has it.
#[derive(Debug, Clone, PartialEq)]
pub struct Found {
    /// Its name.
    pub name: String,
    /// Its first line, the begin marker.
    pub begin: String,
    /// Its text between the markers (lines joined with `\n`, no trailing newline).
    pub content: String,
    /// Whether its end marker's line ends with a newline (not at the end of a file without
    /// one).
    end_newline: bool,
}

/// README's text cut at its blocks: the text before each block, each block, the text after
/// the last.
struct Parsed {
    /// Text (whole lines, each ending in `\n`) before each block.
    between: Vec<String>,
    /// The blocks.
    blocks: Vec<Found>,
}

/// The marker line of a block.
fn begin_line(b: &Block) -> String {
    format!("{BEGIN}{} from {}{BEGIN_END}", b.name, b.sources)
}

/// README's blocks, or what is wrong with its markers.
fn parse(readme: &str) -> Result<Parsed, String> {
    let mut between = vec![String::new()];
    let mut blocks: Vec<Found> = Vec::new();
    let mut open: Option<(Found, Vec<&str>, usize)> = None;
    for (i, line) in readme.split_inclusive('\n').enumerate() {
        let bare = line.trim_end_matches('\n').trim_end_matches('\r');
        if let Some((mut found, lines, at)) = open.take() {
            if bare == END {
                found.content = lines.join("\n");
                found.end_newline = line.ends_with('\n');
                blocks.push(found);
                between.push(String::new());
            } else if bare.starts_with(BEGIN) {
                return Err(format!(
                    "README.md line {}: a block begins inside block `{}` (line {at}), which has \
                     no `{END}`",
                    i + 1,
                    found.name
                ));
            } else {
                let mut lines = lines;
                lines.push(bare);
                open = Some((found, lines, at));
            }
            continue;
        }
        if let Some(rest) = bare.strip_prefix(BEGIN) {
            let name = rest
                .split(" from ")
                .next()
                .filter(|n| !n.is_empty() && !n.contains(' ') && rest.ends_with(BEGIN_END))
                .ok_or_else(|| {
                    format!(
                        "README.md line {}: `{bare}` is not `{BEGIN}NAME from SOURCES{BEGIN_END}`",
                        i + 1
                    )
                })?;
            open = Some((
                Found {
                    name: name.to_string(),
                    begin: bare.to_string(),
                    content: String::new(),
                    end_newline: true,
                },
                Vec::new(),
                i + 1,
            ));
        } else if bare == END {
            return Err(format!(
                "README.md line {}: `{END}` without a block before it",
                i + 1
            ));
        } else {
            between.last_mut().expect("never empty").push_str(line);
        }
    }
    if let Some((found, _, at)) = open {
        return Err(format!(
            "README.md line {at}: block `{}` has no `{END}`",
            found.name
        ));
    }
    Ok(Parsed { between, blocks })
}

/// README's blocks (name, begin line, content).
///
/// # Errors
/// A marker out of place (an unterminated block, an end without a beginning, a malformed
/// begin line).
pub fn blocks(readme: &str) -> Result<Vec<Found>, String> {
    parse(readme).map(|p| p.blocks)
}

/// README's text with each block's content replaced by `content(name)` where it returns
/// `Some` (the begin line rewritten with the registry's sources), the rest byte for byte.
fn splice(readme: &str, content: &dyn Fn(&str) -> Option<String>) -> Result<String, String> {
    let parsed = parse(readme)?;
    let mut out = String::with_capacity(readme.len());
    for (i, text) in parsed.between.iter().enumerate() {
        out.push_str(text);
        let Some(found) = parsed.blocks.get(i) else {
            break;
        };
        let (begin, body) = match (block(&found.name), content(&found.name)) {
            (Some(b), Some(body)) => (begin_line(b), body),
            _ => (found.begin.clone(), found.content.clone()),
        };
        let _ = writeln!(out, "{begin}");
        if !body.is_empty() {
            let _ = writeln!(out, "{body}");
        }
        out.push_str(END);
        if found.end_newline {
            out.push('\n');
        }
    }
    Ok(out)
}

/// What regenerating README.md found.
pub struct Regenerated {
    /// README's text with every block that could be generated rewritten.
    pub text: String,
    /// The blocks whose text (or marker) differs from README's.
    pub changed: Vec<&'static str>,
    /// Blocks that could not be generated, README blocks not in the registry and registry
    /// entries without a block, each as a message.
    pub errors: Vec<String>,
}

/// Regenerates every block of `readme` from `root/reports/`.
///
/// # Errors
/// README's markers out of place (nothing can be spliced then).
pub fn regenerate(readme: &str, root: &Path) -> Result<Regenerated, String> {
    let found = blocks(readme)?;
    let mut errors = Vec::new();
    for f in &found {
        if block(&f.name).is_none() {
            errors.push(format!(
                "README.md has a block `{}` that xtask/src/readme.rs does not generate",
                f.name
            ));
        }
    }
    for b in BLOCKS {
        if found.iter().filter(|f| f.name == b.name).count() > 1 {
            errors.push(format!("README.md has the block `{}` twice", b.name));
        }
    }
    let mut rendered: Vec<(&'static str, String)> = Vec::new();
    let mut changed = Vec::new();
    for b in BLOCKS {
        let Some(f) = found.iter().find(|f| f.name == b.name) else {
            errors.push(format!(
                "README.md has no block `{}` ({BEGIN}{} from {}{BEGIN_END} … {END})",
                b.name, b.name, b.sources
            ));
            continue;
        };
        match generate(b, root) {
            Ok(text) => {
                if text != f.content || begin_line(b) != f.begin {
                    changed.push(b.name);
                }
                rendered.push((b.name, text));
            }
            Err(e) => errors.push(format!("block `{}` ({}): {e}", b.name, b.sources)),
        }
    }
    let text = splice(readme, &|name| {
        rendered
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, t)| t.clone())
    })?;
    Ok(Regenerated {
        text,
        changed,
        errors,
    })
}

/// Rewrites `root/README.md`'s blocks from `root/reports/`: the names of the blocks that
/// changed. Blocks that cannot be generated keep their text.
///
/// # Errors
/// README.md cannot be read or written, its markers are out of place, or a block cannot be
/// generated (the others are written all the same).
pub fn update(root: &Path) -> Result<Vec<&'static str>, String> {
    let path = root.join("README.md");
    let readme = std::fs::read_to_string(&path).map_err(|e| format!("README.md: {e}"))?;
    let r = regenerate(&readme, root)?;
    if r.text != readme {
        std::fs::write(&path, &r.text).map_err(|e| format!("README.md: {e}"))?;
    }
    if r.errors.is_empty() {
        Ok(r.changed)
    } else {
        Err(r.errors.join("; "))
    }
}

/// After a command that writes reports: brings README.md's blocks up to date, printing what
/// changed or what went wrong (never fatal for the command, whose exit status is kept).
pub fn after(command: &str, root: &Path) {
    match update(root) {
        Ok(changed) if changed.is_empty() => {
            eprintln!("{command}: README.md's generated blocks match the reports");
        }
        Ok(changed) => eprintln!(
            "{command}: README.md's generated blocks updated from reports/: {}",
            changed.join(", ")
        ),
        Err(e) => eprintln!("{command}: README.md's generated blocks: {e}"),
    }
}

/// `cargo xtask readme [--check]`.
pub fn main(args: &[String], root: &Path) -> ExitCode {
    let mut check = false;
    for a in args {
        match a.as_str() {
            "--check" => check = true,
            other => {
                eprintln!("readme: unknown option `{other}`; allowed: --check");
                return ExitCode::from(2);
            }
        }
    }
    let path = root.join("README.md");
    let readme = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("readme: README.md: {e}");
            return ExitCode::from(2);
        }
    };
    let r = match regenerate(&readme, root) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("readme: {e}");
            return ExitCode::from(2);
        }
    };
    for e in &r.errors {
        eprintln!("readme: {e}");
    }
    if check {
        if r.changed.is_empty() && r.errors.is_empty() {
            eprintln!(
                "readme: all {} generated blocks match the reports",
                BLOCKS.len()
            );
            return ExitCode::SUCCESS;
        }
        for name in &r.changed {
            eprintln!("readme: block `{name}` differs from the reports");
        }
        if !r.changed.is_empty() {
            eprintln!("readme: run `cargo xtask readme` to rewrite them");
        }
        return ExitCode::FAILURE;
    }
    if r.text != readme
        && let Err(e) = std::fs::write(&path, &r.text)
    {
        eprintln!("readme: README.md: {e}");
        return ExitCode::from(2);
    }
    if r.changed.is_empty() {
        eprintln!("readme: no block changed ({} blocks)", BLOCKS.len());
    } else {
        eprintln!("readme: rewrote {}", r.changed.join(", "));
    }
    if r.errors.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn root() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
    }

    fn readme() -> String {
        std::fs::read_to_string(root().join("README.md")).unwrap()
    }

    #[test]
    fn every_generated_block_of_the_readme_matches_the_committed_reports() {
        let readme = readme();
        let found = blocks(&readme).expect("README.md's markers");
        let mut wrong = Vec::new();
        for b in BLOCKS {
            let Some(f) = found.iter().find(|f| f.name == b.name) else {
                continue; // the next test names it
            };
            match generate(b, &root()) {
                Ok(text) => {
                    if text != f.content {
                        wrong.push(format!(
                            "block `{}` differs from {}:\n--- README.md\n{}\n--- generated\n{}",
                            b.name, b.sources, f.content, text
                        ));
                    } else if f.begin != begin_line(b) {
                        wrong.push(format!(
                            "block `{}`: its marker is `{}`, not `{}`",
                            b.name,
                            f.begin,
                            begin_line(b)
                        ));
                    }
                }
                Err(e) => wrong.push(format!("block `{}` cannot be generated: {e}", b.name)),
            }
        }
        assert!(
            wrong.is_empty(),
            "{}\n\nrun `cargo xtask readme` to rewrite README.md's blocks from reports/",
            wrong.join("\n\n")
        );
    }

    #[test]
    fn the_readme_has_exactly_the_registrys_blocks() {
        let readme = readme();
        let found = blocks(&readme).expect("README.md's markers");
        let mut names: Vec<&str> = found.iter().map(|f| f.name.as_str()).collect();
        let unknown: Vec<&str> = names
            .iter()
            .copied()
            .filter(|n| block(n).is_none())
            .collect();
        assert!(
            unknown.is_empty(),
            "README.md has blocks that xtask/src/readme.rs does not generate: {unknown:?}"
        );
        let absent: Vec<&str> = BLOCKS
            .iter()
            .map(|b| b.name)
            .filter(|n| !names.contains(n))
            .collect();
        assert!(
            absent.is_empty(),
            "xtask/src/readme.rs generates blocks README.md does not have: {absent:?}"
        );
        let n = names.len();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), n, "README.md has a block twice");
        // The registry's names are unique and its sources are files under reports/.
        for b in BLOCKS {
            assert_eq!(BLOCKS.iter().filter(|c| c.name == b.name).count(), 1);
            assert!(!b.name.contains(' '), "{}", b.name);
            for s in b.sources.split(", ") {
                assert!(
                    s.starts_with("reports/") && root().join(s).is_file(),
                    "block `{}` reads {s}, which is not a committed report",
                    b.name
                );
            }
        }
    }

    #[test]
    fn regenerating_replaces_only_what_lies_between_the_markers() {
        let perf = &BLOCKS
            .iter()
            .find(|b| b.name == "performance")
            .expect("the performance block");
        let old =
            format!("a\n{BEGIN}performance from somewhere{BEGIN_END}\nold\nlines\n{END}\nb\n");
        let out = splice(&old, &|name| {
            (name == "performance").then(|| "| new |".into())
        })
        .unwrap();
        assert_eq!(out, format!("a\n{}\n| new |\n{END}\nb\n", begin_line(perf)));
        // Unknown blocks and text outside blocks stay as they were.
        let other = format!("x\n{BEGIN}other from y{BEGIN_END}\nkept\n{END}\n");
        assert_eq!(splice(&other, &|_| None).unwrap(), other);
        assert_eq!(splice("no markers\n", &|_| None).unwrap(), "no markers\n");
    }

    #[test]
    fn misplaced_markers_are_refused_with_their_line() {
        let unterminated = format!("a\n{BEGIN}claims from reports/summary.json{BEGIN_END}\nx\n");
        assert!(blocks(&unterminated).unwrap_err().contains("line 2"));
        let stray = format!("a\n{END}\n");
        assert!(blocks(&stray).unwrap_err().contains("line 2"));
        let nested = format!("{BEGIN}a from b{BEGIN_END}\n{BEGIN}c from d{BEGIN_END}\n{END}\n");
        assert!(blocks(&nested).is_err());
        let nameless = format!("{BEGIN}from b{BEGIN_END}\n{END}\n");
        assert!(blocks(&nameless).is_err());
    }
}
