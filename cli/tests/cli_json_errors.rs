//! `--message-format json` covers every error of the three tools, fatal ones included:
//! clap's usage errors, I/O, target and PLC-link errors are each one JSON object on
//! stdout (`{"type":"error","tool","kind","message","hint"}`, docs/cli.md), nothing on
//! stderr, and the exit status stays 2.

mod common;

use std::process::{Command, Output};

use common::{cc, stderr, stdout};

/// The one JSON error object of a run that failed with status 2.
fn json_error(out: &Output) -> serde_json::Value {
    assert_eq!(out.status.code(), Some(2), "{}{}", stdout(out), stderr(out));
    assert!(stderr(out).is_empty(), "stderr: {}", stderr(out));
    let text = stdout(out);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 1, "one object: {}", stdout(out));
    let value: serde_json::Value = serde_json::from_str(lines[0]).expect("JSON");
    assert_eq!(value["type"], "error", "{value}");
    assert!(
        value["message"].as_str().is_some_and(|m| !m.is_empty()),
        "{value}"
    );
    assert!(
        value["hint"].is_null() || value["hint"].is_string(),
        "{value}"
    );
    value
}

#[test]
fn clap_usage_errors_are_json() {
    let e = json_error(&cc(&["--message-format", "json", "--no-such-flag"]));
    assert_eq!(e["kind"], "usage");
    assert_eq!(e["tool"], "gutta-cc");
    assert!(
        e["message"]
            .as_str()
            .unwrap_or("")
            .contains("--no-such-flag"),
        "{e}"
    );
    // The flag after the error, and in its `=` spelling.
    let e = json_error(&cc(&["read", "--message-format=json"]));
    assert_eq!(e["kind"], "usage");
    let e = json_error(&cc(&["--message-format", "json", "explain"]));
    assert_eq!(e["kind"], "usage");
}

#[test]
fn io_and_target_errors_are_json() {
    let e = json_error(&cc(&["--message-format", "json", "/no/such/file.lad"]));
    assert_eq!(e["kind"], "io");
    assert!(
        e["message"]
            .as_str()
            .unwrap_or("")
            .contains("/no/such/file.lad"),
        "{e}"
    );
    let e = json_error(&cc(&["--message-format", "json", "dis", "/no/such/image"]));
    assert_eq!(e["kind"], "io");
    let e = json_error(&cc(&[
        "--message-format",
        "json",
        "--plc",
        "NO-SUCH-PLC",
        "modbus",
        "MW0",
    ]));
    assert_eq!(e["kind"], "target");
    let e = json_error(&cc(&["--message-format", "json", "explain", "E9999"]));
    assert_eq!(e["kind"], "usage");
}

#[test]
fn link_errors_are_json() {
    // A port nobody listens on: bound, then closed.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("free port")
        .port();
    let address = format!("127.0.0.1:{port}");
    let e = json_error(&cc(&[
        "status",
        "--tcp",
        &address,
        "--timeout",
        "200",
        "--retries",
        "0",
        "--message-format",
        "json",
    ]));
    assert_eq!(e["kind"], "link", "{e}");
}

#[test]
fn human_errors_stay_on_stderr() {
    let out = cc(&["/no/such/file.lad"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stdout(&out).is_empty());
    assert!(stderr(&out).starts_with("gutta-cc: error: cannot read /no/such/file.lad"));
}

fn tool(bin: &str, args: &[&str]) -> Output {
    Command::new(bin).args(args).output().expect("runs")
}

#[test]
fn gutta_vm_errors_are_json() {
    let vm = env!("CARGO_BIN_EXE_gutta-vm");
    let e = json_error(&tool(vm, &["--message-format", "json"]));
    assert_eq!(
        (e["tool"].as_str(), e["kind"].as_str()),
        (Some("gutta-vm"), Some("usage"))
    );
    let e = json_error(&tool(vm, &["/no/such/image", "--message-format", "json"]));
    assert!(
        e["message"]
            .as_str()
            .unwrap_or("")
            .contains("/no/such/image"),
        "{e}"
    );
    // The old spelling still asks for JSON.
    let e = json_error(&tool(vm, &["/no/such/image", "--json"]));
    assert_eq!(e["tool"], "gutta-vm");
}

#[test]
fn gutta_sim_errors_are_json() {
    let sim = env!("CARGO_BIN_EXE_gutta-sim");
    let e = json_error(&tool(sim, &["--message-format", "json"]));
    assert_eq!(
        (e["tool"].as_str(), e["kind"].as_str()),
        (Some("gutta-sim"), Some("usage"))
    );
    let e = json_error(&tool(sim, &["--message-format", "json", "--scan-ms", "x"]));
    assert_eq!(e["kind"], "usage");
}

/// Errors raised by the commands themselves carry the kind of their cause, not "other":
/// a variable that is neither symbol nor address is a usage error, an image that does
/// not verify a program error, a missing PLC endpoint a usage error, a project name
/// taken a usage error.
#[test]
fn command_errors_carry_their_kind() {
    let dir = std::env::temp_dir().join(format!("gutta-json-kinds-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let image = common::image_dir("json-kinds", &common::example("blink.lad"));
    let vm = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_gutta-vm"))
            .args(args)
            .output()
            .expect("gutta-vm runs")
    };
    let image_arg = image.to_str().expect("utf-8 path");
    let e = json_error(&vm(&[
        image_arg,
        "--read",
        "Lmap",
        "--message-format",
        "json",
    ]));
    assert_eq!(
        (e["tool"].as_str(), e["kind"].as_str()),
        (Some("gutta-vm"), Some("usage")),
        "{e}"
    );
    let e = json_error(&cc(&["read", "MW0", "--message-format", "json"]));
    assert_eq!(e["kind"], "usage", "no PLC given: {e}");
    std::fs::create_dir_all(dir.join("taken")).expect("mkdir");
    std::fs::write(dir.join("taken/x"), "").expect("a file");
    let e = json_error(&common::cc_in(
        &dir,
        &["new", "taken", "--message-format", "json"],
    ));
    assert_eq!(e["kind"], "usage", "{e}");
    // A page of the image cut short: it does not verify.
    let page = std::fs::read_dir(&image)
        .expect("image dir")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .find(|p| p.extension().is_some_and(|x| x == "bin"))
        .expect("a page file");
    std::fs::write(&page, b"\x01").expect("cut");
    let e = json_error(&vm(&[image_arg, "--message-format", "json"]));
    assert!(matches!(e["kind"].as_str(), Some("program" | "io")), "{e}");
}
