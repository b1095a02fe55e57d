//! The studio's simulator (`gutta_cli::studio::Simulator`, docs/studio.md "Simulate")
//! without a browser or a server, on the demo project `gutta-cc new` writes (its
//! templates, in a temporary folder): Start clicked latches Running, Lamp blinks by
//! the clock, a TON counts in real time, STOP empties power flow; the session's
//! unsaved buffers are what runs, a program with errors is refused with its code; the
//! watch table's reads, writes and forces; and the live routes of the real
//! `gutta-cc studio` over HTTP (EDIT, simulate, toggle, read, write, stop, edit-mode,
//! the refusals).

mod common;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use gutta_cli::studio::{Session, Simulator};
use serde_json::Value;

use common::studio::Studio;

const TEMPLATES: &[(&str, &str)] = &[
    ("gutta.toml", include_str!("../templates/gutta.toml")),
    ("src/main.lad", include_str!("../templates/main.lad")),
    ("symbols.csv", include_str!("../templates/symbols.csv")),
];

/// The demo project (`gutta-cc new demo`) in a fresh folder, main.lad's text replaced
/// by `main` when given.
fn demo(tag: &str, main: Option<&str>) -> PathBuf {
    let root = std::env::temp_dir().join(format!("gutta-studio-sim-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    for (file, template) in TEMPLATES {
        let text = template
            .replace("{name}", "demo")
            .replace("{plc}", gutta_catalog::stdlib::DEFAULT);
        let text = match (*file, main) {
            ("src/main.lad", Some(main)) => main.to_string(),
            _ => text,
        };
        let path = root.join(file);
        std::fs::create_dir_all(path.parent().expect("a folder")).expect("folder");
        std::fs::write(path, text).expect("write");
    }
    root
}

fn simulate(root: &Path) -> Simulator {
    let session = Session::open(&[root.to_path_buf()]).expect("the project opens");
    let program = session.run_program().expect("the demo compiles");
    Simulator::start(program).expect("the simulator starts")
}

/// Polls `check` every 5 ms until it holds or `within` passes.
fn wait_until(within: Duration, mut check: impl FnMut() -> bool) -> bool {
    let start = Instant::now();
    while start.elapsed() < within {
        if check() {
            return true;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    check()
}

/// The energized element ids of network `number` of MAIN in `state`.
fn on(state: &Value, number: u64) -> Vec<u64> {
    state["networks"]
        .as_array()
        .expect("networks")
        .iter()
        .find(|n| n["block"] == "MAIN" && n["network"] == number)
        .map(|n| {
            n["on"]
                .as_array()
                .expect("on")
                .iter()
                .map(|v| v.as_u64().expect("an id"))
                .collect()
        })
        .unwrap_or_default()
}

#[test]
fn start_clicked_latches_running_and_lamp_blinks_by_the_clock() {
    let root = demo("latch", None);
    let sim = simulate(&root);
    assert!(wait_until(Duration::from_secs(2), || sim.scans() >= 5));
    let state = sim.state();
    assert_eq!(state["mode"], "SIMULATE");
    assert_eq!(state["run"], true);
    assert_eq!(state["values"]["M0.0"], "0", "{state}");
    assert!(
        on(&state, 1).is_empty(),
        "nothing passes Start yet: {state}"
    );

    // A click on Start forces it on: Running latches.
    sim.toggle("I0.0").expect("Start toggles");
    assert_eq!(sim.forced(), ["I0.0"]);
    assert!(wait_until(Duration::from_secs(2), || sim
        .value("Running")
        .is_ok_and(|v| v == "1")));
    let state = sim.state();
    assert_eq!(state["forced"], serde_json::json!(["I0.0"]));
    assert!(
        !on(&state, 1).is_empty(),
        "the latch rung is powered: {state}"
    );

    // A second click releases it: Running holds.
    sim.toggle("Start").expect("Start toggles back");
    assert!(sim.forced().is_empty());
    std::thread::sleep(Duration::from_millis(100));
    assert_eq!(sim.value("Start").expect("Start"), "0");
    assert_eq!(sim.value("Running").expect("Running"), "1", "latched");

    // Lamp follows SM0.5 (500 ms on, 500 ms off) by the VM's clock, and the VM's clock
    // is the wall clock.
    let (wall, clock) = (Instant::now(), sim.clock_ms());
    let mut changes = 0;
    let mut last = None;
    while wall.elapsed() < Duration::from_millis(2300) {
        let state = sim.state();
        let scans = state["scans"].as_u64().expect("scans");
        let lamp = state["values"]["Q0.0"].clone();
        // The scan that wrote Lamp started at (scans - 1) x 10 ms.
        let sm05 = ((scans - 1) * u64::from(gutta_cli::studio::sim::SCAN_MS) / 500) % 2 == 1;
        assert_eq!(lamp, if sm05 { "1" } else { "0" }, "after scan {scans}");
        if last.as_ref().is_some_and(|l| *l != lamp) {
            changes += 1;
        }
        last = Some(lamp);
        std::thread::sleep(Duration::from_millis(5));
    }
    assert!(changes >= 2, "Lamp blinks: {changes} changes seen");
    let (vm_ms, wall_ms) = (sim.clock_ms() - clock, wall.elapsed().as_millis() as u64);
    assert!(
        vm_ms * 10 >= wall_ms * 6 && vm_ms * 10 <= wall_ms * 14,
        "{vm_ms} ms of VM time in {wall_ms} ms"
    );
    let _ = std::fs::remove_dir_all(&root);
}

const TIMER: &str = "\
ORGANIZATION_BLOCK MAIN:OB1
BEGIN
Network 1 // T4 counts while M0.0 is off
LDN    M0.0
TON    T4, 30000
END_ORGANIZATION_BLOCK
";

#[test]
fn a_ton_counts_in_real_time() {
    let root = demo("ton", Some(TIMER));
    let sim = simulate(&root);
    let target = gutta_catalog::stdlib::shared(gutta_catalog::stdlib::DEFAULT).expect("target");
    let resolution = u64::from(target.memory.timer_resolution(4).expect("T4 exists"));
    assert!(wait_until(Duration::from_secs(2), || sim.scans() >= 1));
    let read = |sim: &Simulator| -> u64 {
        sim.value("T4")
            .expect("T4")
            .parse::<i64>()
            .expect("a number") as u64
    };
    let (t0, v0, c0) = (Instant::now(), read(&sim), sim.clock_ms());
    std::thread::sleep(Duration::from_millis(1200));
    let (t1, v1, c1) = (Instant::now(), read(&sim), sim.clock_ms());
    // T4 counts the VM's clock, in 100 ms steps ...
    let counted_ms = (v1 - v0) * resolution;
    let vm_ms = c1 - c0;
    assert!(
        counted_ms + 2 * resolution >= vm_ms && counted_ms <= vm_ms + 2 * resolution,
        "T4 counted {counted_ms} ms in {vm_ms} ms of VM time"
    );
    // ... and the VM's clock is the wall clock (a busy machine delays scans; they are
    // caught up).
    let wall_ms = (t1 - t0).as_millis() as u64;
    assert!(
        vm_ms * 10 >= wall_ms * 6 && vm_ms * 10 <= wall_ms * 14,
        "{vm_ms} ms of VM time in {wall_ms} ms of wall time"
    );
    // The box is energized while it counts (the TON's input is on).
    assert!(!on(&sim.state(), 1).is_empty());
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn stop_empties_power_flow_and_run_starts_again() {
    let root = demo("stop", None);
    let sim = simulate(&root);
    sim.toggle("Start").expect("Start");
    assert!(wait_until(Duration::from_secs(2), || sim
        .value("Running")
        .is_ok_and(|v| v == "1")));
    assert!(!on(&sim.state(), 1).is_empty());
    sim.stop();
    let state = sim.state();
    assert_eq!(state["run"], false);
    assert_eq!(state["networks"], serde_json::json!([]), "{state}");
    assert!(state["message"]
        .as_str()
        .expect("message")
        .starts_with("STOP"));
    let scans = sim.scans();
    std::thread::sleep(Duration::from_millis(100));
    assert_eq!(sim.scans(), scans, "nothing scans in STOP");
    // Outputs keep their values in STOP.
    assert_eq!(sim.value("Running").expect("Running"), "1");
    sim.run();
    assert!(wait_until(Duration::from_secs(2), || sim.scans() > scans));
    assert_eq!(sim.state()["run"], true);
    assert!(!on(&sim.state(), 1).is_empty());
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn the_watch_table_reads_writes_and_forces_with_formats() {
    let root = demo("watch", None);
    let sim = simulate(&root);
    sim.write("Blinks", "16#00FF").expect("Blinks written");
    let row = sim.read("Blinks", Some("hex")).expect("Blinks reads");
    assert_eq!(row.address, "MW10");
    assert_eq!(row.format, "hex");
    assert_eq!(row.value, "16#00FF");
    assert!(!row.forced);
    assert_eq!(sim.read("MW10", None).expect("MW10").value, "255");
    assert_eq!(
        sim.read("MW10", Some("signed")).expect("MW10").format,
        "int"
    );

    sim.force("Lamp", "1").expect("Q0.0 forces");
    std::thread::sleep(Duration::from_millis(50));
    let lamp = sim.read("Lamp", Some("bit")).expect("Lamp");
    assert_eq!((lamp.value.as_str(), lamp.forced), ("1", true));
    assert_eq!(sim.state()["forced"], serde_json::json!(["Q0.0"]));
    sim.release("Q0.0").expect("released");
    std::thread::sleep(Duration::from_millis(50));
    assert_eq!(sim.value("Lamp").expect("Lamp"), "0", "Running is off");

    let codes = [
        sim.force("Blinks", "1").map_err(|e| e.code),
        sim.write("Nowhere", "1").map_err(|e| e.code),
        sim.write("Blinks", "many").map_err(|e| e.code),
        sim.read("MW10", Some("roman"))
            .map(|_| ())
            .map_err(|e| e.code),
        sim.read("M0.0", Some("real"))
            .map(|_| ())
            .map_err(|e| e.code),
        sim.toggle("Lamp").map_err(|e| e.code),
    ];
    assert_eq!(
        codes,
        [
            Err("not-forceable"),
            Err("no-operand"),
            Err("bad-value"),
            Err("bad-format"),
            Err("bad-format"),
            Err("not-an-input"),
        ]
    );
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn the_unsaved_buffer_runs_and_errors_are_refused_with_their_code() {
    let root = demo("buffer", None);
    let mut session = Session::open(std::slice::from_ref(&root)).expect("opens");
    // Network 2's coil Lamp becomes Q0.1, in the buffer only.
    let coil = "blocks[0].networks[1].rung.series[2]";
    let edit = serde_json::json!({"op": "set_operands", "at": coil, "operands": ["Q0.1"]});
    session
        .apply("src/main.lad", &edit.to_string())
        .expect("the edit applies");
    assert!(session.is_dirty("src/main.lad").expect("open"));
    let sim = Simulator::start(session.run_program().expect("compiles")).expect("starts");
    sim.force("Running", "1").unwrap_err();
    sim.write("Running", "1").expect("M0.0 written");
    assert!(wait_until(Duration::from_secs(2), || sim
        .value("Q0.1")
        .is_ok_and(|v| v == "1")));
    drop(sim);

    let broken = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLD     Nowhere\n=      Q0.0\nEND_ORGANIZATION_BLOCK\n";
    let root2 = demo("broken", Some(broken));
    let session = Session::open(std::slice::from_ref(&root2)).expect("opens");
    let error = session.run_program().expect_err("refused");
    assert!(error.code.starts_with('E'), "{error}");
    assert_eq!(error.file, "src/main.lad");
    assert_eq!(error.line, 4, "{error}");
    let _ = std::fs::remove_dir_all(&root);
    let _ = std::fs::remove_dir_all(&root2);
}

#[test]
fn the_live_routes_of_the_studio_drive_the_simulator() {
    let root = demo("http", None);
    let studio = Studio::start(&root);
    assert_eq!(
        studio.call("GET", "/api/live", ""),
        (200, serde_json::json!({"mode": "EDIT"}))
    );
    let (status, refused) = studio.call("POST", "/api/live/run", "");
    assert_eq!((status, refused["code"].as_str()), (409, Some("not-live")));

    let (status, state) = studio.call("POST", "/api/simulate", "");
    assert_eq!(status, 200, "{state}");
    assert_eq!(
        (state["mode"].as_str(), state["run"].as_bool()),
        (Some("SIMULATE"), Some(true))
    );
    let (status, state) = studio.call("POST", "/api/live/toggle", r#"{"operand": "Start"}"#);
    assert_eq!(status, 200, "{state}");
    assert_eq!(state["forced"], serde_json::json!(["I0.0"]));
    let running = || studio.call("GET", "/api/live", "").1["values"]["M0.0"] == "1";
    assert!(wait_until(Duration::from_secs(5), running));
    let (status, rows) = studio.call(
        "POST",
        "/api/live/read",
        r#"{"rows": [{"operand": "Running", "format": null}, {"operand": "Blinks", "format": "hex"}, {"operand": "Nowhere", "format": null}]}"#,
    );
    assert_eq!(status, 200, "{rows}");
    assert_eq!(rows["rows"][0]["value"], "1");
    assert_eq!(rows["rows"][1]["address"], "MW10");
    assert_eq!(rows["rows"][2]["error"]["code"], "no-operand");
    let (status, refused) = studio.call(
        "POST",
        "/api/live/write",
        r#"{"operand": "Blinks", "value": "lots"}"#,
    );
    assert_eq!((status, refused["code"].as_str()), (400, Some("bad-value")));
    let (status, refused) = studio.call("POST", "/api/live/force", "not json");
    assert_eq!(
        (status, refused["code"].as_str()),
        (400, Some("bad-request"))
    );
    let (status, state) = studio.call(
        "POST",
        "/api/live/force",
        r#"{"operand": "I0.0", "value": null}"#,
    );
    assert_eq!(
        (status, state["forced"].clone()),
        (200, serde_json::json!([]))
    );

    let (status, state) = studio.call("POST", "/api/live/stop", "");
    assert_eq!(status, 200);
    assert_eq!(
        (state["run"].as_bool(), state["networks"].clone()),
        (Some(false), serde_json::json!([]))
    );
    let (status, state) = studio.call("POST", "/api/edit-mode", "");
    assert_eq!((status, state), (200, serde_json::json!({"mode": "EDIT"})));
    assert_eq!(
        studio.call("GET", "/api/live", "").1,
        serde_json::json!({"mode": "EDIT"})
    );
    drop(studio);

    // A program with an error does not run: 409 with the compiler's code and place.
    let broken = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLD     Nowhere\n=      Q0.0\nEND_ORGANIZATION_BLOCK\n";
    let root2 = demo("http-broken", Some(broken));
    let studio = Studio::start(&root2);
    let (status, refused) = studio.call("POST", "/api/simulate", "");
    assert_eq!(status, 409, "{refused}");
    assert!(
        refused["code"].as_str().is_some_and(|c| c.starts_with('E')),
        "{refused}"
    );
    assert_eq!(
        (refused["file"].as_str(), refused["line"].as_u64()),
        (Some("src/main.lad"), Some(4))
    );
    assert_eq!(
        studio.call("GET", "/api/live", "").1,
        serde_json::json!({"mode": "EDIT"})
    );
    drop(studio);
    let _ = std::fs::remove_dir_all(&root);
    let _ = std::fs::remove_dir_all(&root2);
}
