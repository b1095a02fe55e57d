//! The compiler's stages import in one direction (ARCHITECTURE.md, "Micro/WIN
//! dialect"): the graph of its top-level modules (`source`, `syntax`, `check`,
//! `microwin`, ...), read from every `crate::` path of compiler/src, has no circle;
//! `microwin` is imported by `lib.rs` alone; and the checker never asks whether a
//! program is a Micro/WIN export. The reader is plain text (comments dropped, `use
//! crate::{a, b::c}` groups split), and a test below shows it finds a circle.

#![allow(
    clippy::disallowed_methods,
    reason = "tests read the compiler's sources"
)]

mod common;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Every `.rs` file under `dir`, sorted.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap_or_else(|e| panic!("{}: {e}", d.display())) {
            let path = entry.expect("dir entry").path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|x| x == "rs") {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

/// The text without `//` comments (doc comments name modules without importing them).
fn code_of(text: &str) -> String {
    text.lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The first segment of every `crate::` path in `code`, groups included:
/// `crate::{check::Conventions, source::Span}` names `check` and `source`.
fn crate_paths(code: &str) -> BTreeSet<String> {
    let mut names = BTreeSet::new();
    let mut rest = code;
    while let Some(at) = rest.find("crate::") {
        rest = &rest[at + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            // The group's items at its own level: `a::{b, c}, d` is `a` and `d`.
            let mut depth = 0;
            let mut item = String::new();
            for c in group.chars() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => break,
                    '}' => depth -= 1,
                    ',' if depth == 0 => {
                        insert_first_segment(&mut names, &item);
                        item.clear();
                        continue;
                    }
                    _ => {}
                }
                item.push(c);
            }
            insert_first_segment(&mut names, &item);
        } else {
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            names.insert(name);
        }
    }
    names
}

/// The first segment of a path (`check::{A, B}` -> `check`), if any.
fn insert_first_segment(names: &mut BTreeSet<String>, path: &str) {
    let first = path.trim().split("::").next().unwrap_or("").trim();
    if !first.is_empty() {
        names.insert(first.to_string());
    }
}

/// Top-level module -> the top-level modules it imports (`lib.rs` left out: it is the
/// pipeline, which imports every stage).
fn module_graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let modules: BTreeSet<String> = std::fs::read_dir(src)
        .expect("compiler/src")
        .map(|e| e.expect("dir entry").path())
        .filter_map(|p| Some(p.file_stem()?.to_str()?.to_string()))
        .filter(|m| m != "lib")
        .collect();
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for file in rust_files(src) {
        let relative = file.strip_prefix(src).expect("under src");
        let top = relative
            .components()
            .next()
            .and_then(|c| Path::new(c.as_os_str()).file_stem()?.to_str())
            .unwrap_or("")
            .to_string();
        if top == "lib" {
            continue;
        }
        let text = std::fs::read_to_string(&file).expect("read source");
        let used = crate_paths(&code_of(&text));
        let entry = graph.entry(top.clone()).or_default();
        entry.extend(
            used.into_iter()
                .filter(|m| *m != top && modules.contains(m)),
        );
    }
    graph
}

/// A circle of the graph, if there is one (the modules on it, in order).
fn find_circle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        node: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(at) = path.iter().position(|n| n == node) {
            let mut circle = path[at..].to_vec();
            circle.push(node.to_string());
            return Some(circle);
        }
        if done.contains(node) {
            return None;
        }
        path.push(node.to_string());
        for next in graph.get(node).into_iter().flatten() {
            if let Some(circle) = visit(next, graph, path, done) {
                return Some(circle);
            }
        }
        path.pop();
        done.insert(node.to_string());
        None
    }
    let mut done = BTreeSet::new();
    graph
        .keys()
        .find_map(|start| visit(start, graph, &mut Vec::new(), &mut done))
}

fn src() -> PathBuf {
    common::root().join("compiler/src")
}

#[test]
fn the_compiler_has_no_import_circle() {
    let graph = module_graph(&src());
    assert!(
        graph.contains_key("check") && graph.contains_key("microwin"),
        "{graph:?}"
    );
    assert_eq!(find_circle(&graph), None, "{graph:?}");
    // The circle issue 25 names went with the dialect's detection moving into source.rs.
    assert_eq!(graph.get("source"), Some(&BTreeSet::new()), "{graph:?}");
}

#[test]
fn only_the_pipeline_imports_the_dialect_stage() {
    let graph = module_graph(&src());
    let importers: Vec<&String> = graph
        .iter()
        .filter(|(_, used)| used.contains("microwin"))
        .map(|(module, _)| module)
        .collect();
    assert!(importers.is_empty(), "{importers:?} import crate::microwin");
}

#[test]
fn the_checker_never_asks_whether_a_program_is_an_export() {
    for file in rust_files(&src().join("check")) {
        let code = code_of(&std::fs::read_to_string(&file).expect("read source"));
        for asks in [
            ".microwin",
            "gutta_boxes",
            "is_microwin",
            "interrupt_placements",
        ] {
            let hits: Vec<&str> = code
                .lines()
                .filter(|l| l.contains(asks) && !l.contains("microwin_system_bit"))
                .collect();
            assert!(hits.is_empty(), "{}: {hits:?}", file.display());
        }
    }
}

#[test]
fn the_reader_finds_groups_and_circles() {
    let code = code_of(
        "use crate::{check::{A, B}, source::Span};\n// crate::microwin in a comment\nlet x = crate::syntax::parse(t);",
    );
    assert_eq!(
        crate_paths(&code),
        ["check", "source", "syntax"]
            .map(String::from)
            .into_iter()
            .collect()
    );
    let edge = |a: &str, b: &[&str]| (a.to_string(), b.iter().map(|s| s.to_string()).collect());
    let circle: BTreeMap<String, BTreeSet<String>> = [
        edge("source", &["microwin"]),
        edge("microwin", &["diagnostics"]),
        edge("diagnostics", &["source"]),
    ]
    .into_iter()
    .collect();
    assert_eq!(
        find_circle(&circle),
        Some(
            ["diagnostics", "source", "microwin", "diagnostics"]
                .map(String::from)
                .to_vec()
        )
    );
    let line: BTreeMap<String, BTreeSet<String>> =
        [edge("microwin", &["source"]), edge("source", &[])]
            .into_iter()
            .collect();
    assert_eq!(find_circle(&line), None);
}
