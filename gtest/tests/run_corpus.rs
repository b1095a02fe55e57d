//! The VM corpus (docs/testing.md, "VM corpus"): every `tests/data/run/*.gtest` parsed,
//! its program compiled for the header's PLC type and options, planned, and every test
//! run with the VM's pre-decoded operations, again with the generic semantics, and
//! again compiled at load (the compiled tier).
//! Failures of all files are collected into one report (`file:line [engine] message`);
//! a diagnostic of a test file (even a warning) fails too. It uses only gutta_gtest's
//! public API, the one `gutta-cc test` uses, and never adjusts an expectation to what
//! the VM does.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

use std::path::{Path, PathBuf};

use gutta_catalog::stdlib;
use gutta_compiler::diagnostics::Diagnostic;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{ExplicitTarget, ProgramSources};
use gutta_gtest::report::{failure_message, line_of};
use gutta_gtest::{plan, run_test, BuildError, ProgramUnderTest, RunOptions, TestSource};

/// Fewer files than this means the corpus went missing, not that it passed.
const MIN_FILES: usize = 20;

/// The engines every test runs on, (name, fast, native_after): the interpreter's fast
/// operations, the generic semantics, and the compiled tier from load (docs/vm-jit.md).
const ENGINES: [(&str, bool, Option<u64>); 3] = [
    ("fast", true, None),
    ("generic", false, None),
    ("compiled", true, Some(0)),
];

/// Diagnostics as failure lines `name:line: CODE message`.
fn diagnostic_lines<'a>(
    name: &'a str,
    file: &'a SourceFile,
    diagnostics: &'a [Diagnostic],
) -> impl Iterator<Item = String> + 'a {
    diagnostics.iter().map(move |d| {
        let line = line_of(file, d.primary.span.start as usize);
        format!("{name}:{line}: {} {}", d.code.as_str(), d.message)
    })
}

/// Check one test file, shown as `name`; `read_program` reads the file its `PROGRAM`
/// line names. Every problem becomes a line in `failures`; returns the tests run.
fn check_file(
    name: &str,
    file: SourceFile,
    read_program: impl FnOnce(&str) -> Result<SourceFile, String>,
    failures: &mut Vec<String>,
) -> usize {
    let source = TestSource::parse(file);
    if !source.diagnostics.is_empty() {
        failures.extend(diagnostic_lines(name, &source.file, &source.diagnostics));
        return 0;
    }
    let header = &source.parsed.header;
    let Some((program_path, _)) = &header.program else {
        failures.push(format!("{name}: no PROGRAM line"));
        return 0;
    };
    let program = match read_program(program_path) {
        Ok(p) => p,
        Err(e) => {
            failures.push(format!("{name}: PROGRAM {program_path}: {e}"));
            return 0;
        }
    };
    let explicit = match &header.plc_type {
        None => None,
        Some((plc, _)) => match stdlib::shared(plc) {
            Ok(target) => Some(ExplicitTarget {
                target,
                origin: format!("PLC_TYPE {plc} in the test file"),
            }),
            Err(e) => {
                failures.push(format!("{name}: PLC_TYPE {plc}: {e}"));
                return 0;
            }
        },
    };
    let mut sources = ProgramSources::single(program);
    sources.options = source.compile_options();
    let program = match ProgramUnderTest::build(sources, explicit.as_ref()) {
        Ok(p) => p,
        Err(BuildError::Compile(checked)) => {
            let errors: Vec<Diagnostic> = checked
                .diagnostics()
                .iter()
                .filter(|d| d.is_error())
                .cloned()
                .collect();
            let shown = format!("{name}: PROGRAM {program_path}");
            failures.extend(diagnostic_lines(&shown, &checked.file, &errors));
            return 0;
        }
        Err(BuildError::Verify(e)) => {
            failures.push(format!(
                "{name}: PROGRAM {program_path} does not verify: {e}"
            ));
            return 0;
        }
    };
    let plan = match plan(&source.file, &source.parsed, &program) {
        Ok(plan) => plan,
        Err(diagnostics) => {
            failures.extend(diagnostic_lines(name, &source.file, &diagnostics));
            return 0;
        }
    };
    if !plan.warnings.is_empty() {
        failures.extend(diagnostic_lines(name, &source.file, &plan.warnings));
        return 0;
    }
    for (engine, fast, native_after) in ENGINES {
        for test in &plan.tests {
            let options = RunOptions {
                fast,
                native_after,
                ..RunOptions::default()
            };
            let result = run_test(&program, &plan, test, options);
            if let Some(failure) = &result.failure {
                failures.push(format!(
                    "{name}:{} [{engine}] {}: {}",
                    failure.line,
                    result.name,
                    failure_message(failure)
                ));
            }
        }
    }
    plan.tests.len()
}

/// Check a test file of the corpus; its `PROGRAM` is relative to its folder.
fn check_corpus_file(path: &Path, failures: &mut Vec<String>) -> usize {
    let name = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let file = match std::fs::read(path).map(|b| SourceFile::from_bytes(name.as_str(), b)) {
        Ok(Ok(file)) => file,
        Ok(Err(e)) => {
            failures.push(format!("{name}: not UTF-8: {e:?}"));
            return 0;
        }
        Err(e) => {
            failures.push(format!("{name}: {e}"));
            return 0;
        }
    };
    let dir = path.parent().unwrap_or(Path::new("."));
    let read_program = |program: &str| {
        let full = dir.join(program);
        let bytes = std::fs::read(&full).map_err(|e| format!("{}: {e}", full.display()))?;
        SourceFile::from_program_file_bytes(full.display().to_string(), bytes, false)
            .map(|(file, _)| file)
            .map_err(|e| format!("{}: not text: {e:?}", full.display()))
    };
    check_file(&name, file, read_program, failures)
}

fn corpus_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/run")
}

#[test]
fn every_test_of_the_vm_corpus_passes_on_every_engine() {
    let dir = corpus_dir();
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "gtest"))
        .collect();
    files.sort();
    let mut failures = Vec::new();
    if files.len() < MIN_FILES {
        failures.push(format!(
            "{}: {} test files, expected at least {MIN_FILES}",
            dir.display(),
            files.len()
        ));
    }
    let tests: usize = files
        .iter()
        .map(|path| check_corpus_file(path, &mut failures))
        .sum();
    assert!(
        failures.is_empty(),
        "failures ({}) in {} files ({tests} tests) of tests/data/run:\n{}",
        failures.len(),
        files.len(),
        failures.join("\n")
    );
}

const PROGRAM: &str = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD I0.0\n= Q0.0\n\
                       END_ORGANIZATION_BLOCK\n";

/// The failures of `gtest` (as `t.gtest`) against [`PROGRAM`] (as `t.lad`).
fn failures_of(gtest: &str) -> Vec<String> {
    let mut failures = Vec::new();
    let read_program = |path: &str| {
        assert_eq!(path, "t.lad");
        Ok(SourceFile::new("t.lad", PROGRAM))
    };
    check_file(
        "t.gtest",
        SourceFile::new("t.gtest", gtest),
        read_program,
        &mut failures,
    );
    failures
}

#[test]
fn a_wrong_expectation_or_a_missing_fault_fails_naming_line_engine_and_scan() {
    let text = "PROGRAM t.lad\n\nTEST wrong_value\n  SET I0.0 = 1\n  SCAN 2\n  \
                EXPECT Q0.0 = 1\n  EXPECT Q0.0 = 0\nEND_TEST\n\nTEST missing_fault\n  \
                SCAN 3\n  EXPECT FAULT 3\n  EXPECT Q0.0 = 1\nEND_TEST\n";
    let wanted: Vec<String> = ENGINES
        .iter()
        .flat_map(|(engine, ..)| {
            [
                format!(
                    "t.gtest:7 [{engine}] wrong_value: EXPECT failed after scan 2 (20 ms): \
                     Q0.0 = 0 expected, is 1"
                ),
                format!(
                    "t.gtest:12 [{engine}] missing_fault: EXPECT FAULT 3: the scans ran \
                     without a fault, after scan 3 (30 ms)"
                ),
            ]
        })
        .collect();
    assert_eq!(failures_of(text), wanted);
}

#[test]
fn a_diagnostic_of_a_test_file_is_a_failure() {
    // A warning (the test checks nothing) and an error (no such variable) alike.
    assert_eq!(
        failures_of("PROGRAM t.lad\nTEST idle\n  SCAN 1\nEND_TEST\n"),
        ["t.gtest:2: W0801 test `idle` has no EXPECT or UNTIL: it cannot fail"]
    );
    let failures = failures_of("PROGRAM t.lad\nTEST t\n  SCAN\n  EXPECT Lamp = 1\nEND_TEST\n");
    assert_eq!(failures.len(), 1, "{failures:?}");
    assert!(failures[0].starts_with("t.gtest:4: E08"), "{failures:?}");
}
