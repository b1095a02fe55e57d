//! What the start of every scan writes, against what it must be, on every engine: the
//! system bits of SMB0 from the virtual time (kept in steps, `clock.rs`) and the input
//! image from the terminals (copied to where each area starts, `terminals.rs`), on
//! targets of different input sizes; and the routines still to run in a scan, dropped
//! with it. Not the instructions: the scan around them.

mod common;

use gutta_catalog::{stdlib, AreaKind};
use gutta_vm::{ScanEnd, Vm, VmConfig};

use common::{load_on, read, set, three_engines};

fn main_block(body: &str) -> String {
    format!("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n{body}\nEND_ORGANIZATION_BLOCK\n")
}

/// SMB0 as the scan starting at `ms` virtual milliseconds, after `scans` completed
/// scans, must see it (docs/vm.md, "System bits"): SM0.0 on, SM0.1 on the first scan,
/// SM0.4 off and on every 30 s, SM0.5 every 0.5 s, SM0.6 every other scan.
fn expected_smb0(scans: u64, ms: u64) -> u32 {
    let halves = ms / 500;
    1 | u32::from(scans == 0) << 1
        | u32::from((halves / 60) % 2 == 1) << 4
        | u32::from(halves % 2 == 1) << 5
        | u32::from(scans % 2 == 1) << 6
}

/// Every scan copies SMB0 to MB0; after each scan MB0 holds what the formula says for
/// that scan's start, whatever the scan time (none, odd, a divisor or not of 500 ms,
/// longer than a half second), across SM0.4's 30 s step and after a reset.
#[test]
fn system_bits_follow_the_virtual_time_on_every_engine() {
    let text = main_block("NETWORK 1\nLD SM0.0\nMOVB SMB0, MB0");
    for scan_ms in [0, 7, 10, 250, 333, 500, 1000, 29_999, 30_000] {
        // Enough scans to pass 61 s (SM0.4 on, then off again), at most 9,000.
        let scans = if scan_ms == 0 {
            50
        } else {
            (61_000 / u64::from(scan_ms) + 2).min(9_000)
        };
        for config in three_engines(VmConfig {
            scan_ms,
            ..VmConfig::default()
        }) {
            let mut vm = common::load(&text, config);
            for round in 0..2 {
                for k in 0..scans {
                    vm.scan().expect("scan");
                    let want = expected_smb0(k, k * u64::from(scan_ms));
                    assert_eq!(
                        read(&vm, "MB0"),
                        want,
                        "scan {k} at {scan_ms} ms a scan, round {round}, {config:?}"
                    );
                }
                // A reset starts the clock again: the first scan, time 0.
                vm.reset();
            }
        }
    }
}

/// The input image after a host write: the first and the last byte of I and the first
/// and last word of AI reach the program, on targets whose input areas are 8 and 16,
/// 8 and 24, 32 and 256 bytes, and hold across a reset (the terminals keep them).
#[test]
fn inputs_reach_the_program_whole_on_every_target() {
    for target in [stdlib::DEFAULT, "EC30-EK51", "EC30-EKSTM32-XC"] {
        let shared = stdlib::shared(target).expect("target");
        let size = |kind: AreaKind| {
            shared
                .memory
                .areas
                .iter()
                .find(|a| a.kind == kind)
                .map(|a| a.size)
                .expect("an input area")
        };
        let (i_last, ai_last) = (
            size(AreaKind::DigitalInput) - 1,
            size(AreaKind::AnalogInput) - 2,
        );
        let text = main_block(&format!(
            "NETWORK 1\nLD SM0.0\nMOVB IB0, MB1\nMOVB IB{i_last}, MB2\n\
             MOVW AIW0, MW4\nMOVW AIW{ai_last}, MW6"
        ));
        for config in three_engines(VmConfig::default()) {
            let mut vm = load_on(target, &text, config);
            set(&mut vm, "IB0", 0x5A);
            set(&mut vm, &format!("IB{i_last}"), 0xA5);
            set(&mut vm, "AIW0", 0x1234);
            set(&mut vm, &format!("AIW{ai_last}"), 0xBEEF);
            for round in 0..2 {
                for _ in 0..3 {
                    vm.scan().expect("scan");
                }
                let got = ["MB1", "MB2", "MW4", "MW6"].map(|v| read(&vm, v));
                assert_eq!(
                    got,
                    [0x5A, 0xA5, 0x1234, 0xBEEF],
                    "{target} round {round} {config:?}"
                );
                vm.reset();
            }
        }
    }
}

/// Two timed events of the scan's period (10 ms): both routines run after every MAIN,
/// each counting its runs; either one stops the PLC when I0.0 is on.
const TWO_ROUTINES: &str = "
ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1
LD     SM0.1
MOVB   10, SMB10
MOVB   10, SMB11
ATCH   A, 10
ATCH   B, 11
ENI
END_ORGANIZATION_BLOCK
INTERRUPT_BLOCK A:INT1
BEGIN
NETWORK 1
LD     SM0.0
INCW   MW40
NETWORK 2
LD     I0.0
STOP
END_INTERRUPT_BLOCK
INTERRUPT_BLOCK B:INT2
BEGIN
NETWORK 1
LD     SM0.0
INCW   MW42
NETWORK 2
LD     I0.0
STOP
END_INTERRUPT_BLOCK
";

/// The routines still to run in a scan (`Engine::events`, kept between scans) are
/// dropped when a routine ends the scan (STOP in A: B does not run after it) and when a
/// paused scan is abandoned (going to STOP while paused in A: the next scan runs each
/// routine once, not the abandoned scan's B as well).
#[test]
fn the_routines_left_in_a_scan_are_dropped_with_it() {
    for config in three_engines(VmConfig::default()) {
        let mut vm = common::load(TWO_ROUTINES, config);
        let runs = |vm: &Vm| (read(vm, "MW40"), read(vm, "MW42"));
        for _ in 0..3 {
            vm.scan().expect("scan");
        }
        assert_eq!(runs(&vm), (3, 3), "{config:?}");
        // Paused in A (event 10 is served before event 11) with B still to run; STOP
        // abandons the scan.
        let in_a = gutta_vm::Position {
            function: 1,
            network: 1,
            step: 1,
        };
        vm.set_breakpoint(Some(in_a)).expect("breakpoint");
        assert_eq!(vm.run_scan(), Ok(ScanEnd::Paused(in_a)), "{config:?}");
        assert_eq!(runs(&vm), (3, 3), "{config:?}");
        vm.set_breakpoint(None).expect("clear");
        vm.set_running(false);
        vm.set_running(true);
        vm.scan().expect("scan");
        assert_eq!(runs(&vm), (4, 4), "{config:?}");
        // STOP in A: B does not run after it.
        set(&mut vm, "I0.0", 1);
        vm.scan().expect("scan");
        assert_eq!(runs(&vm), (5, 4), "{config:?}");
        assert!(!vm.is_running(), "{config:?}");
    }
}
