//! Programs compiled by gutta-cc, verified, and run on the VM: the memory document's
//! pointer example exactly, bit logic and edges, arithmetic flags, CALL with arguments,
//! data blocks at reset, and the watchdog.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

mod common;

use common::{read, set};
use gutta_vm::{Fault, Vm, VmConfig};

fn vm_for(text: &str) -> Vm {
    vm_with(text, VmConfig::default())
}

fn vm_with(text: &str, config: VmConfig) -> Vm {
    common::load(text, config)
}

fn main_block(code: &str) -> String {
    format!("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n{code}\nEND_ORGANIZATION_BLOCK\n")
}

#[test]
fn the_memory_documents_pointer_example() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/in1001_pointers.lad"
    ))
    .expect("example");
    let mut vm = vm_for(&text);
    vm.scan().expect("scan");
    assert_eq!(read(&vm, "MW24"), 0x0E01);
    assert_eq!(read(&vm, "MW26"), 0x0E02);
    assert_eq!(
        read(&vm, "MD4"),
        0x0400_001A,
        "MD4 locates MB26: slot 4, offset 26"
    );
    assert_eq!(
        read(&vm, "MB24"),
        0x01,
        "little-endian: MB24 is the low byte"
    );
}

#[test]
fn latch_and_edges() {
    let mut vm = vm_for(&main_block(
        "NETWORK 1\nLD I0.0\nO M0.0\nAN I0.1\n= M0.0\nNETWORK 2\nLD I0.2\nEU\n= Q0.0\nNETWORK 3\nLD I0.2\nED\n= Q0.1",
    ));
    vm.scan().expect("scan");
    assert_eq!(read(&vm, "M0.0"), 0);
    set(&mut vm, "I0.0", 1);
    vm.scan().expect("scan");
    assert_eq!(read(&vm, "M0.0"), 1);
    set(&mut vm, "I0.0", 0);
    vm.scan().expect("scan");
    assert_eq!(read(&vm, "M0.0"), 1, "latched");
    set(&mut vm, "I0.1", 1);
    vm.scan().expect("scan");
    assert_eq!(read(&vm, "M0.0"), 0, "unlatched");
    set(&mut vm, "I0.2", 1);
    vm.scan().expect("scan");
    assert_eq!(
        (read(&vm, "Q0.0"), read(&vm, "Q0.1")),
        (1, 0),
        "rising edge for one scan"
    );
    vm.scan().expect("scan");
    assert_eq!(read(&vm, "Q0.0"), 0);
    set(&mut vm, "I0.2", 0);
    vm.scan().expect("scan");
    assert_eq!(
        (read(&vm, "Q0.0"), read(&vm, "Q0.1")),
        (0, 1),
        "falling edge"
    );
}

#[test]
fn arithmetic_wraps_and_sets_flags() {
    let mut vm = vm_for(&main_block(
        "NETWORK 1\nLD SM0.1\nMOVW 32767, MW0\n+I 1, MW0\nMOVD 100000, MD4\n*D -3, MD4\nMOVW 300, MW10\nMUL 1000, MD10\nMOVW 7, MW2\n/I 0, MW2",
    ));
    vm.scan().expect("scan");
    assert_eq!(read(&vm, "MW0"), 0x8000, "32767 + 1 wraps");
    assert_eq!(read(&vm, "MD4") as i32, -300_000);
    assert_eq!(
        read(&vm, "MD10"),
        300_000,
        "MUL: INT x low word of OUT into a DINT"
    );
    assert_eq!(read(&vm, "MW2"), 7, "division by zero leaves OUT");
    assert_eq!(
        (read(&vm, "SM1.3"), read(&vm, "SM1.1")),
        (1, 0),
        "the last instruction's flags: division by zero sets SM1.3, clears SM1.1"
    );
}

#[test]
fn compares_read_signed_words_and_unsigned_bytes() {
    let mut vm = vm_for(&main_block(
        "NETWORK 1\nLD SM0.0\nMOVW -5, MW0\nMOVB 200, MB2\nNETWORK 2\nLDW< MW0, 0\n= Q0.0\nNETWORK 3\nLDB> MB2, 100\n= Q0.1\nNETWORK 4\nLDW>= MW0, 0\nO Q0.0\nA Q0.1\n= Q0.2",
    ));
    vm.scan().expect("scan");
    assert_eq!(
        (read(&vm, "Q0.0"), read(&vm, "Q0.1"), read(&vm, "Q0.2")),
        (1, 1, 1)
    );
}

#[test]
fn call_passes_arguments_through_l() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/blink.lad"
    ))
    .expect("example");
    let mut vm = vm_for(&text);
    set(&mut vm, "MW10", 100);
    set(&mut vm, "I0.0", 1);
    vm.scan().expect("scan");
    // MW12 := MW10 + 5 + 3, called while the latch M0.0 is on.
    assert_eq!(read(&vm, "MW12"), 108);
    // The data block was applied at reset.
    assert_eq!(
        (
            read(&vm, "MW22"),
            read(&vm, "MB30"),
            read(&vm, "MD40") as i32
        ),
        (6, 1, -70000)
    );
}

#[test]
fn a_runaway_loop_trips_the_watchdog() {
    let mut vm = vm_with(
        &main_block("NETWORK 1\nLBL 1\nLD SM0.0\nJMP 1"),
        VmConfig {
            scan_ms: 10,
            watchdog: 10_000,
            ..VmConfig::default()
        },
    );
    assert!(matches!(vm.scan(), Err(Fault::Watchdog { limit: 10_000 })));
    assert!(vm.fault().is_some());
    assert!(vm.scan().is_err(), "a faulted VM stays stopped until reset");
    vm.reset();
    assert!(vm.fault().is_none());
}

#[test]
fn first_scan_bit_and_clock() {
    let mut vm = vm_for(&main_block(
        "NETWORK 1\nLD SM0.1\nINCW MW0\nNETWORK 2\nLD SM0.0\nINCW MW2",
    ));
    for _ in 0..5 {
        vm.scan().expect("scan");
    }
    assert_eq!((read(&vm, "MW0"), read(&vm, "MW2")), (1, 5));
    assert_eq!(vm.clock_ms(), 50);
}

#[test]
fn for_next_runs_the_body_and_leaves_the_index_past_final() {
    let mut vm = vm_for(&main_block(
        "NETWORK 1\nLD SM0.0\nMOVW 0, MW2\nFOR MW0, 1, 10\nINCW MW2\nNEXT\nNETWORK 2\nLD SM0.0\nMOVW 0, MW6\nFOR MW4, 5, 1\nINCW MW6\nNEXT\nNETWORK 3\nLD I0.0\nMOVW 0, MW10\nFOR MW8, 1, 3\nINCW MW10\nNEXT",
    ));
    set(&mut vm, "MW10", 77);
    vm.scan().expect("scan");
    assert_eq!(
        (read(&vm, "MW0"), read(&vm, "MW2")),
        (11, 10),
        "FOR MW0, 1, 10 runs 10 times, leaves 11"
    );
    assert_eq!(
        (read(&vm, "MW4"), read(&vm, "MW6")),
        (5, 0),
        "INIT > FINAL skips the body"
    );
    assert_eq!(
        read(&vm, "MW10"),
        77,
        "without power flow the whole loop is skipped"
    );
}

#[test]
fn stop_ends_the_scan_and_stays_stopped() {
    let mut vm = vm_for(&main_block(
        "NETWORK 1\nLD SM0.0\nINCW MW0\nNETWORK 2\nLD I0.0\nSTOP\nNETWORK 3\nLD SM0.0\nINCW MW2",
    ));
    vm.scan().expect("scan");
    assert_eq!((read(&vm, "MW0"), read(&vm, "MW2")), (1, 1));
    set(&mut vm, "I0.0", 1);
    vm.scan().expect("scan");
    assert_eq!(
        (read(&vm, "MW0"), read(&vm, "MW2")),
        (2, 1),
        "STOP ends the scan at once"
    );
    assert!(!vm.is_running());
    vm.scan().expect("scan");
    assert_eq!(read(&vm, "MW0"), 2, "stopped: scans do nothing");
    set(&mut vm, "I0.0", 0);
    vm.set_running(true);
    vm.scan().expect("scan");
    assert_eq!((read(&vm, "MW0"), read(&vm, "MW2")), (3, 2));
}

#[test]
fn forces_hold_across_scans_for_inputs_and_outputs() {
    let mut vm = vm_for(&main_block(
        "NETWORK 1\nLD I0.0\n= Q0.0\nNETWORK 2\nLD SM0.0\n= Q0.1\nMOVB 16#FF, QB1",
    ));
    let at = |vm: &Vm, v: &str| vm.target().memory.parse_address(v).expect("address");
    let (i00, q01, qb1) = (at(&vm, "I0.0"), at(&vm, "Q0.1"), at(&vm, "QB1"));
    vm.force(i00, 1).expect("force input");
    vm.force(q01, 0).expect("force output bit");
    vm.force(qb1, 0x0F).expect("force output byte");
    set(&mut vm, "I0.0", 0); // the terminal says 0; the force wins
    vm.scan().expect("scan");
    assert_eq!(read(&vm, "Q0.0"), 1, "forced input reads its force value");
    assert_eq!(
        read(&vm, "Q0.1"),
        0,
        "forced output is written with its force value"
    );
    assert_eq!(read(&vm, "QB1"), 0x0F);
    let (mask, image) = vm.force_image(i00.slot);
    assert_eq!((mask[0], image[0]), (0x01, 0x01));
    assert!(vm.force(at(&vm, "MB0"), 1).is_err(), "M cannot be forced");
    vm.unforce_all();
    vm.scan().expect("scan");
    assert_eq!(
        (read(&vm, "Q0.0"), read(&vm, "Q0.1"), read(&vm, "QB1")),
        (0, 1, 0xFF)
    );
}

#[test]
fn timed_interrupts_run_their_routine_each_period() {
    // ENI and DISI are unconditional (Flow Always): a jump decides whether ENI runs.
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.1\nMOVB 50, SMB10\nATCH TICK, 10\nNETWORK 2\nLDN I0.0\nJMP 1\nNETWORK 3\nENI\nNETWORK 4\nLBL 1\nLD I0.2\nDTCH 10\nEND_ORGANIZATION_BLOCK\n\
                INTERRUPT_BLOCK TICK:INT1\nBEGIN\nNETWORK 1\nLD SM0.0\nINCW MW30\nEND_INTERRUPT_BLOCK\n";
    let mut vm = vm_for(text);
    for _ in 0..10 {
        vm.scan().expect("scan");
    }
    assert_eq!(
        read(&vm, "MW30"),
        0,
        "interrupts are off after entering RUN"
    );
    set(&mut vm, "I0.0", 1);
    vm.scan().expect("scan");
    assert_eq!(
        read(&vm, "MW30"),
        1,
        "the one pending occurrence runs once ENI is on"
    );
    for _ in 0..10 {
        vm.scan().expect("scan");
    }
    assert_eq!(
        read(&vm, "MW30"),
        3,
        "every 50 ms of virtual time: 100 ms = 2 more"
    );
    set(&mut vm, "I0.2", 1);
    for _ in 0..10 {
        vm.scan().expect("scan");
    }
    assert_eq!(read(&vm, "MW30"), 3, "detached");
}

#[test]
fn an2002_sample2_touch_screen_selects_the_analog_input() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/an2002_sample2_touchscreen.lad"
    ))
    .expect("example");
    let mut vm = vm_for(&text);
    set(&mut vm, "AIW0", 456);
    set(&mut vm, "AIW2", 123);
    set(&mut vm, "Q3.0", 1); // the touch screen's button writes coil 000025
    vm.scan().expect("scan");
    assert_eq!(read(&vm, "MW20"), 123, "Q3.0 selects channel 1 (AIW2)");
    set(&mut vm, "Q3.0", 0);
    set(&mut vm, "Q3.1", 1);
    vm.scan().expect("scan");
    assert_eq!(read(&vm, "MW20"), 456, "Q3.1 selects channel 0 (AIW0)");
    set(&mut vm, "AIW0", 789);
    vm.scan().expect("scan");
    assert_eq!(
        read(&vm, "MW20"),
        789,
        "an input terminal holds until changed and is read every scan"
    );
}

#[test]
fn edge_events_run_their_routine_once_per_edge() {
    // Event 0: rising edge of I0.0; event 3: falling edge of I0.1.
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.1\nATCH UP, 0\nATCH DOWN, 3\nNETWORK 2\nENI\nEND_ORGANIZATION_BLOCK\n\
                INTERRUPT_BLOCK UP:INT1\nBEGIN\nNETWORK 1\nLD SM0.0\nINCW MW40\nEND_INTERRUPT_BLOCK\n\
                INTERRUPT_BLOCK DOWN:INT2\nBEGIN\nNETWORK 1\nLD SM0.0\nINCW MW42\nEND_INTERRUPT_BLOCK\n";
    let mut vm = vm_for(text);
    set(&mut vm, "I0.1", 1);
    vm.scan().expect("scan");
    assert_eq!(
        (read(&vm, "MW40"), read(&vm, "MW42")),
        (0, 0),
        "entering RUN raises no edge"
    );
    set(&mut vm, "I0.0", 1);
    vm.scan().expect("scan");
    vm.scan().expect("scan");
    assert_eq!(read(&vm, "MW40"), 1, "one rising edge, one run");
    set(&mut vm, "I0.1", 0);
    vm.scan().expect("scan");
    assert_eq!(read(&vm, "MW42"), 1, "falling edge of I0.1");
    set(&mut vm, "I0.0", 0);
    vm.scan().expect("scan");
    set(&mut vm, "I0.0", 1);
    vm.scan().expect("scan");
    assert_eq!((read(&vm, "MW40"), read(&vm, "MW42")), (2, 1));
}
