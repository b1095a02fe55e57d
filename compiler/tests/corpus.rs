//! The data-driven check corpus: every file in tests/data/check/ok must check without
//! errors, every file in tests/data/check/err must give exactly the diagnostics its
//! lines announce (`// error: E0302`, `// warning: W0201, W0203`), and every example
//! must check clean. A first line `// plc: NAME` selects the PLC type.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

mod common;

use common::{actual, expected, lad_files, root};
use std::path::Path;

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, CheckedFile, ExplicitTarget};

fn check(path: &Path) -> CheckedFile {
    let bytes = std::fs::read(path).expect("read test file");
    let file =
        SourceFile::from_bytes(path.display().to_string(), bytes).expect("test files are UTF-8");
    let first = file.text.lines().next().unwrap_or("").trim().to_string();
    let explicit = first.strip_prefix("// plc:").map(|name| {
        let name = name.trim();
        ExplicitTarget {
            target: stdlib::shared(name).unwrap_or_else(|e| panic!("{}: {e}", path.display())),
            origin: format!("--plc {name}"),
        }
    });
    // The whole pipeline: clean programs must also encode within their target's limits.
    let compiled = compile(file, explicit.as_ref());
    assert_eq!(
        compiled.image.is_some(),
        !compiled.checked.has_errors(),
        "{}",
        path.display()
    );
    compiled.checked
}

fn describe(c: &CheckedFile) -> String {
    c.diagnostics()
        .iter()
        .map(|d| {
            let lc = c
                .index
                .line_col(&c.file.text, d.primary.span.start as usize);
            format!("  line {}: {} {}", lc.line, d.code.as_str(), d.message)
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn ok_programs_check_clean() {
    let files = lad_files(&root().join("tests/data/check/ok"));
    assert!(!files.is_empty(), "the ok corpus is empty");
    let mut failures = Vec::new();
    for path in files {
        let c = check(&path);
        if actual(&c) != expected(&c.file.text) {
            failures.push(format!("{}:\n{}", path.display(), describe(&c)));
        }
    }
    assert!(
        failures.is_empty(),
        "unexpected diagnostics:\n{}",
        failures.join("\n")
    );
}

#[test]
fn err_programs_give_exactly_their_annotated_diagnostics() {
    let files = lad_files(&root().join("tests/data/check/err"));
    assert!(!files.is_empty(), "the err corpus is empty");
    let mut failures = Vec::new();
    for path in files {
        let c = check(&path);
        let (want, got) = (expected(&c.file.text), actual(&c));
        assert!(
            !want.is_empty(),
            "{} announces no diagnostic",
            path.display()
        );
        if want != got {
            let missing: Vec<String> = want
                .iter()
                .filter(|(k, n)| got.get(*k) != Some(n))
                .map(|((l, c), n)| format!("line {l} {c} x{n}"))
                .collect();
            let extra: Vec<String> = got
                .iter()
                .filter(|(k, n)| want.get(*k) != Some(n))
                .map(|((l, c), n)| format!("line {l} {c} x{n}"))
                .collect();
            failures.push(format!("{}:\n  expected but not given: {missing:?}\n  given but not expected: {extra:?}\n{}", path.display(), describe(&c)));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn every_diagnostic_code_is_exercised_by_the_corpus() {
    let mut seen = std::collections::BTreeSet::new();
    for path in lad_files(&root().join("tests/data/check/err"))
        .into_iter()
        .chain(lad_files(&root().join("tests/data/check/ok")))
    {
        let text = std::fs::read_to_string(&path).expect("read");
        seen.extend(expected(&text).into_keys().map(|(_, c)| c));
    }
    // Programs in several files (tests/programs.rs): `FILE:LINE CODE` lines.
    let programs = root().join("tests/data/check/programs");
    for entry in std::fs::read_dir(&programs).expect("the programs corpus") {
        let expected = entry.expect("dir entry").path().join("expected");
        if let Ok(text) = std::fs::read_to_string(expected) {
            seen.extend(
                text.lines()
                    .filter_map(|l| l.split_whitespace().nth(1))
                    .map(String::from),
            );
        }
    }
    // Test files (.gtest, docs/testing-programs.md) have their own corpus, run through
    // `gutta-cc test` by cli/tests/cc_test_diagnostics.rs, with the same comments.
    let gtest = root().join("tests/data/check/gtest");
    for entry in std::fs::read_dir(&gtest).expect("the test-file corpus") {
        let path = entry.expect("dir entry").path();
        if path.extension().is_some_and(|x| x == "gtest") {
            let text = std::fs::read_to_string(&path).expect("read");
            seen.extend(expected(&text).into_keys().map(|(_, c)| c));
        }
    }
    // Image limits need programs too large for a corpus file: `gutta-cc -o`'s tests
    // (cli/tests/cc_image_write.rs) assert them.
    let image_tests = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../cli/tests/cc_image_write.rs"),
    )
    .expect("read cli/tests/cc_image_write.rs");
    for code in gutta_compiler::diagnostics::Code::ALL {
        if image_tests.contains(&format!("\"{}\"", code.as_str())) {
            seen.insert(code.as_str().to_string());
        }
    }
    let missing: Vec<&str> = gutta_compiler::diagnostics::Code::ALL
        .iter()
        .map(|c| c.as_str())
        .filter(|c| !seen.contains(*c))
        .collect();
    assert!(
        missing.is_empty(),
        "codes without a corpus case: {missing:?}"
    );
}

#[test]
fn examples_check_clean() {
    let files = lad_files(&root().join("examples"));
    assert!(files.len() >= 6, "examples are missing");
    for path in files {
        let c = check(&path);
        assert!(
            c.diagnostics().is_empty(),
            "{}:\n{}",
            path.display(),
            describe(&c)
        );
        assert!(c.output.program.is_some());
    }
}
