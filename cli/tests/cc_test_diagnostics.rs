//! The test-file diagnostics corpus (tests/data/check/gtest, docs/testing-programs.md):
//! every `.gtest` there is run by the real `gutta-cc test --message-format json`, and the
//! diagnostics it reports in that file must be exactly those its lines announce
//! (`// error: E0801`, `// warning: W0801`), the way the compiler's check corpus works.
//! A file with an error must exit 2 and run no test.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use common::{cc, text};

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/check/gtest")
}

/// (line, code) -> count, from the `// error:` and `// warning:` comments.
fn expected(text: &str) -> BTreeMap<(u64, String), usize> {
    let mut map = BTreeMap::new();
    for (i, line) in text.lines().enumerate() {
        for tag in ["// error:", "// warning:"] {
            if let Some(at) = line.find(tag) {
                for code in line[at + tag.len()..].split(',') {
                    if let Some(code) = code.split_whitespace().next() {
                        *map.entry((i as u64 + 1, code.to_string())).or_insert(0) += 1;
                    }
                }
            }
        }
    }
    map
}

#[test]
fn every_test_file_gives_exactly_its_announced_diagnostics() {
    let mut files: Vec<PathBuf> = std::fs::read_dir(corpus())
        .expect("the corpus folder")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "gtest"))
        .collect();
    files.sort();
    assert!(files.len() >= 8, "the corpus went missing: {files:?}");
    let mut failures = Vec::new();
    for path in &files {
        let name = path
            .file_name()
            .expect("name")
            .to_string_lossy()
            .into_owned();
        let source = std::fs::read_to_string(path).expect("reads");
        let want = expected(&source);
        let o = cc(&[
            "test",
            path.to_str().expect("path"),
            "--message-format",
            "json",
        ]);
        let mut got = BTreeMap::new();
        let mut ran = 0;
        for line in String::from_utf8_lossy(&o.stdout).lines() {
            let v: serde_json::Value =
                serde_json::from_str(line).unwrap_or_else(|e| panic!("{name}: {line}: {e}"));
            if v["type"] == "test" {
                ran += 1;
            }
            let (Some(code), Some(file)) = (v["code"].as_str(), v["file"].as_str()) else {
                continue;
            };
            if file.ends_with(&name) {
                let line = v["line"].as_u64().expect("line");
                *got.entry((line, code.to_string())).or_insert(0) += 1;
            }
        }
        if got != want {
            failures.push(format!(
                "{name}: expected {want:?}\n  got {got:?}\n{}",
                text(&o)
            ));
        }
        let errors = want.keys().any(|(_, c)| c.starts_with('E'));
        if errors && (o.status.code() != Some(2) || ran != 0) {
            failures.push(format!(
                "{name}: exit {:?} with {ran} tests run",
                o.status.code()
            ));
        }
        if !errors && o.status.code() != Some(0) {
            failures.push(format!("{name}: exit {:?}\n{}", o.status.code(), text(&o)));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
