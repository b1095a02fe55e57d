//! What `gutta-cc test` prints and writes, as text: the one line per test, a failure
//! with its source line, scan, time, expected and actual values and the other
//! variables, the summary, one JSON object per test, JUnit XML (quick-junit) and a
//! failing test's waveform (VCD). No I/O: the caller prints and writes.

use std::fmt::Write as _;
use std::time::Duration;

use gutta_catalog::plural;
use gutta_compiler::source::{LineIndex, SourceFile};
use gutta_vm::vcd::{Dump, Signal};
use quick_junit::{NonSuccessKind, Report, TestCase, TestCaseStatus, TestSuite};
use serde_json::{json, Value};

use crate::resolve::PlannedTest;
use crate::run::{Failure, FailureKind, Mismatch, TestResult};

/// Virtual time as people read it: `40 ms`, `2.000 s`.
pub fn show_time(ms: u64) -> String {
    if ms < 1000 {
        format!("{ms} ms")
    } else {
        format!("{}.{:03} s", ms / 1000, ms % 1000)
    }
}

/// `5 scans, 50 ms`.
fn scans_and_time(scans: u64, ms: u64) -> String {
    let s = if scans == 1 { "" } else { "s" };
    format!("{scans} scan{s}, {}", show_time(ms))
}

/// Terminal colours for the status words, or none.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Style {
    pub color: bool,
}

impl Style {
    fn paint(self, text: &str, code: &str) -> String {
        if self.color {
            format!("\x1b[{code}m{text}\x1b[0m")
        } else {
            text.to_string()
        }
    }
}

/// The one line of a test: `PASS  tests/lamp.gtest::lamp_latches (2 scans, 20 ms)`.
pub fn test_line(file: &str, result: &TestResult, style: Style) -> String {
    let status = if result.passed() {
        style.paint("PASS", "32")
    } else {
        style.paint("FAIL", "1;31")
    };
    format!(
        "{status}  {file}::{} ({})",
        result.name,
        scans_and_time(result.scans, result.time_ms)
    )
}

/// A comparison that did not hold, as a sentence: `Q0.0 = 1 expected, is 0`.
fn mismatch_lines(out: &mut String, mismatches: &[Mismatch]) {
    let width = mismatches.iter().map(|m| m.var.len()).max().unwrap_or(0);
    for m in mismatches {
        let _ = writeln!(
            out,
            "    expected  {:width$} {} {}",
            m.var,
            m.op.as_str(),
            m.expected
        );
        let _ = writeln!(out, "    actual    {:width$} = {}", m.var, m.actual);
    }
}

/// Comparisons that did not hold, in one line: `Lamp (Q0.0) = 1 expected, is 0; ...`.
fn joined(mismatches: &[Mismatch]) -> String {
    mismatches
        .iter()
        .map(|m| {
            format!(
                "{} {} {} expected, is {}",
                m.var,
                m.op.as_str(),
                m.expected,
                m.actual
            )
        })
        .collect::<Vec<_>>()
        .join("; ")
}

/// What went wrong, in one line (JUnit's message, JSON's `message`).
pub fn failure_message(failure: &Failure) -> String {
    let at = format!(
        "after scan {} ({})",
        failure.scan,
        show_time(failure.time_ms)
    );
    match &failure.kind {
        FailureKind::Expect(m) => format!("EXPECT failed {at}: {}", joined(m)),
        FailureKind::Until { within, mismatches } => format!(
            "UNTIL did not hold within {}, {at}: {}",
            plural::count(*within, "scan"),
            joined(mismatches)
        ),
        FailureKind::Fault {
            code,
            message,
            still: false,
        } => format!(
            "the PLC faulted in scan {}: {message} (fault code {code})",
            failure.scan
        ),
        FailureKind::Fault {
            code,
            message,
            still: true,
        } => format!(
            "the PLC is still in fault ({message}, fault code {code}) and runs no scan: RESET clears a fault"
        ),
        FailureKind::FaultExpected {
            expected,
            got: None,
        } => {
            format!("EXPECT FAULT {expected}: the scans ran without a fault, {at}")
        }
        FailureKind::FaultExpected {
            expected,
            got: Some((code, message)),
        } => format!("EXPECT FAULT {expected}: the PLC faulted with code {code} ({message}), {at}"),
        FailureKind::Mode { expected_run } => {
            let (want, is) = if *expected_run {
                ("RUN", "STOP")
            } else {
                ("STOP", "RUN")
            };
            format!("EXPECT {want}: the PLC is in {is}, {at}")
        }
        FailureKind::Access(message) => format!("{message}, {at}"),
    }
}

/// The failure of a test, with its source line:
///
/// ```text
/// ---- tests/lamp.gtest::timer_runs_out
///   tests/lamp.gtest:16, after scan 200 (2.000 s)
///      |
///   16 |   EXPECT Q0.0 = 1
///      |
///     expected  Q0.0 = 1
///     actual    Q0.0 = 0
///   other variables: I0.0 = 1, Q0.1 = 0
/// ```
pub fn failure_detail(display: &str, file: &SourceFile, result: &TestResult) -> String {
    let Some(failure) = &result.failure else {
        return String::new();
    };
    let mut out = String::new();
    let _ = writeln!(out, "---- {display}::{}", result.name);
    let _ = writeln!(
        out,
        "  {display}:{}, after scan {} ({})",
        failure.line,
        failure.scan,
        show_time(failure.time_ms)
    );
    let source = source_line(file, failure.line);
    let number = failure.line.to_string();
    let pad = " ".repeat(number.len());
    let _ = writeln!(out, "  {pad} |");
    let _ = writeln!(out, "  {number} | {source}");
    let _ = writeln!(out, "  {pad} |");
    match &failure.kind {
        FailureKind::Expect(m) => mismatch_lines(&mut out, m),
        FailureKind::Until { within, mismatches } => {
            let _ = writeln!(
                out,
                "    not true within {}; at the last:",
                plural::count(*within, "scan")
            );
            mismatch_lines(&mut out, mismatches);
        }
        _ => {
            let _ = writeln!(out, "    {}", failure_message(failure));
        }
    }
    if !failure.others.is_empty() {
        let others: Vec<String> = failure
            .others
            .iter()
            .map(|(label, value)| format!("{label} = {value}"))
            .collect();
        let _ = writeln!(out, "  other variables: {}", others.join(", "));
    }
    out
}

/// The text of 1-based line `line` of `file`, without its line end.
pub fn source_line(file: &SourceFile, line: u32) -> &str {
    file.text
        .lines()
        .nth(line.saturating_sub(1) as usize)
        .unwrap_or("")
        .trim_end()
}

/// The command that runs test `name` of file `display` alone: `gutta-cc test FILE
/// --filter NAME --exact`, with `flags` (the run's `--plc`, `--target`...) after it. A
/// path with characters a shell reads is single-quoted.
pub fn rerun_command(display: &str, name: &str, flags: &[String]) -> String {
    let mut words = vec![
        "gutta-cc".to_string(),
        "test".into(),
        shell_word(display),
        "--filter".into(),
        shell_word(name),
        "--exact".into(),
    ];
    words.extend(flags.iter().map(|f| shell_word(f)));
    words.join(" ")
}

/// `word` as a POSIX shell reads it back: as is when plain, else in single quotes.
fn shell_word(word: &str) -> String {
    let plain = !word.is_empty()
        && word
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "_-./:=@%+,".contains(c));
    if plain {
        word.to_string()
    } else {
        format!("'{}'", word.replace('\'', "'\\''"))
    }
}

/// The closing list of failed tests, each with the command that re-runs it alone
/// (empty when none failed):
///
/// ```text
/// failed tests (each re-runs alone with the command beside it):
///   t.gtest::level_is_wrong  gutta-cc test t.gtest --filter level_is_wrong --exact
/// ```
pub fn failed_list(failed: &[(&str, &str)], flags: &[String]) -> String {
    if failed.is_empty() {
        return String::new();
    }
    let names: Vec<String> = failed
        .iter()
        .map(|(file, test)| format!("{file}::{test}"))
        .collect();
    let width = names.iter().map(|n| n.chars().count()).max().unwrap_or(0);
    let mut out = String::from("failed tests (each re-runs alone with the command beside it):\n");
    for (name, (file, test)) in names.iter().zip(failed) {
        let _ = writeln!(out, "  {name:width$}  {}", rerun_command(file, test, flags));
    }
    out
}

/// The summary line: `2 passed, 1 failed (3 tests in 1 file)`.
pub fn summary(passed: usize, failed: usize, files: usize, filtered: usize) -> String {
    let tests = passed + failed;
    let t = if tests == 1 { "test" } else { "tests" };
    let f = if files == 1 { "file" } else { "files" };
    let mut line = format!("{passed} passed, {failed} failed ({tests} {t} in {files} {f}");
    if filtered > 0 {
        let _ = write!(line, "; {filtered} filtered out");
    }
    line.push(')');
    line
}

/// One test as a JSON object (`--message-format json`).
pub fn json_test(
    display: &str,
    file: &SourceFile,
    result: &TestResult,
    duration: Duration,
) -> Value {
    let untils: Vec<Value> = result
        .untils
        .iter()
        .map(|u| json!({"line": u.line, "after_scans": u.after_scans, "scan": u.scan, "time_ms": u.time_ms}))
        .collect();
    let failure = result.failure.as_ref().map(|f| {
        let (kind, mismatches) = match &f.kind {
            FailureKind::Expect(m) => ("expect", m.as_slice()),
            FailureKind::Until { mismatches, .. } => ("until", mismatches.as_slice()),
            FailureKind::Fault { .. } => ("fault", &[][..]),
            FailureKind::FaultExpected { .. } => ("expect_fault", &[][..]),
            FailureKind::Mode { .. } => ("mode", &[][..]),
            FailureKind::Access(_) => ("access", &[][..]),
        };
        json!({
            "kind": kind,
            "message": failure_message(f),
            "line": f.line,
            "source": source_line(file, f.line).trim(),
            "scan": f.scan,
            "time_ms": f.time_ms,
            "mismatches": mismatches.iter().map(|m| json!({
                "variable": m.var, "op": m.op.as_str(), "expected": m.expected, "actual": m.actual
            })).collect::<Vec<_>>(),
            "others": f.others.iter().map(|(v, x)| json!({"variable": v, "value": x})).collect::<Vec<_>>(),
        })
    });
    json!({
        "type": "test",
        "file": display,
        "test": result.name,
        "line": result.line,
        "status": if result.passed() { "passed" } else { "failed" },
        "scans": result.scans,
        "time_ms": result.time_ms,
        "duration_ms": duration.as_secs_f64() * 1000.0,
        "untils": untils,
        "failure": failure,
    })
}

/// The summary as JSON.
pub fn json_summary(passed: usize, failed: usize, files: usize, errors: usize) -> Value {
    json!({"type": "summary", "passed": passed, "failed": failed, "files": files, "file_errors": errors})
}

/// One file's results for JUnit: its display name, its text, and each test with its
/// wall-clock duration.
#[derive(Debug)]
pub struct FileResults<'a> {
    pub display: &'a str,
    pub file: &'a SourceFile,
    pub results: &'a [(TestResult, Duration)],
    /// A file whose tests could not run: why (its diagnostics, rendered).
    pub error: Option<String>,
}

/// JUnit XML: one `<testsuite>` per file, one `<testcase>` per test (classname the file,
/// `file` and `line` where its `TEST` line is), a `<failure>` with the message and the detail; a file with errors is one `<error>`
/// test case named after the file.
pub fn junit(files: &[FileResults]) -> Result<String, String> {
    let mut report = Report::new("gutta-cc test");
    for f in files {
        let mut suite = TestSuite::new(f.display);
        if let Some(error) = &f.error {
            let mut status = TestCaseStatus::non_success(NonSuccessKind::Error);
            status.set_message("the test file or its program has errors; no test ran");
            status.set_description(error.as_str());
            let mut case = TestCase::new("(file)", status);
            case.set_classname(f.display);
            case.extra.insert("file".into(), f.display.into());
            suite.add_test_case(case);
        }
        for (result, duration) in f.results {
            let status = match &result.failure {
                None => TestCaseStatus::success(),
                Some(failure) => {
                    let mut s = TestCaseStatus::non_success(NonSuccessKind::Failure);
                    s.set_message(failure_message(failure));
                    s.set_type(match failure.kind {
                        FailureKind::Expect(_) => "EXPECT",
                        FailureKind::Until { .. } => "UNTIL",
                        FailureKind::Fault { .. } => "FAULT",
                        FailureKind::FaultExpected { .. } => "EXPECT FAULT",
                        FailureKind::Mode { .. } => "EXPECT MODE",
                        FailureKind::Access(_) => "ACCESS",
                    });
                    s.set_description(failure_detail(f.display, f.file, result));
                    s
                }
            };
            let mut case = TestCase::new(result.name.as_str(), status);
            case.set_classname(f.display);
            case.set_time(*duration);
            // Where the test is (GitLab and the Jenkins/GitHub reporters link to it).
            case.extra.insert("file".into(), f.display.into());
            case.extra
                .insert("line".into(), result.line.to_string().into());
            suite.add_test_case(case);
        }
        report.add_test_suite(suite);
    }
    report.to_string().map_err(|e| e.to_string())
}

/// A failing test's waveform: every variable it mentions (symbol names), each sample.
pub fn vcd(test: &PlannedTest, result: &TestResult) -> Option<String> {
    let trace = result.trace.as_ref()?;
    let signals = test
        .vars
        .iter()
        .map(|v| Signal::of(v.name(), v.address.width, v.format))
        .collect();
    let (first, rest) = trace.samples.split_first()?;
    let mut dump = Dump::new(&format!("gutta-cc test {}", result.name), signals, &first.1);
    for (time, values) in rest {
        dump.sample(*time, values);
    }
    Some(dump.finish(result.time_ms))
}

/// Column of a byte offset, for JSON diagnostics of test files (1-based).
pub fn line_of(file: &SourceFile, offset: usize) -> u32 {
    LineIndex::new(&file.text).line_col(&file.text, offset).line
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rerun_command_is_read_back_by_a_shell() {
        assert_eq!(
            rerun_command("tests/main.gtest", "lamp", &[]),
            "gutta-cc test tests/main.gtest --filter lamp --exact"
        );
        assert_eq!(
            rerun_command(
                "my tests/it's.gtest",
                "t",
                &["--plc".into(), "CPU-EC20".into()]
            ),
            "gutta-cc test 'my tests/it'\\''s.gtest' --filter t --exact --plc CPU-EC20"
        );
    }

    #[test]
    fn the_failed_list_aligns_its_commands() {
        assert_eq!(failed_list(&[], &[]), "");
        assert_eq!(
            failed_list(&[("a.gtest", "x"), ("b.gtest", "long_name")], &[]),
            "failed tests (each re-runs alone with the command beside it):\n\
             \x20 a.gtest::x          gutta-cc test a.gtest --filter x --exact\n\
             \x20 b.gtest::long_name  gutta-cc test b.gtest --filter long_name --exact\n"
        );
    }
}
