//! `gutta-vm` by symbol, through the binary: `--symbols main.lad` names for --set,
//! --force and --read, `:fmt` suffixes, values printed in their types (text and JSON),
//! and a VCD whose signals carry the symbols' names (REAL as `real` vars).

mod common;

use common::{stderr, stdout, text};

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const PROGRAM: &str = "PLC_TYPE CPU-EC20\n\nSYMBOLS\n  Lamp  : Q0.0\n  Pump  : Q0.1\n  \
     Speed : MW20\n  Temp  : MD44\n  Copy  : MD48\nEND_SYMBOLS\n\n\
     ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD     SM0.5\n=      Lamp\n\
     NETWORK 2\nLD     SM0.0\nMOVD   Temp, Copy\nEND_ORGANIZATION_BLOCK\n";

/// The image directory and the source beside it.
fn setup(tag: &str) -> (PathBuf, PathBuf) {
    let dir = common::image_dir(
        &format!("vm-symbols-{tag}"),
        &common::image("main.lad", PROGRAM),
    );
    let source = dir.with_extension("lad");
    std::fs::write(&source, PROGRAM).expect("writes the source");
    (dir, source)
}

fn vm(dir: &Path, source: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gutta-vm"))
        .arg(dir)
        .args(["--symbols", source.to_str().expect("path")])
        .args(args)
        .output()
        .expect("gutta-vm runs")
}

#[test]
fn set_force_and_read_by_symbol_in_their_types() {
    let (dir, source) = setup("read");
    let o = vm(
        &dir,
        &source,
        &[
            "--set",
            "Speed=-5",
            "--set",
            "Temp:real=21.5",
            "--force",
            "Pump=ON",
            "--read",
            "Speed",
            "--read",
            "Speed:hex",
            "--read",
            "Copy:real",
            "--read",
            "Pump",
            "--read",
            "MW20",
        ],
    );
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(
        stdout(&o),
        "Speed (MW20) = -5\nSpeed (MW20) = 16#FFFB\nCopy (MD48) = 21.5\nPump (Q0.1) = 1\nMW20 = -5\n"
    );
    let o = vm(
        &dir,
        &source,
        &[
            "--set",
            "Temp:real=-0.25",
            "--read",
            "Copy:real",
            "--read",
            "Speed:hex",
            "--json",
        ],
    );
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON");
    assert_eq!(v["values"]["Copy"], -0.25);
    assert_eq!(v["values"]["Speed"], "16#0000");
    // A name that is not a symbol says which it might be.
    let o = vm(&dir, &source, &["--read", "Sped"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("did you mean `Speed`?"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn vcd_signals_carry_symbol_names() {
    let (dir, source) = setup("vcd");
    let vcd = dir.with_extension("vcd");
    let o = vm(
        &dir,
        &source,
        &[
            "--scans",
            "120",
            "--set",
            "Speed=-1",
            "--set",
            "Temp:real=1.5",
            "--read",
            "Lamp",
            "--read",
            "Speed",
            "--read",
            "Copy:real",
            "--read",
            "MW20",
            "--vcd",
            vcd.to_str().expect("path"),
        ],
    );
    assert!(o.status.success(), "{}", text(&o));
    let text = std::fs::read_to_string(&vcd).expect("the VCD");
    for line in [
        "$var wire 1 ! Lamp $end",
        "$var wire 16 \" Speed $end",
        "$var real 64 # Copy $end",
        "$var wire 16 $ MW20 $end",
        "r1.5 #",
    ] {
        assert!(text.lines().any(|l| l == line), "{line}:\n{text}");
    }
    // The lamp blinks: it rises at 0.5 s and falls at 1 s.
    assert!(text.contains("#510\n1!"), "{text}");
}
