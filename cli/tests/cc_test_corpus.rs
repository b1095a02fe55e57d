//! `gutta-cc test tests/data/run`: the real binary runs the repository's VM corpus
//! (docs/testing.md, "VM corpus") and passes every test of it: exit status 0 and a
//! summary of N passed, 0 failed, with N counted here from the files' `TEST` lines.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

use std::path::{Path, PathBuf};
use std::process::Command;

/// Fewer tests than this means the corpus went missing, not that it passed.
const MIN_TESTS: usize = 20;

fn corpus_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/run")
}

/// The `TEST name` lines of the folder's `.gtest` files (the keyword in any case).
fn count_tests(dir: &Path) -> usize {
    let entries = std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    entries
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "gtest"))
        .map(|p| {
            let text =
                std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            text.lines()
                .filter(|line| {
                    let mut words = line.split_whitespace();
                    words.next().is_some_and(|w| w.eq_ignore_ascii_case("TEST"))
                        && words.next().is_some()
                })
                .count()
        })
        .sum()
}

#[test]
fn gutta_cc_test_passes_every_test_of_the_vm_corpus() {
    let dir = corpus_dir();
    let tests = count_tests(&dir);
    assert!(
        tests >= MIN_TESTS,
        "{}: {tests} tests, expected at least {MIN_TESTS}",
        dir.display()
    );
    let out = Command::new(env!("CARGO_BIN_EXE_gutta-cc"))
        .arg("test")
        .arg(&dir)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("gutta-cc runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let summary = stdout
        .lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .unwrap_or_default();
    assert!(
        out.status.code() == Some(0) && summary.starts_with(&format!("{tests} passed, 0 failed")),
        "exit {:?}, summary `{summary}`, expected `{tests} passed, 0 failed`\n{stdout}{stderr}",
        out.status.code()
    );
}
