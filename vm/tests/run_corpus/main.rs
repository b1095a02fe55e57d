//! The data-driven VM corpus: every program in tests/data/run is compiled for its PLC
//! type, verified, and its header's timeline (inputs, forces and expectations before
//! the first scan, at given scans or virtual times, after the last scan; header
//! language in docs/testing.md, "VM corpus") run with the pre-decoded operations and
//! again with the generic semantics. Failures of all files are collected and reported
//! together. It uses only the VM's public API and never adjusts an expectation to
//! what the VM does.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

mod header;
mod language_tests;
mod run;
mod values;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile_with, CompileOptions, ExplicitTarget};
use gutta_vm::VmConfig;

use header::parse_header;
use run::{prepare, run_mode};

/// Fewer files than this means the corpus went missing, not that it passed.
const MIN_PROGRAMS: usize = 20;

/// Check one program file; every problem becomes a line in `failures`.
fn run_program(path: &Path, failures: &mut Vec<String>) {
    let name = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into(),
    );
    let bytes = match std::fs::read(path) {
        Ok(b) => b,
        Err(e) => return failures.push(format!("{name}: {e}")),
    };
    match SourceFile::from_bytes(path.display().to_string(), bytes) {
        Ok(file) => run_source(&name, file, failures),
        Err(e) => failures.push(format!("{name}: not UTF-8: {e:?}")),
    }
}

/// Check one program's text, reported as `name`.
fn run_source(name: &str, file: SourceFile, failures: &mut Vec<String>) {
    let header = match parse_header(&file.text) {
        Ok(h) => h,
        Err(errors) => {
            failures.extend(errors.into_iter().map(|e| format!("{name}: {e}")));
            return;
        }
    };
    let explicit = match &header.plc {
        None => None,
        Some(plc) => match stdlib::shared(plc) {
            Ok(target) => Some(ExplicitTarget {
                target,
                origin: format!("--plc {plc}"),
            }),
            Err(e) => return failures.push(format!("{name}: `// plc: {plc}`: {e}")),
        },
    };
    let options = CompileOptions {
        scale_timer_presets: header.options.iter().any(|o| o == "scale-timer-presets"),
    };
    let compiled = compile_with(file, explicit.as_ref(), options);
    let checked = &compiled.checked;
    let Some(image) = &compiled.image else {
        for d in checked.diagnostics().iter().filter(|d| d.is_error()) {
            let line = checked
                .index
                .line_col(&checked.file.text, d.primary.span.start as usize)
                .line;
            failures.push(format!(
                "{name}:{line}: does not compile: {} {}",
                d.code.as_str(),
                d.message
            ));
        }
        return;
    };
    let target = Arc::clone(&checked.target);
    let verified = match gutta_format::verify(image, &target) {
        Ok(v) => v,
        Err(e) => return failures.push(format!("{name}: does not verify: {e:?}")),
    };
    let Some(prepared) = prepare(name, verified, target, &header, failures) else {
        return;
    };
    let base = VmConfig {
        scan_ms: header.scan_ms(),
        watchdog: header.watchdog.unwrap_or(VmConfig::default().watchdog),
        ..VmConfig::default()
    };
    for (mode, fast) in [("fast", true), ("generic", false)] {
        run_mode(&prepared, mode, VmConfig { fast, ..base }, failures);
    }
}

fn corpus_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/run")
}

#[test]
fn every_program_gives_its_expected_values() {
    let dir = corpus_dir();
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "lad"))
        .collect();
    files.sort();
    let mut failures = Vec::new();
    if files.len() < MIN_PROGRAMS {
        failures.push(format!(
            "{}: {} programs, expected at least {MIN_PROGRAMS}",
            dir.display(),
            files.len()
        ));
    }
    for path in &files {
        run_program(path, &mut failures);
    }
    assert!(
        failures.is_empty(),
        "{} failure(s) in {} programs of tests/data/run:\n{}",
        failures.len(),
        files.len(),
        failures.join("\n")
    );
}

#[test]
fn a_wrong_expectation_or_fault_fails_naming_line_mode_and_scan() {
    let text = "// set: I0.0 = 1\n// after 2 scans: expect Q0.0 = 0\n// then expect: Q0.1 = 0\n\
                // after 1 scan: fault 3\n// then expect: Q0.0 = 0\n\n\
                ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD I0.0\n= Q0.0\n\
                END_ORGANIZATION_BLOCK\n";
    let mut failures = Vec::new();
    run_source("t.lad", SourceFile::new("t.lad", text), &mut failures);
    // Q0.1 = 0 holds; the missing fault ends the run, so line 5 is never checked.
    let wanted: Vec<String> = ["fast", "generic"]
        .iter()
        .flat_map(|mode| {
            [
                format!("t.lad:2 [{mode}] after scan 2: Q0.0 expected 0, got 1"),
                format!(
                    "t.lad:4 [{mode}] after scan 3: expected fault code 3, the scan ran without one"
                ),
            ]
        })
        .collect();
    assert_eq!(failures, wanted);
}
