//! Notes with `--message-format json` (docs/microwin.md, "Interrupt blocks"): every
//! note is one JSON object on stdout beside the diagnostics' lines, nothing goes to
//! stderr as text. The split export (tests/data/microwin/split_program: GBK files, an
//! S7-200 interrupt placed on INT1) gives code-page notes and the interrupt note, for
//! `gutta-cc FILE...` and for `gutta-cc test` of a GBK export; the human format keeps
//! today's text.

#![allow(clippy::disallowed_methods, reason = "tests write their scratch files")]

mod common;

use std::path::{Path, PathBuf};

use common::{cc_in, scratch, stderr, stdout};
use serde_json::Value;

fn program_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/microwin/split_program")
}

/// Every stdout line as JSON (failing on one that is not).
fn json_lines(out: &str) -> Vec<Value> {
    out.lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("not JSON ({e}): {l}")))
        .collect()
}

fn notes<'a>(lines: &'a [Value], kind: &str) -> Vec<&'a Value> {
    lines
        .iter()
        .filter(|v| v["severity"] == "note" && v["kind"] == kind)
        .collect()
}

const SPLIT: &[&str] = &[
    "MAIN.awl",
    "SBR_0.awl",
    "INT_0.awl",
    "--symbols",
    "symbols.csv",
    "--symbols",
    "symbols_gbk.txt",
];

#[test]
fn json_notes_on_stdout_and_nothing_on_stderr() {
    let mut args = SPLIT.to_vec();
    args.extend(["--check", "--message-format", "json"]);
    let o = cc_in(&program_dir(), &args);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stderr(&o), "", "nothing on stderr");
    let lines = json_lines(&stdout(&o));
    let pages = notes(&lines, "code-page");
    let files: Vec<&str> = pages.iter().filter_map(|n| n["file"].as_str()).collect();
    assert_eq!(
        files,
        ["MAIN.awl", "SBR_0.awl", "symbols_gbk.txt"],
        "{lines:?}"
    );
    assert_eq!(pages[0]["message"], "MAIN.awl is not UTF-8; read as GBK");
    for n in &pages {
        assert!(n.get("code").is_none(), "a note has no code: {n}");
    }
    let interrupts = notes(&lines, "interrupts");
    assert_eq!(interrupts.len(), 1, "{lines:?}");
    assert_eq!(
        interrupts[0]["message"],
        "S7-200 interrupts: 中断程序_0 (INT0) -> INT1"
    );
    assert_eq!(interrupts[0]["file"], "MAIN.awl");
    // Every line is a note or a diagnostic (the program's warnings, if any).
    for v in &lines {
        assert!(v["severity"] == "note" || v.get("code").is_some(), "{v}");
    }
}

#[test]
fn the_human_format_keeps_the_note_and_the_summary_line() {
    let mut args = SPLIT.to_vec();
    args.push("--check");
    let o = cc_in(&program_dir(), &args);
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("note: MAIN.awl is not UTF-8; read as GBK\n"),
        "{err}"
    );
    assert!(
        err.contains("3 files: S7-200 interrupts: 中断程序_0 (INT0) -> INT1"),
        "{err}"
    );
    assert_eq!(stdout(&o), "");
}

#[test]
fn gutta_cc_test_prints_the_code_page_note_as_json() {
    let dir = scratch("microwin-notes-test");
    let program = "ORGANIZATION_BLOCK 主程序:OB1\r\nBEGIN\r\nNetwork 1 // 输出\r\nLD     CPU_输入0\r\n=      CPU_输出0\r\nEND_ORGANIZATION_BLOCK\r\n";
    let (gbk, _, bad) = encoding_rs::GBK.encode(program);
    assert!(!bad);
    std::fs::write(dir.join("main.awl"), &gbk).expect("write the program");
    std::fs::write(
        dir.join("main.gtest"),
        "PROGRAM main.awl\nTEST output_follows_input\n  SET CPU_输入0 = 1\n  SCAN 1\n  EXPECT CPU_输出0 = 1\nEND_TEST\n",
    )
    .expect("write the test");
    let o = cc_in(&dir, &["test", "main.gtest", "--message-format", "json"]);
    assert!(o.status.success(), "{}{}", stdout(&o), stderr(&o));
    assert_eq!(stderr(&o), "", "nothing on stderr");
    let lines = json_lines(&stdout(&o));
    let pages = notes(&lines, "code-page");
    assert_eq!(pages.len(), 1, "{lines:?}");
    assert!(pages[0]["file"]
        .as_str()
        .is_some_and(|f| f.ends_with("main.awl")));
    // The human format: the note as before.
    let o = cc_in(&dir, &["test", "main.gtest"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("is not UTF-8; read as GBK"),
        "{}",
        stderr(&o)
    );
}
