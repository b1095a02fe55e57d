//! `gutta-cc dis --format awl` through the binary: it writes Micro/WIN's layout
//! (headers, CRLF, no step comments) that the binary compiles back to the same image
//! directory. That every example and corpus program round-trips through the layout is
//! compiler/tests/roundtrip.rs's test.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

mod common;

use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The binary's output for blink.lad (MAIN, an interrupt routine, a subroutine with
/// parameters, data and system blocks): Micro/WIN's layout, compiled back by the binary
/// to the same image directory.
#[test]
fn the_binary_writes_micro_win_layout_that_compiles_back() {
    let base = std::env::temp_dir().join(format!("gutta-cc-dis-awl-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&base);
    std::fs::create_dir_all(&base).expect("temp dir");
    let blink = root().join("examples/blink.lad");
    let (first, second) = (base.join("first"), base.join("second"));
    let out = common::cc(&[
        blink.to_str().expect("utf-8 path"),
        "-o",
        first.to_str().expect("utf-8 path"),
    ]);
    assert!(out.status.success(), "{}", common::text(&out));

    let out = common::cc(&["dis", "--format", "awl", first.to_str().expect("utf-8")]);
    assert!(out.status.success(), "{}", common::text(&out));
    let text = common::stdout(&out);
    assert!(
        !text.replace("\r\n", "").contains('\n'),
        "not CRLF:\n{text}"
    );
    let lines: Vec<&str> = text.lines().map(|l| l.trim_end_matches('\r')).collect();
    for expected in [
        "ORGANIZATION_BLOCK MAIN:OB1",
        "END_ORGANIZATION_BLOCK",
        "SUBROUTINE_BLOCK SBR_0:SBR0",
        "END_SUBROUTINE_BLOCK",
        "INTERRUPT_BLOCK INT_0:INT0", // GUTTA INT1: S7-200 numbers user interrupts from 0
        "END_INTERRUPT_BLOCK",
        "TITLE=",
        "BEGIN",
        "Network 1",
        "VAR_INPUT",
        "END_VAR",
        "SYSTEM_BLOCK",
    ] {
        assert!(
            lines.contains(&expected),
            "no line {expected:?} in:\n{text}"
        );
    }
    assert!(!text.contains("// step"), "step comments in:\n{text}");
    assert!(
        !text.contains("NETWORK"),
        "toolchain NETWORK lines in:\n{text}"
    );
    assert!(
        lines.iter().any(|l| l.starts_with("in0:")),
        "no Micro/WIN VAR line in:\n{text}"
    );
    let note = lines
        .iter()
        .position(|l| l.starts_with("// Micro/WIN exports data blocks"))
        .expect("the data block note");
    let last_program_end = lines
        .iter()
        .rposition(|l| l.starts_with("END_") && l.ends_with("_BLOCK") && !l.contains("DATA"))
        .expect("blocks");
    let first_data = lines
        .iter()
        .position(|l| l.starts_with("DATA_BLOCK"))
        .expect("a data block");
    assert!(
        note < first_data && lines[..note].iter().all(|l| !l.starts_with("DATA_BLOCK")),
        "the note is not before the data blocks:\n{text}"
    );
    assert!(
        lines[..note]
            .iter()
            .filter(|l| l.starts_with("END_") && l.ends_with("_BLOCK"))
            .count()
            >= 3
            && last_program_end > note,
        "program blocks are not all before the note:\n{text}"
    );

    let awl = base.join("back.awl");
    std::fs::write(&awl, &out.stdout).expect("writes back.awl");
    let out = common::cc(&[
        awl.to_str().expect("utf-8"),
        "-o",
        second.to_str().expect("utf-8"),
    ]);
    assert!(out.status.success(), "{}", common::text(&out));
    let read = |dir: &Path| gutta_io::read_image_dir(dir).expect("an image directory");
    let (a, b) = (read(&first), read(&second));
    assert_eq!(a.plc_type, b.plc_type);
    assert!(a.pages == b.pages, "the pages differ after the round trip");
    let _ = std::fs::remove_dir_all(&base);
}

#[test]
fn stl_stays_the_default_format() {
    let blink = root().join("examples/blink.lad");
    let dir = std::env::temp_dir().join(format!("gutta-cc-dis-stl-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = common::cc(&[
        blink.to_str().expect("utf-8"),
        "-o",
        dir.to_str().expect("utf-8"),
    ]);
    assert!(out.status.success(), "{}", common::text(&out));
    let default = common::cc(&["dis", dir.to_str().expect("utf-8")]);
    let stl = common::cc(&["dis", "--format", "stl", dir.to_str().expect("utf-8")]);
    assert_eq!(default.stdout, stl.stdout);
    let text = common::stdout(&default);
    assert!(text.contains("NETWORK 1") && !text.contains('\r'), "{text}");
    let bad = common::cc(&["dis", "--format", "lad", dir.to_str().expect("utf-8")]);
    assert!(!bad.status.success());
    assert!(
        common::stderr(&bad).contains("awl"),
        "{}",
        common::stderr(&bad)
    );
    let _ = std::fs::remove_dir_all(&dir);
}
