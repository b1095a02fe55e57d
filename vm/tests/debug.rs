//! Debugging as UM4001 describes it: a breakpoint by (function, network, step), pause
//! and continue, single-step stop, STEP_IN / STEP_OVER / STEP_OUT, the 16-byte debug
//! information block, the status byte, reset requests, scans while stopped, and access
//! by packed address. These stay in Rust, not in the run corpus: each drives the
//! debugger or status API (`set_breakpoint`, `debug_step`, `debug_info`, `status`,
//! `read_packed`, ...) that a corpus header cannot call.

mod common;

use common::{load, read, set};
use gutta_catalog::Address;
use gutta_format::{Operand, PackedOperand, UnitRef};
use gutta_sim::vm_access;
use gutta_vm::{DebugError, Position, ScanEnd, Step, VmConfig};

/// MAIN: network 1 counts scans in MW0; network 2 calls ADD with MW0 into MW2 when
/// I0.0 is on; network 3 sets Q0.0 from M0.0. ADD: two networks.
const PROGRAM: &str = "\
ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1
LD SM0.0
INCW MW0
NETWORK 2
LD I0.0
CALL ADD, MW0, MW2
NETWORK 3
LD M0.0
= Q0.0
END_ORGANIZATION_BLOCK
SUBROUTINE_BLOCK ADD:SBR0
VAR_INPUT
  a : INT;
END_VAR
VAR_OUTPUT
  r : INT;
END_VAR
BEGIN
NETWORK 1
LD SM0.0
MOVW #a, #r
NETWORK 2
LD SM0.0
+I 100, #r
END_SUBROUTINE_BLOCK
";

fn at(function: u8, network: u16, step: u16) -> Position {
    Position {
        function,
        network,
        step,
    }
}

fn sbr0(vm: &gutta_vm::Vm) -> u8 {
    UnitRef::subroutine(0)
        .page(&vm.target().plc)
        .expect("SBR0 has a page")
}

#[test]
fn breakpoint_pauses_before_its_instruction_and_continues() {
    let mut vm = load(PROGRAM, VmConfig::default());
    vm.set_breakpoint(Some(at(0, 1, 1)))
        .expect("INCW MW0 exists");
    assert_eq!(vm.run_scan(), Ok(ScanEnd::Paused(at(0, 1, 1))));
    assert!(vm.is_paused());
    assert_eq!(read(&vm, "MW0"), 0, "INCW has not run yet");
    // Scans do nothing while paused.
    assert_eq!(vm.run_scan(), Ok(ScanEnd::Paused(at(0, 1, 1))));
    assert_eq!(vm.scans(), 0);
    let info = vm_access::debug_info(&vm).encode();
    assert_eq!(
        &info[0..5],
        &[0, 0, 1, 0, 1],
        "breakpoint function 0, network 1, step 1"
    );
    assert_eq!(&info[5..10], &[0, 0, 1, 0, 1], "paused there");
    assert_eq!(&info[12..14], &[0, 1], "logic stack: SM0.0 loaded");
    assert_eq!(info[14], 0, "no call open");
    assert_eq!(info[15], 0, "no error");
    // Run: the scan finishes, the next one stops at the breakpoint again.
    vm.debug_run();
    assert_eq!(vm.run_scan(), Ok(ScanEnd::Completed));
    assert_eq!(read(&vm, "MW0"), 1);
    assert_eq!(vm.scans(), 1);
    assert_eq!(vm.run_scan(), Ok(ScanEnd::Paused(at(0, 1, 1))));
    assert_eq!(read(&vm, "MW0"), 1);
    // Cleared, scans run freely.
    vm.set_breakpoint(None).expect("clear");
    assert_eq!(vm_access::debug_info(&vm).encode()[0], 0xFF);
    vm.debug_run();
    for _ in 0..3 {
        assert_eq!(vm.run_scan(), Ok(ScanEnd::Completed));
    }
    assert_eq!(read(&vm, "MW0"), 4);
}

#[test]
fn breakpoint_in_a_subroutine_shows_the_call() {
    let mut vm = load(PROGRAM, VmConfig::default());
    set(&mut vm, "I0.0", 1);
    let sbr = sbr0(&vm);
    vm.set_breakpoint(Some(at(sbr, 2, 1))).expect("+I exists");
    assert_eq!(vm.run_scan(), Ok(ScanEnd::Paused(at(sbr, 2, 1))));
    let info = vm_access::debug_info(&vm).encode();
    assert_eq!(info[5], sbr);
    assert_eq!(info[14], 1, "one call open");
    assert!(
        u16::from_be_bytes([info[10], info[11]]) > 0,
        "caller L saved"
    );
    // #r holds a (MW0 = 1) before the +I.
    vm.debug_run();
    assert_eq!(vm.run_scan(), Ok(ScanEnd::Completed));
    assert_eq!(read(&vm, "MW2"), 101);
}

#[test]
fn a_breakpoint_must_name_an_instruction() {
    let mut vm = load(PROGRAM, VmConfig::default());
    for p in [at(0, 1, 2), at(0, 9, 0), at(7, 1, 0)] {
        assert_eq!(
            vm.set_breakpoint(Some(p)),
            Err(DebugError::NoInstruction(p))
        );
    }
    assert_eq!(vm.breakpoint(), None);
}

#[test]
fn step_in_over_and_out() {
    let mut vm = load(PROGRAM, VmConfig::default());
    set(&mut vm, "I0.0", 1);
    let sbr = sbr0(&vm);
    // Single-step stop: paused before MAIN's first instruction.
    vm.debug_stop().expect("stop");
    assert_eq!(vm.position(), Some(at(0, 1, 0)));
    assert_eq!(vm.debug_byte() & 1, 0, "not running");
    let step = |vm: &mut gutta_vm::Vm, s| match vm.debug_step(s).expect("step") {
        ScanEnd::Paused(p) => p,
        other => panic!("{other:?}"),
    };
    assert_eq!(step(&mut vm, Step::In), at(0, 1, 1));
    assert_eq!(
        step(&mut vm, Step::In),
        at(0, 2, 0),
        "INCW ran, next network"
    );
    assert_eq!(read(&vm, "MW0"), 1);
    assert_eq!(step(&mut vm, Step::In), at(0, 2, 1));
    // STEP_IN enters the subroutine.
    assert_eq!(step(&mut vm, Step::In), at(sbr, 1, 0));
    assert_eq!(vm_access::debug_info(&vm).encode()[14], 1);
    assert_eq!(step(&mut vm, Step::Over), at(sbr, 1, 1));
    // STEP_OUT: back after the CALL, outputs copied.
    assert_eq!(step(&mut vm, Step::Out), at(0, 3, 0));
    assert_eq!(read(&vm, "MW2"), 101);
    assert_eq!(vm_access::debug_info(&vm).encode()[14], 0);
    // Through the end of the scan into the next one.
    assert_eq!(step(&mut vm, Step::Over), at(0, 3, 1));
    assert_eq!(vm.scans(), 0);
    assert_eq!(step(&mut vm, Step::Over), at(0, 1, 0));
    assert_eq!(vm.scans(), 1);
    // STEP_OVER runs a whole call.
    for _ in 0..3 {
        step(&mut vm, Step::Over);
    }
    assert_eq!(vm.position(), Some(at(0, 2, 1)));
    assert_eq!(step(&mut vm, Step::Over), at(0, 3, 0));
    assert_eq!(read(&vm, "MW2"), 102);
    // Scans do nothing in single-step stop; running continues the paused scan.
    assert!(matches!(vm.run_scan(), Ok(ScanEnd::Paused(_))));
    vm.debug_run();
    assert_eq!(vm.run_scan(), Ok(ScanEnd::Completed));
    assert_eq!(vm.scans(), 2);
}

#[test]
fn step_over_stops_at_a_breakpoint_inside_the_call() {
    let mut vm = load(PROGRAM, VmConfig::default());
    set(&mut vm, "I0.0", 1);
    let sbr = sbr0(&vm);
    vm.set_breakpoint(Some(at(0, 2, 1))).expect("CALL");
    assert_eq!(vm.run_scan(), Ok(ScanEnd::Paused(at(0, 2, 1))));
    vm.set_breakpoint(Some(at(sbr, 2, 0))).expect("in ADD");
    assert_eq!(
        vm.debug_step(Step::Over),
        Ok(ScanEnd::Paused(at(sbr, 2, 0)))
    );
}

#[test]
fn debug_reset_and_a_breakpoint_in_a_loop() {
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\nFOR MW10, 1, 3\n\
        NETWORK 2\nLD SM0.0\nINCW MW12\nNETWORK 3\nNEXT\nEND_ORGANIZATION_BLOCK\n";
    let mut vm = load(text, VmConfig::default());
    vm.scan().expect("scan");
    assert_eq!(read(&vm, "MW12"), 3);
    vm.debug_reset().expect("reset");
    assert_eq!(read(&vm, "MW12"), 0);
    assert_eq!(vm.position(), Some(at(0, 1, 0)));
    assert_eq!(vm.debug_byte(), 0b10, "DEBUG_READ: RESET, not running");
    vm.set_breakpoint(Some(at(0, 2, 1))).expect("INCW");
    vm.debug_run();
    for pass in 0..3 {
        assert_eq!(vm.run_scan(), Ok(ScanEnd::Paused(at(0, 2, 1))));
        assert_eq!(read(&vm, "MW12"), pass);
        vm.debug_run();
    }
    assert_eq!(vm.run_scan(), Ok(ScanEnd::Completed));
    assert_eq!(read(&vm, "MW12"), 3);
    assert_eq!(vm.debug_byte(), 0b01, "running, the reset is behind");
}

#[test]
fn status_byte() {
    let mut vm = load(
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLBL 1\nLD SM0.0\nJMP 1\nEND_ORGANIZATION_BLOCK\n",
        VmConfig {
            watchdog: 1000,
            ..VmConfig::default()
        },
    );
    assert_eq!(vm.status().byte(), 0b0001, "RUN");
    vm.set_attached(true);
    assert_eq!(vm.status().byte(), 0b0101);
    vm.set_running(false);
    assert_eq!(vm.status().byte(), 0b0100);
    vm.set_running(true);
    let fault = vm.scan().expect_err("runaway loop");
    assert_eq!(vm.status().byte() & 0b1000, 0b1000, "ERROR");
    assert_eq!(vm_access::debug_info(&vm).encode()[15], fault.code());
    assert!(matches!(vm.debug_stop(), Err(DebugError::Fault(_))));
    vm.reset();
    assert_eq!(vm.status().byte(), 0b0101);
}

/// STATUS_RESET requests a reset: RESET shows until the next scan performs it.
/// STATUS_SCAN runs scans while in STOP.
#[test]
fn reset_request_and_scans_while_stopped() {
    let mut vm = load(PROGRAM, VmConfig::default());
    for _ in 0..3 {
        vm.scan().expect("scan");
    }
    assert_eq!(read(&vm, "MW0"), 3);
    vm.request_reset();
    assert_eq!(vm.status().byte() & 0b10, 0b10);
    assert_eq!(read(&vm, "MW0"), 3, "not yet");
    vm.scan().expect("scan");
    assert_eq!(read(&vm, "MW0"), 1, "reset, then one scan");
    assert_eq!(vm.status().byte() & 0b10, 0);
    vm.set_running(false);
    vm.scan().expect("stopped: nothing");
    assert_eq!(read(&vm, "MW0"), 1);
    vm.scan_while_stopped(4).expect("four scans");
    assert_eq!(read(&vm, "MW0"), 5);
    assert!(!vm.is_running());
}

/// STATUS_VAR_READ / WRITE and the force values by packed address (UM4001's operand
/// word, USE 0: gutta-format's `PackedOperand`).
#[test]
fn reading_writing_and_forcing_by_packed_address() {
    let mut vm = load(PROGRAM, VmConfig::default());
    let address =
        |vm: &gutta_vm::Vm, var: &str| vm.target().memory.parse_address(var).expect("address");
    let packed =
        |vm: &gutta_vm::Vm, var: &str| PackedOperand::encode(Operand::Value(address(vm, var))).0;
    let mw4 = packed(&vm, "MW4");
    vm_access::write_packed(&mut vm, mw4, 0x1234).expect("write");
    assert_eq!(read(&vm, "MW4"), 0x1234);
    // Only SLOT and OFFSET count for reads: 4 bytes from MB4.
    set(&mut vm, "MW6", 0xBEEF);
    let mb4 = packed(&vm, "MB4");
    assert_eq!(
        vm_access::read_packed(&vm, mb4),
        Ok([0x34, 0x12, 0xEF, 0xBE])
    );
    // A bit write changes only that bit.
    let m4_0 = packed(&vm, "M4.0");
    vm_access::write_packed(&mut vm, m4_0, 1).expect("bit");
    assert_eq!(read(&vm, "MW4"), 0x1235);
    // Force Q0.0 to 1: the program's `= Q0.0` (from M0.0 = 0) cannot clear it.
    let q0_0 = packed(&vm, "Q0.0");
    vm_access::force_packed(&mut vm, q0_0, 1).expect("force");
    vm.scan().expect("scan");
    assert_eq!(read(&vm, "Q0.0"), 1);
    let qb0 = packed(&vm, "QB0");
    assert_eq!(vm_access::read_force_packed(&vm, qb0), Ok([1, 0, 0, 0]));
    // Writing a forced variable changes its force value too.
    vm_access::write_packed(&mut vm, q0_0, 0).expect("write");
    vm.scan().expect("scan");
    assert_eq!(read(&vm, "Q0.0"), 0);
    assert_eq!(vm_access::read_force_packed(&vm, qb0), Ok([0, 0, 0, 0]));
    // M0.0 (bit 0 of MW0, which network 1 counts up) drives Q0.0 unless forced.
    for _ in 0..2 {
        vm.scan().expect("scan");
        assert_eq!(read(&vm, "Q0.0"), 0, "still forced, to 0");
    }
    vm.unforce(vm.target().memory.parse_address("Q0.0").expect("address"));
    for _ in 0..2 {
        vm.scan().expect("scan");
        assert_eq!(
            read(&vm, "Q0.0"),
            read(&vm, "M0.0"),
            "the program drives it again"
        );
    }
    // M cannot be forced; a read past the area is an error.
    assert!(vm_access::force_packed(&mut vm, m4_0, 1).is_err());
    let past_m = Address {
        offset: 0xFFFF,
        ..address(&vm, "MB4")
    };
    let past_m = PackedOperand::encode(Operand::Value(past_m)).0;
    assert!(vm_access::read_packed(&vm, past_m).is_err());
}

/// Bit logic runs fused on the fast path; a breakpoint or a step inside a fused run
/// stops at the exact instruction with the logic stack as it is there.
#[test]
fn breakpoints_inside_fused_bit_logic() {
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD I0.0\nA I0.1\nAN I0.2\nO I0.3\n= Q0.0\n= Q0.1\nEND_ORGANIZATION_BLOCK\n";
    for (input, q) in [(0b0011, 1), (0b0111, 0), (0b1000, 1), (0b0001, 0)] {
        for step in 0..6u16 {
            let mut vm = load(text, VmConfig::default());
            set(&mut vm, "IB0", input);
            vm.set_breakpoint(Some(at(0, 1, step)))
                .expect("instruction");
            assert_eq!(vm.run_scan(), Ok(ScanEnd::Paused(at(0, 1, step))));
            // The top after `step` instructions, computed here.
            let bit = |k: u32| input >> k & 1 == 1;
            let mut top = bit(0);
            for k in 1..step.min(4) {
                top = match k {
                    1 => top && bit(1),
                    2 => top && !bit(2),
                    _ => top || bit(3),
                };
            }
            if step > 0 {
                assert_eq!(
                    vm_access::debug_info(&vm).encode()[13] & 1,
                    u8::from(top),
                    "input {input:04b} step {step}"
                );
            }
            assert_eq!(read(&vm, "Q0.0"), u32::from(step > 4 && q == 1));
            vm.debug_run();
            assert_eq!(vm.run_scan(), Ok(ScanEnd::Completed));
            assert_eq!(read(&vm, "Q0.0"), q, "input {input:04b}");
            assert_eq!(read(&vm, "Q0.1"), q);
            // Cleared: the fused form runs again and agrees.
            vm.set_breakpoint(None).expect("clear");
            vm.debug_run();
            assert_eq!(vm.run_scan(), Ok(ScanEnd::Completed));
            assert_eq!(read(&vm, "Q0.1"), q);
        }
    }
}

/// Fused chains (networks 1, and 3 with 4 across their network record), a generic
/// record (+I with a literal), a fast MOVW and a planned CALL: what `decode.rs` stores
/// differently for each kind of record.
const LAYOUT: &str = "\
ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1
LD I0.0
A I0.1
O M0.0
= Q0.0
= M0.1
NETWORK 2
LD SM0.0
+I 3, MW10
MOVW MW10, MW12
CALL ADD, MW10, MW2
NETWORK 3
LDN Q0.0
AN M0.1
= Q0.1
NETWORK 4
LD Q0.1
= M0.2
END_ORGANIZATION_BLOCK
SUBROUTINE_BLOCK ADD:SBR0
VAR_INPUT
  a : INT;
END_VAR
VAR_OUTPUT
  r : INT;
END_VAR
BEGIN
NETWORK 1
LD SM0.0
MOVW #a, #r
NETWORK 2
LD SM0.0
+I 100, #r
END_SUBROUTINE_BLOCK
";

/// Every instruction's position, in the order STEP_IN visits them in one scan.
fn step_in_positions(vm: &mut gutta_vm::Vm) -> Vec<Position> {
    vm.debug_stop().expect("stop");
    let mut seen = vec![vm.position().expect("paused")];
    loop {
        match vm.debug_step(Step::In).expect("step") {
            ScanEnd::Paused(p) if vm.scans() == 0 => seen.push(p),
            ScanEnd::Paused(_) => return seen,
            other => panic!("{other:?}"),
        }
    }
}

fn layout_vm(fast: bool) -> gutta_vm::Vm {
    let mut vm = load(
        LAYOUT,
        VmConfig {
            fast,
            ..VmConfig::default()
        },
    );
    set(&mut vm, "I0.0", 1);
    vm
}

#[test]
fn positions_breakpoints_and_steps_on_every_kind_of_record() {
    let sbr = sbr0(&layout_vm(true));
    let mut expected: Vec<Position> = (0..5).map(|s| at(0, 1, s)).collect();
    expected.extend((0..4).map(|s| at(0, 2, s)));
    expected.extend([at(sbr, 1, 0), at(sbr, 1, 1), at(sbr, 2, 0), at(sbr, 2, 1)]);
    expected.extend((0..3).map(|s| at(0, 3, s)));
    expected.extend((0..2).map(|s| at(0, 4, s)));
    // Memory after two scans without a breakpoint: the reference.
    let mut plain = layout_vm(true);
    plain.scan().expect("scan");
    plain.scan().expect("scan");
    let reference = |vm: &gutta_vm::Vm| {
        ["Q0.0", "Q0.1", "M0.1", "M0.2", "MW10", "MW12", "MW2"].map(|v| read(vm, v))
    };
    for fast in [true, false] {
        assert_eq!(
            step_in_positions(&mut layout_vm(fast)),
            expected,
            "fast {fast}"
        );
        for &p in &expected {
            // A breakpoint pauses before its instruction (in a chain too), and the
            // scan goes on exactly as without it.
            let mut vm = layout_vm(fast);
            vm.set_breakpoint(Some(p)).expect("an instruction");
            assert_eq!(vm.run_scan(), Ok(ScanEnd::Paused(p)), "fast {fast}");
            vm.debug_run();
            assert_eq!(vm.run_scan(), Ok(ScanEnd::Completed), "fast {fast} {p}");
            assert_eq!(vm.run_scan(), Ok(ScanEnd::Paused(p)), "fast {fast}");
            vm.set_breakpoint(None).expect("clear");
            vm.debug_run();
            assert_eq!(vm.run_scan(), Ok(ScanEnd::Completed));
            assert_eq!(reference(&vm), reference(&plain), "fast {fast} {p}");
        }
        // One past each network's last step is no instruction.
        let vm = &mut layout_vm(fast);
        for p in [
            at(0, 1, 5),
            at(0, 2, 4),
            at(0, 3, 3),
            at(0, 4, 2),
            at(sbr, 2, 2),
        ] {
            assert_eq!(
                vm.set_breakpoint(Some(p)),
                Err(DebugError::NoInstruction(p))
            );
        }
    }
}

/// A fault in a generic record names its byte offset in the instruction page and its
/// position.
#[test]
fn a_fault_names_the_records_offset_and_position() {
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\n\
                MOVD 16#FFFFFFFF, MD4\nNETWORK 2\nLD SM0.0\nMOVW MW0, MW20\n\
                MOVW *MD4, MW8\nEND_ORGANIZATION_BLOCK\n";
    let target = gutta_catalog::stdlib::shared(gutta_catalog::stdlib::DEFAULT).expect("target");
    let explicit = gutta_compiler::ExplicitTarget {
        target: target.clone(),
        origin: "test".into(),
    };
    let c = gutta_compiler::compile(
        gutta_compiler::source::SourceFile::new("t.lad", text),
        Some(&explicit),
    );
    let verified = gutta_format::verify(&c.image.expect("compiles"), &target).expect("verifies");
    let offset = verified
        .main()
        .expect("MAIN")
        .records
        .iter()
        .rev()
        .find_map(|r| match r {
            gutta_format::UnitRecord::Instruction { offset, .. } => Some(*offset),
            gutta_format::UnitRecord::Network { .. } => None,
        })
        .expect("MOVW *MD4");
    for fast in [true, false] {
        let mut vm = gutta_vm::Vm::new(
            verified.clone(),
            std::sync::Arc::clone(&target),
            VmConfig {
                fast,
                ..VmConfig::default()
            },
        )
        .expect("loads");
        let fault = vm.scan().expect_err("a bad pointer");
        assert!(
            fault
                .to_string()
                .contains(&format!("instruction/00.bin byte {offset}:")),
            "{fault}"
        );
        assert_eq!(vm.fault_position(), Some(at(0, 2, 2)));
    }
}
