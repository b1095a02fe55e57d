//! Issue 31's benchmark: the VM on programs shaped like real ones, per tier, all from one
//! run. The programs: every Micro/WIN export of the corpus that compiles and runs
//! (tests/data/microwin, each file alone, and split_program/ as one program),
//! every example (examples/*.lad, no port attached; tank.lad started, the AN2002 master
//! polling, blink latched),
//! the conveyor plant of gutta-bench-native (40 stations of every family) and its mixing
//! station (20 tanks: an SCR sequence, TONR, TOF, CTUD, conversions), whose native Rust
//! transcriptions (checked against the VM by bench-native/tests/agree.rs) are the limit. Per program: instructions per scan, ns per executed instruction
//! interpreted (`native_after` None) and compiled at load (`Some(0)`), the speed-up,
//! native ns per instruction and compiled / native, the compiled regions and the share
//! of executed instructions they ran (`Vm::executed_natively`, over as many scans as the
//! warm-up), and per tier what a scan costs beyond the fixed cost per instruction; the
//! fixed cost of a scan (an empty MAIN through `Vm::scan`, measured first); and a summary,
//! one line per bar of issue 31 with the program that decides it (a per-instruction bar
//! with the whole scan counted over the programs where it can hold: `reachable`). Each VM runs 1,000 warm-up scans, then batches of
//! about 2 ms of scans, timed one after the other per program (interpreted, compiled,
//! native); figures are medians of the batches, instructions counted in the timed scans.
//! `cargo bench -p gutta-vm --bench real_programs` (`-- fixed`: the fixed cost alone,
//! e.g. under callgrind; `-- NAME`: only the programs whose name contains NAME); `cargo test --benches` (no `--bench`) runs every program a few
//! scans only.

#![allow(
    clippy::disallowed_methods,
    clippy::disallowed_types,
    clippy::disallowed_macros,
    reason = "a benchmark is a program: it reads the corpus, times and prints"
)]

use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use gutta_bench_native::Plant;
use gutta_catalog::{stdlib, Target};
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, compile_program, Compiled, ExplicitTarget, ProgramSources};
use gutta_format::VerifiedImage;
use gutta_vm::{TierState, Vm, VmConfig};

/// The conveyor plant's target (the one bench-native's memory sizes follow).
const PLANT_TARGET: &str = "EC30-EKSTM32-XC";

/// A MAIN without instructions: what a scan costs around the program.
const EMPTY_MAIN: &str = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nEND_ORGANIZATION_BLOCK\n";

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// How much to measure.
#[derive(Debug, Clone, Copy)]
struct Effort {
    warm_up: usize,
    batches: usize,
    /// Nanoseconds a batch should last (its scans are chosen from the warm-up).
    batch_ns: f64,
}

/// A program to run: its verified image, target, and the inputs to set before scanning.
struct Program {
    name: String,
    image: VerifiedImage,
    target: Arc<Target>,
    inputs: Vec<(&'static str, u32)>,
}

fn verified(name: &str, c: Compiled) -> Option<(VerifiedImage, Arc<Target>)> {
    let image = c.image?;
    let target = Arc::clone(&c.checked.target);
    match gutta_format::verify(&image, &target) {
        Ok(v) => Some((v, target)),
        Err(e) => {
            eprintln!("{name}: does not verify: {e}");
            None
        }
    }
}

fn read(path: &Path) -> SourceFile {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let name = path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into());
    SourceFile::from_code_page_bytes(name, bytes).0
}

/// The corpus's programs that compile, as published.
fn corpus() -> Vec<Program> {
    let dir = root().join("tests/data/microwin");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("the corpus")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "awl" || x == "lad"))
        .collect();
    files.sort();
    let mut programs: Vec<Program> = files
        .iter()
        .filter_map(|p| {
            let name = p.file_name()?.to_string_lossy().into_owned();
            let (image, target) = verified(&name, compile(read(p), None))?;
            Some(Program {
                name,
                image,
                target,
                inputs: Vec::new(),
            })
        })
        .collect();
    let split = dir.join("split_program");
    let sources = ProgramSources {
        sources: ["MAIN.awl", "SBR_0.awl", "INT_0.awl"]
            .map(|f| read(&split.join(f)))
            .to_vec(),
        symbol_tables: ["symbols.csv", "symbols_gbk.txt"]
            .map(|f| read(&split.join(f)))
            .to_vec(),
        options: Default::default(),
    };
    if let Some((image, target)) = verified("split_program/", compile_program(sources, None)) {
        programs.push(Program {
            name: "split_program/".into(),
            image,
            target,
            inputs: Vec::new(),
        });
    }
    programs
}

fn lad(name: &str, text: &str, target: Option<&str>, inputs: Vec<(&'static str, u32)>) -> Program {
    let explicit = target.map(|t| ExplicitTarget {
        target: stdlib::shared(t).expect("target"),
        origin: "bench".into(),
    });
    let c = compile(SourceFile::new(name, text), explicit.as_ref());
    let (image, target) = verified(name, c).unwrap_or_else(|| panic!("{name} compiles"));
    Program {
        name: name.into(),
        image,
        target,
        inputs,
    }
}

/// The inputs an example is timed with: those that put it to work (tank.lad's pump
/// started, the AN2002 master polling, blink latched); the others run as loaded.
const EXAMPLE_INPUTS: &[(&str, &[(&str, u32)])] = &[
    ("tank.lad", &[("I0.0", 1)]),
    ("an2002_sample3_master.lad", &[("I0.1", 1)]),
    ("blink.lad", &[("I0.0", 1)]),
];

/// Every example program (examples/*.lad), on the PLC type it names or the default,
/// no port attached.
fn examples() -> Vec<Program> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(root().join("examples"))
        .expect("the examples")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "lad"))
        .collect();
    files.sort();
    files
        .iter()
        .map(|p| {
            let name = p
                .file_name()
                .expect("a file")
                .to_string_lossy()
                .into_owned();
            let text = std::fs::read_to_string(p).expect("example");
            let inputs = EXAMPLE_INPUTS
                .iter()
                .find(|(n, _)| *n == name)
                .map_or_else(Vec::new, |(_, i)| i.to_vec());
            lad(&name, &text, None, inputs)
        })
        .collect()
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Tier {
    Interpreted,
    Compiled,
}

fn load(p: &Program, tier: Tier) -> Vm {
    let config = VmConfig {
        native_after: match tier {
            Tier::Interpreted => None,
            Tier::Compiled => Some(0),
        },
        ..VmConfig::default()
    };
    let mut vm = Vm::new(p.image.clone(), Arc::clone(&p.target), config).expect("loads");
    for (var, value) in &p.inputs {
        let a = p.target.memory.parse_address(var).expect("address");
        vm.write(a, *value).expect("write");
    }
    vm
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// Something to time: a scan, returning the instructions it executed.
trait Scanner {
    fn scan(&mut self) -> u64;
}

impl Scanner for Vm {
    #[inline]
    fn scan(&mut self) -> u64 {
        Vm::scan(self).expect("the program runs without a fault");
        self.executed_last_scan()
    }
}

/// A native transcription (the conveyor plant's or the mixing station's scan); it
/// counts the instructions the VM counted per scan.
struct Native {
    plant: Plant,
    run: fn(&mut Plant),
    per_scan: u64,
}

impl Scanner for Native {
    #[inline]
    fn scan(&mut self) -> u64 {
        (self.run)(black_box(&mut self.plant));
        self.per_scan
    }
}

/// The native transcription of a program of the benchmark, if it has one.
fn transcription(name: &str) -> Option<fn(&mut Plant)> {
    if name.starts_with("conveyor") {
        Some(gutta_bench_native::conveyor_scan)
    } else if name.starts_with("mixing") {
        Some(gutta_bench_native::mixing_scan)
    } else {
        None
    }
}

/// Warm up, then time: ns per scan and instructions per scan of each batch.
fn warm(effort: Effort, s: &mut impl Scanner) -> usize {
    let t = Instant::now();
    for _ in 0..effort.warm_up {
        s.scan();
    }
    let per_scan = t.elapsed().as_secs_f64() * 1e9 / effort.warm_up.max(1) as f64;
    ((effort.batch_ns / per_scan.max(1.0)) as usize).clamp(1, 1_000_000)
}

/// One batch: (ns per scan, instructions per scan).
fn batch(scans: usize, s: &mut impl Scanner) -> (f64, f64) {
    let mut instructions = 0;
    let t = Instant::now();
    for _ in 0..scans {
        instructions += s.scan();
    }
    let ns = t.elapsed().as_secs_f64() * 1e9;
    (ns / scans as f64, instructions as f64 / scans as f64)
}

/// Median ns per scan and per instruction of the batches of several scanners timed in
/// turn (one batch each, then the next round), so they see the same machine.
fn measure(
    effort: Effort,
    scanners: &mut [&mut dyn FnMut(usize) -> (f64, f64)],
    scans: &[usize],
) -> Vec<(f64, f64)> {
    let mut per = vec![(Vec::new(), Vec::new()); scanners.len()];
    for _ in 0..effort.batches {
        for (k, s) in scanners.iter_mut().enumerate() {
            let (ns, instr) = s(scans[k]);
            per[k].0.push(ns);
            per[k].1.push(ns / instr.max(1e-9));
        }
    }
    per.into_iter()
        .map(|(a, b)| (median(a), median(b)))
        .collect()
}

fn main() {
    let bench = std::env::args().any(|a| a == "--bench");
    let effort = if bench {
        Effort {
            warm_up: 1000,
            batches: 31,
            batch_ns: 2e6,
        }
    } else {
        Effort {
            warm_up: 3,
            batches: 1,
            batch_ns: 1.0,
        }
    };
    if std::env::args().any(|a| a == "fixed") {
        let _ = fixed_cost(effort, bench);
        return;
    }
    let mut programs = corpus();
    programs.extend(examples());
    let conveyor = lad(
        "conveyor (40 stations)",
        gutta_bench_native::CONVEYOR,
        Some(PLANT_TARGET),
        plant_inputs(),
    );
    programs.push(conveyor);
    programs.push(lad(
        "mixing station (20 tanks)",
        gutta_bench_native::MIXING,
        Some(PLANT_TARGET),
        mixing_inputs(),
    ));
    let names: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    programs.retain(|p| names.is_empty() || names.iter().any(|n| p.name.contains(n.as_str())));
    let fixed = fixed_cost(effort, bench);

    println!(
        "\nReal programs (issue 31): ns per executed instruction per tier, median of {} \
         batches of ~{:.0} us after {} warm-up scans",
        effort.batches,
        effort.batch_ns / 1e3,
        effort.warm_up
    );
    println!(
        "{:<34} {:>10} {:>8} {:>8} {:>9} {:>8} {:>8} {:>10} {:>10} {:>7} {:>8} {:>14} {:>6}",
        "program",
        "instr/scan",
        "interp",
        "compiled",
        "interp/cc",
        "native",
        "cc/nat",
        "interp ns/scan",
        "cc ns/scan",
        "regions",
        "native%",
        "beyond: interp",
        "cc"
    );
    let mut rows = Vec::new();
    for p in &programs {
        let mut interpreted = load(p, Tier::Interpreted);
        let mut compiled = load(p, Tier::Compiled);
        let compiled_state = compiled.tier().clone();
        let s_i = warm(effort, &mut interpreted);
        let s_c = warm(effort, &mut compiled);
        let native_share = native_share(&mut compiled, effort.warm_up.max(1));
        let per_scan = interpreted.executed_last_scan();
        if per_scan == 0 {
            println!("{:<34} runs no instruction per scan: skipped", p.name);
            continue;
        }
        let run = transcription(&p.name);
        let is_plant = run.is_some();
        let mut native = Native {
            plant: Plant::new(VmConfig::default().scan_ms),
            run: run.unwrap_or(gutta_bench_native::conveyor_scan),
            per_scan,
        };
        if is_plant {
            for (var, value) in &p.inputs {
                let a = p.target.memory.parse_address(var).expect("address");
                native.plant.mem.i[a.offset as usize] = *value as u8;
            }
        }
        let s_n = if is_plant {
            warm(effort, &mut native)
        } else {
            1
        };
        let mut run_i = |n: usize| batch(n, &mut interpreted);
        let mut run_c = |n: usize| batch(n, &mut compiled);
        let mut run_n = |n: usize| batch(n, &mut native);
        let figures = if is_plant {
            measure(
                effort,
                &mut [&mut run_i, &mut run_c, &mut run_n],
                &[s_i, s_c, s_n],
            )
        } else {
            measure(effort, &mut [&mut run_i, &mut run_c], &[s_i, s_c])
        };
        let (i_scan, i_instr) = figures[0];
        let beyond = |scan: f64| (scan - fixed).max(0.0) / per_scan as f64;
        let (c_scan, c_instr) = figures[1];
        let (regions, compiled_note) = match compiled_state {
            TierState::Compiled { regions, .. } => (regions.to_string(), String::new()),
            TierState::NothingToCompile => ("0".into(), String::new()),
            other => ("-".into(), format!("   ({other:?})")),
        };
        let (native_col, ratio_col) = match figures.get(2) {
            Some(&(_, n_instr)) => (
                format!("{n_instr:.3}"),
                format!("{:.1}x", c_instr / n_instr),
            ),
            None => ("-".into(), "-".into()),
        };
        println!(
            "{:<34} {:>10} {:>8.2} {:>8.2} {:>8.2}x {:>8} {:>8} {:>10.0} {:>10.0} {:>7} {:>7.1}% {:>14.2} {:>6.2}{compiled_note}",
            p.name,
            per_scan,
            i_instr,
            c_instr,
            i_instr / c_instr,
            native_col,
            ratio_col,
            i_scan,
            c_scan,
            regions,
            native_share * 100.0,
            beyond(i_scan),
            beyond(c_scan),
        );
        rows.push(Row {
            name: p.name.clone(),
            per_scan,
            interpreted: i_instr,
            compiled: c_instr,
            native: figures.get(2).map(|f| f.1),
            interpreted_beyond: beyond(i_scan),
            compiled_beyond: beyond(c_scan),
        });
    }
    summary(&rows, fixed);
}

/// Issue 31's bars: ns per instruction compiled and interpreted, ns of fixed cost.
const COMPILED_BAR: f64 = 2.0;
const INTERPRETED_BAR: f64 = 8.0;
const FIXED_BAR: f64 = 30.0;

/// The fewest instructions per scan for which a per-instruction bar can hold with the
/// whole scan counted while the fixed cost is at its bar: a scan of n instructions
/// costs at least the fixed cost, so n * bar >= FIXED_BAR (15 compiled, 4 interpreted).
fn reachable(bar: f64) -> u64 {
    (FIXED_BAR / bar).ceil() as u64
}

/// One program's figures, for the summary.
struct Row {
    name: String,
    per_scan: u64,
    /// ns per instruction interpreted, compiled, native (the transcription, if any).
    interpreted: f64,
    compiled: f64,
    native: Option<f64>,
    /// ns per instruction of what a scan costs beyond the fixed cost (an empty MAIN's
    /// scan, measured in the same run), interpreted and compiled.
    interpreted_beyond: f64,
    compiled_beyond: f64,
}

/// The share of executed instructions the compiled regions ran, over `scans` scans.
fn native_share(vm: &mut Vm, scans: usize) -> f64 {
    let before = vm.executed_natively();
    let mut executed = 0;
    for _ in 0..scans {
        executed += Scanner::scan(vm);
    }
    (vm.executed_natively() - before) as f64 / executed.max(1) as f64
}

/// The worst program of `rows` by `key` (largest, or smallest with `min`), as
/// "value (program)".
fn worst(rows: &[&Row], key: impl Fn(&Row) -> f64, min: bool) -> Option<(f64, String)> {
    rows.iter()
        .map(|r| (key(r), r.name.clone()))
        .reduce(|a, b| if (b.0 > a.0) != min { b } else { a })
}

/// One line per bar of issue 31 ("Done when"), from this run: the note quotes them.
fn summary(rows: &[Row], fixed: f64) {
    let all: Vec<&Row> = rows.iter().collect();
    let large: Vec<&Row> = rows.iter().filter(|r| r.per_scan > 200).collect();
    let with_native: Vec<&Row> = rows.iter().filter(|r| r.native.is_some()).collect();
    let line =
        |what: &str, found: Option<(f64, String)>, unit: &str, bar: &str, ok: fn(f64) -> bool| {
            match found {
                Some((v, name)) => println!(
                    "  {what:<56} {v:>7.2}{unit:<9} ({name}; bar {bar}: {})",
                    if ok(v) { "met" } else { "NOT met" }
                ),
                None => println!("  {what:<56} {:>7} (no program)", "-"),
            }
        };
    let (n_c, n_i) = (reachable(COMPILED_BAR), reachable(INTERPRETED_BAR));
    println!(
        "\nSummary (issue 31's bars, this run). With the whole scan counted, a bar per \
         instruction can hold only from {n_c} instr/scan compiled and {n_i} interpreted \
         (a scan costs at least the fixed cost, whose bar is {FIXED_BAR} ns); \
         \"beyond\": the scan less the fixed cost measured above, per instruction:"
    );
    let at_least = |n: u64| -> Vec<&Row> { rows.iter().filter(|r| r.per_scan >= n).collect() };
    let compiled_set = at_least(n_c);
    let interpreted_set = at_least(n_i);
    let c_ok = |v: f64| v <= COMPILED_BAR;
    let i_ok = |v: f64| v <= INTERPRETED_BAR;
    line(
        &format!("compiled, max ns/instr (>= {n_c} instr/scan)"),
        worst(&compiled_set, |r| r.compiled, false),
        " ns",
        "<= 2",
        c_ok,
    );
    line(
        "compiled, max ns/instr (every program)",
        worst(&all, |r| r.compiled, false),
        " ns",
        "<= 2",
        c_ok,
    );
    line(
        "compiled, max ns/instr beyond the fixed cost (every)",
        worst(&all, |r| r.compiled_beyond, false),
        " ns",
        "<= 2",
        c_ok,
    );
    line(
        "compiled / native, worst",
        worst(
            &with_native,
            |r| r.compiled / r.native.unwrap_or(f64::NAN),
            false,
        ),
        "x",
        "<= 3",
        |v| v <= 3.0,
    );
    line(
        "interpreted / compiled, min (> 200 instr/scan)",
        worst(&large, |r| r.interpreted / r.compiled, true),
        "x",
        ">= 4",
        |v| v >= 4.0,
    );
    line(
        &format!("interpreted, max ns/instr (>= {n_i} instr/scan)"),
        worst(&interpreted_set, |r| r.interpreted, false),
        " ns",
        "<= 8",
        i_ok,
    );
    line(
        "interpreted, max ns/instr (every program)",
        worst(&all, |r| r.interpreted, false),
        " ns",
        "<= 8",
        i_ok,
    );
    line(
        "interpreted, max ns/instr beyond the fixed cost (every)",
        worst(&all, |r| r.interpreted_beyond, false),
        " ns",
        "<= 8",
        i_ok,
    );
    line(
        "fixed cost per scan",
        Some((fixed, "empty MAIN".into())),
        " ns",
        "<= 30",
        |v| v <= FIXED_BAR,
    );
}

/// The fixed cost of a scan: an empty MAIN (nothing to compile) through `Vm::scan`, in
/// ns (printed too).
fn fixed_cost(effort: Effort, bench: bool) -> f64 {
    let empty = lad("empty MAIN", EMPTY_MAIN, None, Vec::new());
    let mut vm = load(&empty, Tier::Interpreted);
    let scans = warm(effort, &mut vm).max(if bench { 10_000 } else { 1 });
    let mut run = |n: usize| batch(n, &mut vm);
    let (ns, _) = measure(effort, &mut [&mut run], &[scans])[0];
    println!("\nFixed cost per scan (empty MAIN through Vm::scan): {ns:.1} ns (bar: 30 ns)");
    ns
}

/// The mixing station's inputs while timed: every tank started (IB0..IB2) and cycling
/// fill, mix, drain; acknowledge released.
fn mixing_inputs() -> Vec<(&'static str, u32)> {
    vec![("IB0", 0xFF), ("IB1", 0xFF), ("IB2", 0xFF)]
}

/// The conveyor plant's inputs while timed: every station started (IB0..IB4), stations
/// 0 and 7 held stopped (their blocks jumped over), acknowledge released.
fn plant_inputs() -> Vec<(&'static str, u32)> {
    vec![
        ("IB0", 0xFF),
        ("IB1", 0xFF),
        ("IB2", 0xFF),
        ("IB3", 0xFF),
        ("IB4", 0xFF),
        ("IB5", 0x81),
    ]
}
