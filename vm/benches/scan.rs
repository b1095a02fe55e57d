//! VM speed: nanoseconds per executed instruction on (a) a generated bit-logic program
//! of 10,000 instructions per scan and (b) a mixed program (moves, arithmetic, compares,
//! calls). Median of several timed batches of scans. Issue 4's bar: <= 3 ns per
//! instruction on (a), within 5x of a native transcription (not built yet).

use std::sync::Arc;
use std::time::Instant;

use gutta_catalog::stdlib;
use gutta_compiler::encode::ImageMeta;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_vm::{Vm, VmConfig};

/// (a): networks of LD/A/AN/O/= on I, Q and M bits; `count` instructions in all.
fn bit_logic(count: usize) -> String {
    let mut code = String::new();
    let mut n = 0;
    let mut net = 1;
    while n < count {
        code.push_str(&format!(
            "NETWORK {net}\nLD I0.{}\nA M{}.{}\nAN I1.{}\nO M{}.{}\n= M{}.{}\n",
            net % 8,
            net % 16,
            net % 8,
            (net + 3) % 8,
            (net + 5) % 16,
            net % 8,
            (net + 7) % 16,
            (net + 1) % 8
        ));
        n += 5;
        net += 1;
    }
    format!("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n{code}END_ORGANIZATION_BLOCK\n")
}

/// (b): moves, integer math, compares and a subroutine call per network.
fn mixed(count: usize) -> String {
    let mut code = String::new();
    let mut n = 0;
    let mut net = 1;
    while n < count {
        code.push_str(&format!(
            "NETWORK {net}\nLD SM0.0\nMOVW MW{a}, MW{b}\n+I 3, MW{b}\n*I 2, MW{b}\nLDW>= MW{b}, 100\nMOVD MD40, MD44\n+D 1, MD44\nCALL ADD1, MW{b}, MW{c}\n",
            a = (net * 2) % 32,
            b = 32 + (net * 2) % 32,
            c = 64 + (net * 2) % 32
        ));
        n += 8 + 3;
        net += 1;
    }
    format!(
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n{code}END_ORGANIZATION_BLOCK\n\
         SUBROUTINE_BLOCK ADD1:SBR0\nVAR_INPUT\n  a : INT;\nEND_VAR\nVAR_OUTPUT\n  r : INT;\nEND_VAR\nBEGIN\nNETWORK 1\nLD SM0.0\nMOVW #a, #r\n+I 1, #r\nEND_SUBROUTINE_BLOCK\n"
    )
}

fn load(text: &str) -> Vm {
    // A target with room for large programs (131,072 instruction bytes).
    let target = stdlib::shared("EC30-EKSTM32-XC").expect("target");
    let explicit = ExplicitTarget {
        target: target.clone(),
        origin: "bench".into(),
    };
    let c = compile(
        SourceFile::new("bench.lad", text),
        Some(&explicit),
        &ImageMeta {
            source: "bench.lad".into(),
            tool: "bench".into(),
        },
    );
    let image = c
        .image
        .unwrap_or_else(|| panic!("{:?}", c.checked.diagnostics().first()));
    let verified = gutta_format::verify(&image, &target).expect("verifies");
    Vm::new(verified, Arc::clone(&target), VmConfig::default()).expect("loads")
}

/// Executed instructions per scan (counted by the VM) and median ns per instruction.
fn measure(vm: &mut Vm, batches: usize, scans: usize) -> (u64, f64) {
    vm.scan().expect("warm-up");
    let per_scan = vm.executed_last_scan();
    let mut times = Vec::new();
    for _ in 0..batches {
        let t = Instant::now();
        for _ in 0..scans {
            vm.scan().expect("scan");
        }
        times.push(t.elapsed().as_secs_f64() * 1e9 / (scans as f64 * per_scan as f64));
    }
    times.sort_by(|a, b| a.total_cmp(b));
    (per_scan, times[times.len() / 2])
}

fn main() {
    let bench = std::env::args().any(|a| a == "--bench");
    let (batches, scans) = if bench { (9, 200) } else { (1, 1) };
    for (name, text) in [("bit logic", bit_logic(10_000)), ("mixed", mixed(10_000))] {
        let mut vm = load(&text);
        let (per_scan, ns) = measure(&mut vm, batches, scans);
        println!("{name:<10} {per_scan:>7} instructions/scan  {ns:>8.2} ns/instruction (median of {batches} x {scans} scans)");
    }
}
