//! The `gutta-cc` binary as users run it: exit codes, human and JSON diagnostics,
//! target selection, the Modbus query and `explain`.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn gutta_cc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gutta-cc"))
        .args(args)
        .env_remove("NO_COLOR")
        .current_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join(".."))
        .output()
        .expect("run gutta-cc")
}

fn temp_file(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gutta-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write");
    path
}

const VB_PROGRAM: &str = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLD SM0.0\nMOVB 1, VB100\nEND_ORGANIZATION_BLOCK\n";

#[test]
fn clean_program_exits_zero() {
    let out = gutta_cc(&["--check", "examples/blink.lad"]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stderr).contains("ok on CPU-EC20"));
}

#[test]
fn errors_exit_one_with_plain_rendering_when_not_a_terminal() {
    let path = temp_file("vb.lad", VB_PROGRAM);
    let out = gutta_cc(&["--check", path.to_str().expect("utf-8 path")]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("[E0306]"), "{err}");
    assert!(
        !err.contains('\u{1b}'),
        "colour escape codes on a pipe: {err}"
    );
}

#[test]
fn plc_option_selects_the_target() {
    let path = temp_file("vb2.lad", VB_PROGRAM);
    let p = path.to_str().expect("utf-8 path");
    assert_eq!(
        gutta_cc(&["--check", "--plc", "EC30-EKSTM32-XC", p])
            .status
            .code(),
        Some(0)
    );
    assert_eq!(
        gutta_cc(&["--check", "--plc", "EC30-EKSTM32", p])
            .status
            .code(),
        Some(1)
    );
    let hc = temp_file("hc.lad", "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLD SM0.0\nMOVD HC0, MD0\nEND_ORGANIZATION_BLOCK\n");
    let h = hc.to_str().expect("utf-8 path");
    assert_eq!(
        gutta_cc(&["--check", "--plc", "EC30-EKSTM32", h])
            .status
            .code(),
        Some(0)
    );
    assert_eq!(
        gutta_cc(&["--check", "--plc", "CPU-EC20-M3", h])
            .status
            .code(),
        Some(1)
    );
    let mb = temp_file("mb.lad", "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLD SM0.0\nMOVB 1, MB200\nEND_ORGANIZATION_BLOCK\n");
    let m = mb.to_str().expect("utf-8 path");
    assert_eq!(gutta_cc(&["--check", m]).status.code(), Some(1));
    assert_eq!(
        gutta_cc(&["--check", "--plc", "CPU-EC20-AVR", m])
            .status
            .code(),
        Some(0)
    );
}

#[test]
fn json_diagnostics_have_the_documented_fields() {
    let path = temp_file("json.lad", "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLD SM0.0\nMOVW   MB0, MW2\nMOWV 1, MW4\nMOVW   M0.0, MW6\nEND_ORGANIZATION_BLOCK\n");
    let out = gutta_cc(&[
        "--check",
        "--message-format",
        "json",
        path.to_str().expect("utf-8 path"),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let text = String::from_utf8_lossy(&out.stdout);
    let lines: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).expect("one JSON object per line"))
        .collect();
    assert_eq!(lines.len(), 3);
    let d = &lines[0];
    assert_eq!(d["code"], "E0302");
    assert_eq!(d["severity"], "error");
    assert_eq!(
        (d["line"].as_u64(), d["column"].as_u64()),
        (Some(5), Some(8))
    );
    assert_eq!(
        (d["end_line"].as_u64(), d["end_column"].as_u64()),
        (Some(5), Some(11))
    );
    assert!(d["help"].is_null() || d["help"].is_string());
    assert!(d["file"].as_str().is_some_and(|f| f.ends_with("json.lad")));
    assert_eq!(lines[1]["code"], "E0201");
    assert_eq!(lines[1]["help"], "did you mean `MOVW`?");
    // The did-you-mean as an edit a tool can apply: MOWV (line 6, columns 1-5) -> MOVW.
    // E0302 on a direct address: the address of the wanted width at the same byte.
    assert_eq!(
        d["fixes"][0]["title"],
        "Replace `MB0` with `MW0` (the word at the same byte)"
    );
    assert_eq!(d["fixes"][0]["edits"][0]["replacement"], "MW0");
    // E0302 on a bit: which word was meant is not known.
    assert_eq!(lines[2]["code"], "E0302");
    assert!(
        lines[2].get("fixes").is_none(),
        "no fix, no field: {}",
        lines[2]
    );
    let fix = &lines[1]["fixes"][0];
    assert_eq!(fix["title"], "Replace with `MOVW`", "{fix}");
    let edit = &fix["edits"][0];
    assert_eq!(edit["replacement"], "MOVW");
    assert_eq!(
        (
            edit["line"].as_u64(),
            edit["column"].as_u64(),
            edit["end_column"].as_u64()
        ),
        (Some(6), Some(1), Some(5))
    );
    let source = std::fs::read_to_string(&path).expect("reads it back");
    let (a, b) = (
        edit["start_offset"].as_u64().unwrap_or(0) as usize,
        edit["end_offset"].as_u64().unwrap_or(0) as usize,
    );
    assert_eq!(&source[a..b], "MOWV");
}

#[test]
fn modbus_query_matches_the_documents() {
    for (var, want) in [
        ("MB31", "400024 bits 8..15"),
        ("MW20", "400019"),
        ("Q3.0", "000025"),
        ("I0.4", "100005"),
    ] {
        let out = gutta_cc(&["modbus", var]);
        assert_eq!(out.status.code(), Some(0));
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(text.contains(want), "{var}: {text}");
    }
    let out = gutta_cc(&["modbus", "VB100", "--plc", "EC30-EKSTM32-XC"]);
    assert!(
        String::from_utf8_lossy(&out.stdout).contains("401715"),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    assert_eq!(gutta_cc(&["modbus", "KB0"]).status.code(), Some(2));
    assert_eq!(gutta_cc(&["modbus", "MB999"]).status.code(), Some(2));
}

#[test]
fn usage_and_io_errors_exit_two() {
    assert_eq!(
        gutta_cc(&["--check", "does/not/exist.lad"]).status.code(),
        Some(2)
    );
    assert_eq!(
        gutta_cc(&["--check", "--plc", "NO-SUCH-PLC", "examples/blink.lad"])
            .status
            .code(),
        Some(2)
    );
    assert_eq!(
        gutta_cc(&["--check", "--target", "/nonexistent", "examples/blink.lad"])
            .status
            .code(),
        Some(2)
    );
    let bad = temp_file("latin1.lad", "");
    std::fs::write(&bad, b"LD \xff\n").expect("write");
    assert_eq!(
        gutta_cc(&["--check", bad.to_str().expect("utf-8 path")])
            .status
            .code(),
        Some(2)
    );
}

#[test]
fn target_folder_is_loaded_from_disk() {
    let stdlib = Path::new(env!("CARGO_MANIFEST_DIR")).join("../stdlib");
    let root = stdlib.join("targets/CPU-EC20");
    // A folder of all three files, and a stdlib target folder (no ManagerFun.xml: the
    // stdlib instruction set) both load.
    let full = std::env::temp_dir().join(format!("gutta-fulltarget-{}", std::process::id()));
    std::fs::create_dir_all(&full).expect("dir");
    for (from, name) in [
        (&root, "PlcType.xml"),
        (&root, "ManagerVar.xml"),
        (&stdlib, "ManagerFun.xml"),
    ] {
        std::fs::copy(from.join(name), full.join(name)).expect("copy");
    }
    for folder in [&full, &root] {
        let out = gutta_cc(&[
            "--check",
            "--target",
            folder.to_str().expect("utf-8 path"),
            "examples/blink.lad",
        ]);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{}: {}",
            folder.display(),
            String::from_utf8_lossy(&out.stderr)
        );
    }
    // A broken target folder is a coded error, exit 2.
    let dir = std::env::temp_dir().join(format!("gutta-badtarget-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    std::fs::copy(root.join("ManagerVar.xml"), dir.join("ManagerVar.xml")).expect("copy");
    std::fs::write(dir.join("PlcType.xml"), "<PlcType Name=\"X\"/>").expect("write");
    let out = gutta_cc(&[
        "--check",
        "--target",
        dir.to_str().expect("utf-8 path"),
        "examples/blink.lad",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("T0002"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn explain_prints_the_registry_entry() {
    let out = gutta_cc(&["explain", "e0302"]);
    assert_eq!(out.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&out.stdout).contains("MOVW MB0, MW2"));
}

#[test]
fn listing_shows_each_source_line_with_its_bytes() {
    let out = gutta_cc(&["examples/in1001_pointers.lad", "--emit", "listing"]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    // MOVD &MB24, MD4: opcode, 2 operands, &MB24 = 0x0018_0341, MD4 = 0x0004_0340.
    let line = text
        .lines()
        .find(|l| l.contains("MOVD   &MB24, MD4"))
        .expect("MOVD line");
    assert!(
        line.contains("I00") && line.contains("41 03 18 00 40 03 04 00"),
        "{line}"
    );
    assert!(
        text.lines()
            .any(|l| l.starts_with("; K") && l.contains("01 0E")),
        "{text}"
    );
}
