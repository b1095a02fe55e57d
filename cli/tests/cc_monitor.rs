//! `gutta-cc monitor` end to end through the real binaries: a program in `gutta-sim`
//! over TCP, the monitor serving it on a free port; no STATUS_VAR_READ while no page is
//! open; forced inputs reported; another program in the
//! PLC is said instead of values (the page and `--once`), and so is a PLC without a
//! program; `/events` pushes an update at once and the PLC is left alone once the last
//! stream closes; STOP keeps the values and drops the power flow; the view resumes by
//! itself once the right program is downloaded; a network shown as STL gets its lines'
//! logic results. The page in a browser is studio_e2e/test_monitor_live.py's (Playwright:
//! `chromium --dump-dom` cannot wait for an event stream's first event).

mod common;

use common::{cc, stderr, stdout, Sim};

use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::Duration;

const PROGRAM: &str = "PLC_TYPE CPU-EC20\n\nSYMBOLS\n  Start : I0.0\n  Lamp : Q0.0\n\
     END_SYMBOLS\n\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1 // start\nLD     Start\n\
     AN     I0.1\n=      Lamp\nNETWORK 2 // a value\nLD     SM0.0\nMOVW   16#00FF, MW10\n\
     NETWORK 3 // two rungs: shown as STL\nLD     I0.2\nA      I0.3\n=      Q0.2\n\
     LDN    I0.2\n=      Q0.3\nEND_ORGANIZATION_BLOCK\n";

/// Another program: the same shape, another output.
const OTHER: &str = "PLC_TYPE CPU-EC20\n\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\n\
     LD     I0.0\n=      Q0.1\nEND_ORGANIZATION_BLOCK\n";

/// The monitor process, killed when dropped, and its base URL.
struct Monitor(Child, String);

impl Drop for Monitor {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// The source file, and a simulator running `running` (the source's program, or another).
fn setup(tag: &str, running: &str) -> (PathBuf, Sim) {
    let image = common::image("prog.lad", running);
    let dir = common::image_dir(&format!("monitor-{tag}"), &image);
    let source = dir.with_extension("lad");
    std::fs::write(&source, PROGRAM).expect("writes the source");
    (source.clone(), common::sim("CPU-EC20", Some(&dir)))
}

/// `gutta-cc monitor SOURCE --tcp SIM --http 127.0.0.1:0`; the URL from its stderr line.
fn monitor(source: &Path, sim: &Sim) -> Monitor {
    let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-cc"))
        .args(["monitor", source.to_str().expect("path"), "--tcp", &sim.1])
        .args(["--http", "127.0.0.1:0"])
        .env_remove("GUTTA_PASSWORD")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("gutta-cc monitor starts");
    let line = BufReader::new(child.stderr.take().expect("stderr"))
        .lines()
        .next()
        .expect("a line")
        .expect("text");
    let url = line
        .split_whitespace()
        .find(|w| w.starts_with("http://"))
        .unwrap_or_else(|| panic!("no URL in `{line}`"))
        .trim_end_matches('/')
        .to_string();
    Monitor(child, url)
}

/// GET `path` from the monitor: the body.
fn get(monitor: &Monitor, path: &str) -> String {
    let host = monitor.1.trim_start_matches("http://");
    let mut stream = std::net::TcpStream::connect(host).expect("connects");
    write!(
        stream,
        "GET {path} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n"
    )
    .expect("sends");
    let mut response = String::new();
    stream.read_to_string(&mut response).expect("reads");
    assert!(response.starts_with("HTTP/1.1 200"), "{response}");
    response
        .split_once("\r\n\r\n")
        .map(|(_, body)| body.to_string())
        .expect("a body")
}

fn json(monitor: &Monitor, path: &str) -> serde_json::Value {
    let body = get(monitor, path);
    serde_json::from_str(&body).unwrap_or_else(|e| panic!("{path}: {e}: {body}"))
}

fn var_reads(monitor: &Monitor) -> u64 {
    json(monitor, "/metrics")["var_reads"]
        .as_u64()
        .expect("a count")
}

fn cc_ok(args: &[&str]) {
    let o = cc(args);
    assert!(o.status.success(), "{args:?}: {}{}", stdout(&o), stderr(&o));
}

#[test]
fn the_plc_is_read_only_while_a_page_fetches() {
    let (source, sim) = setup("idle", PROGRAM);
    let monitor = monitor(&source, &sim);
    std::thread::sleep(Duration::from_millis(1500));
    assert_eq!(var_reads(&monitor), 0, "read before any page");
    cc_ok(&["write", "I0.0=1", "--tcp", &sim.1]);
    let state = json(&monitor, "/state");
    assert_eq!(state["live"], true, "{state}");
    assert_eq!(state["program_matches"], true, "{state}");
    assert_eq!(state["run"], true, "{state}");
    assert_eq!(state["values"]["MW10"], "255", "{state}");
    let first = &state["networks"][0];
    assert_eq!(first["on"], serde_json::json!([0, 1, 2]), "{state}");
    // Polling runs while the demand lasts (one second), then stops.
    std::thread::sleep(Duration::from_millis(600));
    let busy = var_reads(&monitor);
    assert!(busy >= 3, "only {busy} reads in the second after a fetch");
    std::thread::sleep(Duration::from_millis(1000));
    let idle = var_reads(&monitor);
    std::thread::sleep(Duration::from_millis(1000));
    assert_eq!(
        var_reads(&monitor),
        idle,
        "the PLC was read with no page open"
    );
    // Each update is one STATUS_VAR_READ: the reads count the updates.
    let metrics = json(&monitor, "/metrics");
    assert_eq!(metrics["var_reads"], metrics["updates"], "{metrics}");
}

#[test]
fn forced_inputs_are_reported() {
    let (source, sim) = setup("forced", PROGRAM);
    let monitor = monitor(&source, &sim);
    cc_ok(&["force", "I0.1=1", "--tcp", &sim.1]);
    // The force values are read on the first update and every tenth after it.
    let mut state = json(&monitor, "/state");
    for _ in 0..20 {
        if state["forced"] == serde_json::json!(["I0.1"]) {
            break;
        }
        std::thread::sleep(Duration::from_millis(100));
        state = json(&monitor, "/state");
    }
    assert_eq!(state["forced"], serde_json::json!(["I0.1"]), "{state}");
    // I0.1 forced on opens the NC contact: power stops after I0.0.
    cc_ok(&["write", "I0.0=1", "--tcp", &sim.1]);
    std::thread::sleep(Duration::from_millis(300));
    let state = json(&monitor, "/state");
    assert_eq!(
        state["networks"][0]["on"],
        serde_json::json!([0]),
        "{state}"
    );
}

#[test]
fn another_program_in_the_plc_is_said_instead_of_values() {
    let (source, sim) = setup("other", OTHER);
    let monitor = monitor(&source, &sim);
    let state = json(&monitor, "/state");
    assert_eq!(state["live"], false, "{state}");
    assert_eq!(state["program_matches"], false, "{state}");
    assert_eq!(state["program"], "other", "{state}");
    let message = state["message"].as_str().expect("a message");
    assert!(
        message.contains(&format!(
            "the PLC runs another program than {}",
            source.display()
        )),
        "{message}"
    );
    assert_eq!(state["values"], serde_json::json!({}), "{state}");
    assert_eq!(var_reads(&monitor), 0);
    let once = cc(&[
        "monitor",
        source.to_str().expect("path"),
        "--tcp",
        &sim.1,
        "--once",
    ]);
    assert_eq!(once.status.code(), Some(1), "{}", stderr(&once));
    assert!(
        stdout(&once).contains("runs another program"),
        "{}",
        stdout(&once)
    );
}

#[test]
fn once_prints_one_live_update() {
    let (source, sim) = setup("once", PROGRAM);
    let o = cc(&[
        "monitor",
        source.to_str().expect("path"),
        "--tcp",
        &sim.1,
        "--once",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let state: serde_json::Value = serde_json::from_str(stdout(&o).trim()).expect("JSON");
    assert_eq!(state["live"], true, "{state}");
    // Network 1 without I0.0: the NC contact I0.1 would pass, but no power reaches it.
    assert_eq!(state["networks"][0]["on"], serde_json::json!([]), "{state}");
    assert_eq!(
        state["networks"][1]["on"],
        serde_json::json!([0, 1]),
        "{state}"
    );
    assert_eq!(state["updates"], 1, "{state}");
}

#[test]
fn a_plc_without_a_program_is_said_so() {
    // A fresh simulator holds nothing: the monitor says to download, not "another program".
    let (source, _) = setup("empty", PROGRAM);
    let sim = common::sim("CPU-EC20", None);
    let once = cc(&[
        "monitor",
        source.to_str().expect("path"),
        "--tcp",
        &sim.1,
        "--once",
    ]);
    assert_eq!(once.status.code(), Some(1), "{}", stderr(&once));
    let state: serde_json::Value = serde_json::from_str(stdout(&once).trim()).expect("JSON");
    assert_eq!(state["live"], false, "{state}");
    assert_eq!(state["program_matches"], false, "{state}");
    assert_eq!(state["program"], "none", "{state}");
    assert_eq!(
        state["message"],
        format!(
            "the PLC holds no program: download {} with `gutta-cc download`; the view resumes by itself (checked every 2 s)",
            source.display()
        ),
        "{state}"
    );
}

/// Opens `/events` and reads until the first event: the stream (still open), the
/// response head and the first event's JSON.
fn first_event(monitor: &Monitor) -> (std::net::TcpStream, String, serde_json::Value) {
    let host = monitor.1.trim_start_matches("http://");
    let mut stream = std::net::TcpStream::connect(host).expect("connects");
    stream
        .set_read_timeout(Some(Duration::from_secs(10)))
        .expect("timeout");
    write!(stream, "GET /events HTTP/1.1\r\nHost: {host}\r\n\r\n").expect("sends");
    let mut seen = Vec::new();
    let mut buf = [0u8; 4096];
    loop {
        let n = stream.read(&mut buf).expect("reads an event in time");
        assert!(
            n > 0,
            "the stream closed: {}",
            String::from_utf8_lossy(&seen)
        );
        seen.extend_from_slice(&buf[..n]);
        let text = String::from_utf8_lossy(&seen).into_owned();
        if let Some((head, rest)) = text.split_once("\r\n\r\n") {
            // Chunked: the event is the line after `data:` up to its blank line.
            if let Some(data) = rest.split("data:").nth(1) {
                if let Some((json, _)) = data.split_once('\n') {
                    if let Ok(value) = serde_json::from_str(json.trim()) {
                        return (stream, head.to_string(), value);
                    }
                }
            }
        }
    }
}

/// `/state` until `done` holds of it, for at most `within`: the state, or a panic saying
/// what was awaited.
fn state_until(
    monitor: &Monitor,
    within: Duration,
    what: &str,
    done: impl Fn(&serde_json::Value) -> bool,
) -> serde_json::Value {
    let start = std::time::Instant::now();
    loop {
        let state = json(monitor, "/state");
        if done(&state) {
            return state;
        }
        assert!(
            start.elapsed() < within,
            "not {what} within {within:?}: {state}"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
}

#[test]
fn events_push_at_once_and_the_plc_rests_when_the_last_page_goes() {
    let (source, sim) = setup("events", PROGRAM);
    let monitor = monitor(&source, &sim);
    std::thread::sleep(Duration::from_millis(300));
    assert_eq!(var_reads(&monitor), 0, "read before any page");
    let (stream, head, event) = first_event(&monitor);
    assert!(
        head.to_ascii_lowercase()
            .contains("content-type: text/event-stream"),
        "{head}"
    );
    assert_eq!(event["live"], true, "{event}");
    assert_eq!(event["run"], true, "{event}");
    assert_eq!(event["plc"], sim.1.as_str(), "{event}");
    assert_eq!(event["connection"], "connected", "{event}");
    // The stream keeps the poller going without any /state fetch.
    std::thread::sleep(Duration::from_millis(1500));
    let busy = var_reads(&monitor);
    assert!(busy >= 5, "only {busy} reads in 1.5 s with a stream open");
    drop(stream);
    std::thread::sleep(Duration::from_millis(1000));
    let idle = var_reads(&monitor);
    std::thread::sleep(Duration::from_millis(1000));
    assert_eq!(
        var_reads(&monitor),
        idle,
        "the PLC was read with no page open"
    );
}

#[test]
fn stop_keeps_the_bits_and_drops_the_power_flow() {
    let (source, sim) = setup("stop", PROGRAM);
    let monitor = monitor(&source, &sim);
    cc_ok(&["write", "I0.0=1", "--tcp", &sim.1]);
    let state = state_until(&monitor, Duration::from_secs(3), "powered", |s| {
        s["networks"][0]["on"] == serde_json::json!([0, 1, 2])
    });
    assert_eq!(state["bits"]["I0.0"], 1, "{state}");
    cc_ok(&["stop", "--tcp", &sim.1]);
    let stopped = std::time::Instant::now();
    let state = state_until(&monitor, Duration::from_secs(2), "STOP", |s| {
        s["run"] == false
    });
    assert!(
        stopped.elapsed() < Duration::from_secs(1),
        "STOP took {:?}",
        stopped.elapsed()
    );
    assert_eq!(state["live"], true, "{state}");
    assert_eq!(state["networks"][0]["on"], serde_json::json!([]), "{state}");
    // The bits still read: I0.0 is 1 although no power flows.
    assert_eq!(state["bits"]["I0.0"], 1, "{state}");
    assert!(state["stl"][0]["lines"]
        .as_array()
        .expect("lines")
        .iter()
        .all(|l| l["rlo"].is_null()));
}

#[test]
fn the_view_resumes_once_the_right_program_is_downloaded() {
    let (source, sim) = setup("resume", OTHER);
    let monitor = monitor(&source, &sim);
    let state = state_until(&monitor, Duration::from_secs(3), "the mismatch", |s| {
        s["program"] == "other"
    });
    assert!(
        state["message"]
            .as_str()
            .is_some_and(|m| m.contains("another program") && m.contains("resumes by itself")),
        "{state}"
    );
    // Keep a page open while the right program goes in.
    let (_stream, _, _) = first_event(&monitor);
    let right = common::image_dir("monitor-resume-right", &common::image("prog.lad", PROGRAM));
    cc_ok(&["download", right.to_str().expect("path"), "--tcp", &sim.1]);
    let downloaded = std::time::Instant::now();
    let state = state_until(&monitor, Duration::from_secs(5), "live again", |s| {
        s["live"] == true
    });
    assert_eq!(state["program"], "same", "{state}");
    assert!(downloaded.elapsed() < Duration::from_secs(5));
    assert_eq!(state["values"]["MW10"], "255", "{state}");
}

#[test]
fn a_network_shown_as_stl_gets_each_lines_logic_result() {
    let (source, sim) = setup("stl", PROGRAM);
    let monitor = monitor(&source, &sim);
    cc_ok(&["write", "I0.2=1", "--tcp", &sim.1]);
    let state = state_until(&monitor, Duration::from_secs(3), "I0.2 read", |s| {
        s["bits"]["I0.2"] == 1
    });
    let stl = &state["stl"][0];
    assert_eq!(
        (&stl["block"], &stl["network"]),
        (&"MAIN".into(), &3.into()),
        "{stl}"
    );
    let lines: Vec<(u64, serde_json::Value, serde_json::Value)> = stl["lines"]
        .as_array()
        .expect("lines")
        .iter()
        .map(|l| {
            (
                l["index"].as_u64().expect("index"),
                l["rlo"].clone(),
                l["value"].clone(),
            )
        })
        .collect();
    // LD I0.2 (1), A I0.3 (0), = Q0.2, LDN I0.2, = Q0.3.
    let rlos: Vec<_> = lines.iter().map(|(_, r, _)| r.clone()).collect();
    assert_eq!(
        rlos,
        serde_json::json!([1, 0, 0, 0, 0])
            .as_array()
            .unwrap()
            .clone(),
        "{stl}"
    );
    assert_eq!(lines[0].0, 0);
    assert_eq!(lines[0].2, "I0.2 = 1", "{stl}");
    assert_eq!(lines[1].2, "I0.3 = 0", "{stl}");
}
