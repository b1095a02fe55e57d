//! What entering a unit costs: scans of tiny programs whose cost is nearly all around
//! their instructions (an empty MAIN; a CALL of a subroutine of one network; the same
//! with parameters; a timed interrupt routine run every scan; ten events attached, as
//! the corpus's events_all program does, whose routine runs 0.83 times a scan),
//! interpreted and compiled
//! at load, ns per scan, medians of batches. `cargo bench -p gutta-vm --bench
//! scan_entry` (`-- NAME`: only the case named NAME, or else the cases whose name
//! contains NAME; e.g. under callgrind: `-- call --scans 100000 --interpreted` runs that
//! many scans of the CALL case, untimed, of one tier: `--interpreted` or `--compiled`).

#![allow(
    clippy::disallowed_methods,
    clippy::disallowed_macros,
    reason = "a benchmark is a program: it times and prints"
)]

use std::hint::black_box;
use std::sync::Arc;
use std::time::Instant;

use gutta_catalog::stdlib;
use gutta_compiler::compile;
use gutta_compiler::source::SourceFile;
use gutta_vm::{Vm, VmConfig};

const EMPTY: &str = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nEND_ORGANIZATION_BLOCK\n";

const CALL: &str = "\
ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1
LD     SM0.0
CALL   SBR0
END_ORGANIZATION_BLOCK
SUBROUTINE_BLOCK MOTOR:SBR0
BEGIN
NETWORK 1
LD     I0.0
=      Q0.0
END_SUBROUTINE_BLOCK
";

const CALL_PARAMETERS: &str = "\
ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1
LD     SM0.0
CALL   ADD, MW10, MW12, MW14
END_ORGANIZATION_BLOCK
SUBROUTINE_BLOCK ADD:SBR0
VAR_INPUT
  a : INT;
  b : INT;
END_VAR
VAR_OUTPUT
  r : INT;
END_VAR
BEGIN
NETWORK 1
LD     SM0.0
MOVW   #a, #r
+I     #b, #r
END_SUBROUTINE_BLOCK
";

/// A timed interrupt of 10 ms (the scan's time): its routine runs after every MAIN.
const INTERRUPT: &str = "\
ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1
LD     SM0.1
MOVB   10, SMB10
ATCH   TICK, 10
ENI
END_ORGANIZATION_BLOCK
INTERRUPT_BLOCK TICK:INT1
BEGIN
NETWORK 1
LD     SM0.0
INCW   MW0
END_INTERRUPT_BLOCK
";

/// The corpus's `events_all_utf8_crlf.awl`: eight edge events and two timed ones (20
/// and 30 ms at 10 ms scans) attached to one routine, which runs 0.83 times a scan.
const TEN_EVENTS: &str = "\
ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1
LD     SM0.1
MOVB   20, SMB10
MOVB   30, SMB11
ATCH   TICK, 0
ATCH   TICK, 1
ATCH   TICK, 2
ATCH   TICK, 3
ATCH   TICK, 4
ATCH   TICK, 5
ATCH   TICK, 6
ATCH   TICK, 7
ATCH   TICK, 10
ATCH   TICK, 11
ENI
END_ORGANIZATION_BLOCK
INTERRUPT_BLOCK TICK:INT1
BEGIN
NETWORK 1
LD     SM0.0
INCW   MW0
END_INTERRUPT_BLOCK
";

fn load(text: &str, native_after: Option<u64>) -> Vm {
    let target = stdlib::shared(stdlib::DEFAULT).expect("target");
    let c = compile(SourceFile::new("entry.lad", text), None);
    let image = c
        .image
        .unwrap_or_else(|| panic!("does not compile: {:?}", c.checked.diagnostics()));
    let verified = gutta_format::verify(&image, &target).expect("verifies");
    let config = VmConfig {
        native_after,
        ..VmConfig::default()
    };
    Vm::new(verified, Arc::clone(&target), config).expect("loads")
}

/// ns per scan: the median of 31 batches of `batch` scans, after a warm-up.
fn time(vm: &mut Vm, batch: usize) -> f64 {
    for _ in 0..1_000 {
        vm.scan().expect("scan");
    }
    let mut figures: Vec<f64> = (0..31)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..batch {
                black_box(&mut *vm).scan().expect("scan");
            }
            t.elapsed().as_nanos() as f64 / batch as f64
        })
        .collect();
    figures.sort_by(f64::total_cmp);
    figures[figures.len() / 2]
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let bench = args.iter().any(|a| a == "--bench");
    let scans: Option<usize> = args
        .iter()
        .position(|a| a == "--scans")
        .and_then(|k| args.get(k + 1))
        .and_then(|n| n.parse().ok());
    let filter: Vec<&String> = args
        .iter()
        .filter(|a| !a.starts_with("--") && a.parse::<usize>().is_err())
        .collect();
    let cases = [
        ("empty MAIN", EMPTY),
        ("call", CALL),
        ("call with parameters", CALL_PARAMETERS),
        ("interrupt every scan", INTERRUPT),
        ("ten events", TEN_EVENTS),
    ];
    println!(
        "{:<24} {:>8} {:>14} {:>12}",
        "program", "instr", "interpreted", "compiled"
    );
    for (name, text) in cases {
        // A filter that is a case's whole name selects that case alone ("call" is not
        // "call with parameters"); otherwise every case whose name contains it.
        let exact = filter.iter().any(|f| cases.iter().any(|(n, _)| n == f));
        let selected = |f: &&String| {
            if exact {
                name == f.as_str()
            } else {
                name.contains(f.as_str())
            }
        };
        if !filter.is_empty() && !filter.iter().any(selected) {
            continue;
        }
        let mut row = format!("{name:<24}");
        for (k, tier) in [None, Some(0)].into_iter().enumerate() {
            let wanted = match tier {
                None => !args.iter().any(|a| a == "--compiled"),
                Some(_) => !args.iter().any(|a| a == "--interpreted"),
            };
            if !wanted {
                continue;
            }
            let mut vm = load(text, tier);
            vm.scan().expect("first scan");
            vm.scan().expect("scan");
            if k == 0 || row.len() <= 24 {
                row += &format!(" {:>8}", vm.executed_last_scan());
            }
            match scans {
                Some(n) => {
                    for _ in 0..n {
                        black_box(&mut vm).scan().expect("scan");
                    }
                }
                None => {
                    let ns = time(&mut vm, if bench { 20_000 } else { 10 });
                    row += &format!(" {ns:>11.1} ns");
                }
            }
        }
        println!("{row}");
    }
}
