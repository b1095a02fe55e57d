//! The runner on small programs through the library's public API: virtual time
//! (ADVANCE rounds up to whole scans), UNTIL (checked before scanning, the count it
//! reports, its failure), forces over SET, REAL and text values in their types, the
//! other variables of a failure, and the trace a waveform is made from.

use gutta_compiler::source::SourceFile;
use gutta_compiler::ProgramSources;
use gutta_gtest::{
    plan, run_test, FailureKind, ProgramUnderTest, RunOptions, TestResult, TestSource,
};

const PROGRAM: &str = "SYMBOLS\n  Start : I0.0\n  Lamp : Q0.0\n  Temp : MD8 : REAL\n  Count : MW20 : WORD\nEND_SYMBOLS\n\
ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD Start\n= Lamp\nNETWORK 2\nLD Start\nEU\nINCW Count\n\
NETWORK 3\nLD SM0.0\nMOVR 21.5, Temp\nMOVB 16#31, MB40\nMOVB 16#41, MB41\nNETWORK 4\nLD I0.1\nTON T4, 3\n= Q0.1\nEND_ORGANIZATION_BLOCK\n";

fn run(tests: &str) -> Vec<TestResult> {
    run_with(tests, RunOptions::default())
}

fn run_with(tests: &str, options: RunOptions) -> Vec<TestResult> {
    let program = ProgramUnderTest::build(
        ProgramSources::single(SourceFile::new("p.lad", PROGRAM)),
        None,
    )
    .expect("the program compiles");
    let source = TestSource::parse(SourceFile::new("t.gtest", tests));
    assert!(!source.has_errors(), "{:?}", source.diagnostics);
    let plan = plan(&source.file, &source.parsed, &program).expect("plans");
    plan.tests
        .iter()
        .map(|t| run_test(&program, &plan, t, options))
        .collect()
}

#[test]
fn advance_runs_whole_scans_until_the_time_has_passed() {
    let r = run("SCAN_TIME 10ms\nTEST t\nADVANCE 25ms\nEXPECT Lamp = 0\nEND_TEST\n");
    assert!(r[0].passed(), "{:?}", r[0].failure);
    assert_eq!((r[0].scans, r[0].time_ms), (3, 30));
}

#[test]
fn until_checks_first_counts_its_scans_and_fails_with_the_last_values() {
    let r = run("TEST now\nUNTIL Lamp = 0 WITHIN 5 SCANS\nEND_TEST\n\
        TEST timer\nSET I0.1 = 1\nUNTIL Q0.1 = 1 WITHIN 40 SCANS\nEND_TEST\n\
        TEST never\nUNTIL Lamp = 1, Count > 0 WITHIN 4 SCANS\nEND_TEST\n");
    assert_eq!(r[0].untils[0].after_scans, 0);
    assert_eq!(r[0].scans, 0);
    // T4 counts 100 ms on CPU-EC20; a preset of 3 is done in the scan 300 ms after the
    // first: scan 31 of 10 ms.
    assert!(r[1].passed(), "{:?}", r[1].failure);
    assert_eq!(
        (r[1].untils[0].after_scans, r[1].untils[0].time_ms),
        (31, 310)
    );
    let failure = r[2].failure.as_ref().expect("fails");
    assert_eq!((failure.line, failure.scan, failure.time_ms), (9, 4, 40));
    match &failure.kind {
        FailureKind::Until {
            within: 4,
            mismatches,
        } => {
            let shown: Vec<String> = mismatches
                .iter()
                .map(|m| format!("{} {} {} / {}", m.var, m.op.as_str(), m.expected, m.actual))
                .collect();
            assert_eq!(shown, ["Lamp (Q0.0) = 1 / 0", "Count (MW20) > 0 / 0"]);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_force_holds_against_set_and_the_program_until_unforced() {
    let r = run("TEST t\nFORCE Lamp = 1\nSCAN\nEXPECT Lamp = 1\nFORCE Start = 1\nSET Start = 0\nSCAN\nEXPECT Lamp = 1, Count = 1\n\
        UNFORCE ALL\nSCAN\nEXPECT Lamp = 0\nEND_TEST\n");
    assert!(r[0].passed(), "{:?}", r[0].failure);
}

#[test]
fn values_compare_in_the_variables_types() {
    let r = run("TEST ok\nSCAN\nEXPECT Temp = 21.5, Temp > 21, Temp < 1e3, MB40 = \"1A\", MB40 <> \"1B\", Count < 1, MW20 >= 0\nEND_TEST\n\
        TEST wrong\nSCAN\nEXPECT Temp = 20, MB40 = \"1B\", Lamp = TRUE\nEND_TEST\n");
    assert!(r[0].passed(), "{:?}", r[0].failure);
    let failure = r[1].failure.as_ref().expect("fails");
    match &failure.kind {
        FailureKind::Expect(m) => {
            let shown: Vec<String> = m
                .iter()
                .map(|m| format!("{} {} {} / {}", m.var, m.op.as_str(), m.expected, m.actual))
                .collect();
            assert_eq!(
                shown,
                [
                    "Temp (MD8) = 20.0 / 21.5",
                    "MB40 = \"1B\" / \"1A\"",
                    "Lamp (Q0.0) = 1 / 0"
                ]
            );
        }
        other => panic!("{other:?}"),
    }
    // The other variables are those whose comparisons held, or that the test set.
    assert!(failure.others.is_empty(), "{:?}", failure.others);
}

#[test]
fn a_recorded_run_keeps_every_value_change_for_the_waveform() {
    let r = run_with(
        "TEST t\nSET Start = 1\nSCAN 2\nSET Start = 0\nSCAN\nEXPECT Count = 2\nEND_TEST\n",
        RunOptions {
            record: true,
            ..RunOptions::default()
        },
    );
    let trace = r[0].trace.as_ref().expect("recorded");
    let times: Vec<u64> = trace.samples.iter().map(|s| s.0).collect();
    assert_eq!(times, [0, 0, 10, 20, 20, 30]);
    assert_eq!(trace.samples[2].1, [1, 1]);
    assert!(!r[0].passed());
}

#[test]
fn both_engines_agree() {
    let tests = "TEST t\nSET Start = 1, I0.1 = 1\nADVANCE 1s\nSET Start = 0\nSCAN\nSET Start = 1\nSCAN\nEXPECT Count = 2, Q0.1 = 1, T4 >= 3\nEND_TEST\n";
    let fast = run_with(tests, RunOptions::default());
    let generic = run_with(
        tests,
        RunOptions {
            fast: false,
            ..RunOptions::default()
        },
    );
    assert!(fast[0].passed(), "{:?}", fast[0].failure);
    assert_eq!(fast, generic);
}
