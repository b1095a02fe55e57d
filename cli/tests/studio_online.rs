//! The studio's tests and online parts (docs/studio.md, "Tests" and "Online"):
//! `Session::run_tests` runs the project's `.gtest` files on the session's current
//! program (an edit not saved makes a test fail, with its detail), and `gutta-cc
//! studio` online against a real `gutta-sim` at gutta.toml's `[connection]`: download,
//! power flow with program `same`, STOP (run false, no networks), another program
//! (`other`), and the recovery after a download. HTTP/1.1 is written by hand over a
//! std TcpStream, as cli/tests/cc_studio.rs does.

mod common;

use std::path::PathBuf;

use gutta_cli::studio::Session;

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
