//! No circle of imports, of any length, among source files or among folders: for every crate,
//! each file's references to other modules of its crate (`crate::a::b`, `super::c`, in `use`
//! lines and in code, tests aside) are resolved to files, and any strongly connected set of
//! files fails the test — but for a module and its own submodules (a parent `mod.rs` and the
//! files it declares belong together). At folder level every module counts as its crate's
//! top-level module (`sim::coupling` as `sim`), and the same holds.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives one level below the workspace root")
        .to_path_buf()
}

/// A module path within its crate (`["sim", "coupling"]`).
type ModPath = Vec<String>;

/// Every `.rs` file of the crate whose sources are in `src`, by module path.
fn modules(src: &Path) -> BTreeMap<ModPath, PathBuf> {
    fn walk(dir: &Path, prefix: &[String], out: &mut BTreeMap<ModPath, PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            let name = entry.file_name().to_string_lossy().to_string();
            if path.is_dir() {
                let mut p = prefix.to_vec();
                p.push(name);
                walk(&path, &p, out);
            } else if let Some(stem) = name.strip_suffix(".rs") {
                let mut p = prefix.to_vec();
                if !["mod", "lib", "main"].contains(&stem) {
                    p.push(stem.to_string());
                }
                out.insert(p, path);
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(src, &[], &mut out);
    // Binaries' roots (src/bin/*.rs) are crates of their own.
    out.retain(|p, _| p.first().map(String::as_str) != Some("bin"));
    out
}

/// The code before the first `#[cfg(test)]` (tests may reach anywhere), without comments
/// (a doc link names a module without importing it).
fn code_without_tests(text: &str) -> String {
    let code = text.find("#[cfg(test)]").map_or(text, |i| &text[..i]);
    code.lines()
        .map(|l| l.find("//").map_or(l, |i| &l[..i]))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The module paths `text` (code without comments) names after `crate::` or `super::` (each a path of identifiers,
/// brace groups expanded one level: `super::{a::B, c}` names `a::B` and `c`).
fn referenced(text: &str) -> Vec<(bool, Vec<String>)> {
    let mut out = Vec::new();
    for (anchor, is_crate) in [("crate::", true), ("super::", false)] {
        let mut rest = text;
        while let Some(i) = rest.find(anchor) {
            // Not part of a longer identifier (`my_crate::`).
            let before = rest[..i].chars().last();
            rest = &rest[i + anchor.len()..];
            if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
                continue;
            }
            let mut supers = 0;
            while let Some(r) = rest.strip_prefix("super::") {
                supers += 1;
                rest = r;
            }
            let groups: Vec<String> = if let Some(r) = rest.strip_prefix('{') {
                let end = r.find('}').unwrap_or(r.len());
                r[..end].split(',').map(|s| s.trim().to_string()).collect()
            } else {
                vec![
                    rest.chars()
                        .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
                        .collect(),
                ]
            };
            for g in groups {
                let mut path: Vec<String> = vec!["super".to_string(); supers];
                path.extend(
                    g.split("::")
                        .map(|s| s.trim().trim_start_matches('{').to_string())
                        .take_while(|s| {
                            !s.is_empty() && s.chars().all(|c| c.is_alphanumeric() || c == '_')
                        }),
                );
                if !path.is_empty() {
                    out.push((is_crate, path));
                }
            }
        }
    }
    out
}

/// The file a reference from module `from` (file `from_file`) resolves to: the longest prefix
/// of the absolute path that is a module of the crate.
fn resolve(
    from: &ModPath,
    from_file: &Path,
    (is_crate, path): &(bool, Vec<String>),
    mods: &BTreeMap<ModPath, PathBuf>,
) -> Option<ModPath> {
    let mut abs: ModPath = if *is_crate {
        Vec::new()
    } else {
        // `super` of a `mod.rs` is its directory's parent module; of `x.rs`, its directory.
        let mut base = from.clone();
        let is_mod_rs = from_file.file_name().is_some_and(|n| n == "mod.rs");
        if !is_mod_rs || !base.is_empty() {
            base.pop();
        }
        base
    };
    for part in path {
        if part == "super" {
            abs.pop();
        } else if part != "self" {
            abs.push(part.clone());
        }
    }
    (1..=abs.len())
        .rev()
        .map(|n| abs[..n].to_vec())
        .find(|p| mods.contains_key(p))
}

/// The import graph of the crate at `src`: each module's file and the modules it refers to
/// (a module's references to its own submodules and parents aside: they belong together).
fn import_graph(src: &Path) -> (BTreeMap<ModPath, PathBuf>, Graph) {
    let mods = modules(src);
    let nested = |a: &ModPath, b: &ModPath| a.starts_with(b) || b.starts_with(a);
    let mut edges = Graph::new();
    for (m, file) in &mods {
        let text = std::fs::read_to_string(file).unwrap_or_default();
        edges.entry(m.clone()).or_default();
        for r in referenced(&code_without_tests(&text)) {
            if let Some(to) = resolve(m, file, &r, &mods)
                && !nested(m, &to)
            {
                edges.entry(m.clone()).or_default().insert(to);
            }
        }
    }
    (mods, edges)
}

/// A directed graph of module paths.
type Graph = BTreeMap<ModPath, BTreeSet<ModPath>>;

/// The strongly connected components of `graph` with more than one node: each is a circle of
/// imports of some length (Tarjan's algorithm, iterative so that deep graphs cannot overflow).
fn cycles(graph: &Graph) -> Vec<Vec<ModPath>> {
    let nodes: Vec<&ModPath> = graph
        .keys()
        .chain(graph.values().flatten())
        .collect::<BTreeSet<_>>()
        .into_iter()
        .collect();
    let id: BTreeMap<&ModPath, usize> = nodes.iter().enumerate().map(|(i, n)| (*n, i)).collect();
    let succ: Vec<Vec<usize>> = nodes
        .iter()
        .map(|n| {
            graph
                .get(*n)
                .map_or(Vec::new(), |t| t.iter().map(|m| id[m]).collect())
        })
        .collect();
    let n = nodes.len();
    let (mut index, mut low) = (vec![usize::MAX; n], vec![0; n]);
    let (mut on_stack, mut stack, mut next) = (vec![false; n], Vec::new(), 0);
    let mut out = Vec::new();
    for root in 0..n {
        if index[root] != usize::MAX {
            continue;
        }
        // (node, position in its successor list)
        let mut work = vec![(root, 0)];
        while let Some(&mut (v, ref mut pos)) = work.last_mut() {
            if *pos == 0 {
                index[v] = next;
                low[v] = next;
                next += 1;
                stack.push(v);
                on_stack[v] = true;
            }
            if let Some(&w) = succ[v].get(*pos) {
                *pos += 1;
                if index[w] == usize::MAX {
                    work.push((w, 0));
                } else if on_stack[w] {
                    low[v] = low[v].min(index[w]);
                }
                continue;
            }
            work.pop();
            if let Some(&(parent, _)) = work.last() {
                low[parent] = low[parent].min(low[v]);
            }
            if low[v] == index[v] {
                let mut component = Vec::new();
                while let Some(w) = stack.pop() {
                    on_stack[w] = false;
                    component.push(nodes[w].clone());
                    if w == v {
                        break;
                    }
                }
                if component.len() > 1 {
                    component.sort();
                    out.push(component);
                }
            }
        }
    }
    out.sort();
    out
}

/// Circles of files of the crate at `src` (a module and its own submodules aside), each as
/// `a -> b -> … ` relative to `root`.
fn circles(root: &Path, src: &Path) -> Vec<String> {
    let (mods, edges) = import_graph(src);
    let rel = |m: &ModPath| {
        mods[m]
            .strip_prefix(root)
            .unwrap_or(&mods[m])
            .display()
            .to_string()
    };
    cycles(&edges)
        .iter()
        .map(|c| c.iter().map(rel).collect::<Vec<_>>().join(" <-> "))
        .collect()
}

/// Circles of folders of the crate at `src`: each module counted as its crate's top-level
/// module (`sim::coupling` as `sim`), so that two folders leaning on each other through
/// different files are found too.
fn folder_circles(root: &Path, src: &Path) -> Vec<String> {
    let (_, edges) = import_graph(src);
    let top = |m: &ModPath| m.iter().take(1).cloned().collect::<ModPath>();
    let mut folders = Graph::new();
    for (a, tos) in &edges {
        for b in tos {
            let (fa, fb) = (top(a), top(b));
            // The crate root (lib.rs) re-exports; it is nobody's folder.
            if fa != fb && !fa.is_empty() && !fb.is_empty() {
                folders.entry(fa).or_default().insert(fb);
            }
        }
    }
    let name = src.strip_prefix(root).unwrap_or(src).display().to_string();
    cycles(&folders)
        .iter()
        .map(|c| {
            let parts: Vec<String> = c
                .iter()
                .map(|m| format!("{name}/{}", m.join("/")))
                .collect();
            parts.join(" <-> ")
        })
        .collect()
}

/// Every crate's `src` in the workspace.
fn crate_sources(root: &Path) -> Vec<PathBuf> {
    let mut dirs: Vec<PathBuf> = ["validation", "maps", "benches", "xtask"]
        .iter()
        .map(|d| root.join(d))
        .collect();
    if let Ok(entries) = std::fs::read_dir(root.join("crates")) {
        dirs.extend(entries.flatten().map(|e| e.path()));
    }
    let mut out: Vec<PathBuf> = dirs
        .into_iter()
        .map(|d| {
            if d.join("src").is_dir() {
                d.join("src")
            } else {
                d
            }
        })
        .filter(|d| d.join("lib.rs").is_file() || d.join("main.rs").is_file())
        .collect();
    out.sort();
    out
}

#[test]
fn no_two_files_import_each_other() {
    let root = workspace_root();
    let crates = crate_sources(&root);
    assert!(crates.len() >= 9, "{crates:?}");
    let found: Vec<String> = crates.iter().flat_map(|src| circles(&root, src)).collect();
    assert!(found.is_empty(), "files that import each other: {found:#?}");
}

#[test]
fn no_two_folders_import_each_other() {
    let root = workspace_root();
    let found: Vec<String> = crate_sources(&root)
        .iter()
        .flat_map(|src| folder_circles(&root, src))
        .collect();
    assert!(
        found.is_empty(),
        "folders that import each other: {found:#?}"
    );
}

#[test]
fn a_pair_of_files_that_import_each_other_is_found() {
    let tmp = std::env::temp_dir().join(format!("stickslip-circles-{}", std::process::id()));
    let src = tmp.join("src");
    std::fs::create_dir_all(src.join("sim")).unwrap();
    let files = [
        ("lib.rs", "//! x\npub mod a;\npub mod b;\npub mod sim;\n"),
        ("a.rs", "//! a\nuse crate::b::B;\npub struct A;\n"),
        ("b.rs", "//! b\npub struct B(crate::a::A);\n"),
        ("sim/mod.rs", "//! sim\npub mod step;\npub use step::S;\n"),
        (
            "sim/step.rs",
            "//! step\nuse super::{super::a::A, T};\npub struct S;\n#[cfg(test)]\nuse crate::b::B;\n",
        ),
    ];
    for (name, text) in files {
        std::fs::write(src.join(name), text).unwrap();
    }
    let found = circles(&tmp, &src);
    std::fs::remove_dir_all(&tmp).unwrap();
    // a <-> b; sim/step refers to a and to its parent, a module and its submodule belong
    // together, and its test-only import of b does not count.
    assert_eq!(found, ["src/a.rs <-> src/b.rs"]);
}

#[test]
fn a_circle_of_three_files_and_one_of_two_folders_are_found() {
    let tmp = std::env::temp_dir().join(format!("stickslip-circles3-{}", std::process::id()));
    let src = tmp.join("src");
    std::fs::create_dir_all(src.join("sim")).unwrap();
    std::fs::create_dir_all(src.join("config")).unwrap();
    let files = [
        (
            "lib.rs",
            "//! x\npub mod a;\npub mod b;\npub mod c;\npub mod config;\npub mod sim;\n",
        ),
        ("a.rs", "//! a\nuse crate::b::B;\npub struct A;\n"),
        ("b.rs", "//! b\npub struct B(crate::c::C);\n"),
        ("c.rs", "//! c\npub struct C(super::a::A);\n"),
        ("sim/mod.rs", "//! sim\npub mod step;\n"),
        ("sim/step.rs", "//! step\nuse crate::config::Config;\n"),
        (
            "config/mod.rs",
            "//! config\npub mod check;\npub struct Config;\n",
        ),
        (
            "config/check.rs",
            "//! check\nuse crate::sim::step::Step;\n",
        ),
    ];
    for (name, text) in files {
        std::fs::write(src.join(name), text).unwrap();
    }
    let files = circles(&tmp, &src);
    let folders = folder_circles(&tmp, &src);
    std::fs::remove_dir_all(&tmp).unwrap();
    // No two files import each other, but a -> b -> c -> a is a circle; and sim/step and
    // config/check are no circle of files, but their folders lean on each other.
    assert_eq!(files, ["src/a.rs <-> src/b.rs <-> src/c.rs"]);
    assert_eq!(
        folders,
        ["src/a <-> src/b <-> src/c", "src/config <-> src/sim"]
    );
}
