//! Shared helpers of the compiler's integration tests: where the repository is, and
//! which programs the tests run over.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]
#![allow(dead_code)]

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use gutta_catalog::{stdlib, Target};
use gutta_compiler::{CheckedFile, ExplicitTarget};

/// The repository root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The `.lad` files of a directory, sorted.
pub fn lad_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("dir entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "lad"))
        .collect();
    files.sort();
    files
}

/// Every program that compiles: the examples and the clean check corpus.
pub fn compiling_programs() -> Vec<PathBuf> {
    let mut files = lad_files(&root().join("examples"));
    files.extend(lad_files(&root().join("tests/data/check/ok")));
    files
}

/// (line, code) -> count, from the `// error:` / `// warning:` annotations.
pub fn expected(text: &str) -> BTreeMap<(u32, String), usize> {
    let mut map = BTreeMap::new();
    for (i, line) in text.lines().enumerate() {
        for tag in ["// error:", "// warning:"] {
            if let Some(at) = line.find(tag) {
                for code in line[at + tag.len()..].split(',') {
                    let code = code.split_whitespace().next().unwrap_or("").to_string();
                    if !code.is_empty() {
                        *map.entry((i as u32 + 1, code)).or_insert(0) += 1;
                    }
                }
            }
        }
    }
    map
}

pub fn actual(c: &CheckedFile) -> BTreeMap<(u32, String), usize> {
    let mut map = BTreeMap::new();
    for d in c.diagnostics() {
        let line = c
            .index
            .line_col(&c.file.text, d.primary.span.start as usize)
            .line;
        *map.entry((line, d.code.as_str().to_string())).or_insert(0) += 1;
    }
    map
}

/// CPU-EC20 with timed interrupt 0 renumbered to GUTTA event 20 (still S7-200's 10),
/// and timed interrupt 1 (GUTTA 11) given no S7-200 number.
pub fn renumbered() -> ExplicitTarget {
    let mut target: Target = (*stdlib::shared("CPU-EC20").expect("stdlib target")).clone();
    for e in &mut target.memory.events {
        match e.number {
            10 => e.number = 20,
            11 => e.microwin = None,
            _ => {}
        }
    }
    target.memory.events.sort_by_key(|e| e.number);
    ExplicitTarget {
        target: Arc::new(target),
        origin: "a renumbered CPU-EC20".to_string(),
    }
}
