//! Interrupt routines started without a frame (`Engine::run_direct`, docs/vm.md,
//! "Interrupts"): a routine's compiled regions and fast operations run from its first
//! record outside `exec`, and its frame is pushed only where they stop. Over random
//! inputs, the interpreter and the compiled tier must do what the reference engine does
//! (which starts every routine in a frame): memory and instruction count after every
//! scan, and the same fault at the same point when the watchdog trips inside a routine.
//! The routines stop in every way there is: a straight one at a box that detaches or
//! attaches the next event (so the queued routine is skipped or runs) and at the
//! watchdog's bound, not at all (a routine of two instructions), and one with a FOR
//! loop, a CALL and STOP, which gets its frame at once.

mod common;

use common::{load, same_as_reference, set, three_engines};
use gutta_vm::VmConfig;

/// Events 10 and 11 (both every 10 ms scan) run D then B; event 0 (I0.0 rising) runs A
/// before them. D runs straight (only boxes stop it, when powered): a run long enough
/// for a region, a DTCH and an ATCH of B's event, then twenty instructions. A stops
/// whatever the scan (FOR, CALL, STOP): its frame is pushed at once.
const PROGRAM: &str = "
ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1
LD     SM0.1
MOVB   10, SMB10
MOVB   10, SMB11
ATCH   D, 10
ATCH   B, 11
ATCH   A, 0
ENI
NETWORK 2
LD     SM0.0
INCW   MW0
END_ORGANIZATION_BLOCK
SUBROUTINE_BLOCK S:SBR0
BEGIN
NETWORK 1
LD     SM0.0
INCW   MW70
END_SUBROUTINE_BLOCK
INTERRUPT_BLOCK D:INT1
BEGIN
NETWORK 1
LD     SM0.0
INCW   MW40
MOVW   MW40, MW44
+I     3, MW44
A      I0.1
=      M5.0
AW>=   MW44, 100
=      M5.1
NETWORK 2
LD     I0.2
DTCH   11
NETWORK 3
LD     I0.3
ATCH   B, 11
NETWORK 4
LD     SM0.0
INCW   MW46
INCW   MW46
INCW   MW46
INCW   MW46
INCW   MW46
INCW   MW46
INCW   MW46
INCW   MW46
INCW   MW46
INCW   MW46
INCW   MW46
INCW   MW46
INCW   MW46
INCW   MW46
INCW   MW46
INCW   MW46
INCW   MW46
INCW   MW46
INCW   MW46
END_INTERRUPT_BLOCK
INTERRUPT_BLOCK B:INT2
BEGIN
NETWORK 1
LD     SM0.0
INCW   MW42
END_INTERRUPT_BLOCK
INTERRUPT_BLOCK A:INT3
BEGIN
NETWORK 1
LD     I0.4
FOR    MW60, 1, IW2
NETWORK 2
LD     SM0.0
INCW   MW62
NETWORK 3
NEXT
NETWORK 4
LD     I0.5
CALL   S
NETWORK 5
LD     I0.6
STOP
NETWORK 6
LD     SM0.0
INCW   MW48
END_INTERRUPT_BLOCK
";

fn next(state: &mut u64) -> u64 {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    *state
}

/// Random inputs every scan on the three engines; after each scan the same memory,
/// count and fault. A fault or STOP is compared, then the engines are reset and go on.
fn run(seed: u64, config: VmConfig, scans: usize) -> (usize, usize) {
    let mut vms = three_engines(config).map(|c| load(PROGRAM, c));
    let mut state = seed;
    let (mut faults, mut stops) = (0, 0);
    for scan in 0..scans {
        let r = next(&mut state);
        // I0.6 (STOP) rarely; the FOR loop's count up to 63.
        let i0 = (r as u8 & 0x3F) | if r >> 40 & 0x1F == 0 { 0x40 } else { 0 };
        for vm in &mut vms {
            set(vm, "IB0", u32::from(i0));
            set(vm, "IW2", ((r >> 8) & 0x3F) as u32);
        }
        let results = vms.each_mut().map(|vm| vm.scan());
        for (k, result) in results.iter().enumerate() {
            assert_eq!(*result, results[0], "seed {seed}, scan {scan}, engine {k}");
        }
        same_as_reference(&vms, scan as u32);
        if results[0].is_err() || !vms[0].is_running() {
            if results[0].is_err() {
                faults += 1;
            } else {
                stops += 1;
            }
            for vm in &mut vms {
                vm.reset();
                vm.set_running(true);
            }
        }
    }
    (faults, stops)
}

#[test]
fn routines_started_without_a_frame_run_as_the_reference_does() {
    for seed in [3, 0x9E37_79B9_7F4A_7C15, 77] {
        let (faults, stops) = run(seed, VmConfig::default(), 400);
        assert_eq!(faults, 0, "seed {seed}");
        assert!(stops > 0, "seed {seed}: STOP never ran");
    }
}

#[test]
fn the_watchdog_trips_inside_a_routine_at_the_same_instruction() {
    // MAIN is 9 instructions, A's FOR loop 3 an iteration, D 31: with a limit of 120
    // the watchdog trips inside A's loop or D's straight run in some scans, not in
    // others.
    let config = VmConfig {
        watchdog: 120,
        ..VmConfig::default()
    };
    let mut tripped = 0;
    for seed in [5, 0xDEAD_BEEF_1234_5678] {
        let (faults, _) = run(seed, config, 300);
        tripped += faults;
    }
    assert!(tripped > 10, "the watchdog tripped {tripped} times");
}
