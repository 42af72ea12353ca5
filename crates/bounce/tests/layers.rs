//! The workspace's modules form layers: no import circle among any crate's top-level modules
//! (a folder counts as one), and in the core no layer that looks up and no file over the size
//! that keeps one idea a file.
//!
//! Read from the sources: every `crate::module` a file names outside its unit tests is an
//! import of that module, and so is `crate::Name` where the crate's root re-exports `Name`
//! from a module (`pub use module::Name`), and `super::module` in a top-level module's file.
//! A circle is reported with its path.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

/// The most production lines (unit tests excluded) a core file may have.
const MAX_PRODUCTION_LINES: usize = 600;

/// The core's sources.
fn core() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

fn sources(src: &Path) -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                out.push(path);
            }
        }
    }
    let mut out = Vec::new();
    walk(src, &mut out);
    out.sort();
    out
}

/// The top-level module a source file of the crate in `src` belongs to (`None` for the
/// crate's root, `lib.rs` or `main.rs`).
fn module_of(src: &Path, path: &Path) -> Option<String> {
    let rel = path.strip_prefix(src).unwrap();
    let first = rel.components().next()?.as_os_str().to_str()?.to_owned();
    let name = first.trim_end_matches(".rs").to_owned();
    (name != "lib" && name != "main").then_some(name)
}

/// Whether `path` is a top-level module's own file (`src/a.rs` or `src/a/mod.rs`), where
/// `super::` is the crate's root.
fn top_level(src: &Path, path: &Path) -> bool {
    let rel = path.strip_prefix(src).unwrap();
    let depth = rel.components().count();
    depth == 1 || (depth == 2 && rel.ends_with("mod.rs"))
}

/// A file's text without its unit tests: up to `#[cfg(test)]` before `mod tests {`, and
/// nothing at all for a file that is a test module (`tests.rs`).
fn production(path: &Path, text: &str) -> String {
    if path.file_name().is_some_and(|n| n == "tests.rs") {
        return String::new();
    }
    let lines: Vec<&str> = text.lines().collect();
    let end = lines
        .windows(2)
        .position(|w| w[0].starts_with("#[cfg(test)]") && w[1].starts_with("mod tests {"))
        .unwrap_or(lines.len());
    lines[..end].join("\n")
}

/// The names a crate's root re-exports from its modules: `pub use module::{A, b::C};` gives
/// `A` and `C` from `module`.
fn reexports(root: &str, modules: &BTreeSet<String>) -> BTreeMap<String, String> {
    let code: String = root
        .lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join(" ");
    let mut out = BTreeMap::new();
    for statement in code.split(';') {
        let Some(at) = statement.find("use ") else {
            continue;
        };
        let path = statement[at + 4..].trim();
        let Some((module, rest)) = path.split_once("::") else {
            continue;
        };
        if !modules.contains(module) {
            continue;
        }
        for part in rest.split([',', '{', '}']) {
            let part = part.trim();
            let name = part.rsplit(" as ").next().unwrap_or(part);
            let name = name.rsplit("::").next().unwrap_or(name).trim();
            if !name.is_empty() && name != "self" {
                out.insert(name.to_owned(), module.to_owned());
            }
        }
    }
    out
}

/// The top-level modules `text` names: `crate::name` (a module, or a name the root
/// re-exports from one) and, in a top-level module's file, `super::name`; comments left out.
fn imports(
    text: &str,
    modules: &BTreeSet<String>,
    names: &BTreeMap<String, String>,
    top: bool,
) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let resolve = |name: &str, out: &mut BTreeSet<String>| {
        if modules.contains(name) {
            out.insert(name.to_owned());
        } else if let Some(module) = names.get(name) {
            out.insert(module.clone());
        }
    };
    let prefixes: &[&str] = if top {
        &["crate::", "super::"]
    } else {
        &["crate::"]
    };
    for line in text.lines() {
        let code = line.split("//").next().unwrap_or("");
        for prefix in prefixes {
            let mut rest = code;
            while let Some(at) = rest.find(prefix) {
                let after = &rest[at + prefix.len()..];
                let name: String = after
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                resolve(&name, &mut out);
                // `use crate::{a, b::c}` groups.
                if let Some(group) = after.strip_prefix('{') {
                    let group = group.split('}').next().unwrap_or("");
                    for part in group.split(',') {
                        resolve(part.trim().split("::").next().unwrap_or(""), &mut out);
                    }
                }
                rest = after;
            }
        }
    }
    out
}

/// The import graph of the crate whose sources are in `src`.
fn graph_of(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let files = sources(src);
    let modules: BTreeSet<String> = files.iter().filter_map(|p| module_of(src, p)).collect();
    let root = ["lib.rs", "main.rs"]
        .iter()
        .find_map(|r| fs::read_to_string(src.join(r)).ok())
        .unwrap_or_default();
    let names = reexports(&root, &modules);
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for path in &files {
        let Some(module) = module_of(src, path) else {
            continue;
        };
        let text = fs::read_to_string(path).unwrap();
        let entry = edges.entry(module.clone()).or_default();
        let found = imports(
            &production(path, &text),
            &modules,
            &names,
            top_level(src, path),
        );
        for target in found {
            if target != module {
                entry.insert(target);
            }
        }
    }
    edges
}

fn graph() -> BTreeMap<String, BTreeSet<String>> {
    graph_of(&core())
}

fn find_circle(edges: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        node: &str,
        edges: &BTreeMap<String, BTreeSet<String>>,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(at) = path.iter().position(|n| n == node) {
            let mut circle = path[at..].to_vec();
            circle.push(node.to_owned());
            return Some(circle);
        }
        if done.contains(node) {
            return None;
        }
        path.push(node.to_owned());
        for next in edges.get(node).into_iter().flatten() {
            if let Some(circle) = visit(next, edges, path, done) {
                return Some(circle);
            }
        }
        path.pop();
        done.insert(node.to_owned());
        None
    }
    let mut done = BTreeSet::new();
    for node in edges.keys() {
        if let Some(circle) = visit(node, edges, &mut Vec::new(), &mut done) {
            return Some(circle);
        }
    }
    None
}

#[test]
fn the_core_has_no_import_circle() {
    let edges = graph();
    assert!(edges.len() > 15, "too few modules found: {edges:?}");
    // The checker finds a circle where there is one.
    let mut with_circle = edges.clone();
    with_circle
        .entry("config".to_owned())
        .or_default()
        .insert("world".to_owned());
    assert!(find_circle(&with_circle).is_some());
    if let Some(circle) = find_circle(&edges) {
        panic!("import circle: {}", circle.join(" -> "));
    }
}

#[test]
fn no_crate_in_the_workspace_has_an_import_circle() {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut checked = 0;
    for entry in fs::read_dir(&crates).unwrap() {
        let src = entry.unwrap().path().join("src");
        if !src.is_dir() {
            continue;
        }
        let edges = graph_of(&src);
        if let Some(circle) = find_circle(&edges) {
            panic!("{}: import circle: {}", src.display(), circle.join(" -> "));
        }
        checked += 1;
    }
    assert!(checked >= 7, "only {checked} crates found");
}

#[test]
fn a_name_the_root_reexports_counts_as_an_import_of_its_module() {
    let modules: BTreeSet<String> = ["geometry", "sum"].map(String::from).into();
    let names = reexports(
        "pub use geometry::{Geometry, WallImpulse as Walls};",
        &modules,
    );
    assert_eq!(names.get("Walls").map(String::as_str), Some("geometry"));
    let found = imports("fn f() -> crate::Walls {}", &modules, &names, false);
    assert_eq!(found, ["geometry".to_string()].into());
    let found = imports("use super::sum::ExactSum;", &modules, &names, true);
    assert_eq!(found, ["sum".to_string()].into());
}

#[test]
fn the_layers_run_one_way() {
    let edges = graph();
    // Plain data and numerics at the bottom, the law above them, the world above the stages.
    for bottom in ["config", "lanes", "parallel", "sum"] {
        assert!(
            edges[bottom].is_empty(),
            "{bottom} imports {:?}",
            edges[bottom]
        );
    }
    assert!(
        edges["law"].iter().all(|m| m == "config" || m == "lanes"),
        "law imports {:?}",
        edges["law"]
    );
    for (module, targets) in &edges {
        if module != "plain" {
            assert!(!targets.contains("world"), "{module} imports world");
        }
    }
}

#[test]
fn no_core_file_is_over_the_size_of_one_idea() {
    for path in sources(&core()) {
        let text = fs::read_to_string(&path).unwrap();
        let lines = production(&path, &text).lines().count();
        assert!(
            lines <= MAX_PRODUCTION_LINES,
            "{}: {lines} production lines (at most {MAX_PRODUCTION_LINES})",
            path.display()
        );
    }
}
