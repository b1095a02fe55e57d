//! CALLs with BOOL parameters run from their plan (`decode::plan_call`, `calls.rs`) and
//! compile as a Call step (docs/vm.md, CALL): a subroutine with BOOL, INT and DINT
//! parameters of each section, called with bits of I, M, Q and the caller's own L
//! (several in one byte) and with INT and DINT literals, run by the reference
//! semantics (`fast` off), the interpreter and compiled at load over many scans of
//! changing inputs: memory and counts agree after every scan. And the Micro/WIN export
//! whose CALL has a BOOL output (tests/data/microwin/ltemp_cp1252_lf.awl) runs no CALL
//! generically and compiles its MAIN whole.
#![cfg(feature = "jit")]
#![allow(clippy::disallowed_methods, reason = "the test reads a corpus export")]

mod common;

use std::path::Path;
use std::sync::Arc;

use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile_program, ProgramSources};
use gutta_vm::{TierState, Vm, VmConfig};

const PROGRAM: &str = "ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1
LD I0.4
= L0.0
LDN I0.5
= L0.2
LD SM0.0
CALL SUB, I0.0, I0.3, MW0, MD4, M8.1, M8.2, MW10, MD12, Q0.0, Q0.5, MW16, MD20
NETWORK 2
LD I0.1
CALL SUB, M8.1, L0.0, MW2, MD24, Q0.5, L0.2, MW10, MD12, Q0.1, L0.1, MW18, MD28
NETWORK 3
LD L0.1
= Q1.0
LD L0.2
= Q1.1
LD SM0.0
CALL SUB, Q0.1, I1.7, 100, -70000, L0.0, L0.0, MW30, MD32, Q1.2, Q1.3, LW4, LD8
MOVW LW4, MW40
MOVD LD8, MD42
END_ORGANIZATION_BLOCK
SUBROUTINE_BLOCK SUB:SBR0
VAR_INPUT
  a : BOOL;
  b : BOOL;
  i : INT;
  d : DINT;
END_VAR
VAR_IN_OUT
  x : BOOL;
  y : BOOL;
  j : INT;
  e : DINT;
END_VAR
VAR_OUTPUT
  p : BOOL;
  q : BOOL;
  k : INT;
  f : DINT;
END_VAR
BEGIN
NETWORK 1
LD #a
A #b
= #p
LD #a
O #x
= #q
LDN #y
= #x
LD #b
= #y
NETWORK 2
LD SM0.0
MOVW #i, #k
+I #j, #k
MOVD #d, #f
+D #e, #f
INCW #j
INCD #e
END_SUBROUTINE_BLOCK
";

/// A simple generator of input values.
fn next(state: &mut u32) -> u32 {
    *state = state.wrapping_mul(1_103_515_245).wrapping_add(12_345);
    *state >> 8
}

#[test]
fn bool_int_and_dint_parameters_agree_on_three_engines() {
    let mut vms = common::three_engines(VmConfig::default()).map(|c| common::load(PROGRAM, c));
    assert_eq!(
        vms[1].generic_records().iter().find(|(m, _)| m == "CALL"),
        None,
        "every CALL planned"
    );
    // Two regions: MAIN whole and SUB whole (entered so when an interpreted caller
    // calls it); MAIN's CALLs are Call steps inside its region.
    assert!(
        matches!(vms[2].tier(), TierState::Compiled { regions: 2, .. }),
        "MAIN compiles as one region: {:?}",
        vms[2].tier()
    );
    let mut state = 7u32;
    let mut executed = 0;
    for scan in 0..400 {
        let (ib0, ib1, mw0, md4) = (
            next(&mut state),
            next(&mut state),
            next(&mut state),
            next(&mut state),
        );
        let md24 = next(&mut state).wrapping_mul(0x0101);
        let mut after = Vec::new();
        for vm in &mut vms {
            common::set(vm, "IB0", ib0 & 0xFF);
            common::set(vm, "IB1", ib1 & 0xFF);
            if scan % 5 == 0 {
                common::set(vm, "MW0", mw0 & 0xFFFF);
                common::set(vm, "MW2", mw0 >> 8);
                common::set(vm, "MD4", md4.wrapping_mul(977));
                common::set(vm, "MD24", md24);
            }
            vm.run_scan().expect("a scan");
            after.push((common::areas(vm), vm.executed_last_scan()));
        }
        assert_eq!(after[1], after[0], "interpreter, scan {scan}");
        assert_eq!(after[2], after[0], "compiled, scan {scan}");
        executed += after[2].1;
    }
    // The compiled tier ran every instruction of every scan.
    assert_eq!(vms[2].executed_natively(), executed);
}

fn ltemp() -> Vm {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let path = root.join("tests/data/microwin/ltemp_cp1252_lf.awl");
    let bytes = std::fs::read(&path).expect("the export");
    let file = SourceFile::from_code_page_bytes(String::from("ltemp_cp1252_lf.awl"), bytes).0;
    let c = compile_program(ProgramSources::single(file), None);
    let image = c.image.expect("compiles");
    let target = Arc::clone(&c.checked.target);
    let verified = gutta_format::verify(&image, &target).expect("verifies");
    Vm::new(
        verified,
        target,
        VmConfig {
            native_after: Some(0),
            ..VmConfig::default()
        },
    )
    .expect("loads")
}

#[test]
fn the_microwin_call_with_a_bool_output_is_planned_and_main_compiles_whole() {
    let mut vm = ltemp();
    assert_eq!(
        vm.generic_records().iter().find(|(m, _)| m == "CALL"),
        None,
        "CALL SBR_0, MW10, MW12, Q0.2, MW14 is planned"
    );
    // MAIN whole and SBR_0 whole (for an interpreted caller); before BOOL parameters
    // were planned the CALL ended MAIN's region and ran generically.
    assert!(
        matches!(vm.tier(), TierState::Compiled { regions: 2, .. }),
        "MAIN one region: {:?}",
        vm.tier()
    );
    common::set(&mut vm, "MW10", 5);
    common::set(&mut vm, "MW12", 3);
    vm.run_scan().expect("a scan");
    assert_eq!(vm.executed_natively(), vm.executed_last_scan());
    assert_eq!(common::read(&vm, "Q0.2"), 1, "5 > 3");
    assert_eq!(common::read(&vm, "MW14"), 8, "5 + 3");
    common::set(&mut vm, "MW12", 9);
    vm.run_scan().expect("a scan");
    assert_eq!(common::read(&vm, "Q0.2"), 0, "5 > 9 is false");
    assert_eq!(common::read(&vm, "MW14"), 14, "5 + 9");
}
