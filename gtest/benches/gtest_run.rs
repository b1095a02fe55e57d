//! Issue 14's speed bar for the library of `gutta-cc test` (criterion):
//! `scans_1000_expect_each`: `run_test` alone (the program built and the file planned
//! outside the timed loop) on one test of 1,000 `SCAN` + `EXPECT` pairs over a generated
//! 200-instruction program; bar < 10 ms. `file_of_100_tests`: a file of 100 tests from
//! text to results (parse, build the program, plan, run every test); bar < 100 ms (the
//! process end to end is `cli/benches/test_command.rs`). The setup checks the
//! instruction count from the compiled image and that every test passes, so a bench
//! that stopped measuring what it says fails. `cargo bench -p gutta-gtest --bench
//! gtest_run` measures; `cargo test --benches` runs each once.

mod bench_program;

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use gutta_compiler::source::SourceFile;
use gutta_compiler::ProgramSources;
use gutta_format::UnitRecord;
use gutta_gtest::{plan, run_test, BuildError, Plan, ProgramUnderTest, RunOptions, TestSource};

/// Compile and verify the program text; any error stops the bench with its diagnostics.
fn build(text: &str) -> ProgramUnderTest {
    let sources = ProgramSources::single(SourceFile::new(bench_program::PROGRAM_FILE, text));
    match ProgramUnderTest::build(sources, None) {
        Ok(program) => program,
        Err(BuildError::Compile(checked)) => {
            panic!(
                "the bench program does not compile: {:?}",
                checked.diagnostics()
            )
        }
        Err(BuildError::Verify(e)) => panic!("the bench program does not verify: {e}"),
    }
}

/// Parse and plan a test file; any diagnostic stops the bench.
fn parse_and_plan(name: &str, text: &str, program: &ProgramUnderTest) -> Plan {
    let source = TestSource::parse(SourceFile::new(name, text));
    assert!(
        source.diagnostics.is_empty(),
        "{name}: {:?}",
        source.diagnostics
    );
    plan(&source.file, &source.parsed, program).unwrap_or_else(|d| panic!("{name}: {d:?}"))
}

/// Instructions in the compiled image, every unit.
fn instructions(program: &ProgramUnderTest) -> usize {
    program
        .image
        .units()
        .values()
        .flat_map(|unit| &unit.records)
        .filter(|r| matches!(r, UnitRecord::Instruction { .. }))
        .count()
}

/// Text to results: what the library does for one file of `gutta-cc test`. The number
/// of tests that passed.
fn file_to_results(program_text: &str, test_text: &str) -> usize {
    let program = build(program_text);
    let source = TestSource::parse(SourceFile::new("tests.gtest", test_text));
    let Ok(plan) = plan(&source.file, &source.parsed, &program) else {
        return 0;
    };
    plan.tests
        .iter()
        .map(|test| run_test(&program, &plan, test, RunOptions::default()))
        .filter(|result| result.passed())
        .count()
}

fn scans_1000_expect_each(c: &mut Criterion) {
    const SCANS: u32 = 1000;
    let program = build(&bench_program::program());
    assert_eq!(instructions(&program), bench_program::INSTRUCTIONS);
    let plan = parse_and_plan("scans.gtest", &bench_program::scans_test(SCANS), &program);
    let [test] = &plan.tests[..] else {
        panic!("one test expected, got {}", plan.tests.len());
    };
    let expects = test
        .statements
        .iter()
        .filter(|s| matches!(s.step, gutta_gtest::resolve::Step::Expect(_)))
        .count();
    assert_eq!(expects, SCANS as usize);
    let result = run_test(&program, &plan, test, RunOptions::default());
    assert!(result.passed(), "{:?}", result.failure);
    assert_eq!(result.scans, u64::from(SCANS));
    c.bench_function("scans_1000_expect_each", |b| {
        b.iter(|| run_test(black_box(&program), &plan, test, RunOptions::default()))
    });
}

fn file_of_100_tests(c: &mut Criterion) {
    const TESTS: u32 = 100;
    let program_text = bench_program::program();
    let test_text = bench_program::many_tests(TESTS);
    let program = build(&program_text);
    let plan = parse_and_plan("tests.gtest", &test_text, &program);
    assert_eq!(plan.tests.len(), TESTS as usize);
    for test in &plan.tests {
        let result = run_test(&program, &plan, test, RunOptions::default());
        assert!(result.passed(), "{}: {:?}", test.name, result.failure);
    }
    assert_eq!(file_to_results(&program_text, &test_text), TESTS as usize);
    c.bench_function("file_of_100_tests", |b| {
        b.iter(|| file_to_results(black_box(&program_text), black_box(&test_text)))
    });
}

criterion_group!(benches, scans_1000_expect_each, file_of_100_tests);
criterion_main!(benches);
