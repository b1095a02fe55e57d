//! Live values against a real `gutta-sim` process whose program blinks Lamp (Q0.0,
//! SM0.5: 0.5 s on, 0.5 s off), through the server (inlay hints and inline values over
//! the in-process connection) and through `Live` itself: a value changes between two
//! answers; refresh requests follow changes; the setting and the toggle command turn it
//! on and off; a PLC that does not answer gives one warning and `?`. Needs the simulator binary: `cargo build -p
//! gutta-cli --bin gutta-sim` (the workspace's `cargo test` builds it).

#![allow(
    clippy::disallowed_methods,
    reason = "tests write projects and start processes"
)]

use std::io::BufRead;
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_lsp::live::{self, LinkSettings, Live, Refresh};
use lsp_server::Message;
use serde_json::{json, Value};
use session::Session;

mod external;
mod session;

const PROGRAM: &str = "PLC_TYPE CPU-EC20\n\nSYMBOLS\n  Lamp  : Q0.0\n  Speed : MW20\n\
     END_SYMBOLS\n\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1 // blink\nLD     SM0.5\n\
     =      Lamp\nNETWORK 2\nLD     SM0.0\nMOVW   16#0102, Speed\nEND_ORGANIZATION_BLOCK\n";

/// A `gutta-sim` process, killed when dropped, and its Modbus TCP address.
struct Sim(std::process::Child, String);

impl Drop for Sim {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// A scratch folder named after `tag` and this process.
fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gutta-lsp-live-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    dir
}

/// `gutta-sim IMAGE --plc CPU-EC20 --tcp 127.0.0.1:0` running PROGRAM.
fn blinking_sim(dir: &Path) -> Sim {
    let target = stdlib::shared("CPU-EC20").expect("target");
    let explicit = ExplicitTarget {
        target,
        origin: "test".into(),
    };
    let compiled = compile(SourceFile::new("main.lad", PROGRAM), Some(&explicit));
    let image = compiled.image.expect("PROGRAM compiles");
    let image_dir = dir.join("image");
    gutta_io::write_image(&image_dir, &image).expect("writes the image");
    let mut child = std::process::Command::new(external::sim_binary())
        .arg(&image_dir)
        .args(["--plc", "CPU-EC20", "--tcp", "127.0.0.1:0"])
        .env_remove(live::PASSWORD_ENV)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("gutta-sim starts");
    let line = std::io::BufReader::new(child.stdout.take().expect("stdout"))
        .lines()
        .next()
        .expect("a listener line")
        .expect("text");
    let address = line.rsplit(' ').next().expect("address").to_string();
    Sim(child, address)
}

/// A PLC that takes connections and never answers: a listener nobody accepts from (kept
/// bound while the test runs, so no other test's simulator gets its port), and its
/// address.
fn silent_plc() -> (std::net::TcpListener, String) {
    let listener = std::net::TcpListener::bind("127.0.0.1:0").expect("a free port");
    let address = listener.local_addr().expect("its address").to_string();
    (listener, address)
}

/// A project in `dir` whose PLC is at `address`.
fn project(dir: &Path, address: &str) -> gutta_io::Project {
    std::fs::write(dir.join("main.lad"), PROGRAM).expect("writes main.lad");
    let manifest = dir.join("gutta.toml");
    std::fs::write(
        &manifest,
        format!(
            "[program]\nplc = \"CPU-EC20\"\nsources = [\"main.lad\"]\n\n\
             [connection]\ntcp = \"{address}\"\ntimeout = 300\nretries = 0\n"
        ),
    )
    .expect("writes gutta.toml");
    gutta_io::Project::load(&manifest).expect("the project loads")
}

/// Live values on, every message to the client collected.
fn live_with_outbox() -> (Live, Arc<Mutex<mpsc::Receiver<Message>>>) {
    let (tx, rx) = mpsc::channel();
    let tx = Mutex::new(tx);
    let outbox: live::Outbox = Arc::new(move |m| {
        let _ = tx.lock().map(|t| t.send(m));
    });
    let refresh = Refresh {
        inlay_hints: true,
        inline_values: false,
    };
    (Live::new(true, refresh, outbox), Arc::new(Mutex::new(rx)))
}

fn shown(live: &mut Live, p: &gutta_io::Project) -> Vec<String> {
    let checked = gutta_compiler::check_source(SourceFile::new("main.lad", PROGRAM), None);
    let settings = LinkSettings::from_connection(&p.connection, checked.target.plc.exch_pack_size);
    live.values(&p.manifest, settings, &checked, 0..PROGRAM.len())
        .into_iter()
        .map(|(o, v)| format!("{} = {}", o.label, live::show(&o.address, v)))
        .collect()
}

#[test]
fn the_lamp_blinks_between_two_answers() {
    let dir = scratch("blink");
    let sim = blinking_sim(&dir);
    let p = project(&dir, &sim.1);
    let (mut live, messages) = live_with_outbox();
    let first = shown(&mut live, &p);
    assert_eq!(first.len(), 4, "{first:?}");
    assert!(
        first.iter().all(|s| s.ends_with(" = ?")),
        "nothing read yet: {first:?}"
    );
    let start = Instant::now();
    let mut seen: Vec<String> = Vec::new();
    let mut speed_read = false;
    while start.elapsed() < Duration::from_secs(20) {
        std::thread::sleep(Duration::from_millis(100));
        let now = shown(&mut live, &p);
        let lamp = now[1].clone();
        speed_read |= now[3] == "Speed = 258";
        if !lamp.ends_with('?') && !seen.contains(&lamp) {
            seen.push(lamp);
        }
        if seen.len() == 2 && speed_read {
            break;
        }
    }
    seen.sort();
    assert_eq!(seen, ["Lamp = 0", "Lamp = 1"], "the lamp did not blink");
    assert!(speed_read, "MOVW 16#0102, Speed: 258");
    let refreshes = messages
        .lock()
        .map(|rx| {
            rx.try_iter()
                .filter(|m| matches!(m, Message::Request(r) if r.method == "workspace/inlayHint/refresh"))
                .count()
        })
        .unwrap_or(0);
    assert!(refreshes >= 2, "a refresh per change: {refreshes}");
}

#[test]
fn a_silent_plc_warns_once_and_shows_question_marks() {
    let dir = scratch("silent");
    let (_silent, address) = silent_plc();
    let p = project(&dir, &address);
    let (mut live, messages) = live_with_outbox();
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(3) {
        let now = shown(&mut live, &p);
        assert!(now.iter().all(|s| s.ends_with(" = ?")), "{now:?}");
        std::thread::sleep(Duration::from_millis(100));
    }
    let warnings: Vec<String> = messages
        .lock()
        .map(|rx| {
            rx.try_iter()
                .filter_map(|m| match m {
                    Message::Notification(n) if n.method == "window/showMessage" => {
                        Some(n.params["message"].to_string())
                    }
                    _ => None,
                })
                .collect()
        })
        .unwrap_or_default();
    assert_eq!(warnings.len(), 1, "one warning per outage: {warnings:?}");
    assert!(warnings[0].contains(&address), "{warnings:?}");
}

#[test]
fn off_means_no_values_and_no_poller() {
    let dir = scratch("off");
    let p = project(&dir, "127.0.0.1:9");
    let (mut live, _) = live_with_outbox();
    live.set_enabled(false);
    assert!(shown(&mut live, &p).is_empty());
}

fn uri_of(path: &Path) -> String {
    gutta_lsp::documents::path_to_uri(path)
        .expect("a file URI")
        .as_str()
        .to_string()
}

fn whole(uri: &str) -> Value {
    json!({"textDocument": {"uri": uri},
           "range": {"start": {"line": 0, "character": 0}, "end": {"line": 99, "character": 0}}})
}

/// The live inlay hints of the document: `line:character label`.
/// The live-value inlay hints (` = VALUE`) of `uri`, as `line:character = VALUE`; the
/// symbol-address and Modbus hints of the same answer are left out.
fn hints(s: &mut Session, uri: &str) -> Vec<String> {
    let answer = s.request("textDocument/inlayHint", whole(uri));
    let hints = answer.result.expect("inlay hints");
    hints
        .as_array()
        .expect("a list")
        .iter()
        .filter(|h| h["label"].as_str().is_some_and(|l| l.starts_with(" = ")))
        .map(|h| {
            format!(
                "{}:{}{}",
                h["position"]["line"],
                h["position"]["character"],
                h["label"].as_str().unwrap_or("")
            )
        })
        .collect()
}

#[test]
fn inlay_hints_follow_the_blinking_lamp_and_the_toggle_turns_them_off() {
    let dir = scratch("server");
    let sim = blinking_sim(&dir);
    project(&dir, &sim.1);
    let uri = uri_of(&dir.join("main.lad"));
    let mut s = Session::start(json!({"liveValues": true}));
    s.open_at(&uri, PROGRAM);
    let first = hints(&mut s, &uri);
    assert_eq!(first, ["10:12 = ?", "11:11 = ?", "13:12 = ?", "14:21 = ?"]);
    let start = Instant::now();
    let mut lamp: Vec<String> = Vec::new();
    while start.elapsed() < Duration::from_secs(20) && lamp.len() < 2 {
        std::thread::sleep(Duration::from_millis(100));
        let now = hints(&mut s, &uri);
        assert_eq!(now.len(), 4, "{now:?}");
        if !now[1].ends_with('?') && !lamp.contains(&now[1]) {
            lamp.push(now[1].clone());
        }
    }
    lamp.sort();
    assert_eq!(lamp, ["11:11 = 0", "11:11 = 1"], "the lamp did not blink");
    assert!(
        s.server_requests
            .iter()
            .any(|m| m == "workspace/inlayHint/refresh"),
        "{:?}",
        s.server_requests
    );

    let network_1 = json!({"textDocument": {"uri": uri},
        "range": {"start": {"line": 9, "character": 0}, "end": {"line": 12, "character": 0}},
        "context": {"frameId": 0, "stoppedLocation": {"start": {"line": 0, "character": 0},
                                                     "end": {"line": 0, "character": 0}}}});
    let values = s
        .request("textDocument/inlineValue", network_1)
        .result
        .expect("inline values");
    let texts: Vec<&str> = values
        .as_array()
        .expect("a list")
        .iter()
        .map(|v| v["text"].as_str().unwrap_or(""))
        .collect();
    assert_eq!(texts.len(), 2, "{texts:?}");
    assert!(
        texts[0].starts_with("SM0.5 = ") && texts[1].starts_with("Lamp = "),
        "{texts:?}"
    );

    let toggled = s.request(
        "workspace/executeCommand",
        json!({"command": live::TOGGLE_COMMAND, "arguments": []}),
    );
    assert_eq!(toggled.result, Some(json!({"liveValues": false})));
    assert!(hints(&mut s, &uri).is_empty());
    let unknown = s.request(
        "workspace/executeCommand",
        json!({"command": "gutta.nothing"}),
    );
    assert!(unknown.error.is_some(), "{unknown:?}");
    s.finish();
}

#[test]
fn the_setting_turns_live_values_on_and_a_silent_plc_warns_once() {
    let dir = scratch("server-silent");
    let (_silent, address) = silent_plc();
    project(&dir, &address);
    let uri = uri_of(&dir.join("main.lad"));
    let mut s = Session::start(json!({}));
    s.open_at(&uri, PROGRAM);
    assert!(hints(&mut s, &uri).is_empty(), "off until asked for");
    s.notify(
        "workspace/didChangeConfiguration",
        json!({"settings": {"gutta": {"liveValues": true}}}),
    );
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(3) {
        let now = hints(&mut s, &uri);
        assert!(
            now.len() == 4 && now.iter().all(|h| h.ends_with(" = ?")),
            "{now:?}"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    let warnings: Vec<&Value> = s
        .notifications
        .iter()
        .filter(|n| n.method == "window/showMessage")
        .map(|n| &n.params)
        .collect();
    assert_eq!(warnings.len(), 1, "one warning per outage: {warnings:?}");
    assert_eq!(warnings[0]["type"], json!(2), "a warning");
    assert!(warnings[0]["message"]
        .as_str()
        .unwrap_or("")
        .contains(&address));
    s.finish();
}
