//! The daily workflow of issue 11 end to end, through the real binaries and nothing
//! else: `gutta-cc new` -> `build` -> a `gutta-sim` at gutta.toml's `[connection]` ->
//! `download` -> `watch` and `force` by the symbols of the project's SYMBOLS block and
//! of its symbols.csv, with values in their types (a negative INT, a REAL from the
//! table). The lamp must really blink: watch samples see it both off and on.

mod common;
mod projects;

use std::time::{Duration, Instant};

use common::{cc_in, stdout, text};
use projects::{connect_to, new_project, read, write};

/// `gutta-cc ARGS` in the project, which must succeed; its stdout.
fn ok(dir: &std::path::Path, args: &[&str]) -> String {
    let o = cc_in(dir, args);
    assert!(
        o.status.success(),
        "gutta-cc {}: {}",
        args.join(" "),
        text(&o)
    );
    stdout(&o)
}

/// One `watch --once --json` sample: (name, value) pairs.
fn sample(dir: &std::path::Path, names: &[&str]) -> Vec<(String, serde_json::Value)> {
    let mut args = vec!["watch", "--once", "--json"];
    args.extend_from_slice(names);
    let out = ok(dir, &args);
    let line = out.lines().next().expect("one sample");
    let v: serde_json::Value = serde_json::from_str(line).expect("a JSON sample");
    v["values"]
        .as_array()
        .expect("values")
        .iter()
        .map(|x| {
            (
                x["name"].as_str().unwrap_or("").to_string(),
                x["value"].clone(),
            )
        })
        .collect()
}

fn value(sample: &[(String, serde_json::Value)], name: &str) -> serde_json::Value {
    sample
        .iter()
        .find(|(n, _)| n == name)
        .map(|(_, v)| v.clone())
        .unwrap_or_else(|| panic!("{name} not in {sample:?}"))
}

#[test]
fn new_build_download_watch_and_force_by_symbol() {
    let dir = new_project("workflow", "plant");
    // A typed symbol in the table: the table's REAL prints and parses as REAL.
    let table = read(&dir.join("symbols.csv"));
    write(
        &dir.join("symbols.csv"),
        &format!(
            "{}\nSetpoint,MD20:REAL,\"Tank setpoint, in °C\"\n",
            table.trim_end()
        ),
    );
    let built = cc_in(&dir, &["build"]);
    assert!(built.status.success(), "{}", text(&built));
    assert!(dir.join("target/image/manifest.json").is_file());
    assert!(dir.join("target/image.map.json").is_file());

    let sim = common::sim("CPU-EC20", None);
    connect_to(&dir, &sim.1);
    let out = ok(&dir, &["download", "target/image"]);
    assert!(out.contains("the PLC verified and runs the image"), "{out}");

    // Nothing pressed: the lamp is off, nothing latched.
    let s = sample(&dir, &["Lamp", "Running", "Start"]);
    assert_eq!(value(&s, "Running"), 0, "{s:?}");
    assert_eq!(value(&s, "Lamp"), 0, "{s:?}");

    // Press Start by its symbol (a table symbol): Running latches, Lamp blinks at 1 Hz.
    let out = ok(&dir, &["force", "Start=1"]);
    assert!(out.contains("Start (I0.0) = 1"), "{out}");
    let (mut seen_on, mut seen_off) = (false, false);
    let deadline = Instant::now() + Duration::from_secs(10);
    while !(seen_on && seen_off) {
        assert!(
            Instant::now() < deadline,
            "Lamp never blinked: on {seen_on}, off {seen_off}"
        );
        let s = sample(&dir, &["Lamp", "Running"]);
        if value(&s, "Running") == 1 {
            seen_on |= value(&s, "Lamp") == 1;
            seen_off |= value(&s, "Lamp") == 0;
        }
        std::thread::sleep(Duration::from_millis(100));
    }

    // Values in their types: a negative INT and a REAL from the table, read back.
    ok(&dir, &["force", "Stop=1"]);
    ok(&dir, &["write", "Blinks=-5", "Setpoint=21.5"]);
    let out = ok(
        &dir,
        &["read", "Blinks", "Blinks:hex", "Setpoint", "Running"],
    );
    assert!(out.contains("Blinks (MW10) = -5"), "{out}");
    assert!(out.contains("Blinks (MW10) = 16#FFFB"), "{out}");
    assert!(out.contains("Setpoint (MD20) = 21.5"), "{out}");
    assert!(
        out.contains("Running (M0.0) = 0"),
        "Stop releases the latch: {out}"
    );

    // Released, the inputs follow their terminals again.
    let out = ok(&dir, &["unforce", "Start", "Stop"]);
    assert!(out.contains("released"), "{out}");

    // A mistyped symbol: a clear error with the project's close name.
    let o = cc_in(&dir, &["read", "Lmap"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("Lamp"), "did-you-mean: {}", text(&o));
}
