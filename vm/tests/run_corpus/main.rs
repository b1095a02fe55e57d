//! The data-driven VM corpus: every program in tests/data/run is compiled for its PLC
//! type, verified, and its header's timeline (inputs, forces and expectations before
//! the first scan, at given scans or virtual times, after the last scan; header
//! language in docs/testing.md, "VM corpus") run with the pre-decoded operations and
//! again with the generic semantics. Failures of all files are collected and reported
//! together. It uses only the VM's public API and never adjusts an expectation to
//! what the VM does.

mod header;
mod run;
mod values;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_vm::VmConfig;

use header::parse_header;
use run::{prepare, run_mode};
use values::{resolve, Assignment, Bits, Value};

/// Fewer files than this means the corpus went missing, not that it passed.
const MIN_PROGRAMS: usize = 20;

/// Check one program; every problem becomes a line in `failures`.
fn run_program(path: &Path, failures: &mut Vec<String>) {
    let name = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into(),
    );
    let bytes = match std::fs::read(path) {
        Ok(b) => b,
        Err(e) => return failures.push(format!("{name}: {e}")),
    };
    let file = match SourceFile::from_bytes(path.display().to_string(), bytes) {
        Ok(f) => f,
        Err(e) => return failures.push(format!("{name}: not UTF-8: {e:?}")),
    };
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
    let compiled = compile(file, explicit.as_ref());
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
    let Some(prepared) = prepare(&name, verified, target, &header, failures) else {
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
fn values_resolve_against_the_target() {
    let target = stdlib::shared(stdlib::DEFAULT).expect("target");
    let minus_one = Assignment {
        line: 5,
        var: "MW0".into(),
        value: Value::Number(-1),
    };
    let r = resolve(&target, &minus_one).expect("resolves");
    assert!(
        matches!(r.bits, Bits::Word(0xFFFF)),
        "negative values are masked to the width"
    );
    let text = Assignment {
        line: 6,
        var: "MB40".into(),
        value: Value::Text(b"1A".to_vec()),
    };
    let Bits::Bytes(bytes) = resolve(&target, &text).expect("resolves").bits else {
        panic!("a text resolves to bytes");
    };
    assert_eq!(
        bytes
            .iter()
            .map(|(a, b)| (a.offset, *b))
            .collect::<Vec<_>>(),
        [(40, b'1'), (41, b'A')]
    );
    let too_big = Assignment {
        line: 4,
        var: "MB0".into(),
        value: Value::Number(256),
    };
    let err = resolve(&target, &too_big).expect_err("256 is no byte");
    assert!(err.starts_with("line 4"), "{err}");
    let text_on_word = Assignment {
        line: 7,
        var: "MW40".into(),
        value: Value::Text(b"1A".to_vec()),
    };
    let err = resolve(&target, &text_on_word).expect_err("a text needs bytes");
    assert!(err.starts_with("line 7"), "{err}");
}
