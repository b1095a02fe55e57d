//! Tests from the page (docs/studio.md, "Tests"): the project's `.gtest` files run on
//! the reference VM against the session's CURRENT program (every buffer, saved or not,
//! compiled as one program with the project's tables, target and options), with
//! `gutta_gtest`'s parser, planner, runner and report (the ones `gutta-cc test` uses);
//! this file only gathers the sources and shapes the results for the page. The test
//! files themselves are read from disk at each run (the studio does not edit them).

use std::time::Instant;

use gutta_compiler::source::SourceFile;
use gutta_compiler::ProgramSources;
use gutta_gtest::{report, BuildError, ProgramUnderTest, RunOptions, TestSource};
use serde::Serialize;

use super::Session;

/// Why no test ran: the current program does not compile (its first error's code, the
/// file and line it is at, and its message), or does not verify.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ProgramRefused {
    pub code: String,
    pub message: String,
    pub file: Option<String>,
    pub line: Option<u32>,
}

impl std::fmt::Display for ProgramRefused {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (&self.file, self.line) {
            (Some(file), Some(line)) => write!(f, "{file}:{line}: {}", self.message),
            _ => f.write_str(&self.message),
        }
    }
}

/// One `.gtest` file's run: its tests in file order (each `gutta-cc test
/// --message-format json`'s test object, with `detail`: the failure as `gutta-cc test`
/// prints it), or the errors that kept it from running.
#[derive(Debug, Clone, Serialize)]
pub struct TestFileRun {
    pub file: String,
    pub tests: Vec<serde_json::Value>,
    /// The file's own errors (syntax, unknown variables): none of its tests ran.
    pub errors: Vec<String>,
}

/// Every test file's run and the totals.
#[derive(Debug, Clone, Serialize)]
pub struct TestRun {
    pub passed: usize,
    pub failed: usize,
    /// Files that did not run (their `errors`).
    pub file_errors: usize,
    pub files: Vec<TestFileRun>,
}

impl Session {
    /// The program as the buffers hold it now: every open source (saved or not) with the
    /// project's symbol tables and options, what `gutta-cc build` would compile if the
    /// buffers were saved.
    pub fn sources_now(&self) -> ProgramSources {
        ProgramSources {
            sources: self
                .files
                .iter()
                .map(|f| SourceFile::new(&f.name, &f.text))
                .collect(),
            symbol_tables: self.tables.clone(),
            options: self.options.clone(),
        }
    }

    /// The project's `.gtest` files (those found when the session opened) run on the
    /// current program, each test on a fresh VM in virtual time. A program that does not
    /// compile runs no test: its first error is the refusal.
    pub fn run_tests(&self) -> Result<TestRun, ProgramRefused> {
        self.tests_now().run()
    }

    /// What `run_tests` needs, copied: a server runs them without holding the session.
    pub fn tests_now(&self) -> TestsNow {
        TestsNow {
            sources: self.sources_now(),
            target: self.target.clone(),
            root: self.root.clone(),
            tests: self.tests.clone(),
        }
    }
}

/// The session's program and test files at one moment (`Session::tests_now`).
#[derive(Debug, Clone)]
pub struct TestsNow {
    sources: ProgramSources,
    target: Option<gutta_compiler::ExplicitTarget>,
    root: super::Root,
    tests: Vec<String>,
}

impl TestsNow {
    /// Every test file run on the program: `Session::run_tests`.
    pub fn run(&self) -> Result<TestRun, ProgramRefused> {
        let program = ProgramUnderTest::build(self.sources.clone(), self.target.as_ref())
            .map_err(|e| refusal(&e))?;
        let mut run = TestRun {
            passed: 0,
            failed: 0,
            file_errors: 0,
            files: Vec::new(),
        };
        for name in &self.tests {
            let file = self.run_test_file(name, &program);
            if !file.errors.is_empty() {
                run.file_errors += 1;
            }
            for test in &file.tests {
                if test["status"] == "passed" {
                    run.passed += 1;
                } else {
                    run.failed += 1;
                }
            }
            run.files.push(file);
        }
        Ok(run)
    }

    /// One test file read, planned against `program` and run.
    fn run_test_file(&self, name: &str, program: &ProgramUnderTest) -> TestFileRun {
        let mut run = TestFileRun {
            file: name.to_string(),
            tests: Vec::new(),
            errors: Vec::new(),
        };
        let bytes = match self
            .root
            .confine(&self.root.dir().join(name))
            .map_err(|e| e.to_string())
            .and_then(|path| std::fs::read(&path).map_err(|e| format!("cannot read {name}: {e}")))
        {
            Ok(bytes) => bytes,
            Err(e) => {
                run.errors.push(e);
                return run;
            }
        };
        let file = match SourceFile::from_bytes(name, bytes) {
            Ok(file) => file,
            Err(e) => {
                run.errors.push(format!(
                    "{name} is not UTF-8 text (invalid byte at offset {})",
                    e.offset
                ));
                return run;
            }
        };
        let source = TestSource::parse(file);
        let index = gutta_compiler::source::LineIndex::new(&source.file.text);
        let shown = |d: &gutta_compiler::diagnostics::Diagnostic| {
            let at = source.file.locate(&index, d.primary.span.start as usize);
            format!("{name}:{}: {} [{}]", at.line, d.message, d.code.as_str())
        };
        run.errors.extend(
            source
                .diagnostics
                .iter()
                .filter(|d| d.is_error())
                .map(shown),
        );
        if !run.errors.is_empty() {
            return run;
        }
        let plan = match gutta_gtest::plan(&source.file, &source.parsed, program) {
            Ok(plan) => plan,
            Err(diagnostics) => {
                run.errors.extend(diagnostics.iter().map(shown));
                return run;
            }
        };
        for test in &plan.tests {
            let started = Instant::now();
            let result = gutta_gtest::run_test(program, &plan, test, RunOptions::default());
            let mut json = report::json_test(name, &source.file, &result, started.elapsed());
            json["detail"] = report::failure_detail(name, &source.file, &result).into();
            run.tests.push(json);
        }
        run
    }
}

/// A program that cannot be tested, as its first error.
fn refusal(e: &BuildError) -> ProgramRefused {
    match e {
        BuildError::Compile(checked) => {
            let first = checked.diagnostics().iter().find(|d| d.is_error()).cloned();
            match first {
                Some(d) => {
                    let at = checked
                        .file
                        .locate(&checked.index, d.primary.span.start as usize);
                    ProgramRefused {
                        code: d.code.as_str().to_string(),
                        message: d.message.clone(),
                        file: Some(at.file.to_string()),
                        line: Some(at.line),
                    }
                }
                None => ProgramRefused {
                    code: "E0000".into(),
                    message: "the program does not compile".into(),
                    file: None,
                    line: None,
                },
            }
        }
        BuildError::Verify(e) => ProgramRefused {
            code: "verify".into(),
            message: format!("the compiled image does not verify (a compiler defect): {e}"),
            file: None,
            line: None,
        },
    }
}

impl Session {
    /// The project's choice of target (`[program] plc`/`target`), None when each file's
    /// `PLC_TYPE` (or the default) decides: what compiling `sources_now` takes.
    pub fn explicit_target(&self) -> Option<&gutta_compiler::ExplicitTarget> {
        self.target.as_ref()
    }
}
