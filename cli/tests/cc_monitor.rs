//! `gutta-cc monitor` end to end through the real binaries: a program in `gutta-sim`
//! over TCP, the monitor serving it on a free port; headless Chromium loads the page and
//! the contact of the input set is `on`, then not once the input is cleared; no
//! STATUS_VAR_READ while no page is open; forced inputs reported; another program in the
//! PLC is said instead of values (the page and `--once`), and so is a PLC without a
//! program. The browser test needs chromium.

mod common;

use common::{cc, stderr, stdout, Sim};

use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::Duration;

const PROGRAM: &str = "PLC_TYPE CPU-EC20\n\nSYMBOLS\n  Start : I0.0\n  Lamp : Q0.0\n\
     END_SYMBOLS\n\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1 // start\nLD     Start\n\
     AN     I0.1\n=      Lamp\nNETWORK 2 // a value\nLD     SM0.0\nMOVW   16#00FF, MW10\n\
     END_ORGANIZATION_BLOCK\n";

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

/// The `<g class="contact ...">` start tag of the contact of `operand` in the page
/// Chromium rendered after its script ran.
fn rendered_contact(url: &str, operand: &str) -> String {
    let out = Command::new("chromium")
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--virtual-time-budget=3000",
            "--dump-dom",
            url,
        ])
        .output()
        .expect("chromium runs");
    let dom = String::from_utf8_lossy(&out.stdout).into_owned();
    let needle = format!("data-operand=\"{operand}\"");
    dom.split('<')
        .find(|tag| tag.starts_with("g class=\"contact") && tag.contains(&needle))
        .unwrap_or_else(|| panic!("no contact of {operand} in the page:\n{dom}"))
        .to_string()
}

#[test]
fn the_browser_sees_the_energized_contact_come_and_go() {
    if !common::have("chromium") {
        return;
    }
    let (source, sim) = setup("browser", PROGRAM);
    let monitor = monitor(&source, &sim);
    cc_ok(&["write", "I0.0=1", "--tcp", &sim.1]);
    let contact = rendered_contact(&monitor.1, "I0.0");
    assert!(contact.contains("class=\"contact on\""), "{contact}");
    cc_ok(&["write", "I0.0=0", "--tcp", &sim.1]);
    let contact = rendered_contact(&monitor.1, "I0.0");
    assert!(contact.starts_with("g class=\"contact\""), "{contact}");
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
            "the PLC holds no program: download {} first with `gutta-cc download`, then reload",
            source.display()
        ),
        "{state}"
    );
}
