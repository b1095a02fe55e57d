//! Issue 4's VM figures, all from one run: nanoseconds per executed instruction on (a)
//! a generated bit-logic program of 10,000 instructions per scan and (b) a mixed
//! program (moves, math, compares, calls), each against its native Rust transcription
//! (crate gutta-bench-native, checked against the VM by its tests/agree.rs); the scan
//! time of the AN2002 sample 3 master; the memory of a loaded EC30-EKSTM32-XC image.
//! Issue 17's per-scan cost: ns per `Vm::scan` of a small program (awlsim/scan_cost.lad,
//! 10 instructions) and of an empty MAIN, median and spread (min/max) of batches.
//! Medians of timed batches. `cargo bench -p gutta-vm --bench scan` measures (`-- per-scan`:
//! the per-scan table alone); `cargo test --benches` (no `--bench`) only runs everything once.

#![allow(
    clippy::disallowed_methods,
    clippy::disallowed_types,
    clippy::disallowed_macros,
    reason = "a benchmark is a program: it reads its arguments, times and prints"
)]

use std::hint::black_box;
use std::sync::Arc;
use std::time::Instant;

use gutta_bench_native::Memory;
use gutta_catalog::{stdlib, Target};
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_format::VerifiedImage;
use gutta_vm::{Vm, VmConfig};

/// The target of the instruction benchmarks: room for large programs (131,072
/// instruction bytes).
const BIG_TARGET: &str = "EC30-EKSTM32-XC";

/// How much to measure.
#[derive(Debug, Clone, Copy)]
struct Effort {
    batches: usize,
    scans: usize,
    /// VMs loaded per step of the memory measurement.
    vms_per_step: usize,
}

/// Compile `text` (for `target`, or the target the program names / the stdlib default)
/// and verify it; the bytes of the image's pages too.
fn image(name: &str, text: &str, target: Option<&str>) -> (VerifiedImage, Arc<Target>, usize) {
    let explicit = target.map(|t| ExplicitTarget {
        target: stdlib::shared(t).expect("target"),
        origin: "bench".into(),
    });
    let c = compile(SourceFile::new(name, text), explicit.as_ref());
    let image = c
        .image
        .unwrap_or_else(|| panic!("{name}: {:?}", c.checked.diagnostics().first()));
    let target = Arc::clone(&c.checked.target);
    let verified = gutta_format::verify(&image, &target).expect("verifies");
    let bytes = image.pages.values().map(Vec::len).sum();
    (verified, target, bytes)
}

/// How the VM runs the program: the interpreter only, or compiled at load (the
/// compiled tier, docs/vm-jit.md; by default it compiles after 100 scans).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Tier {
    Interpreted,
    Compiled,
}

impl Tier {
    const BOTH: [Tier; 2] = [Tier::Interpreted, Tier::Compiled];

    fn config(self) -> VmConfig {
        VmConfig {
            native_after: match self {
                Tier::Interpreted => None,
                Tier::Compiled => Some(0),
            },
            ..VmConfig::default()
        }
    }

    fn name(self) -> &'static str {
        match self {
            Tier::Interpreted => "interpreted",
            Tier::Compiled => "compiled",
        }
    }
}

fn load(verified: &VerifiedImage, target: &Arc<Target>, tier: Tier) -> Vm {
    Vm::new(verified.clone(), Arc::clone(target), tier.config()).expect("loads")
}

/// `load`, and for the compiled tier, proof that it compiled.
fn load_checked(verified: &VerifiedImage, target: &Arc<Target>, tier: Tier) -> Vm {
    let vm = load(verified, target, tier);
    if tier == Tier::Compiled {
        assert!(
            matches!(vm.tier(), gutta_vm::TierState::Compiled { .. }),
            "compiled: {:?}",
            vm.tier()
        );
    }
    vm
}

fn example(name: &str) -> String {
    let path = format!("{}/../examples/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(path).expect("example")
}

/// Set a variable (an input's terminal for I).
fn set(vm: &mut Vm, var: &str, value: u32) {
    let a = vm.target().memory.parse_address(var).expect("address");
    vm.write(a, value).expect("write");
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// Seconds per call of `scan` over one batch of `scans` calls.
fn batch(scans: usize, scan: &mut impl FnMut()) -> f64 {
    let t = Instant::now();
    for _ in 0..scans {
        scan();
    }
    t.elapsed().as_secs_f64() / scans as f64
}

/// Median seconds per call of `scan` over `effort.batches` batches of `effort.scans`.
fn seconds_per_scan(effort: Effort, mut scan: impl FnMut()) -> f64 {
    scan(); // warm-up
    median(
        (0..effort.batches)
            .map(|_| batch(effort.scans, &mut scan))
            .collect(),
    )
}

/// The mixed program's INT inputs (MW0..MW30): large enough that every compare holds,
/// so every network runs its CALL and a scan executes all 10,000 instructions.
fn mixed_inputs(mut write_word: impl FnMut(u32, u16)) {
    for k in 0..16u32 {
        write_word(k * 2, 1000 + 100 * k as u16);
    }
}

/// A program and its native transcriptions (free, and fenced between networks).
struct Program {
    name: &'static str,
    text: &'static str,
    native: fn(&mut Memory),
    fenced: fn(&mut Memory),
}

/// One row of the instruction table: medians of ns per instruction, and of the
/// ratios VM/native and VM/fenced of batches timed one right after the other (the
/// ratios vary less than the times on a busy machine).
struct Row {
    per_scan: u64,
    vm: f64,
    native: f64,
    fenced: f64,
    vm_per_native: f64,
    vm_per_fenced: f64,
}

fn instructions(effort: Effort, program: &Program, tier: Tier) -> Row {
    let text = program.text;
    let (verified, target, _) = image("bench.lad", text, Some(BIG_TARGET));
    let mut vm = load_checked(&verified, &target, tier);
    let mut native = Memory::default();
    mixed_inputs(|at, v| {
        set(&mut vm, &format!("MW{at}"), u32::from(v));
        gutta_bench_native::set_word(&mut native.m, at as usize, v as i16);
    });
    vm.scan().expect("first scan");
    let per_scan = vm.executed_last_scan();
    let mut native_memory = native.clone();
    let mut fenced_memory = native;
    let mut vm_scan = || vm.scan().expect("scan");
    let mut native_scan = || (program.native)(black_box(&mut native_memory));
    let mut fenced_scan = || (program.fenced)(black_box(&mut fenced_memory));
    native_scan(); // warm-up (the VM's was the first scan)
    fenced_scan();
    let mut times = [Vec::new(), Vec::new(), Vec::new()];
    for _ in 0..effort.batches {
        times[0].push(batch(effort.scans, &mut vm_scan));
        times[1].push(batch(effort.scans, &mut native_scan));
        times[2].push(batch(effort.scans, &mut fenced_scan));
    }
    let ratios = |k: usize| median(times[0].iter().zip(&times[k]).map(|(v, n)| v / n).collect());
    let (vm_per_native, vm_per_fenced) = (ratios(1), ratios(2));
    let [vm_s, native_s, fenced_s] = times.map(median);
    let ns = |s: f64| s * 1e9 / per_scan as f64;
    Row {
        per_scan,
        vm: ns(vm_s),
        native: ns(native_s),
        fenced: ns(fenced_s),
        vm_per_native,
        vm_per_fenced,
    }
}

/// Resident set size of this process in bytes (Linux: /proc/self/status VmRSS).
fn resident_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Bytes of resident memory per loaded VM: the growth while loading the last of three
/// steps of `n` VMs each (the first steps soak up heap the compiler freed), and the
/// same for the step before, as a consistency check. The VMs are returned: the caller
/// keeps them while it measures the next tier, so that one grows the heap too instead of
/// reusing what these freed.
fn bytes_per_vm(
    verified: &VerifiedImage,
    target: &Arc<Target>,
    n: usize,
    tier: Tier,
) -> (Option<(f64, f64)>, Vec<Vm>) {
    let mut vms = Vec::with_capacity(3 * n);
    let Some(first) = resident_bytes() else {
        return (None, vms);
    };
    let mut rss = vec![first];
    for _ in 0..3 {
        for _ in 0..n {
            vms.push(load(verified, target, tier));
        }
        rss.push(resident_bytes().unwrap_or(0));
    }
    black_box(&vms);
    let step = |k: usize| rss[k + 1].saturating_sub(rss[k]) as f64 / n as f64;
    (Some((step(2), step(1))), vms)
}

/// Median microseconds of `Vm::new` (the image's clone is made before the clock starts
/// and the VM dropped after it stops).
fn load_micros(verified: &VerifiedImage, target: &Arc<Target>, n: usize, tier: Tier) -> f64 {
    let times = (0..n.max(1))
        .map(|_| {
            let image = verified.clone();
            let t = Instant::now();
            let vm = Vm::new(image, Arc::clone(target), tier.config()).expect("loads");
            let s = t.elapsed().as_secs_f64();
            drop(black_box(vm));
            s * 1e6
        })
        .collect();
    median(times)
}

/// The per-scan benchmark's program (the awlsim comparison's logic).
const SCAN_COST: &str = include_str!("awlsim/scan_cost.lad");

/// A MAIN without instructions: what a scan costs around the program.
const EMPTY_MAIN: &str = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nEND_ORGANIZATION_BLOCK\n";

/// One row of the per-scan table: instructions per scan, ns per scan (median, min
/// and max of the batches).
struct PerScan {
    instructions: u64,
    median: f64,
    min: f64,
    max: f64,
}

/// ns per `Vm::scan` of `text` on a fresh VM: `batches` batches of `scans` scans, the
/// VM reset (untimed) before each, so scan_cost.lad never reaches its STOP.
fn per_scan(text: &str, batches: usize, scans: usize, tier: Tier) -> PerScan {
    let (verified, target, _) = image("per_scan.lad", text, None);
    let mut vm = load(&verified, &target, tier);
    vm.scan().expect("first scan");
    let instructions = vm.executed_last_scan();
    let mut times: Vec<f64> = (0..batches)
        .map(|_| {
            vm.reset();
            let t = batch(scans, &mut || vm.scan().expect("scan"));
            assert!(vm.is_running(), "the program stopped within a batch");
            t * 1e9
        })
        .collect();
    times.sort_by(f64::total_cmp);
    PerScan {
        instructions,
        median: times[times.len() / 2],
        min: times[0],
        max: times[times.len() - 1],
    }
}

/// The per-scan table: scan_cost.lad and an empty MAIN.
fn per_scan_section(bench: bool) {
    let (batches, scans) = if bench { (31, 100_000) } else { (1, 1) };
    println!(
        "\nns per scan through Vm::scan (issue 17; median, min..max of {batches} x {scans} scans):"
    );
    println!(
        "{:<22} {:>12} {:>10} {:>8} {:>16}",
        "program", "tier", "instr/scan", "ns/scan", "min..max"
    );
    let programs = [("scan_cost.lad", SCAN_COST), ("empty MAIN", EMPTY_MAIN)];
    for ((name, text), tier) in programs
        .into_iter()
        .flat_map(|p| Tier::BOTH.map(|t| (p, t)))
    {
        if text == EMPTY_MAIN && tier == Tier::Compiled {
            continue; // nothing to compile
        }
        let r = per_scan(text, batches, scans, tier);
        println!(
            "{:<22} {:>12} {:>10} {:>8.1} {:>16}",
            name,
            tier.name(),
            r.instructions,
            r.median,
            format!("{:.1}..{:.1}", r.min, r.max)
        );
    }
}

fn main() {
    let bench = std::env::args().any(|a| a == "--bench");
    if std::env::args().any(|a| a == "per-scan") {
        // `cargo bench -p gutta-vm --bench scan -- per-scan`: this section alone.
        per_scan_section(bench);
        return;
    }
    let effort = if bench {
        Effort {
            batches: 31,
            scans: 60,
            vms_per_step: 200,
        }
    } else {
        Effort {
            batches: 1,
            scans: 1,
            vms_per_step: 2,
        }
    };
    let how = format!("median of {} x {} scans", effort.batches, effort.scans);

    println!("\nns per executed instruction, VM against native Rust ({how}):");
    println!("(fenced: native with a compiler barrier between networks, so each network");
    println!(" reads and writes memory instead of reusing values of the networks before it)");
    println!(
        "{:<10} {:>12} {:>10} {:>8} {:>10} {:>10} {:>10} {:>10}",
        "program", "tier", "instr/scan", "VM", "native", "VM/native", "fenced", "VM/fenced"
    );
    let programs = [
        Program {
            name: "bit logic",
            text: gutta_bench_native::BIT_LOGIC,
            native: gutta_bench_native::bit_logic_scan,
            fenced: gutta_bench_native::bit_logic_scan_fenced,
        },
        Program {
            name: "mixed",
            text: gutta_bench_native::MIXED,
            native: gutta_bench_native::mixed_scan,
            fenced: gutta_bench_native::mixed_scan_fenced,
        },
    ];
    for program in &programs {
        for tier in Tier::BOTH {
            let r = instructions(effort, program, tier);
            println!(
                "{:<10} {:>12} {:>10} {:>8.2} {:>10.3} {:>9.1}x {:>10.3} {:>9.1}x",
                program.name,
                tier.name(),
                r.per_scan,
                r.vm,
                r.native,
                r.vm_per_native,
                r.fenced,
                r.vm_per_fenced
            );
        }
    }

    let (verified, target, _) = image(
        "an2002_sample3_master.lad",
        &example("an2002_sample3_master.lad"),
        None,
    );
    let mut per_tier = Vec::new();
    for tier in Tier::BOTH {
        let mut master = load(&verified, &target, tier);
        set(&mut master, "I0.1", 1); // polling on: EXCH queued every 200 ms
        per_tier.push(seconds_per_scan(effort, || master.scan().expect("scan")));
    }
    let mut master = load(&verified, &target, Tier::Compiled);
    set(&mut master, "I0.1", 1);
    master.scan().expect("scan");
    // The first table's D (done) bit and error number, after the next exchange at most
    // 200 ms of virtual time away.
    let read = |vm: &Vm, var: &str| {
        vm.read(target.memory.parse_address(var).expect("address"))
            .expect("read")
    };
    for _ in 0..40 {
        if read(&master, "M20.1") == 1 {
            break;
        }
        master.scan().expect("scan");
    }
    let exchange = if read(&master, "M20.1") == 1 {
        format!("error {} (2 = timeout)", read(&master, "MB21"))
    } else {
        "no result within 40 scans".to_string()
    };
    println!(
        "\nAN2002 sample 3 master on {}: {:.2} us per scan interpreted, {:.2} us compiled \
         ({how}, I0.1 on).\n\
         No port is attached: each exchange (every 200 ms) ends at once with {exchange}.",
        target.plc.name,
        per_tier[0] * 1e6,
        per_tier[1] * 1e6
    );

    println!(
        "\nMemory of a loaded {BIG_TARGET} VM (growth of resident memory per VM, \
         loading steps of {} VMs):",
        effort.vms_per_step
    );
    println!(
        "{:<22} {:>12} {:>12} {:>14} {:>16} {:>10}",
        "image", "tier", "image bytes", "bytes per VM", "(step before)", "load (us)"
    );
    let images = [
        ("in1001_pointers.lad", example("in1001_pointers.lad")),
        (
            "mixed (10,000 instr)",
            gutta_bench_native::MIXED.to_string(),
        ),
    ];
    let mut shared_code = Vec::new();
    for (name, text) in images {
        let (verified, target, bytes) = image(name, &text, Some(BIG_TARGET));
        let mut alive = Vec::new();
        for tier in Tier::BOTH {
            let n = effort.vms_per_step;
            // The first VM of the program compiles it (later ones share the code).
            let t = Instant::now();
            let first = load(&verified, &target, tier);
            let ms = t.elapsed().as_secs_f64() * 1e3;
            if let gutta_vm::TierState::Compiled { code_bytes, .. } = first.tier() {
                shared_code.push(format!(
                    "{name}: {code_bytes} bytes of machine code, loaded and compiled in \
                     {ms:.1} ms"
                ));
            }
            let load = load_micros(&verified, &target, n, tier);
            let t = tier.name();
            let (growth, vms) = bytes_per_vm(&verified, &target, n, tier);
            alive.push(vms);
            match growth {
                Some((last, before)) => println!(
                    "{name:<22} {t:>12} {bytes:>12} {last:>14.0} {before:>16.0} {load:>10.0}"
                ),
                None => println!(
                    "{name:<22} {t:>12} {bytes:>12} {:>14} {:>16} {load:>10.0}",
                    "no /proc", ""
                ),
            }
        }
    }
    println!(
        "(compiled: the VMs of one program share its code, compiled once per process: {})",
        shared_code.join("; ")
    );

    per_scan_section(bench);
}
