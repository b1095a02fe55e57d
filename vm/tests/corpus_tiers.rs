//! The corpora through the three engines, compared with each other rather than with
//! expectations: every program of the VM corpus (tests/data/run, with its test file's
//! PLC type, scan time and options), every Micro/WIN export of tests/data/microwin that
//! compiles as published (each file alone, and split_program/ as one program) and every
//! example (examples/*.lad), loaded with the generic semantics (`fast` off), the
//! interpreter (`native_after: None`) and compiled at load (`Some(0)`), run for
//! `SCANS` scans with inputs (every I byte and AI word) that change every few scans. The
//! outcome, the instruction count, the fault's position and all memory (hidden state
//! included) must agree after every scan; a fault ends the program's run (all three
//! fault alike). gtest/tests/run_corpus.rs checks the same corpus against its
//! expectations on each engine alone.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

mod common;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use gutta_catalog::{stdlib, AreaKind};
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile_program, CompileOptions, ExplicitTarget, ProgramSources};
use gutta_format::VerifiedImage;
use gutta_vm::{TierState, Vm, VmConfig};

/// Scans per program: the timers of the corpus (up to a few seconds at 10 ms) finish.
const SCANS: u32 = 400;

/// Fewer programs than this means a corpus went missing, not that it passed.
const MIN_PROGRAMS: usize = 120;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn read(path: &Path) -> SourceFile {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let name = path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into());
    SourceFile::from_code_page_bytes(name, bytes).0
}

/// A program to run three ways.
struct Program {
    name: String,
    image: VerifiedImage,
    target: Arc<gutta_catalog::Target>,
    scan_ms: u32,
}

/// Compile and verify; None (with the reason in `refused`) when it does not compile.
fn build(
    name: String,
    sources: ProgramSources,
    plc: Option<&str>,
    scan_ms: u32,
    refused: &mut Vec<String>,
) -> Option<Program> {
    let explicit = plc.map(|p| ExplicitTarget {
        target: stdlib::shared(p).expect("the PLC type"),
        origin: "test".into(),
    });
    let c = compile_program(sources, explicit.as_ref());
    let Some(image) = c.image else {
        refused.push(name);
        return None;
    };
    let target = Arc::clone(&c.checked.target);
    let image = gutta_format::verify(&image, &target)
        .unwrap_or_else(|e| panic!("{name}: compiles but does not verify: {e}"));
    Some(Program {
        name,
        image,
        target,
        scan_ms,
    })
}

fn single(file: SourceFile, options: CompileOptions) -> ProgramSources {
    let mut sources = ProgramSources::single(file);
    sources.options = options;
    sources
}

/// The VM corpus: each test file's program with the header's PLC type, scan time and
/// compile options. Every one must compile.
fn run_corpus(programs: &mut Vec<Program>) {
    let dir = root().join("tests/data/run");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("tests/data/run")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "gtest"))
        .collect();
    files.sort();
    for path in files {
        let text = std::fs::read_to_string(&path).expect("a test file");
        let (mut program, mut plc, mut scan_ms) = (None, None, 10);
        let mut options = CompileOptions::default();
        for line in text.lines().take_while(|l| !l.starts_with("TEST")) {
            let words: Vec<&str> = line.split_whitespace().collect();
            match words.as_slice() {
                ["PROGRAM", p, ..] => program = Some(dir.join(p)),
                ["PLC_TYPE", t, ..] => plc = Some(t.to_string()),
                ["SCAN_TIME", t, ..] => {
                    scan_ms = t.trim_end_matches("ms").parse().expect("SCAN_TIME Nms");
                }
                ["OPTION", "scale-timer-presets", ..] => options.scale_timer_presets = true,
                ["OPTION", "s-area", at, ..] => options.s_area = Some(at.parse().expect("s-area")),
                _ => {}
            }
        }
        let program = program.unwrap_or_else(|| panic!("{}: no PROGRAM", path.display()));
        let name = format!(
            "run/{}",
            program.file_name().expect("a file name").to_string_lossy()
        );
        let mut refused = Vec::new();
        let built = build(
            name,
            single(read(&program), options),
            plc.as_deref(),
            scan_ms,
            &mut refused,
        );
        assert!(refused.is_empty(), "the VM corpus compiles: {refused:?}");
        programs.extend(built);
    }
}

/// The Micro/WIN corpus as published (what compiles) and the examples.
fn microwin_and_examples(programs: &mut Vec<Program>) {
    let mut refused = Vec::new();
    for (dir, exts) in [
        ("tests/data/microwin", &["awl", "lad"][..]),
        ("examples", &["lad"][..]),
    ] {
        let mut files: Vec<PathBuf> = std::fs::read_dir(root().join(dir))
            .expect("a corpus")
            .map(|e| e.expect("entry").path())
            .filter(|p| p.extension().is_some_and(|x| exts.iter().any(|e| x == *e)))
            .collect();
        files.sort();
        for path in files {
            let name = format!(
                "{dir}/{}",
                path.file_name().expect("a file name").to_string_lossy()
            );
            let sources = single(read(&path), CompileOptions::default());
            programs.extend(build(name, sources, None, 10, &mut refused));
        }
    }
    let split = root().join("tests/data/microwin/split_program");
    let sources = ProgramSources {
        sources: ["MAIN.awl", "SBR_0.awl", "INT_0.awl"]
            .map(|f| read(&split.join(f)))
            .to_vec(),
        symbol_tables: ["symbols.csv", "symbols_gbk.txt"]
            .map(|f| read(&split.join(f)))
            .to_vec(),
        options: CompileOptions::default(),
    };
    programs.extend(build(
        "split_program/".into(),
        sources,
        None,
        10,
        &mut refused,
    ));
    // The corpus holds exports that do not compile on purpose (their diagnostics are
    // its point); the examples all compile.
    assert!(
        refused.iter().all(|n| !n.starts_with("examples")),
        "{refused:?}"
    );
}

/// The input bytes of a scan: a simple generator, each value held 1..8 scans.
struct Inputs {
    state: u32,
    held: u32,
    values: Vec<u8>,
}

impl Inputs {
    fn next(&mut self, n: usize) -> &[u8] {
        if self.held == 0 || self.values.len() != n {
            self.values = (0..n)
                .map(|_| {
                    self.state = self.state.wrapping_mul(1_103_515_245).wrapping_add(12_345);
                    (self.state >> 16) as u8
                })
                .collect();
            self.held = 1 + (self.state >> 8) % 8;
        }
        self.held -= 1;
        &self.values
    }
}

/// Run `p` three ways; the first scan where they differ, as a message.
fn disagreement(p: &Program) -> Option<String> {
    let base = VmConfig {
        scan_ms: p.scan_ms,
        ..VmConfig::default()
    };
    let mut vms: Vec<Vm> = common::three_engines(base)
        .into_iter()
        .map(|c| Vm::new(p.image.clone(), Arc::clone(&p.target), c).expect("loads"))
        .collect();
    assert!(
        !matches!(vms[2].tier(), TierState::Refused(_)),
        "{}: {:?}",
        p.name,
        vms[2].tier()
    );
    let memory = &p.target.memory;
    let inputs: Vec<_> = memory
        .areas
        .iter()
        .filter(|a| matches!(a.kind, AreaKind::DigitalInput | AreaKind::AnalogInput))
        .flat_map(|a| {
            let name = a.name.clone();
            (0..a.size).map(move |k| format!("{name}B{k}"))
        })
        .filter_map(|v| memory.parse_address(&v).ok())
        .collect();
    let mut stimulus = Inputs {
        state: p.name.len() as u32,
        held: 0,
        values: Vec::new(),
    };
    for scan in 0..SCANS {
        let values = stimulus.next(inputs.len()).to_vec();
        let mut outcomes = Vec::new();
        for vm in &mut vms {
            for (a, v) in inputs.iter().zip(&values) {
                vm.write(*a, u32::from(*v)).expect("an input");
            }
            outcomes.push((vm.run_scan(), vm.executed_last_scan(), vm.fault_position()));
        }
        for k in 1..3 {
            if outcomes[k] != outcomes[0] {
                return Some(format!(
                    "{}: scan {scan}: engine {k} {:?}, generic {:?}",
                    p.name, outcomes[k], outcomes[0]
                ));
            }
            if vms[k].memory() != vms[0].memory() {
                return Some(format!("{}: scan {scan}: engine {k}: memory", p.name));
            }
        }
        if outcomes[0].0.is_err() {
            break;
        }
    }
    None
}

#[test]
fn every_corpus_program_runs_alike_on_the_three_engines() {
    let mut programs = Vec::new();
    run_corpus(&mut programs);
    microwin_and_examples(&mut programs);
    assert!(
        programs.len() >= MIN_PROGRAMS,
        "only {} programs",
        programs.len()
    );
    let failures: Vec<String> = programs.iter().filter_map(disagreement).collect();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
