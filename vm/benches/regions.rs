//! What a compiled region's entry and exit cost (issue 31: "no region slower than the
//! interpreter"), measured rather than guessed. Programs of 100 networks, each a region
//! of `r` instructions (LD, r - 2 A, =) ended by an instruction the tier leaves to the
//! interpreter (a conditional END without power flow: M0 stays 0), run interpreted and compiled at load; per scan the compiled tier
//! saves `r * gain - entry` per region. A straight line through (r, saved ns per region)
//! gives `entry` (where it crosses r = 0) and `gain` (its slope), and `entry / gain` is
//! the smallest region worth its entry: `vm/src/tier.rs` `worth` uses it (the sizes
//! timed start at the 6 instructions it compiles: the line extrapolates below). Bit logic is
//! what the interpreter runs fastest (fused chains), so the gain is the smallest any
//! family gives and the rule errs on the side of interpreting.
//! `cargo bench -p gutta-vm --bench regions`; `cargo test --benches` runs it briefly.

#![allow(
    clippy::disallowed_methods,
    clippy::disallowed_macros,
    reason = "a benchmark is a program: it times and prints"
)]

use std::sync::Arc;
use std::time::Instant;

use gutta_catalog::stdlib;
use gutta_compiler::compile;
use gutta_compiler::source::SourceFile;
use gutta_vm::{TierState, Vm, VmConfig};

const NETWORKS: usize = 100;
const TARGET: &str = "EC30-EKSTM32-XC";

/// MAIN of `NETWORKS` regions of `r` instructions (r >= 2), each ended by an END that
/// never has power flow (the tier leaves END to the interpreter).
fn program(r: usize) -> String {
    let mut code = String::from("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n");
    for n in 0..NETWORKS {
        code.push_str(&format!("NETWORK {}\nLD M0.{}\n", n + 1, n % 8));
        for k in 0..r - 2 {
            code.push_str(&format!("AN M1.{}\n", k % 8));
        }
        code.push_str(&format!("= M2.{}\nEND\n", n % 8));
    }
    code.push_str("END_ORGANIZATION_BLOCK\n");
    code
}

fn vm(r: usize, native_after: Option<u64>) -> Vm {
    let target = stdlib::shared(TARGET).expect("target");
    let explicit = gutta_compiler::ExplicitTarget {
        target: Arc::clone(&target),
        origin: "bench".into(),
    };
    let c = compile(SourceFile::new("regions", program(r)), Some(&explicit));
    let image = c.image.expect("compiles");
    let image = gutta_format::verify(&image, &target).expect("verifies");
    let config = VmConfig {
        native_after,
        ..VmConfig::default()
    };
    Vm::new(image, target, config).expect("loads")
}

/// Median ns per scan over `batches` batches of `scans` scans.
fn time(vm: &mut Vm, scans: usize, batches: usize) -> f64 {
    let mut per = Vec::new();
    for _ in 0..batches {
        let t = Instant::now();
        for _ in 0..scans {
            vm.scan().expect("runs");
        }
        per.push(t.elapsed().as_secs_f64() * 1e9 / scans as f64);
    }
    per.sort_by(f64::total_cmp);
    per[per.len() / 2]
}

fn main() {
    let bench = std::env::args().any(|a| a == "--bench");
    let (scans, batches) = if bench { (2_000, 31) } else { (2, 1) };
    // From the shortest run `tier.rs` compiles (`worth`: 6 instructions; it would leave
    // shorter ones to the interpreter, so they cannot be timed compiled here).
    let sizes = [6usize, 8, 12, 16, 24, 32];
    println!(
        "\nRegion entry cost: {NETWORKS} regions of r instructions per scan, each ended by an unpowered END"
    );
    println!(
        "{:>3} {:>14} {:>14} {:>22}",
        "r", "interp ns/scan", "cc ns/scan", "saved ns per region"
    );
    let mut points = Vec::new();
    for r in sizes {
        let mut interpreted = vm(r, None);
        let mut compiled = vm(r, Some(0));
        match compiled.tier() {
            TierState::Compiled { regions, .. } => {
                assert!(*regions >= NETWORKS, "r {r}: {regions} regions")
            }
            other => panic!("r {r}: not compiled: {other:?}"),
        }
        let (mut ti, mut tc) = (Vec::new(), Vec::new());
        // Interleaved, so both see the same machine.
        for _ in 0..batches {
            ti.push(time(&mut interpreted, scans, 1));
            tc.push(time(&mut compiled, scans, 1));
        }
        ti.sort_by(f64::total_cmp);
        tc.sort_by(f64::total_cmp);
        let (i, c) = (ti[ti.len() / 2], tc[tc.len() / 2]);
        let saved = (i - c) / NETWORKS as f64;
        println!("{r:>3} {i:>14.0} {c:>14.0} {saved:>22.2}");
        points.push((r as f64, saved));
    }
    // Least squares: saved = gain * r - entry.
    let n = points.len() as f64;
    let (sx, sy) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), &(x, y)| (a + x, b + y));
    let (mx, my) = (sx / n, sy / n);
    let sxy: f64 = points.iter().map(|&(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = points.iter().map(|&(x, _)| (x - mx) * (x - mx)).sum();
    let gain = sxy / sxx;
    let entry = gain * mx - my;
    println!(
        "gain {gain:.2} ns per instruction, entry {entry:.2} ns per region: worth from {:.1} instructions",
        entry / gain
    );
}
