//! `gutta-cc` with several source files and symbol tables: one program for `--check`
//! and `-o`, diagnostics naming their own file (human and JSON), a `.lad` refused as
//! `--symbols`, and `gutta-vm --break FILE:LINE` on the second file of the image.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// MAIN, using a symbol of the table and calling the subroutine of `B`.
const A: &str = "PLC_TYPE CPU-EC20
ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1
LD     Start
CALL   BUMP
END_ORGANIZATION_BLOCK
";

/// The subroutine, using a symbol of `A`'s SYMBOLS block; b.lad:8 is `MOVW`.
const B: &str = "SYMBOLS
  Count : MW10 : INT   // bumped by BUMP
END_SYMBOLS
SUBROUTINE_BLOCK BUMP:SBR0
BEGIN
NETWORK 1
LD     SM0.0
MOVW   16#BEEF, Count
INCW   Count
END_SUBROUTINE_BLOCK
";

const TABLE: &str = "\u{feff}Symbol,Address,Comment\r\nStart,I0.0,\"the \"\"start\"\" button\"\r\n";

/// A fresh directory holding a.lad, b.lad and s.csv.
fn program_dir(tag: &str) -> PathBuf {
    let root = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("gutta-cc-multi-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).expect("temp dir");
    std::fs::write(root.join("a.lad"), A).expect("a.lad");
    std::fs::write(root.join("b.lad"), B).expect("b.lad");
    std::fs::write(root.join("s.csv"), TABLE).expect("s.csv");
    root
}

fn run(exe: &str, dir: &Path, args: &[&str]) -> Output {
    Command::new(exe)
        .current_dir(dir)
        .args(args)
        .env_remove("NO_COLOR")
        .output()
        .expect("runs")
}

fn gutta_cc(dir: &Path, args: &[&str]) -> Output {
    run(env!("CARGO_BIN_EXE_gutta-cc"), dir, args)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn files_and_a_table_compile_to_one_image_and_break_in_the_second_file() {
    let dir = program_dir("image");
    let o = gutta_cc(
        &dir,
        &["a.lad", "b.lad", "--symbols", "s.csv", "-o", "image"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).starts_with("2 files: wrote image for CPU-EC20:"),
        "{}",
        stderr(&o)
    );
    let map = std::fs::read_to_string(dir.join("image.map.json")).expect("the map");
    assert!(map.contains("\"files\":[\"a.lad\",\"b.lad\"]"), "{map}");
    assert!(map.contains("\"origin\":\"s.csv:2\""), "{map}");
    let o = run(
        env!("CARGO_BIN_EXE_gutta-vm"),
        &dir,
        &[
            "image", "--break", "b.lad:8", "--set", "I0.0=1", "--read", "MW10",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(String::from_utf8_lossy(&o.stdout), "MW10 = 0\n");
    // b.lad's line 8 and its text (the file name gutta-vm prints comes from the map's
    // `file_of`, see the report).
    assert!(
        stderr(&o).contains(":8:1 (SBR0 network 1 step 1): MOVW   16#BEEF, Count in scan 1"),
        "{}",
        stderr(&o)
    );
    let o = run(
        env!("CARGO_BIN_EXE_gutta-vm"),
        &dir,
        &["image", "--break", "8"],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("several files (a.lad, b.lad); write FILE:LINE"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn check_takes_all_files_as_one_program() {
    let dir = program_dir("check");
    let o = gutta_cc(&dir, &["--check", "a.lad", "b.lad", "--symbols", "s.csv"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).starts_with("2 files: ok on CPU-EC20 (2 blocks, 5 instructions"),
        "{}",
        stderr(&o)
    );
    // Without the table, `Start` is undefined, reported in a.lad.
    let o = gutta_cc(
        &dir,
        &["--check", "a.lad", "b.lad", "--message-format", "json"],
    );
    assert_eq!(o.status.code(), Some(1));
    let out = String::from_utf8_lossy(&o.stdout);
    assert_eq!(out.lines().count(), 1, "{out}");
    let v: serde_json::Value = serde_json::from_str(out.trim()).expect("JSON");
    assert_eq!(
        (v["code"].as_str(), v["file"].as_str(), v["line"].as_u64()),
        (Some("E0202"), Some("a.lad"), Some(5))
    );
}

#[test]
fn a_duplicate_in_the_table_shows_both_files() {
    let dir = program_dir("duplicate");
    std::fs::write(dir.join("dup.tsv"), "count\tMW12\tagain\n").expect("dup.tsv");
    let o = gutta_cc(
        &dir,
        &[
            "a.lad",
            "b.lad",
            "--symbols",
            "s.csv",
            "--symbols",
            "dup.tsv",
            "--color",
            "never",
        ],
    );
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(
        err.contains("[E0203] Error: symbol `count` is declared twice\n   ,-[ dup.tsv:1:1 ]"),
        "{err}"
    );
    assert!(err.contains("|-[ b.lad:2:3 ]"), "{err}");
    assert!(err.ends_with("2 files: 1 error, 0 warnings\n"), "{err}");
}

#[test]
fn a_lad_file_as_symbols_is_a_usage_error() {
    let dir = program_dir("usage");
    let o = gutta_cc(&dir, &["a.lad", "--symbols", "b.lad", "-o", "image"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--symbols b.lad: a .lad file is a source of the program; list it with the sources instead"), "{}", stderr(&o));
    assert!(!dir.join("image").exists());
}
