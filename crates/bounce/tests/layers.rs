//! The core's modules form layers: no import circle among `crates/bounce/src`'s top-level
//! modules (a folder counts as one), and no file over the size that keeps one idea a file.
//!
//! Read from the sources: every `crate::module` a file names outside its unit tests is an
//! import of that module. A circle is reported with its path.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

/// The most production lines (unit tests excluded) a core file may have.
const MAX_PRODUCTION_LINES: usize = 600;

fn sources() -> Vec<PathBuf> {
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
    walk(&Path::new(env!("CARGO_MANIFEST_DIR")).join("src"), &mut out);
    out.sort();
    out
}

/// The top-level module a source file belongs to (`None` for `lib.rs`).
fn module_of(path: &Path) -> Option<String> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let rel = path.strip_prefix(&src).unwrap();
    let first = rel.components().next()?.as_os_str().to_str()?.to_owned();
    let name = first.trim_end_matches(".rs").to_owned();
    (name != "lib").then_some(name)
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

/// The top-level modules named as `crate::name` in `text`, comments left out.
fn imports(text: &str, modules: &BTreeSet<String>) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for line in text.lines() {
        let code = line.split("//").next().unwrap_or("");
        let mut rest = code;
        while let Some(at) = rest.find("crate::") {
            let after = &rest[at + "crate::".len()..];
            let name: String = after
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            if modules.contains(&name) {
                out.insert(name);
            }
            rest = after;
        }
        // `use crate::{a, b::c}` groups.
        if let Some(at) = code.find("use crate::{") {
            for part in code[at + "use crate::{".len()..].split([',', '{', '}']) {
                let name = part.trim().split("::").next().unwrap_or("").to_owned();
                if modules.contains(&name) {
                    out.insert(name);
                }
            }
        }
    }
    out
}

fn graph() -> BTreeMap<String, BTreeSet<String>> {
    let files = sources();
    let modules: BTreeSet<String> = files.iter().filter_map(|p| module_of(p)).collect();
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for path in &files {
        let Some(module) = module_of(path) else {
            continue;
        };
        let text = fs::read_to_string(path).unwrap();
        let entry = edges.entry(module.clone()).or_default();
        for target in imports(&production(path, &text), &modules) {
            if target != module {
                entry.insert(target);
            }
        }
    }
    edges
}

/// A circle through `edges`, if there is one, as the modules along it.
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
    for path in sources() {
        let text = fs::read_to_string(&path).unwrap();
        let lines = production(&path, &text).lines().count();
        assert!(
            lines <= MAX_PRODUCTION_LINES,
            "{}: {lines} production lines (at most {MAX_PRODUCTION_LINES})",
            path.display()
        );
    }
}
