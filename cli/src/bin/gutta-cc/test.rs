//! `gutta-cc test [PATH...]` (docs/testing-programs.md): finds `.gtest` files (a
//! project's `tests/` by default), reads them and their programs, compiles each program
//! once, runs the files in parallel (tests of a file in order, each on a fresh VM),
//! prints one line per test in file order, the failures and a summary, and writes
//! JUnit XML and waveforms. Exit status: 0 all passed, 1 a test failed, 2 usage or file
//! errors (a test file or its program with errors: none of its tests runs). The
//! format, the run and the reports are gutta_gtest's; this file does the I/O.

use std::collections::{BTreeMap, HashMap};
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::mpsc;
use std::sync::Arc;
use std::time::{Duration, Instant};

use gutta_catalog::{choose_target, TargetInputs};
use gutta_cli::fatal::{Fatal, MessageFormat};
use gutta_cli::sources::read_source;
use gutta_compiler::diagnostics::json::to_json_lines;
use gutta_compiler::diagnostics::render::{render, RenderStyle};
use gutta_compiler::diagnostics::{Code, Diagnostic};
use gutta_compiler::source::{LineIndex, SourceFile, Span};
use gutta_compiler::{ExplicitTarget, ProgramSources};
use gutta_gtest::report::{self, FileResults, Style};
use gutta_gtest::{BuildError, Plan, ProgramUnderTest, RunOptions, TestResult, TestSource};
use gutta_io::Project;

use crate::args::Cli;

/// What `gutta-cc test` was asked.
#[derive(Debug, Clone)]
pub(crate) struct TestArgs {
    pub paths: Vec<PathBuf>,
    pub filter: Option<String>,
    /// `--exact`: the filter is a whole test name.
    pub exact: bool,
    pub junit: Option<PathBuf>,
    pub vcd: Option<PathBuf>,
    pub jobs: Option<usize>,
}

/// The program a test file tests, as a key: the same key compiles once.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
enum ProgramKey {
    /// A source file (canonical path), with the header's PLC type and options.
    File {
        path: PathBuf,
        plc: Option<String>,
        scale: bool,
        /// `OPTION s-area MB100`, as written.
        s_area: Option<String>,
    },
    /// A project (its gutta.toml), with the header's PLC type and options.
    Project {
        manifest: PathBuf,
        plc: Option<String>,
        scale: bool,
        /// `OPTION s-area MB100`, as written.
        s_area: Option<String>,
    },
}

/// A test file on its way: read, parsed, given its program and plan.
struct TestFileJob {
    /// The path as shown (as found, relative where it was given so).
    display: String,
    source: TestSource,
    /// Errors that stop the file, rendered, in the order found.
    errors: Vec<String>,
    error_json: Vec<String>,
    program: Option<Arc<ProgramUnderTest>>,
    plan: Option<Plan>,
}

/// The results of one file, with wall-clock durations.
struct FileOutcome {
    results: Vec<(TestResult, Duration)>,
    filtered: usize,
}

pub(crate) fn test(cli: &Cli, args: &TestArgs) -> Result<ExitCode, Fatal> {
    let started = Instant::now();
    let json = cli.message_format == MessageFormat::Json;
    let color = gutta_cli::color::use_color(cli.color, std::io::stdout().is_terminal());
    let err_color = gutta_cli::color::use_color(cli.color, std::io::stderr().is_terminal());
    let render_style = RenderStyle {
        color: err_color,
        unicode: err_color,
    };
    let files = find_files(cli.project.as_ref(), &args.paths)?;
    let command_line_target = cli.target.explicit()?;
    let mut jobs: Vec<TestFileJob> = files
        .iter()
        .map(|path| read_test_file(path, render_style))
        .collect::<Result<_, _>>()?;

    // Each distinct program compiles once.
    let mut programs: HashMap<ProgramKey, Result<Arc<ProgramUnderTest>, ProgramFailure>> =
        HashMap::new();
    for (job, path) in jobs.iter_mut().zip(&files) {
        if job.source.has_errors() {
            continue;
        }
        let key = match program_key(job, path, cli.project.as_ref()) {
            Ok(key) => key,
            Err(d) => {
                push_error(job, *d, render_style);
                continue;
            }
        };
        let program = programs.entry(key.clone()).or_insert_with(|| {
            build_program(&key, cli, command_line_target.as_ref(), render_style)
        });
        match program {
            Ok(p) => job.program = Some(Arc::clone(p)),
            Err(failure) => {
                let at = job
                    .source
                    .parsed
                    .header
                    .program
                    .as_ref()
                    .map_or(Span::new(0, 0), |(_, s)| *s);
                let d = Diagnostic::new(Code::TestProgramErrors, at, failure.headline.clone())
                    .help("fix the program first: `gutta-cc --check` shows the same errors");
                push_error(job, d, render_style);
                job.errors.push(failure.rendered.clone());
                job.error_json.push(failure.json.clone());
            }
        }
    }
    for job in &mut jobs {
        let Some(program) = &job.program else {
            continue;
        };
        if !job.errors.is_empty() {
            continue;
        }
        match gutta_gtest::plan(&job.source.file, &job.source.parsed, program) {
            Ok(plan) => job.plan = Some(plan),
            Err(diagnostics) => {
                for d in diagnostics {
                    push_error(job, d, render_style);
                }
            }
        }
    }

    // Warnings of the test files, then their errors, in file order.
    for job in &jobs {
        let plan_warnings = job.plan.as_ref().map_or(&[][..], |p| &p.warnings[..]);
        let warnings: Vec<Diagnostic> = job
            .source
            .diagnostics
            .iter()
            .filter(|d| !d.is_error())
            .chain(plan_warnings)
            .cloned()
            .collect();
        if json {
            let index = LineIndex::new(&job.source.file.text);
            print!("{}", to_json_lines(&job.source.file, &index, &warnings));
            for line in &job.error_json {
                print!("{line}");
            }
        } else {
            eprint!("{}", render(&job.source.file, &warnings, render_style));
            for e in &job.errors {
                eprint!("{e}");
            }
        }
    }

    let options = RunOptions {
        fast: true,
        record: args.vcd.is_some(),
        ..RunOptions::default()
    };
    let outcomes = run_files(&jobs, args, options, json, color);
    let mut passed = 0;
    let mut failed = 0;
    let mut filtered = 0;
    let file_errors = jobs.iter().filter(|j| !j.errors.is_empty()).count();
    let stdout = std::io::stdout();
    let mut failures = String::new();
    let mut failed_tests: Vec<(&str, &str)> = Vec::new();
    for (job, outcome) in jobs.iter().zip(&outcomes) {
        let Some(outcome) = outcome else { continue };
        filtered += outcome.filtered;
        for (result, _) in &outcome.results {
            if result.passed() {
                passed += 1;
            } else {
                failed += 1;
                failed_tests.push((&job.display, &result.name));
                if !failures.is_empty() {
                    failures.push('\n');
                }
                failures.push_str(&report::failure_detail(
                    &job.display,
                    &job.source.file,
                    result,
                ));
            }
        }
    }
    if json {
        let _ = writeln!(
            stdout.lock(),
            "{}",
            report::json_summary(passed, failed, jobs.len(), file_errors)
        );
    } else {
        let mut out = stdout.lock();
        if !failures.is_empty() {
            let _ = write!(out, "\nfailures:\n\n{failures}");
            let _ = write!(
                out,
                "\n{}",
                report::failed_list(&failed_tests, &rerun_flags(cli))
            );
        }
        let mut line = report::summary(passed, failed, jobs.len(), filtered);
        if file_errors > 0 {
            let s = if file_errors == 1 { "" } else { "s" };
            line.push_str(&format!("; {file_errors} file{s} with errors did not run"));
        }
        let _ = writeln!(out, "\n{line} in {:.2} s", started.elapsed().as_secs_f64());
    }
    if let Some(path) = &args.junit {
        let files: Vec<FileResults> = jobs
            .iter()
            .zip(&outcomes)
            .map(|(job, outcome)| FileResults {
                display: &job.display,
                file: &job.source.file,
                results: outcome.as_ref().map_or(&[][..], |o| &o.results),
                error: (!job.errors.is_empty()).then(|| strip_ansi(&job.errors.concat())),
            })
            .collect();
        let xml = report::junit(&files).map_err(|e| Fatal::io(format!("JUnit XML: {e}")))?;
        write_atomically(path, xml.as_bytes())?;
    }
    if let Some(dir) = &args.vcd {
        write_waveforms(dir, &jobs, &outcomes)?;
    }
    Ok(if file_errors > 0 {
        ExitCode::from(2)
    } else if failed > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

/// The flags of this run that a re-run of one test repeats: those that change what
/// the program compiles to (the PLC type, the target, the timer scaling).
fn rerun_flags(cli: &Cli) -> Vec<String> {
    let mut flags = Vec::new();
    if let Some(plc) = &cli.target.plc {
        flags.extend(["--plc".to_string(), plc.clone()]);
    }
    if let Some(dir) = &cli.target.target {
        flags.extend(["--target".to_string(), dir.display().to_string()]);
    }
    if cli.scale_timer_presets {
        flags.push("--scale-timer-presets".into());
    }
    if let Some(s_area) = &cli.s_area {
        flags.extend(["--s-area".to_string(), s_area.to_string()]);
    }
    flags
}

/// A program that cannot be tested: the headline of E0808 and its own diagnostics.
#[derive(Debug, Clone)]
struct ProgramFailure {
    headline: String,
    rendered: String,
    json: String,
}

fn push_error(job: &mut TestFileJob, d: Diagnostic, style: RenderStyle) {
    let file = &job.source.file;
    let index = LineIndex::new(&file.text);
    job.errors
        .push(render(file, std::slice::from_ref(&d), style));
    job.error_json
        .push(to_json_lines(file, &index, std::slice::from_ref(&d)));
}

/// The `.gtest` files of the paths (a folder: every one below it, sorted), or of the
/// project's `tests/` folder.
fn find_files(project: Option<&Project>, paths: &[PathBuf]) -> Result<Vec<PathBuf>, Fatal> {
    let roots: Vec<PathBuf> = if paths.is_empty() {
        let Some(project) = project else {
            return Err(Fatal::usage(
                "no test files given, and no project (gutta.toml) here to take tests/ from",
            )
            .with_hint(
                "run `gutta-cc test FILE.gtest` or `gutta-cc test DIR`, or run it inside a project",
            ));
        };
        let tests = project.root.join("tests");
        if !tests.is_dir() {
            return Err(Fatal::usage(format!(
                "the project has no tests folder ({}): put .gtest files there (docs/testing-programs.md)",
                crate::project::shown(&tests).display()
            )));
        }
        vec![crate::project::shown(&tests)]
    } else {
        paths.to_vec()
    };
    let mut files = Vec::new();
    for root in &roots {
        if root.is_dir() {
            let before = files.len();
            collect(root, &mut files)?;
            files[before..].sort();
        } else if root.is_file() {
            files.push(root.clone());
        } else {
            return Err(Fatal::io(format!(
                "{}: no such file or folder",
                root.display()
            )));
        }
    }
    if files.is_empty() {
        let shown: Vec<String> = roots.iter().map(|r| r.display().to_string()).collect();
        return Err(Fatal::usage(format!(
            "no .gtest files in {}",
            shown.join(", ")
        )));
    }
    Ok(files)
}

fn collect(dir: &Path, files: &mut Vec<PathBuf>) -> Result<(), Fatal> {
    let entries = std::fs::read_dir(dir)
        .map_err(|e| Fatal::io(format!("cannot read {}: {e}", dir.display())))?;
    let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    for path in paths {
        if path.is_dir() {
            collect(&path, files)?;
        } else if path
            .extension()
            .is_some_and(|x| x.eq_ignore_ascii_case("gtest"))
        {
            files.push(path);
        }
    }
    Ok(())
}

fn read_test_file(path: &Path, style: RenderStyle) -> Result<TestFileJob, Fatal> {
    let display = path.display().to_string();
    let bytes =
        std::fs::read(path).map_err(|e| Fatal::io(format!("cannot read {display}: {e}")))?;
    let file = SourceFile::from_bytes(&display, bytes).map_err(|e| {
        Fatal::io(format!(
            "{display} is not UTF-8 text (invalid byte at offset {})",
            e.offset
        ))
    })?;
    let source = TestSource::parse(file);
    let errors: Vec<Diagnostic> = source
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .cloned()
        .collect();
    let index = LineIndex::new(&source.file.text);
    let rendered = if errors.is_empty() {
        Vec::new()
    } else {
        vec![render(&source.file, &errors, style)]
    };
    let json = if errors.is_empty() {
        Vec::new()
    } else {
        vec![to_json_lines(&source.file, &index, &errors)]
    };
    Ok(TestFileJob {
        display,
        source,
        errors: rendered,
        error_json: json,
        program: None,
        plan: None,
    })
}

/// Which program a file tests: `PROGRAM path` (a source file, or a project folder or
/// its gutta.toml), else the project around the test file.
fn program_key(
    job: &TestFileJob,
    path: &Path,
    project: Option<&Project>,
) -> Result<ProgramKey, Box<Diagnostic>> {
    let header = &job.source.parsed.header;
    let plc = header.plc_type.as_ref().map(|(p, _)| p.clone());
    let scale = job.source.compile_options().scale_timer_presets;
    let s_area = header.s_area.as_ref().map(|(v, _)| v.clone());
    let Some((program, span)) = &header.program else {
        let around = path
            .parent()
            .and_then(|dir| Project::find(dir).ok().flatten())
            .or_else(|| project.cloned());
        return match around {
            Some(p) => Ok(ProgramKey::Project {
                manifest: p.manifest,
                plc,
                scale,
                s_area,
            }),
            None => Err(Box::new(Diagnostic::new(
                Code::TestProgramMissing,
                Span::new(0, 0),
                "this test file names no PROGRAM and is not inside a project",
            )
            .help("add `PROGRAM path/to/main.lad` (relative to this file), or put the file in a project's tests/ folder"))),
        };
    };
    let base = path.parent().unwrap_or(Path::new("."));
    let full = base.join(program);
    let missing = |why: String| {
        Box::new(
            Diagnostic::new(
                Code::TestProgramMissing,
                *span,
                format!("cannot read the program `{program}`: {why}"),
            )
            .help(format!(
                "the path is relative to this file: {}",
                full.display()
            )),
        )
    };
    let manifest = if full.is_dir() {
        Some(full.join(gutta_io::MANIFEST))
    } else if full.file_name().is_some_and(|n| n == gutta_io::MANIFEST) {
        Some(full.clone())
    } else {
        None
    };
    if let Some(manifest) = manifest {
        if !manifest.is_file() {
            return Err(missing(format!(
                "{} has no {}",
                full.display(),
                gutta_io::MANIFEST
            )));
        }
        let manifest = manifest
            .canonicalize()
            .map_err(|e| missing(e.to_string()))?;
        return Ok(ProgramKey::Project {
            manifest,
            plc,
            scale,
            s_area,
        });
    }
    let canonical = full.canonicalize().map_err(|e| missing(e.to_string()))?;
    if !canonical.is_file() {
        return Err(missing("it is not a file".into()));
    }
    Ok(ProgramKey::File {
        path: canonical,
        plc,
        scale,
        s_area,
    })
}

/// Compile the program of `key`.
fn build_program(
    key: &ProgramKey,
    cli: &Cli,
    command_line: Option<&ExplicitTarget>,
    style: RenderStyle,
) -> Result<Arc<ProgramUnderTest>, ProgramFailure> {
    let fail = |headline: String| ProgramFailure {
        headline,
        rendered: String::new(),
        json: String::new(),
    };
    let mut notes = Vec::new();
    let (mut sources, plc, scale, project_target, s_area) = match key {
        ProgramKey::File {
            path,
            plc,
            scale,
            s_area,
        } => {
            let source =
                read_source(path, false, &mut notes).map_err(|e| fail(e.message.clone()))?;
            (
                ProgramSources::single(source),
                plc,
                *scale,
                None,
                s_area.clone(),
            )
        }
        ProgramKey::Project {
            manifest,
            plc,
            scale,
            s_area,
        } => {
            let project = Project::load(manifest).map_err(fail)?;
            let mut sources = ProgramSources::default();
            for p in &project.sources {
                sources
                    .sources
                    .push(read_source(p, false, &mut notes).map_err(|e| fail(e.message.clone()))?);
            }
            for p in &project.symbols {
                sources
                    .symbol_tables
                    .push(read_source(p, true, &mut notes).map_err(|e| fail(e.message.clone()))?);
            }
            let scale = *scale || project.scale_timer_presets;
            let s_area = s_area.clone().or(project.s_area);
            (sources, plc, scale, Some(project.plc), s_area)
        }
    };
    // A test's program read in another code page says so, as `gutta-cc` does.
    gutta_cli::notes::print(&notes, cli.message_format, gutta_cli::notes::JsonTo::Stdout);
    sources.options.scale_timer_presets = scale || cli.scale_timer_presets;
    sources.options.s_area = match (cli.s_area.clone(), s_area) {
        (Some(chosen), _) => Some(chosen),
        (None, Some(text)) => Some(text.parse().map_err(fail)?),
        (None, None) => None,
    };
    // The target, by the one rule: the command line's (loaded once, above), the test
    // file's PLC_TYPE, the project's, else the program's own PLC_TYPE or the default.
    let project_target = project_target.and_then(|t| t.spec());
    let inputs = TargetInputs {
        test_file: plc.as_deref(),
        project: project_target.as_ref(),
        ..cli.target.inputs()
    };
    let own = match choose_target(&inputs).named() {
        Some(chosen) if !chosen.origin.is_command_line() => {
            Some(gutta_cli::target::load_explicit(&chosen).map_err(|e| fail(e.message.clone()))?)
        }
        _ => None,
    };
    let explicit = own.as_ref().or(command_line);
    let name = match sources.sources.len() {
        1 => sources.sources[0].name.clone(),
        n => gutta_cli::plural::count(n, "file"),
    };
    match ProgramUnderTest::build(sources, explicit) {
        Ok(p) => Ok(Arc::new(p)),
        Err(BuildError::Compile(checked)) => {
            let errors: Vec<Diagnostic> = checked
                .diagnostics()
                .iter()
                .filter(|d| d.is_error())
                .cloned()
                .collect();
            let n = errors.len();
            Err(ProgramFailure {
                headline: format!(
                    "the program under test, {name}, does not compile ({n} error{})",
                    if n == 1 { "" } else { "s" }
                ),
                rendered: render(&checked.file, &errors, style),
                json: to_json_lines(&checked.file, &checked.index, &errors),
            })
        }
        Err(BuildError::Verify(e)) => Err(fail(format!(
            "the image of {name} does not verify (a compiler defect, please report it): {e}"
        ))),
    }
}

/// Run every runnable file, `jobs` threads at a time; print each file's lines in file
/// order as soon as it and the files before it are done.
fn run_files(
    jobs: &[TestFileJob],
    args: &TestArgs,
    options: RunOptions,
    json: bool,
    color: bool,
) -> Vec<Option<FileOutcome>> {
    let threads = args
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .clamp(1, jobs.len().max(1));
    let next = std::sync::atomic::AtomicUsize::new(0);
    let (send, receive) = mpsc::channel::<(usize, Option<FileOutcome>)>();
    let filter = args.filter.as_deref().map(|name| gutta_gtest::Filter {
        name,
        exact: args.exact,
    });
    let mut outcomes: Vec<Option<FileOutcome>> = (0..jobs.len()).map(|_| None).collect();
    std::thread::scope(|scope| {
        for _ in 0..threads {
            let send = send.clone();
            let next = &next;
            scope.spawn(move || loop {
                let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some(job) = jobs.get(i) else { break };
                let outcome = run_file(job, filter, options);
                if send.send((i, outcome)).is_err() {
                    break;
                }
            });
        }
        drop(send);
        let mut pending: BTreeMap<usize, Option<FileOutcome>> = BTreeMap::new();
        let mut printed = 0;
        let style = Style { color };
        for (i, outcome) in receive {
            pending.insert(i, outcome);
            while let Some(outcome) = pending.remove(&printed) {
                print_file(&jobs[printed], outcome.as_ref(), json, style);
                outcomes[printed] = outcome;
                printed += 1;
            }
        }
    });
    outcomes
}

fn run_file(
    job: &TestFileJob,
    filter: Option<gutta_gtest::Filter>,
    options: RunOptions,
) -> Option<FileOutcome> {
    let (Some(program), Some(plan)) = (&job.program, &job.plan) else {
        return None;
    };
    if !job.errors.is_empty() {
        return None;
    }
    let mut results = Vec::new();
    let mut filtered = 0;
    for test in &plan.tests {
        if !gutta_gtest::selected(&test.name, filter) {
            filtered += 1;
            continue;
        }
        let started = Instant::now();
        let result = gutta_gtest::run_test(program, plan, test, options);
        results.push((result, started.elapsed()));
    }
    Some(FileOutcome { results, filtered })
}

fn print_file(job: &TestFileJob, outcome: Option<&FileOutcome>, json: bool, style: Style) {
    let Some(outcome) = outcome else { return };
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    for (result, duration) in &outcome.results {
        let line = if json {
            report::json_test(&job.display, &job.source.file, result, *duration).to_string()
        } else {
            report::test_line(&job.display, result, style)
        };
        // A closed pipe (`| head`) is not an error of the tests.
        let _ = writeln!(out, "{line}");
    }
}

/// `DIR/<file stem>.<test>.vcd` for every failing test.
fn write_waveforms(
    dir: &Path,
    jobs: &[TestFileJob],
    outcomes: &[Option<FileOutcome>],
) -> Result<(), Fatal> {
    std::fs::create_dir_all(dir)
        .map_err(|e| Fatal::io(format!("cannot create {}: {e}", dir.display())))?;
    for (job, outcome) in jobs.iter().zip(outcomes) {
        let (Some(outcome), Some(plan)) = (outcome, &job.plan) else {
            continue;
        };
        let stem = Path::new(&job.display)
            .file_stem()
            .map_or_else(|| "test".into(), |s| s.to_string_lossy().into_owned());
        for (result, _) in outcome.results.iter().filter(|(r, _)| !r.passed()) {
            let Some(test) = plan.tests.iter().find(|t| t.name == result.name) else {
                continue;
            };
            if let Some(text) = report::vcd(test, result) {
                let path = dir.join(format!("{stem}.{}.vcd", result.name));
                write_atomically(&path, text.as_bytes())?;
            }
        }
    }
    Ok(())
}

/// The file written atomically (`gutta_io::write_file_atomically`), a failure as I/O.
fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), Fatal> {
    gutta_io::write_file_atomically(path, bytes)
        .map_err(|e| Fatal::io(format!("cannot write {}: {e}", path.display())))
}

/// The text without terminal colour codes (for JUnit XML).
fn strip_ansi(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut chars = text.chars();
    while let Some(c) = chars.next() {
        if c == '\x1b' {
            for d in chars.by_ref() {
                if d.is_ascii_alphabetic() {
                    break;
                }
            }
        } else {
            out.push(c);
        }
    }
    out
}
