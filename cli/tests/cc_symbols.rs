//! Symbols and typed values in the client commands, through the real binaries: a
//! `gutta-sim` running a program with a SYMBOLS block, `gutta-cc --symbols main.lad`
//! writing, forcing and reading by name (negative words and double words, REALs, hex)
//! and reading the values back; the errors for an unknown name and a format that does not
//! fit; and the JSON line of every client command, parsed.

mod common;

use common::{cc, stderr, stdout, text, Sim};

use std::path::PathBuf;

/// Lamp blinks (SM0.5); the other symbols are left to the client.
const PROGRAM: &str = "PLC_TYPE CPU-EC20\n\nSYMBOLS\n  Lamp  : Q0.0\n  Motor : Q0.1\n  \
     Start : I0.0\n  Speed : MW20\n  Level : MD40\n  Temp  : MD44\nEND_SYMBOLS\n\n\
     ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD     SM0.5\n=      Lamp\n\
     END_ORGANIZATION_BLOCK\n";

/// The program's source (for --symbols) and a simulator running it.
fn setup(tag: &str) -> (PathBuf, Sim) {
    let image = common::image("main.lad", PROGRAM);
    let dir = common::image_dir(&format!("symbols-{tag}"), &image);
    let source = dir.with_extension("lad");
    std::fs::write(&source, PROGRAM).expect("writes the source");
    let sim = common::sim("CPU-EC20", Some(&dir));
    (source, sim)
}

/// `gutta-cc ARGS --tcp SIM --symbols SOURCE`.
fn run(source: &std::path::Path, sim: &Sim, args: &[&str]) -> std::process::Output {
    let mut all = args.to_vec();
    let source = source.to_str().expect("path");
    all.extend_from_slice(&["--tcp", &sim.1, "--symbols", source]);
    cc(&all)
}

#[test]
fn values_are_written_and_read_back_by_symbol_in_their_types() {
    let (source, sim) = setup("values");
    let o = run(
        &source,
        &sim,
        &[
            "write",
            "Speed=-5",
            "Level=-70000",
            "Temp:real=-3.5e2",
            "MW24:hex=16#00FF",
        ],
    );
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(
        stdout(&o),
        "Speed (MW20) = -5\nLevel (MD40) = -70000\nTemp (MD44) = -350.0\nMW24 = 16#00FF\n"
    );
    let o = run(
        &source,
        &sim,
        &[
            "read",
            "Speed",
            "speed:uint",
            "Level",
            "Temp:real",
            "Temp:hex",
            "MW24",
        ],
    );
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(
        stdout(&o),
        "Speed (MW20) = -5\nSpeed (MW20) = 65531\nLevel (MD40) = -70000\n\
         Temp (MD44) = -350.0\nTemp (MD44) = 16#C3AF0000\nMW24 = 255\n"
    );
    // Raw bits write a REAL too.
    let o = run(&source, &sim, &["write", "Temp:real=16#41AC0000"]);
    assert_eq!(stdout(&o), "Temp (MD44) = 21.5\n", "{}", text(&o));
}

#[test]
fn force_and_unforce_by_symbol() {
    let (source, sim) = setup("force");
    let o = run(&source, &sim, &["force", "Motor=ON", "Start=TRUE"]);
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(stdout(&o), "Motor (Q0.1) = 1\nStart (I0.0) = 1\n");
    std::thread::sleep(std::time::Duration::from_millis(50));
    let o = run(&source, &sim, &["read", "Motor", "Start"]);
    assert_eq!(stdout(&o), "Motor (Q0.1) = 1\nStart (I0.0) = 1\n");
    let o = run(&source, &sim, &["unforce", "Motor", "Start"]);
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(stdout(&o), "Motor (Q0.1) released\nStart (I0.0) released\n");
    // Released, Q0.1 keeps its value until written; I0.0 shows its terminal (0).
    std::thread::sleep(std::time::Duration::from_millis(50));
    let o = run(&source, &sim, &["read", "Start"]);
    assert_eq!(stdout(&o), "Start (I0.0) = 0\n", "{}", text(&o));
}

#[test]
fn unknown_names_and_misfit_formats_are_usage_errors() {
    let (source, sim) = setup("errors");
    for (args, says) in [
        (vec!["read", "Sped"], "did you mean `Speed`?"),
        (
            vec!["read", "Speed:real"],
            "a `real` value needs a double word",
        ),
        (vec!["read", "MW2:flt"], "unknown format `:flt`"),
        (vec!["write", "Speed=70000"], "-32768..65535"),
        (vec!["write", "Speed=1.5"], "not an integer"),
        (vec!["force", "Motor=2"], "a BOOL is 0, 1"),
    ] {
        let o = run(&source, &sim, &args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", text(&o));
        assert!(stderr(&o).contains(says), "{args:?}: {}", stderr(&o));
    }
    // Without --symbols, a name says where symbols come from.
    let o = cc(&["read", "Lamp", "--tcp", &sim.1]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--symbols FILE"), "{}", stderr(&o));
}

fn json_line(o: &std::process::Output) -> serde_json::Value {
    assert!(o.status.success(), "{}", text(o));
    let out = stdout(o);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 1, "one JSON object per line: {out}");
    serde_json::from_str(lines[0]).unwrap_or_else(|e| panic!("{e}: {out}"))
}

#[test]
fn every_client_command_prints_json() {
    let (source, sim) = setup("json");
    let json = |args: &[&str]| {
        let mut all = args.to_vec();
        all.extend_from_slice(&["--message-format", "json"]);
        json_line(&run(&source, &sim, &all))
    };
    let v = json(&["status"]);
    assert_eq!(v["command"], "status");
    assert_eq!(v["plc"], "CPU-EC20");
    assert_eq!(v["run"], true);
    let v = json(&["write", "Speed=-7", "Temp:real=21.5"]);
    assert_eq!(v["command"], "write");
    assert_eq!(v["values"][0]["name"], "Speed");
    assert_eq!(v["values"][0]["address"], "MW20");
    assert_eq!(v["values"][0]["format"], "int");
    assert_eq!(v["values"][0]["value"], -7);
    assert_eq!(v["values"][0]["raw"], 0xFFF9);
    assert_eq!(v["values"][1]["value"], 21.5);
    let v = json(&["read", "Speed:hex", "MW20"]);
    assert_eq!(v["command"], "read");
    assert_eq!(v["values"][0]["value"], "16#FFF9");
    assert_eq!(v["values"][1]["name"], serde_json::Value::Null);
    assert_eq!(v["values"][1]["value"], -7);
    let v = json(&["force", "Motor=1"]);
    assert_eq!(
        (&v["command"], &v["values"][0]["value"]),
        (&"force".into(), &1.into())
    );
    let v = json(&["unforce", "Motor"]);
    assert_eq!(v["command"], "unforce");
    let v = json(&["debug", "info", "--watch", "Speed"]);
    assert_eq!(v["command"], "debug");
    assert_eq!(v["mode"], "run");
    assert_eq!(v["watch"][0]["value"], -7);
    assert_eq!(json(&["stop"])["command"], "stop");
    assert_eq!(json(&["run"])["command"], "run");
    let back = std::env::temp_dir().join(format!("gutta-cc-json-upload-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&back);
    let v = json(&["upload", "-o", back.to_str().expect("path")]);
    assert_eq!(v["command"], "upload");
    assert_eq!(v["program"], true);
    let v = json(&["download", back.to_str().expect("path")]);
    let _ = std::fs::remove_dir_all(&back);
    assert_eq!(v["command"], "download");
    assert_eq!(v["transferred"], 2 * v["bytes"].as_u64().expect("bytes"));
    let v = json(&["watch", "Lamp", "--once"]);
    assert!(v["time_ms"].is_u64(), "{v}");
    assert_eq!(v["values"][0]["format"], "bool");
}

#[test]
fn debug_watch_shows_values_in_their_formats() {
    let (source, sim) = setup("debug");
    assert!(run(&source, &sim, &["write", "Level=-70000"])
        .status
        .success());
    let o = run(
        &source,
        &sim,
        &["debug", "info", "--watch", "Level", "--watch", "Level:hex"],
    );
    assert!(o.status.success(), "{}", text(&o));
    let out = stdout(&o);
    assert!(out.contains("watch: Level (MD40) = -70000\n"), "{out}");
    assert!(out.contains("watch: Level (MD40) = 16#FFFEEE90\n"), "{out}");
}
