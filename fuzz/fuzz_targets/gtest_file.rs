//! Fuzz target of `.gtest` files: arbitrary bytes (lossily decoded) parsed, rendered,
//! resolved against a fixed program (examples/tank.lad, a timer and a subroutine), and
//! every test that plans run on the VM (statements that would scan more than a bound are
//! left out, so an input cannot buy a long run), then every report. Panics are the bugs
//! it looks for; it also asserts that spans lie inside the text on char boundaries and
//! that a failure names a line of the file.
#![no_main]

use std::sync::OnceLock;

use gutta_compiler::diagnostics::render::{render, RenderStyle};
use gutta_compiler::source::{SourceFile, Span};
use gutta_compiler::ProgramSources;
use gutta_gtest::report;
use gutta_gtest::resolve::Step;
use gutta_gtest::{plan, run_test, ProgramUnderTest, RunOptions, TestSource};
use libfuzzer_sys::fuzz_target;

/// Scans one input may run in all.
const MAX_SCANS: u64 = 5_000;

fn program() -> &'static ProgramUnderTest {
    static PROGRAM: OnceLock<ProgramUnderTest> = OnceLock::new();
    PROGRAM.get_or_init(|| {
        let text = include_str!("../../examples/tank.lad");
        ProgramUnderTest::build(
            ProgramSources::single(SourceFile::new("tank.lad", text)),
            None,
        )
        .expect("the worked example compiles")
    })
}

fn assert_span(text: &str, span: Span) {
    let (start, end) = (span.start as usize, span.end as usize);
    assert!(
        start <= end && end <= text.len(),
        "span {start}..{end} outside {} bytes",
        text.len()
    );
    assert!(
        text.is_char_boundary(start) && text.is_char_boundary(end),
        "span {start}..{end}"
    );
}

fn scans(step: &Step) -> u64 {
    match step {
        Step::Scan(n) => u64::from(*n),
        Step::Advance { scans, .. } => u64::from(*scans),
        Step::Until { within, .. } => u64::from(*within),
        _ => 0,
    }
}

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data).into_owned();
    let source = TestSource::parse(SourceFile::new("fuzz.gtest", text.clone()));
    for d in &source.diagnostics {
        assert_span(&text, d.primary.span);
    }
    let _ = render(&source.file, &source.diagnostics, RenderStyle::PLAIN);
    if source.has_errors() {
        return;
    }
    let program = program();
    let mut planned = match plan(&source.file, &source.parsed, program) {
        Ok(p) => p,
        Err(diagnostics) => {
            for d in &diagnostics {
                assert_span(&text, d.primary.span);
            }
            let _ = render(&source.file, &diagnostics, RenderStyle::PLAIN);
            return;
        }
    };
    let mut budget = MAX_SCANS;
    for test in &mut planned.tests {
        test.statements.retain(|s| {
            let n = scans(&s.step);
            let keep = n <= budget;
            budget -= if keep { n } else { 0 };
            keep
        });
    }
    let lines = text.lines().count().max(1) as u32;
    for test in &planned.tests {
        let result = run_test(
            program,
            &planned,
            test,
            RunOptions {
                record: true,
                ..RunOptions::default()
            },
        );
        if let Some(failure) = &result.failure {
            assert!(
                failure.line >= 1 && failure.line <= lines,
                "line {} of {lines}",
                failure.line
            );
            let _ = report::failure_detail("fuzz.gtest", &source.file, &result);
            let _ = report::failure_message(failure);
        }
        let _ = report::json_test(
            "fuzz.gtest",
            &source.file,
            &result,
            std::time::Duration::ZERO,
        );
        let _ = report::vcd(test, &result);
    }
});
