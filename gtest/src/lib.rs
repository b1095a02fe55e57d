//! Unit tests for PLC programs (docs/testing-programs.md): `.gtest` files parsed
//! (`syntax.rs`), resolved against the program under test (`resolve.rs`), run on the
//! reference VM in virtual time (`run.rs`), and reported as text, JSON, JUnit XML and
//! waveforms (`report.rs`). No I/O: `gutta-cc test` finds and reads the files, compiles
//! each program once, runs files in parallel and writes the reports.

pub mod report;
pub mod resolve;
pub mod run;
pub mod syntax;

use std::sync::Arc;

use gutta_catalog::Target;
use gutta_compiler::diagnostics::Diagnostic;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile_program, CheckedFile, ExplicitTarget, ProgramSources};
use gutta_format::{SymbolTable, VerifiedImage};

pub use resolve::{plan, Plan, PlannedTest};
pub use run::{run_test, Failure, FailureKind, RunOptions, TestResult};

/// A compiled, verified program, what every test of it starts from.
#[derive(Debug, Clone)]
pub struct ProgramUnderTest {
    pub image: VerifiedImage,
    pub target: Arc<Target>,
    /// The symbols tests may name (SYMBOLS blocks and symbol tables).
    pub symbols: SymbolTable,
    /// A STEP 7-Micro/WIN export: tests may also name Micro/WIN's system symbols.
    pub microwin: bool,
}

/// Why a program cannot be tested.
#[derive(Debug)]
pub enum BuildError {
    /// It does not compile: the checked program with its diagnostics.
    Compile(Box<CheckedFile>),
    /// The image does not verify (a compiler defect: say so).
    Verify(String),
}

impl ProgramUnderTest {
    /// Compile and verify `program` (once per run: every test file of it shares it).
    pub fn build(
        program: ProgramSources,
        explicit: Option<&ExplicitTarget>,
    ) -> Result<ProgramUnderTest, BuildError> {
        let compiled = compile_program(program, explicit);
        let checked = compiled.checked;
        let Some(image) = compiled.image else {
            return Err(BuildError::Compile(Box::new(checked)));
        };
        let target = Arc::clone(&checked.target);
        let image = gutta_format::verify(&image, &target)
            .map_err(|e| BuildError::Verify(format!("{e:?}")))?;
        Ok(ProgramUnderTest {
            image,
            symbols: checked.symbols(),
            microwin: checked.microwin.is_some(),
            target,
        })
    }
}

/// A test file read and parsed.
#[derive(Debug, Clone)]
pub struct TestSource {
    pub file: SourceFile,
    pub parsed: syntax::TestFile,
    /// The parser's diagnostics (errors stop the file; warnings do not).
    pub diagnostics: Vec<Diagnostic>,
}

impl TestSource {
    pub fn parse(file: SourceFile) -> TestSource {
        let (parsed, diagnostics) = syntax::parse(&file.text);
        TestSource {
            file,
            parsed,
            diagnostics,
        }
    }

    pub fn has_errors(&self) -> bool {
        self.diagnostics.iter().any(Diagnostic::is_error)
    }

    /// The compile options the header asks for.
    pub fn compile_options(&self) -> gutta_compiler::CompileOptions {
        gutta_compiler::CompileOptions {
            scale_timer_presets: self
                .parsed
                .header
                .options
                .iter()
                .any(|(o, _)| o == "scale-timer-presets"),
            s_area: self
                .parsed
                .header
                .s_area
                .as_ref()
                .and_then(|(v, _)| v.parse().ok()),
        }
    }
}

/// `--filter NAME` (and `--exact`): which tests run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Filter<'a> {
    pub name: &'a str,
    /// The whole name, not a part of it (`--exact`): one test of a file.
    pub exact: bool,
}

/// Whether a test runs under `filter`: the filter is part of its name, or with `exact`
/// the whole name (any case, as names are in the file).
pub fn selected(name: &str, filter: Option<Filter>) -> bool {
    filter.is_none_or(|f| {
        let (name, wanted) = (name.to_lowercase(), f.name.to_lowercase());
        if f.exact {
            name == wanted
        } else {
            name.contains(&wanted)
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_filter_selects_by_part_or_by_the_whole_name() {
        let part = Filter {
            name: "LAMP",
            exact: false,
        };
        let whole = Filter {
            name: "lamp",
            exact: true,
        };
        assert!(selected("lamp_latches", None));
        assert!(selected("lamp_latches", Some(part)));
        assert!(!selected("pump", Some(part)));
        assert!(selected("Lamp", Some(whole)));
        assert!(!selected("lamp_latches", Some(whole)));
    }
}
