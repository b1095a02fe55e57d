//! `gutta-cc test` through the real binary (docs/testing-programs.md): the worked
//! example passes; a failure shows file:line, the source line, the scan and virtual
//! time, expected and actual values and the other variables; a test file with mistakes
//! gets coded diagnostics and runs nothing (exit 2) while other files run; a program
//! that does not compile is E0808; --filter, --junit (read back by Python's XML parser),
//! --vcd, --message-format json; files in parallel, printed in file order; faults.

mod common;

use std::path::{Path, PathBuf};

use common::{cc, cc_in, stderr, stdout, text};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// A fresh directory for this test, holding a copy of the worked example's program.
fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gutta-cc-test-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("creates the scratch directory");
    std::fs::copy(root().join("examples/tank.lad"), dir.join("tank.lad")).expect("copies");
    dir
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).expect("creates the folder");
    }
    std::fs::write(&path, text).expect("writes");
    path
}

const PASSING: &str = "PROGRAM tank.lad\n\nTEST fills\n  SET Enable = 1, Sensor = 9600\n  SCAN\n  EXPECT Pump = 1, Level = 300\nEND_TEST\n";

/// A passing test and a failing one: Level is 300 (9600 / 32), not 350.
const FAILING: &str = "PROGRAM tank.lad\nSCAN_TIME 20ms\n\nTEST fills\n  SET Enable = 1, Sensor = 9600\n  SCAN\n  EXPECT Pump = 1\nEND_TEST\n\n\
TEST level_is_wrong\n  SET Enable = 1, Sensor = 9600\n  SCAN 3\n  EXPECT Pump = 1, Level = 350   // wrong on purpose\nEND_TEST\n";

#[test]
fn the_worked_example_passes() {
    let o = cc_in(&root(), &["test", "examples/tank.gtest"]);
    let out = stdout(&o);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    for name in [
        "scale_turns_the_sensor_into_per_mille",
        "pump_fills_until_full_and_refills_below_600",
        "dry_run_trips_after_5_s_and_reset_clears_it",
    ] {
        assert!(
            out.contains(&format!("PASS  examples/tank.gtest::{name} (")),
            "{out}"
        );
    }
    assert!(
        out.contains("3 passed, 0 failed (3 tests in 1 file) in "),
        "{out}"
    );
}

#[test]
fn a_failure_shows_where_when_expected_actual_and_the_other_variables() {
    let dir = scratch("failing");
    write(&dir, "t.gtest", FAILING);
    let o = cc_in(&dir, &["test", "t.gtest"]);
    let out = stdout(&o);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(
        out.contains("PASS  t.gtest::fills (1 scan, 20 ms)"),
        "{out}"
    );
    assert!(
        out.contains("FAIL  t.gtest::level_is_wrong (3 scans, 60 ms)"),
        "{out}"
    );
    let detail = "---- t.gtest::level_is_wrong\n  t.gtest:13, after scan 3 (60 ms)\n     |\n  13 |   EXPECT Pump = 1, Level = 350   // wrong on purpose\n     |\n    expected  Level (MW20) = 350\n    actual    Level (MW20) = 300\n  other variables: Enable (I0.0) = 1, Sensor (AIW0) = 9600, Pump (Q0.0) = 1\n";
    assert!(out.contains(detail), "{out}");
    assert!(
        out.contains("\n1 passed, 1 failed (2 tests in 1 file) in "),
        "{out}"
    );
}

#[test]
fn a_test_file_with_mistakes_gets_coded_diagnostics_and_other_files_still_run() {
    let dir = scratch("mistakes");
    write(&dir, "a_good.gtest", PASSING);
    write(
        &dir,
        "b_bad.gtest",
        "PROGRAM tank.lad\nTEST t\n  SET Enable = 1\n  SCNA 2\n  EXPECT Pmup = 1\n  EXPECT Level = 1.5\nEND_TEST\n",
    );
    let o = cc_in(&dir, &["test", "."]);
    let (out, err) = (stdout(&o), stderr(&o));
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(out.contains("PASS  ./a_good.gtest::fills"), "{out}");
    assert!(
        !out.contains("b_bad.gtest::t"),
        "no test of the bad file runs: {out}"
    );
    assert!(
        err.contains("[E0802]")
            && err.contains("`SCNA` is not a test statement")
            && err.contains("did you mean `SCAN`?"),
        "{err}"
    );
    assert!(
        out.contains("1 passed, 0 failed (1 test in 2 files); 1 file with errors did not run"),
        "{out}"
    );

    // Once the statement is fixed, the variables are checked against the program.
    write(
        &dir,
        "b_bad.gtest",
        "PROGRAM tank.lad\nTEST t\n  SET Enable = 1\n  SCAN 2\n  EXPECT Pmup = 1\n  EXPECT Level = 1.5\nEND_TEST\n",
    );
    let o = cc_in(&dir, &["test", "b_bad.gtest"]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        err.contains("[E0805]")
            && err.contains("`Pmup` is neither a symbol of the program nor an address")
            && err.contains("did you mean `Pump`?"),
        "{err}"
    );
    assert!(
        err.contains("[E0806]")
            && err.contains("1.5 is a REAL; Level (MW20) is INT")
            && err.contains("b_bad.gtest:6:"),
        "{err}"
    );
}

#[test]
fn a_program_with_errors_is_e0808_followed_by_its_own_errors() {
    let dir = scratch("program-errors");
    write(
        &dir,
        "broken.lad",
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD Strat\n= Q0.0\nEND_ORGANIZATION_BLOCK\n",
    );
    write(
        &dir,
        "t.gtest",
        "PROGRAM broken.lad\nTEST t\n  SCAN\n  EXPECT Q0.0 = 0\nEND_TEST\n",
    );
    write(
        &dir,
        "u.gtest",
        "PROGRAM missing.lad\nTEST t\n  SCAN\n  EXPECT Q0.0 = 0\nEND_TEST\n",
    );
    let o = cc_in(&dir, &["test", "t.gtest", "u.gtest"]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        err.contains("[E0808]") && err.contains("the program under test, "),
        "{err}"
    );
    assert!(
        err.contains("[E0202]") && err.contains("Strat"),
        "the program's own error: {err}"
    );
    assert!(
        err.contains("[E0807]") && err.contains("cannot read the program `missing.lad`"),
        "{err}"
    );
}

#[test]
fn filter_junit_vcd_and_json() {
    let dir = scratch("reports");
    write(&dir, "t.gtest", FAILING);
    let junit = dir.join("out/report.xml");
    std::fs::create_dir_all(dir.join("out")).expect("creates out/");
    let waves = dir.join("waves");
    let o = cc_in(
        &dir,
        &[
            "test",
            "t.gtest",
            "--junit",
            junit.to_str().expect("path"),
            "--vcd",
            waves.to_str().expect("path"),
        ],
    );
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));

    // JUnit XML, read by an independent parser.
    let python = std::env::var("GUTTA_PYTHON").unwrap_or_else(|_| "python3".into());
    let script = "import sys, xml.etree.ElementTree as E\n\
        r = E.parse(sys.argv[1]).getroot()\n\
        for s in r.iter('testsuite'):\n\
        \x20   print(s.get('name'), s.get('tests'), s.get('failures'))\n\
        \x20   for c in s.iter('testcase'):\n\
        \x20       f = c.find('failure')\n\
        \x20       print(c.get('classname'), c.get('name'), c.get('file') + ':' + c.get('line'), 'failure' if f is not None else 'ok', (f.get('message') if f is not None else ''))\n";
    let parsed = std::process::Command::new(&python)
        .args(["-c", script, junit.to_str().expect("path")])
        .output()
        .unwrap_or_else(|e| panic!("{python} runs (install python3): {e}"));
    let lines = String::from_utf8_lossy(&parsed.stdout).into_owned();
    assert!(
        parsed.status.success(),
        "{lines}{}",
        String::from_utf8_lossy(&parsed.stderr)
    );
    assert!(lines.contains("t.gtest 2 1\n"), "{lines}");
    // Each test case says where its TEST line is.
    assert!(lines.contains("t.gtest fills t.gtest:4 ok"), "{lines}");
    assert!(
        lines.contains("t.gtest level_is_wrong t.gtest:10 failure EXPECT failed after scan 3 (60 ms): Level (MW20) = 350 expected, is 300"),
        "{lines}"
    );

    // A waveform of the failing test only, signals named by their symbols.
    let names: Vec<String> = std::fs::read_dir(&waves)
        .expect("the vcd folder")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["t.level_is_wrong.vcd"]);
    let vcd = std::fs::read_to_string(waves.join("t.level_is_wrong.vcd")).expect("reads");
    for var in [
        "$var wire 1 ! Enable $end",
        "$var wire 16 \" Sensor $end",
        "$var wire 1 # Pump $end",
        "$var wire 16 $ Level $end",
    ] {
        assert!(vcd.contains(var), "{var}: {vcd}");
    }
    assert!(
        vcd.contains("#20\n1#\nb100101100 $\n") && vcd.trim_end().ends_with("#60"),
        "{vcd}"
    );

    // --filter and JSON: one object per test, then the summary.
    let o = cc_in(
        &dir,
        &[
            "test",
            "t.gtest",
            "--filter",
            "LEVEL",
            "--message-format",
            "json",
        ],
    );
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    let objects: Vec<serde_json::Value> = stdout(&o)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{l}: {e}")))
        .collect();
    assert_eq!(objects.len(), 2, "{objects:?}");
    let test = &objects[0];
    assert_eq!(test["type"], "test");
    assert_eq!(test["test"], "level_is_wrong");
    assert_eq!(test["status"], "failed");
    assert_eq!(test["failure"]["line"], 13);
    assert_eq!(test["failure"]["scan"], 3);
    assert_eq!(test["failure"]["time_ms"], 60);
    assert_eq!(test["failure"]["mismatches"][0]["expected"], "350");
    assert_eq!(test["failure"]["mismatches"][0]["actual"], "300");
    assert_eq!(
        objects[1],
        serde_json::json!({"type": "summary", "passed": 0, "failed": 1, "files": 1, "file_errors": 0})
    );
}

#[test]
fn failed_tests_are_listed_last_with_the_command_that_reruns_each_alone() {
    let dir = scratch("rerun");
    // `level` is part of the name of `level_is_wrong`: only --exact runs it alone.
    let source = format!(
        "{FAILING}\nTEST level\n  SET Sensor = 9600\n  SCAN\n  EXPECT Level = 1\nEND_TEST\n"
    );
    write(&dir, "my tests/t.gtest", &source);
    std::fs::copy(dir.join("tank.lad"), dir.join("my tests/tank.lad")).expect("copies");
    let o = cc_in(&dir, &["test", "my tests"]);
    let out = stdout(&o);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    let list = "\nfailed tests (each re-runs alone with the command beside it):\n\
        \x20 my tests/t.gtest::level_is_wrong  gutta-cc test 'my tests/t.gtest' --filter level_is_wrong --exact\n\
        \x20 my tests/t.gtest::level           gutta-cc test 'my tests/t.gtest' --filter level --exact\n\
        \n1 passed, 2 failed";
    assert!(out.contains(list), "{out}");
    // The list comes after every failure's detail.
    let (detail, list) = (
        out.find("---- my tests/t.gtest::level\n"),
        out.find("failed tests ("),
    );
    assert!(detail.is_some() && detail < list, "{out}");

    // The command runs that one test and no other, as a shell reads it.
    let command = out
        .lines()
        .find(|l| l.ends_with("--filter level --exact"))
        .and_then(|l| l.split_once("  gutta-cc "))
        .map(|(_, c)| c)
        .expect("the re-run command");
    let o = std::process::Command::new("sh")
        .current_dir(&dir)
        .arg("-c")
        .arg(format!("\"$0\" {command}"))
        .arg(env!("CARGO_BIN_EXE_gutta-cc"))
        .output()
        .expect("sh runs");
    let out = stdout(&o);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(out.starts_with("FAIL  my tests/t.gtest::level ("), "{out}");
    assert!(
        out.contains("0 passed, 1 failed (1 test in 1 file; 2 filtered out)"),
        "{out}"
    );

    // A run that passes lists nothing; --exact needs --filter.
    let o = cc_in(&dir, &["test", "my tests", "--filter", "fills", "--exact"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(!stdout(&o).contains("failed tests"), "{}", text(&o));
    let o = cc_in(&dir, &["test", "my tests", "--exact"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(stderr(&o).contains("--filter"), "{}", text(&o));
}

#[test]
fn files_run_in_parallel_and_print_in_file_order() {
    let dir = scratch("parallel");
    let mut expected = Vec::new();
    for i in 0..6 {
        let name = format!("sub/t{i}.gtest");
        // Later files are quicker, so a parallel run finishes them first.
        let scans = 600 - i * 100;
        write(
            &dir,
            &name,
            &format!("PROGRAM ../tank.lad\nTEST run_{i}\n  SET Enable = 1, Sensor = 9600\n  SCAN {scans}\n  EXPECT Level = 300\nEND_TEST\n"),
        );
        expected.push(format!("PASS  sub/t{i}.gtest::run_{i} ({scans} scans"));
    }
    let o = cc_in(&dir, &["test", "sub", "--jobs", "3"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let lines: Vec<String> = stdout(&o)
        .lines()
        .filter(|l| l.starts_with("PASS"))
        .map(String::from)
        .collect();
    assert_eq!(lines.len(), 6, "{lines:?}");
    for (line, want) in lines.iter().zip(&expected) {
        assert!(line.starts_with(want.as_str()), "{line} / {want}");
    }
}

#[test]
fn faults_fail_a_test_unless_it_expects_them() {
    let dir = scratch("faults");
    write(&dir, "loop.lad", "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLBL 1\nNETWORK 2\nLD I0.0\nJMP 1\nEND_ORGANIZATION_BLOCK\n");
    write(
        &dir,
        "t.gtest",
        "PROGRAM loop.lad\nWATCHDOG 1000\n\nTEST expected\n  SET I0.0 = 1\n  SCAN 5\n  EXPECT FAULT 3\n  RESET\n  SET I0.0 = 0\n  SCAN\n  EXPECT RUN\nEND_TEST\n\n\
         TEST unexpected\n  SCAN 2\n  SET I0.0 = 1\n  SCAN 5\n  EXPECT Q0.0 = 0\nEND_TEST\n\n\
         TEST still\n  SET I0.0 = 1\n  SCAN\n  EXPECT FAULT 3\n  SCAN\n  EXPECT Q0.0 = 0\nEND_TEST\n",
    );
    let o = cc_in(&dir, &["test", "t.gtest"]);
    let out = stdout(&o);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(
        out.contains("PASS  t.gtest::expected (2 scans, 20 ms)"),
        "{out}"
    );
    assert!(
        out.contains("FAIL  t.gtest::unexpected (3 scans, 30 ms)"),
        "{out}"
    );
    assert!(
        out.contains("  t.gtest:17, after scan 3 (30 ms)")
            && out.contains("the PLC faulted in scan 3: watchdog: more than 1000 instructions in one scan (fault code 3)"),
        "{out}"
    );
    // An expected fault is not cleared by expecting it: the PLC stays in it until RESET.
    assert!(
        out.contains("FAIL  t.gtest::still (1 scan, 10 ms)"),
        "{out}"
    );
    assert!(
        out.contains("  t.gtest:25, after scan 1 (10 ms)")
            && out.contains("the PLC is still in fault (watchdog: more than 1000 instructions in one scan, fault code 3) and runs no scan: RESET clears a fault"),
        "{out}"
    );
}

#[test]
fn usage_and_file_errors_exit_2() {
    let dir = scratch("usage");
    let o = cc_in(&dir, &["test", "nothing-here"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        stderr(&o).contains("nothing-here: no such file or folder"),
        "{}",
        stderr(&o)
    );
    let o = cc_in(&dir, &["test", "."]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        stderr(&o).contains("no .gtest files in ."),
        "{}",
        stderr(&o)
    );
    let o = cc_in(&dir, &["test"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        stderr(&o).contains("no test files given, and no project (gutta.toml) here"),
        "{}",
        stderr(&o)
    );
    // Outside the example's folder a relative PROGRAM is relative to the test file.
    let o = cc(&[
        "test",
        root().join("examples/tank.gtest").to_str().expect("path"),
        "--filter",
        "scale",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(
        stdout(&o).contains("1 passed, 0 failed (1 test in 1 file; 2 filtered out)"),
        "{}",
        stdout(&o)
    );
}

/// The page shows the worked example as it is; its console examples (the failing run of
/// `docs/examples/testing-programs/t.gtest`, a bad file) are run and compared by
/// `docs_console.rs`, like every console example of the docs.
#[test]
fn the_documentation_shows_the_worked_example() {
    let doc =
        std::fs::read_to_string(root().join("docs/testing-programs.md")).expect("reads the page");
    for file in ["examples/tank.lad", "examples/tank.gtest"] {
        let text = std::fs::read_to_string(root().join(file)).expect("reads the example");
        assert!(
            doc.contains(&text),
            "docs/testing-programs.md does not show {file} as it is"
        );
    }
}
