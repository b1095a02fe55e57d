//! VM tests that are not run-corpus data (tests/data/run holds the programs that are):
//! the programs of examples/ (the memory document's pointer example, CALL with
//! arguments, data blocks and the blinking lamp in blink.lad, AN2002 sample 2), which live in examples/
//! and are run here rather than copied, and the Rust API of faults and forces
//! (`Fault::Watchdog`'s limit, `Vm::fault`, `Vm::fault_position`, `force_image`, refused forces,
//! `unforce_all`).

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

/// blink.lad's first comment line: Lamp (Q0.0) blinks at 1 Hz, 0.5 s on and 0.5 s off,
/// from the first scan on (SM0.5: off while (ms / 500) is even, docs/vm.md). At the
/// default 10 ms a scan, scans 0..49 see it off, 50..99 on, and so on for 3 s.
#[test]
fn blink_toggles_q0_0_every_half_second() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/blink.lad"
    ))
    .expect("example");
    let mut vm = vm_with(
        &text,
        VmConfig {
            scan_ms: 10,
            ..VmConfig::default()
        },
    );
    let mut lamp = Vec::new();
    for _ in 0..300 {
        vm.scan().expect("scan");
        lamp.push(read(&vm, "Q0.0"));
    }
    let expected: Vec<u32> = (0..300u32).map(|scan| (scan / 50) % 2).collect();
    assert_eq!(lamp, expected, "Q0.0 after each scan");
    let toggles = lamp.windows(2).filter(|w| w[0] != w[1]).count();
    assert_eq!(toggles, 5, "on at 0.5 s, off at 1 s, ... on at 2.5 s");
}

/// The fault API: the `Fault` value with its limit and `Vm::fault`. The run-time
/// behaviour (held until reset, SMB2) is tests/data/run data
/// (watchdog_fault_holds_until_reset.lad).
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
    // The fault names the loop's instruction it stopped in (for file:line in gutta-vm).
    let at = vm.fault_position().expect("the faulting instruction");
    assert_eq!((at.function, at.network), (0, 1));
    assert!(at.step < 3, "{at}");
    assert!(vm.scan().is_err(), "a faulted VM stays stopped until reset");
    vm.reset();
    assert!(vm.fault().is_none());
    assert!(vm.fault_position().is_none());
}

/// The force API (what a corpus header cannot reach): the force image, a refused
/// force, `unforce_all`. Forces holding across scans are tests/data/run data
/// (force_inputs_and_outputs_hold.lad).
#[test]
fn force_image_refusals_and_unforce_all() {
    let mut vm = vm_for(&main_block(
        "NETWORK 1\nLD I0.0\n= Q0.0\nNETWORK 2\nLD SM0.0\n= Q0.1\nMOVB 16#FF, QB1",
    ));
    let at = |vm: &Vm, v: &str| vm.target().memory.parse_address(v).expect("address");
    let (i00, q01, qb1) = (at(&vm, "I0.0"), at(&vm, "Q0.1"), at(&vm, "QB1"));
    vm.force(i00, 1).expect("force input");
    vm.force(q01, 0).expect("force output bit");
    vm.force(qb1, 0x0F).expect("force output byte");
    vm.scan().expect("scan");
    assert_eq!(read(&vm, "Q0.0"), 1, "the force took effect");
    let (mask, image) = vm.force_image(i00.slot);
    assert_eq!((mask[0], image[0]), (0x01, 0x01));
    let (mask, image) = vm.force_image(q01.slot);
    assert_eq!(
        (mask[0], image[0], mask[1], image[1]),
        (0x02, 0x00, 0xFF, 0x0F)
    );
    assert!(vm.force(at(&vm, "MB0"), 1).is_err(), "M cannot be forced");
    vm.unforce_all();
    let (mask, _) = vm.force_image(q01.slot);
    assert!(mask.iter().all(|&m| m == 0), "nothing forced");
    vm.scan().expect("scan");
    assert_eq!(
        (read(&vm, "Q0.0"), read(&vm, "Q0.1"), read(&vm, "QB1")),
        (0, 1, 0xFF)
    );
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
