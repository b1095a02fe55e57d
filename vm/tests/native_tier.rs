//! The compiled tier (docs/vm-jit.md) against the interpreter and the reference
//! semantics: random programs whose networks mix what the tier compiles (bit logic,
//! moves, math, compares, CALLs of subroutines that compile whole, nested) with what it
//! does not (a subroutine with a generic instruction, counters, S/R, pointers), run
//! three ways: `fast` off (every instruction through `ops/`), the interpreter
//! (`native_after: None`) and compiled at load (`native_after: Some(0)`). Memory, the
//! instruction count and the outcome must agree after every scan; the watchdog, CallDepth
//! and breakpoints must land on the same instruction.
#![cfg(feature = "jit")]

mod common;

use gutta_vm::{Position, ScanEnd, TierState, Vm, VmConfig};
use proptest::prelude::*;

fn configs(watchdog: u64) -> [VmConfig; 3] {
    common::three_engines(VmConfig {
        watchdog,
        ..VmConfig::default()
    })
}

fn load3(text: &str, watchdog: u64) -> [Vm; 3] {
    configs(watchdog).map(|c| common::load(text, c))
}

fn memory(vm: &Vm) -> Vec<Vec<u8>> {
    vm.target()
        .memory
        .areas
        .iter()
        .map(|a| vm.memory().area(a.slot).unwrap_or(&[]).to_vec())
        .collect()
}

/// Statements a network may hold after its first LD; `{w}`, `{d}`, `{b}` are replaced by
/// operands chosen with the statement.
const STATEMENTS: &[&str] = &[
    "A {bit}",
    "AN {bit}",
    "O {bit}",
    "ON {bit}",
    "NOT",
    "= {out}",
    "LPS\n= {out}\nLPP",
    "LD {bit}\nOLD",
    "LD {bit}\nALD",
    "AW>= {w}, {w2}",
    "OD< {d}, {d2}",
    "AB= {b}, 7",
    "MOVW {w}, {w2}",
    "MOVD {d}, {d2}",
    "MOVB {b}, MB9",
    "+I {w}, {w2}",
    "-I 1000, {w2}",
    "*I {w}, {w2}",
    "+D {d}, {d2}",
    "*D {d}, {d2}",
    "CALL LEAF, {w}, {w2}",
    "CALL MID, {w}, {d2}",
    "CALL SLOW, {w}",
    "INCW {w2}",
    "S {out}, 2",
    "R {out}, 1",
    "MOVW {w}, *MD20",
    "LD {bit}\nCTU C3, 4",
];

const BITS: &[&str] = &[
    "I0.0", "I0.5", "I1.2", "M0.0", "M1.3", "M2.7", "Q0.1", "SM0.0", "SM1.0", "SM1.1",
];
const OUTS: &[&str] = &["M0.0", "M1.3", "M2.7", "Q0.1", "Q0.4", "M3.0"];
const WORDS: &[&str] = &["MW0", "MW2", "MW4", "IW0", "16#7FFF", "-32768", "3"];
const WORDS_OUT: &[&str] = &["MW0", "MW2", "MW4", "MW6"];
const DWORDS: &[&str] = &["MD10", "MD14", "2147483647", "-7"];
const DWORDS_OUT: &[&str] = &["MD10", "MD14"];
const BYTES: &[&str] = &["MB8", "IB1", "200"];

/// The subroutines: LEAF and MID compile whole (MID calls LEAF: depth 2), SLOW has a
/// generic instruction (so a CALL of it ends a region).
const SUBROUTINES: &str = "SUBROUTINE_BLOCK LEAF:SBR0\nVAR_INPUT\n  a : INT;\nEND_VAR\n\
    VAR_OUTPUT\n  r : INT;\nEND_VAR\nBEGIN\nNETWORK 1\nLD SM0.0\nMOVW #a, #r\n+I 7, #r\n\
    LDW> #a, 100\n= M4.0\nEND_SUBROUTINE_BLOCK\n\
    SUBROUTINE_BLOCK MID:SBR1\nVAR_INPUT\n  a : INT;\nEND_VAR\nVAR_IN_OUT\n  b : DINT;\nEND_VAR\n\
    BEGIN\nNETWORK 1\nLD SM0.0\n+D 1, #b\nCALL LEAF, #a, MW30\nAN M4.0\n= M4.1\nEND_SUBROUTINE_BLOCK\n\
    SUBROUTINE_BLOCK SLOW:SBR2\nVAR_INPUT\n  a : INT;\nEND_VAR\nBEGIN\nNETWORK 1\nLD SM0.0\n\
    INCW MW40\nMOVW #a, MW42\nEND_SUBROUTINE_BLOCK\n";

fn statement() -> impl Strategy<Value = String> {
    (
        prop::sample::select(STATEMENTS),
        prop::sample::select(BITS),
        prop::sample::select(OUTS),
        prop::sample::select(WORDS),
        prop::sample::select(WORDS_OUT),
        prop::sample::select(DWORDS),
        prop::sample::select(DWORDS_OUT),
        prop::sample::select(BYTES),
    )
        .prop_map(|(s, bit, out, w, w2, d, d2, b)| {
            s.replace("{bit}", bit)
                .replace("{out}", out)
                .replace("{w2}", w2)
                .replace("{w}", w)
                .replace("{d2}", d2)
                .replace("{d}", d)
                .replace("{b}", b)
        })
}

fn main_block() -> impl Strategy<Value = String> {
    let network = (
        prop::sample::select(BITS),
        any::<bool>(),
        prop::collection::vec(statement(), 1..7),
    );
    prop::collection::vec(network, 1..10).prop_map(|nets| {
        let mut s = String::from(
            "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\nMOVD &MB50, MD20\n",
        );
        for (k, (first, inverted, body)) in nets.iter().enumerate() {
            let ld = if *inverted { "LDN" } else { "LD" };
            s.push_str(&format!("NETWORK {}\n{ld} {first}\n", k + 2));
            for st in body {
                s.push_str(st);
                s.push('\n');
            }
        }
        s.push_str("END_ORGANIZATION_BLOCK\n");
        s.push_str(SUBROUTINES);
        s
    })
}

/// Run all three for `inputs` scans; they must agree after each.
fn agree(text: &str, watchdog: u64, inputs: &[[u8; 3]]) -> Result<[Vm; 3], TestCaseError> {
    let mut vms = load3(text, watchdog);
    prop_assert!(
        matches!(vms[2].tier(), TierState::Compiled { .. }),
        "compiled at load: {:?}",
        vms[2].tier()
    );
    for (scan, input) in inputs.iter().enumerate() {
        let mut outcomes = Vec::new();
        for vm in &mut vms {
            common::set(vm, "IB0", u32::from(input[0]));
            common::set(vm, "IB1", u32::from(input[1]));
            common::set(vm, "MW0", u32::from(input[2]) * 300);
            outcomes.push((vm.run_scan(), vm.executed_last_scan(), vm.fault_position()));
        }
        for (k, vm) in vms.iter().enumerate().skip(1) {
            prop_assert_eq!(
                &outcomes[k],
                &outcomes[0],
                "scan {} outcome, VM {}\n{}",
                scan,
                k,
                text
            );
            prop_assert!(
                memory(vm) == memory(&vms[0]),
                "memory differs after scan {} (VM {})\n{}",
                scan,
                k,
                text
            );
        }
    }
    Ok(vms)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn compiled_interpreted_and_reference_agree(
        text in main_block(),
        inputs in prop::collection::vec(any::<[u8; 3]>(), 1..5),
    ) {
        agree(&text, 10_000_000, &inputs)?;
    }

    /// A small watchdog trips inside what would be a region: the compiled tier must
    /// leave it to the interpreter, which trips on the same instruction.
    #[test]
    fn the_watchdog_trips_on_the_same_instruction(
        text in main_block(),
        watchdog in 1..40u64,
    ) {
        agree(&text, watchdog, &[[1, 2, 3], [4, 5, 6]])?;
    }
}

/// Every region of the fixed program runs natively: MAIN compiles whole (its CALLs
/// are of whole subroutines), so one native call runs the scan.
#[test]
fn a_program_of_compilable_networks_compiles_whole() {
    let text = format!(
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD I0.0\nA M0.1\n= Q0.0\n\
         NETWORK 2\nLD SM0.0\nMOVW 5, MW0\nCALL MID, MW0, MD10\nCALL LEAF, MW0, MW2\n\
         END_ORGANIZATION_BLOCK\n{SUBROUTINES}"
    );
    let [mut reference, _, mut native] = load3(&text, 10_000_000);
    match native.tier() {
        TierState::Compiled {
            regions,
            code_bytes,
            ..
        } => {
            assert!(*regions >= 1 && *code_bytes > 0, "{:?}", native.tier());
        }
        other => panic!("not compiled: {other:?}"),
    }
    // A second VM of the same program shares the code while the first one lives.
    let [.., second] = load3(&text, 10_000_000);
    assert!(
        matches!(second.tier(), TierState::Compiled { shared: true, .. }),
        "{:?}",
        second.tier()
    );
    for _ in 0..3 {
        reference.scan().expect("scan");
        native.scan().expect("scan");
    }
    assert_eq!(memory(&native), memory(&reference));
    assert_eq!(common::read(&native, "MD10"), 3, "MID ran three times");
    assert_eq!(common::read(&native, "MW2"), 12, "LEAF: 5 + 7");
    assert_eq!(native.executed_last_scan(), reference.executed_last_scan());
}

/// The default: compiled after `DEFAULT_NATIVE_AFTER` completed scans, not before.
#[test]
fn the_default_compiles_after_its_scans() {
    // A program no other test compiles, so nothing is shared.
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD I0.0\nA M0.1\nAN M0.2\n= Q0.7\n\
        END_ORGANIZATION_BLOCK\n";
    let mut vm = common::load(text, VmConfig::default());
    for _ in 1..gutta_vm::DEFAULT_NATIVE_AFTER {
        vm.scan().expect("scan");
    }
    assert_eq!(vm.tier(), &TierState::Interpreted);
    vm.scan().expect("scan");
    assert!(
        matches!(vm.tier(), TierState::Compiled { .. }),
        "{:?}",
        vm.tier()
    );
    let mut off = common::load(
        text,
        VmConfig {
            fast: false,
            native_after: Some(0),
            ..VmConfig::default()
        },
    );
    off.scan().expect("scan");
    assert_eq!(off.tier(), &TierState::Interpreted, "no tier without fast");
}

/// CALLs nested as deep as CallDepth (8) allows run natively (MAIN and S0..S6 are
/// regions, S7 of two instructions is only a callee; the chain runs as native calls)
/// and agree. Deeper nesting never
/// loads (the compiler and the verifier refuse it), so the tier's CallDepth guard at a
/// region's entry only matters for routines started on a frame stack that is not empty.
#[test]
fn the_deepest_nesting_runs_natively_and_agrees() {
    let mut text = String::from(
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\nMOVW 1, MW0\nCALL S0\n\
         END_ORGANIZATION_BLOCK\n",
    );
    for k in 0..8 {
        let call = if k < 7 {
            format!("CALL S{}\n", k + 1)
        } else {
            String::new()
        };
        text.push_str(&format!(
            "SUBROUTINE_BLOCK S{k}:SBR{k}\nBEGIN\nNETWORK 1\nLD SM0.0\n+I 1, MW0\n{call}\
             END_SUBROUTINE_BLOCK\n"
        ));
    }
    let mut vms = load3(&text, 10_000_000);
    assert!(
        matches!(vms[2].tier(), TierState::Compiled { regions: 8, .. }),
        "{:?}",
        vms[2].tier()
    );
    let outcomes: Vec<_> = vms
        .iter_mut()
        .map(|vm| (vm.scan(), vm.executed_last_scan(), common::read(vm, "MW0")))
        .collect();
    assert_eq!(outcomes[0], (Ok(()), 3 + 7 * 3 + 2, 9), "{outcomes:?}");
    assert_eq!(outcomes[1], outcomes[0]);
    assert_eq!(outcomes[2], outcomes[0]);
}

/// A breakpoint inside a compiled region pauses there; cleared, the region runs
/// natively again and the VMs still agree.
#[test]
fn a_breakpoint_inside_a_region_pauses_there() {
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\nMOVW 7, MW0\n\
        +I 1, MW2\nMOVW MW2, MW4\n= Q0.0\nEND_ORGANIZATION_BLOCK\n";
    let [mut reference, _, mut native] = load3(text, 10_000_000);
    let at = Position {
        function: 0,
        network: 1,
        step: 2,
    };
    for vm in [&mut reference, &mut native] {
        vm.scan().expect("scan");
        vm.set_breakpoint(Some(at)).expect("breakpoint");
        assert_eq!(vm.run_scan(), Ok(ScanEnd::Paused(at)));
        assert_eq!(common::read(vm, "MW2"), 1, "paused before the second +I");
        vm.set_breakpoint(None).expect("cleared");
        vm.debug_run();
        vm.scan().expect("the paused scan ends");
        vm.scan().expect("scan");
    }
    assert_eq!(memory(&native), memory(&reference));
    assert_eq!(common::read(&native, "MW2"), 3);
}

/// A long MAIN is cut into several regions, run one after the other; the watchdog can
/// trip in any of them (the region it would trip in runs interpreted).
#[test]
fn a_long_unit_runs_as_consecutive_regions() {
    let mut text = String::from("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n");
    for k in 0..200 {
        text.push_str(&format!(
            "NETWORK {}\nLD I0.{}\nA M{}.{}\nO Q1.{}\n= M{}.{}\nLD SM0.0\n+I 1, MW{}\n",
            k + 1,
            k % 8,
            (k / 8) % 16,
            (k * 3) % 8,
            k % 5,
            20 + k / 8,
            k % 8,
            (k % 10) * 2 + 108
        ));
    }
    text.push_str("END_ORGANIZATION_BLOCK\n");
    for watchdog in [10_000_000, 1_300, 700] {
        let mut vms = load3(&text, watchdog);
        assert!(
            matches!(vms[2].tier(), TierState::Compiled { regions, .. } if *regions >= 2),
            "{:?}",
            vms[2].tier()
        );
        for scan in 0..3u32 {
            let outcomes: Vec<_> = vms
                .iter_mut()
                .map(|vm| {
                    common::set(vm, "IB0", (0x5A ^ (scan * 77)) & 0xFF);
                    (vm.scan(), vm.executed_last_scan(), vm.fault_position())
                })
                .collect();
            assert_eq!(outcomes[1], outcomes[0], "scan {scan}, watchdog {watchdog}");
            assert_eq!(outcomes[2], outcomes[0], "scan {scan}, watchdog {watchdog}");
            assert!(memory(&vms[1]) == memory(&vms[0]) && memory(&vms[2]) == memory(&vms[0]));
        }
    }
}
