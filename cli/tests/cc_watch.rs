//! `gutta-cc watch` through the real binaries on a `gutta-sim` whose program blinks
//! Lamp (Q0.0, 0.5 s on, 0.5 s off): `--once` (a table), `--json` (one object per
//! sample, parsed), one line per sample when stdout is a pipe, a lost connection (exit 2),
//! and the live table under tmux: it updates between captures and `q` leaves the
//! terminal as it was. The tmux test needs tmux.

mod common;

use common::{cc, stderr, stdout, text, Sim};

use std::io::BufRead;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const PROGRAM: &str = "PLC_TYPE CPU-EC20\n\nSYMBOLS\n  Lamp  : Q0.0\n  Speed : MW20\n\
     END_SYMBOLS\n\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD     SM0.5\n\
     =      Lamp\nEND_ORGANIZATION_BLOCK\n";

fn setup(tag: &str) -> (PathBuf, Sim) {
    let image = common::image("blink.lad", PROGRAM);
    let dir = common::image_dir(&format!("watch-{tag}"), &image);
    let source = dir.with_extension("lad");
    std::fs::write(&source, PROGRAM).expect("writes the source");
    let sim = common::sim("CPU-EC20", Some(&dir));
    (source, sim)
}

fn watch_args<'a>(source: &'a Path, sim: &'a Sim, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec!["watch", "Lamp", "Speed", "Speed:hex"];
    args.extend_from_slice(extra);
    args.extend_from_slice(&["--tcp", &sim.1, "--symbols", source.to_str().expect("path")]);
    args
}

#[test]
fn once_prints_one_table() {
    let (source, sim) = setup("once");
    assert!(cc(&["write", "MW20=-2", "--tcp", &sim.1]).status.success());
    let o = cc(&watch_args(&source, &sim, &["--once"]));
    assert!(o.status.success(), "{}", text(&o));
    let out = stdout(&o);
    let lines: Vec<Vec<&str>> = out
        .lines()
        .map(|l| l.split_whitespace().collect())
        .collect();
    assert_eq!(lines.len(), 4, "{out}");
    assert_eq!(lines[0], ["NAME", "ADDRESS", "FORMAT", "VALUE", "CHANGED"]);
    assert_eq!(lines[1][..3], ["Lamp", "Q0.0", "bool"], "{out}");
    assert!(["0", "1"].contains(&lines[1][3]), "{out}");
    assert_eq!(lines[2], ["Speed", "MW20", "int", "-2", "-"]);
    assert_eq!(lines[3], ["Speed", "MW20", "hex", "16#FFFE", "-"]);
}

#[test]
fn json_samples_follow_the_blinking_lamp() {
    let (source, sim) = setup("json");
    let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-cc"))
        .args(watch_args(&source, &sim, &["--json", "--interval", "100"]))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("gutta-cc runs");
    let out = std::io::BufReader::new(child.stdout.take().expect("stdout"));
    let samples: Vec<serde_json::Value> = out
        .lines()
        .take(15)
        .map(|l| serde_json::from_str(&l.expect("a line")).expect("a JSON object"))
        .collect();
    let _ = child.kill();
    let _ = child.wait();
    assert_eq!(samples.len(), 15);
    let times: Vec<u64> = samples
        .iter()
        .map(|s| s["time_ms"].as_u64().expect("time_ms"))
        .collect();
    assert!(times.windows(2).all(|w| w[0] < w[1]), "{times:?}");
    // Counted from the first sample, whose time is 0.
    assert_eq!(times[0], 0, "{times:?}");
    let lamp: Vec<u64> = samples
        .iter()
        .map(|s| {
            let v = &s["values"][0];
            assert_eq!(v["name"], "Lamp");
            assert_eq!(v["address"], "Q0.0");
            assert_eq!(v["format"], "bool");
            assert_eq!(v["raw"], v["value"]);
            v["value"].as_u64().expect("a bit")
        })
        .collect();
    // 1.5 s of samples see the 1 Hz lamp both on and off.
    assert!(lamp.contains(&0) && lamp.contains(&1), "{lamp:?}");
    assert_eq!(samples[0]["values"][2]["format"], "hex");
}

#[test]
fn a_pipe_gets_one_line_per_sample_and_a_lost_connection_exits_2() {
    let (source, sim) = setup("lost");
    let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-cc"))
        .args(watch_args(
            &source,
            &sim,
            &["--interval", "50", "--timeout", "200", "--retries", "0"],
        ))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("gutta-cc runs");
    let mut out = std::io::BufReader::new(child.stdout.take().expect("stdout"));
    let mut line = String::new();
    out.read_line(&mut line).expect("a sample");
    assert!(line.contains(" s: Lamp (Q0.0) = "), "{line}");
    assert!(
        line.contains(", Speed (MW20) = 0, Speed (MW20) = 16#0000"),
        "{line}"
    );
    drop(sim); // the PLC goes away
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("waits") {
            break status;
        }
        assert!(
            start.elapsed() < Duration::from_secs(10),
            "watch goes on without a PLC"
        );
        // Keep the pipe drained.
        let mut more = String::new();
        let _ = out.read_line(&mut more);
    };
    assert_eq!(status.code(), Some(2));
    let o = child.wait_with_output().expect("output");
    assert!(
        stderr(&o).contains("lost the connection to the PLC"),
        "{}",
        stderr(&o)
    );
}

/// The Lamp row's value in a captured table.
fn lamp(screen: &str) -> Option<String> {
    screen
        .lines()
        .map(|l| l.split_whitespace().collect::<Vec<_>>())
        .find(|cells| cells.first() == Some(&"Lamp") && cells.get(1) == Some(&"Q0.0"))
        .and_then(|cells| cells.get(3).map(|v| v.to_string()))
}

#[test]
fn the_live_table_updates_and_q_restores_the_terminal() {
    if !common::have("tmux") {
        return;
    }
    let (source, sim) = setup("tmux");
    let tmux = common::Tmux::new("gutta-watch");
    let args = watch_args(&source, &sim, &[]).join(" ");
    let shell = format!(
        "echo before-watch; s=$(stty -g); {} {args}; echo exit=$?; \
         [ \"$(stty -g)\" = \"$s\" ] && echo tty=restored; sleep 60",
        env!("CARGO_BIN_EXE_gutta-cc")
    );
    tmux.run(&[
        "new-session",
        "-d",
        "-s",
        "w",
        "-x",
        "100",
        "-y",
        "30",
        "sh",
        "-c",
        &shell,
    ]);
    let first = tmux.screen_when("w", |s| lamp(s).is_some());
    let first_value = lamp(&first).unwrap_or_else(|| panic!("no table:\n{first}"));
    assert!(first.contains("NAME"), "{first}");
    assert!(first.contains("q, Esc or Ctrl-C: quit"), "{first}");
    assert!(
        !first.contains("before-watch"),
        "the alternate screen:\n{first}"
    );
    // The lamp blinks at 1 Hz: within a second or so the table shows the other value,
    // and the CHANGED column how long ago.
    let next = tmux.screen_when("w", |s| lamp(s).is_some_and(|v| v != first_value));
    assert_ne!(lamp(&next), Some(first_value), "{next}");
    assert!(next.contains(" s ago"), "{next}");
    // A resize redraws without ending the watch.
    tmux.run(&["resize-window", "-t", "w", "-x", "60", "-y", "12"]);
    std::thread::sleep(Duration::from_millis(300));
    assert!(lamp(&tmux.screen("w")).is_some(), "{}", tmux.screen("w"));
    tmux.run(&["send-keys", "-t", "w", "q"]);
    let after = tmux.screen_when("w", |s| s.contains("tty="));
    assert!(after.contains("exit=0"), "{after}");
    assert!(after.contains("tty=restored"), "{after}");
    assert!(
        after.contains("before-watch"),
        "the main screen is back:\n{after}"
    );
    assert!(lamp(&after).is_none(), "the table is gone:\n{after}");
}
