//! The studio's tests and online parts (docs/studio.md, "Tests" and "Online"):
//! `Session::run_tests` runs the project's `.gtest` files on the session's current
//! program (an edit not saved makes a test fail, with its detail), and `gutta-cc
//! studio` online against a real `gutta-sim` at gutta.toml's `[connection]`: download,
//! power flow with program `same`, STOP (run false, no networks), another program
//! (`other`), and the recovery after a download. HTTP/1.1 is written by hand over a
//! std TcpStream, as cli/tests/cc_studio.rs does.

mod common;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use gutta_cli::studio::Session;
use serde_json::Value;

use common::studio::Studio;

/// A `gutta-cc new demo` project in a scratch folder.
fn demo(tag: &str) -> PathBuf {
    let scratch = common::scratch(&format!("studio-online-{tag}"));
    let out = common::cc_in(&scratch, &["new", "demo"]);
    assert!(out.status.success(), "{}", common::text(&out));
    scratch.join("demo")
}

/// The Lamp coil of network 2 (`= Lamp`) made `Q0.1` in the buffer, not saved.
const LAMP_ELSEWHERE: &str =
    r#"{"op": "set_operands", "at": "blocks[0].networks[1].rung.series[2]", "operands": ["Q0.1"]}"#;

#[test]
fn the_demo_tests_pass_then_an_unsaved_edit_fails_one_with_its_detail() {
    let dir = demo("tests");
    let mut session = Session::open(std::slice::from_ref(&dir)).expect("opens");
    let run = session.run_tests().expect("the demo compiles");
    assert_eq!(
        (run.passed, run.failed, run.file_errors),
        (2, 0, 0),
        "{run:?}"
    );
    assert_eq!(run.files.len(), 1);
    assert_eq!(run.files[0].file, "tests/main.gtest");
    let names: Vec<&str> = run.files[0]
        .tests
        .iter()
        .map(|t| t["test"].as_str().expect("a name"))
        .collect();
    assert_eq!(
        names,
        [
            "start_latches_and_stop_releases",
            "lamp_blinks_while_running"
        ]
    );
    assert!(run.files[0].tests.iter().all(|t| t["status"] == "passed"));

    // The buffer, not the disk: Lamp moved to Q0.1 fails the blink test at its UNTIL.
    session
        .apply("src/main.lad", LAMP_ELSEWHERE)
        .expect("the edit applies");
    let run = session.run_tests().expect("still compiles");
    assert_eq!((run.passed, run.failed), (1, 1), "{run:?}");
    let failed = &run.files[0].tests[1];
    assert_eq!(failed["status"], "failed");
    assert_eq!(failed["failure"]["kind"], "until");
    assert_eq!(failed["failure"]["line"], 22, "{failed}");
    assert_eq!(
        failed["failure"]["source"],
        "UNTIL   Lamp = 1 WITHIN 100 SCANS    // SM0.5 is on half of every second"
    );
    let mismatch = &failed["failure"]["mismatches"][0];
    assert_eq!(mismatch["variable"], "Lamp (Q0.0)");
    assert_eq!(
        (&mismatch["expected"], &mismatch["actual"]),
        (&"1".into(), &"0".into())
    );
    let detail = failed["detail"].as_str().expect("the detail");
    assert!(
        detail.contains("tests/main.gtest:22") && detail.contains("expected"),
        "{detail}"
    );
    // Nothing was saved: the file on disk still passes with `gutta-cc test`.
    let out = common::cc_in(&dir, &["test"]);
    assert!(out.status.success(), "{}", common::text(&out));
}

#[test]
fn a_program_with_errors_runs_no_test_and_says_its_first_error() {
    let dir = demo("tests-error");
    let mut session = Session::open(std::slice::from_ref(&dir)).expect("opens");
    session
        .apply(
            "src/main.lad",
            r#"{"op": "set_operands", "at": "blocks[0].networks[1].rung.series[2]", "operands": ["NoSuchLamp"]}"#,
        )
        .expect("an unknown symbol applies, with its diagnostic");
    let refused = session.run_tests().expect_err("does not compile");
    assert!(refused.code.starts_with('E'), "{refused:?}");
    assert_eq!(refused.file.as_deref(), Some("src/main.lad"));
    assert!(refused.message.contains("NoSuchLamp"), "{refused:?}");
}

fn call(studio: &Studio, method: &str, path: &str, body: &str) -> (u16, Value) {
    studio.call(method, path, body)
}

/// The online state until `ok` holds (at most 15 s).
fn state_when(studio: &Studio, what: &str, ok: impl Fn(&Value) -> bool) -> Value {
    let deadline = Instant::now() + Duration::from_secs(15);
    loop {
        let (status, state) = call(studio, "GET", "/api/online", "");
        assert_eq!(status, 200, "{state}");
        if ok(&state) {
            return state;
        }
        assert!(Instant::now() < deadline, "never {what}: {state}");
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// The energized element ids of MAIN's network `n` in `state`.
fn on_in(state: &Value, n: u64) -> Vec<String> {
    state["networks"]
        .as_array()
        .into_iter()
        .flatten()
        .filter(|x| x["block"] == "MAIN" && x["network"] == n)
        .flat_map(|x| x["on"].as_array().cloned().unwrap_or_default())
        .map(|id| id.to_string())
        .collect()
}

/// The demo project pointed at `address` (gutta.toml's `[connection] tcp`).
fn demo_at(tag: &str, address: &str) -> PathBuf {
    let dir = demo(tag);
    let manifest = dir.join("gutta.toml");
    let text = std::fs::read_to_string(&manifest).expect("reads gutta.toml");
    assert!(text.contains("127.0.0.1:5020"), "{text}");
    std::fs::write(&manifest, text.replace("127.0.0.1:5020", address)).expect("writes");
    dir
}

fn plc_of(dir: &Path) -> String {
    let text = std::fs::read_to_string(dir.join("gutta.toml")).expect("reads gutta.toml");
    text.lines()
        .find_map(|l| l.strip_prefix("plc = \""))
        .and_then(|l| l.split('"').next())
        .expect("plc = ...")
        .to_string()
}

#[test]
fn online_download_shows_power_flow_stop_another_program_and_recovers() {
    let plc = plc_of(&demo("plc"));
    let sim = common::sim(&plc, None);
    let dir = demo_at("online", &sim.1);
    let studio = Studio::start(&dir);

    let (status, state) = call(&studio, "GET", "/api/online", "");
    assert_eq!((status, &state["mode"]), (200, &"EDIT".into()), "{state}");
    // Online: a fresh simulator holds no program, and the state says so.
    let (status, state) = call(&studio, "POST", "/api/online", "{}");
    assert_eq!(status, 200, "{state}");
    assert_eq!(state["mode"], "ONLINE");
    assert_eq!(state["address"], sim.1.as_str());
    let state = state_when(&studio, "program none", |s| s["program"] == "none");
    assert_eq!(state["networks"], serde_json::json!([]));
    assert!(
        state["message"]
            .as_str()
            .unwrap_or("")
            .contains("no program"),
        "{state}"
    );

    // Download: the session's program, then power flow from the PLC.
    let (status, answer) = call(&studio, "POST", "/api/online/download", "{}");
    assert_eq!(status, 200, "{answer}");
    let download = &answer["download"];
    assert_eq!(download["plc"], plc.as_str());
    assert!(download["pages"].as_u64() > Some(0), "{answer}");
    assert_eq!(
        download["transferred"],
        2 * download["bytes"].as_u64().unwrap()
    );
    let (_, progress) = call(&studio, "GET", "/api/online/progress", "");
    assert_eq!(progress["active"], false, "{progress}");
    assert_eq!(progress["done"], progress["total"], "{progress}");
    let state = state_when(&studio, "program same, RUN", |s| {
        s["program"] == "same" && s["run"] == true && s["live"] == true
    });
    assert!(
        state["updated"].as_u64() > Some(1_600_000_000_000),
        "{state}"
    );
    // Start pressed (forced, as `gutta-cc force` does): Running latches, network 1's
    // coil and network 2's first contact are energized.
    let o = common::cc_in(&dir, &["force", "I0.0=1"]);
    assert!(o.status.success(), "{}", common::text(&o));
    // (The forces are read every tenth update: an outside force shows within a second.)
    state_when(&studio, "Running latched, I0.0 forced", |s| {
        s["values"]["M0.0"] == "1"
            && !on_in(s, 1).is_empty()
            && !on_in(s, 2).is_empty()
            && s["forced"] == serde_json::json!(["I0.0"])
    });

    // The page's live routes reach the PLC: /api/live is its state, STOP through the
    // studio (run false, no power flow shown; the PLC says STOP), then RUN.
    let (status, live) = call(&studio, "GET", "/api/live", "");
    assert_eq!((status, &live["mode"]), (200, &"ONLINE".into()), "{live}");
    assert_eq!(live["address"], sim.1.as_str());
    let (status, state) = call(&studio, "POST", "/api/live/stop", "{}");
    assert_eq!(status, 200, "{state}");
    assert_eq!(state["run"], false, "{state}");
    assert_eq!(state["networks"], serde_json::json!([]), "{state}");
    let o = common::cc_in(&dir, &["status"]);
    assert!(
        common::stdout(&o).contains(": STOP"),
        "{}",
        common::text(&o)
    );
    let (status, state) = call(&studio, "POST", "/api/live/run", "{}");
    assert_eq!((status, &state["run"]), (200, &true.into()), "{state}");
    state_when(&studio, "RUN again", |s| {
        s["run"] == true && !on_in(s, 1).is_empty()
    });
    // STOP from another client shows too.
    let o = common::cc_in(&dir, &["stop"]);
    assert!(o.status.success(), "{}", common::text(&o));
    let state = state_when(&studio, "STOP", |s| s["run"] == false);
    assert_eq!(state["networks"], serde_json::json!([]), "{state}");
    let o = common::cc_in(&dir, &["run"]);
    assert!(o.status.success(), "{}", common::text(&o));
    state_when(&studio, "RUN again", |s| {
        s["run"] == true && !on_in(s, 1).is_empty()
    });
    // A write and a watch read through the studio: Blinks (MW10) set, read back.
    let (status, state) = call(
        &studio,
        "POST",
        "/api/live/write",
        r#"{"operand": "Blinks", "value": "1234"}"#,
    );
    assert_eq!(status, 200, "{state}");
    let (status, rows) = call(
        &studio,
        "POST",
        "/api/live/read",
        r#"{"rows": [{"operand": "Blinks", "format": null}, {"operand": "Nothing", "format": null}]}"#,
    );
    assert_eq!(status, 200, "{rows}");
    assert_eq!(rows["rows"][0]["address"], "MW10", "{rows}");
    assert_eq!(rows["rows"][0]["value"], "1234", "{rows}");
    assert_eq!(rows["rows"][1]["error"]["code"], "no-operand", "{rows}");

    // Another program downloaded behind the studio's back: `other`, no power flow.
    let main = dir.join("src/main.lad");
    let text = std::fs::read_to_string(&main).expect("reads");
    std::fs::write(&main, text.replace("A      SM0.5", "A      SM0.4")).expect("writes");
    let o = common::cc_in(&dir, &["download"]);
    assert!(o.status.success(), "{}", common::text(&o));
    let state = state_when(&studio, "program other", |s| s["program"] == "other");
    assert_eq!(state["networks"], serde_json::json!([]), "{state}");
    assert!(
        state["message"]
            .as_str()
            .unwrap_or("")
            .contains("another program"),
        "{state}"
    );
    // The studio's download puts its program back: `same`, power flow again (the PLC ran,
    // so it runs).
    let (status, answer) = call(&studio, "POST", "/api/online/download", "{}");
    assert_eq!(status, 200, "{answer}");
    assert_eq!(answer["download"]["run"], true, "{answer}");
    state_when(&studio, "program same after the download", |s| {
        s["program"] == "same" && s["run"] == true && s["live"] == true
    });
    // PLC_CLEAR released the force: Start pressed again latches again.
    let o = common::cc_in(&dir, &["force", "I0.0=1"]);
    assert!(o.status.success(), "{}", common::text(&o));
    state_when(&studio, "power flow after the download", |s| {
        !on_in(s, 1).is_empty()
    });

    // The disk's program again (another client), then the buffers' again: the state
    // follows by itself, without the page asking for a download.
    let o = common::cc_in(&dir, &["download"]);
    assert!(o.status.success(), "{}", common::text(&o));
    state_when(&studio, "other again", |s| s["program"] == "other");
    std::fs::write(&main, &text).expect("writes the old text back");
    let o = common::cc_in(&dir, &["download"]);
    assert!(o.status.success(), "{}", common::text(&o));
    state_when(&studio, "same by itself", |s| s["program"] == "same");

    // The page's program is the session's: an edit not downloaded is `other` (the PLC
    // runs the old one), its undo `same` again.
    let edit = format!(r#"{{"file": "src/main.lad", "edit": {LAMP_ELSEWHERE}}}"#);
    let (status, answer) = call(&studio, "POST", "/api/edit", &edit);
    assert_eq!(status, 200, "{answer}");
    state_when(&studio, "other after an edit", |s| s["program"] == "other");
    let (status, answer) = call(&studio, "POST", "/api/undo", r#"{"file": "src/main.lad"}"#);
    assert_eq!(status, 200, "{answer}");
    state_when(&studio, "same after the undo", |s| s["program"] == "same");
}

#[test]
fn a_plc_that_does_not_answer_is_a_coded_error_and_the_mode_stays_edit() {
    let dir = demo_at("nobody", "127.0.0.1:1");
    let studio = Studio::start(&dir);
    let (status, answer) = call(&studio, "POST", "/api/online", "{}");
    assert_eq!(status, 502, "{answer}");
    assert_eq!(answer["code"], "plc-unreachable", "{answer}");
    assert!(
        answer["message"]
            .as_str()
            .unwrap_or("")
            .contains("127.0.0.1:1"),
        "{answer}"
    );
    let (_, state) = call(&studio, "GET", "/api/online", "");
    assert_eq!(state["mode"], "EDIT", "{state}");
    // A download needs the PLC too: the same refusal, nothing sent anywhere.
    let (status, answer) = call(&studio, "POST", "/api/online/download", "{}");
    assert_eq!(
        (status, &answer["code"]),
        (502, &"plc-unreachable".into()),
        "{answer}"
    );
}

#[test]
fn tests_from_the_server_pass_on_the_demo() {
    let dir = demo("tests-http");
    let studio = Studio::start(&dir);
    let (status, run) = call(&studio, "POST", "/api/tests", "{}");
    assert_eq!(status, 200, "{run}");
    assert_eq!(
        (&run["passed"], &run["failed"]),
        (&2.into(), &0.into()),
        "{run}"
    );
    // The test file changed on disk is read again at each run: a failing EXPECT.
    let gtest = dir.join("tests/main.gtest");
    let text = std::fs::read_to_string(&gtest).expect("reads");
    std::fs::write(
        &gtest,
        text.replace("EXPECT  Blinks = 3", "EXPECT  Blinks = 4"),
    )
    .expect("writes");
    let (status, run) = call(&studio, "POST", "/api/tests", "{}");
    assert_eq!(status, 200, "{run}");
    assert_eq!(
        (&run["passed"], &run["failed"]),
        (&1.into(), &1.into()),
        "{run}"
    );
    let failure = &run["files"][0]["tests"][1]["failure"];
    assert_eq!(failure["kind"], "expect", "{run}");
    assert_eq!(failure["mismatches"][0]["expected"], "4", "{run}");
    assert_eq!(failure["mismatches"][0]["actual"], "3", "{run}");
}

#[test]
fn a_program_with_errors_is_refused_before_anything_is_sent() {
    // Nobody listens at the address: a 409 with the compiler's code (not
    // plc-unreachable) shows the program was refused before any connection.
    let dir = demo_at("refused", "127.0.0.1:1");
    let studio = Studio::start(&dir);
    let edit = r#"{"file": "src/main.lad", "edit": {"op": "set_operands", "at": "blocks[0].networks[1].rung.series[2]", "operands": ["NoSuchLamp"]}}"#;
    let (status, answer) = call(&studio, "POST", "/api/edit", edit);
    assert_eq!(status, 200, "{answer}");
    let (status, answer) = call(&studio, "POST", "/api/online/download", "{}");
    assert_eq!(status, 409, "{answer}");
    let code = answer["code"].as_str().unwrap_or_default();
    assert!(code.starts_with('E'), "{answer}");
    let message = answer["message"].as_str().unwrap_or_default();
    assert!(
        message.starts_with("src/main.lad:") && message.contains("NoSuchLamp"),
        "{answer}"
    );
    let (_, state) = call(&studio, "GET", "/api/online", "");
    assert_eq!(state["mode"], "EDIT", "{state}");
    // The tests say the same, and run none.
    let (status, run) = call(&studio, "POST", "/api/tests", "{}");
    assert_eq!(status, 200, "{run}");
    assert_eq!(run["refused"]["code"], code, "{run}");
}

/// A bit forced to 0 reads as unforced over UM4001; the studio marks it because this
/// session forced it, says so, and forgets it when released.
#[test]
fn a_bit_this_session_forced_to_0_is_marked() {
    let plc = plc_of(&demo("plc0"));
    let sim = common::sim(&plc, None);
    let dir = demo_at("forced0", &sim.1);
    let studio = Studio::start(&dir);
    let (status, state) = call(&studio, "POST", "/api/online", "{}");
    assert_eq!(status, 200, "{state}");
    let (status, answer) = call(&studio, "POST", "/api/online/download", "{}");
    assert_eq!(status, 200, "{answer}");
    state_when(&studio, "live", |s| {
        s["live"] == true && s["program"] == "same"
    });
    let force = r#"{"operand": "I0.1", "value": "0"}"#;
    let (status, answer) = call(&studio, "POST", "/api/live/force", force);
    assert_eq!(status, 200, "{answer}");
    let state = state_when(&studio, "I0.1 marked forced", |s| {
        s["forced"]
            .as_array()
            .is_some_and(|f| f.iter().any(|a| a == "I0.1"))
    });
    assert!(
        state["forced_note"]
            .as_str()
            .is_some_and(|n| n.contains("this studio session forced")),
        "{state}"
    );
    let release = r#"{"operand": "I0.1", "value": null}"#;
    let (status, answer) = call(&studio, "POST", "/api/live/force", release);
    assert_eq!(status, 200, "{answer}");
    state_when(&studio, "I0.1 released", |s| {
        s["forced"]
            .as_array()
            .is_some_and(|f| !f.iter().any(|a| a == "I0.1"))
    });
}
