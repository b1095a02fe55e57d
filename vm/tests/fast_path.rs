//! The pre-decoded operations against the semantics in `ops/`: random programs of bit
//! logic, stack operations, moves, integer math, compares, pointer moves and calls run with
//! `VmConfig::fast` on and off from the same inputs, and every byte of memory must
//! agree after every scan. A second generator nests planned CALLs up to CallDepth, trips
//! the watchdog anywhere (inside fused chains and inside calls) and puts a breakpoint
//! anywhere (inside fused operations) on the fast side only.

mod common;

use gutta_format::UnitRef;
use gutta_vm::{Position, ScanEnd, Vm, VmConfig};
use proptest::prelude::*;

fn bit() -> impl Strategy<Value = String> {
    prop_oneof![
        (0..2u32, 0..8u32).prop_map(|(b, i)| format!("I{b}.{i}")),
        (0..4u32, 0..8u32).prop_map(|(b, i)| format!("M{b}.{i}")),
        (0..2u32, 0..8u32).prop_map(|(b, i)| format!("Q{b}.{i}")),
        Just("SM0.0".to_string()),
        Just("SM0.1".to_string()),
        Just("SM1.1".to_string()),
    ]
}

fn out_bit() -> impl Strategy<Value = String> {
    prop_oneof![
        (0..4u32, 0..8u32).prop_map(|(b, i)| format!("M{b}.{i}")),
        (0..2u32, 0..8u32).prop_map(|(b, i)| format!("Q{b}.{i}")),
    ]
}

fn word() -> impl Strategy<Value = String> {
    (0..6u32).prop_map(|k| format!("MW{}", k * 2))
}

fn dword() -> impl Strategy<Value = String> {
    (0..4u32).prop_map(|k| format!("MD{}", k * 2))
}

fn word_in() -> impl Strategy<Value = String> {
    prop_oneof![
        word(),
        Just("IW0".to_string()),
        (-40000i32..40000).prop_map(|v| v.clamp(-32768, 32767).to_string()),
        Just("16#7FFF".to_string()),
    ]
}

fn dword_in() -> impl Strategy<Value = String> {
    prop_oneof![dword(), any::<i32>().prop_map(|v| v.to_string())]
}

fn byte_in() -> impl Strategy<Value = String> {
    prop_oneof![
        (0..8u32).prop_map(|k| format!("MB{k}")),
        (0..=255u32).prop_map(|v| v.to_string()),
    ]
}

/// Logic that leaves exactly one level on the stack.
fn logic() -> impl Strategy<Value = String> {
    let combine = prop_oneof![
        bit().prop_map(|b| format!("A {b}")),
        bit().prop_map(|b| format!("AN {b}")),
        bit().prop_map(|b| format!("O {b}")),
        bit().prop_map(|b| format!("ON {b}")),
        Just("NOT".to_string()),
        (word(), word_in(), 0..6usize).prop_map(|(a, b, r)| {
            let rel = ["=", "<>", "<", "<=", ">", ">="][r];
            format!("AW{rel} {a}, {b}")
        }),
        (dword(), dword_in(), 0..6usize).prop_map(|(a, b, r)| {
            let rel = ["=", "<>", "<", "<=", ">", ">="][r];
            format!("OD{rel} {a}, {b}")
        }),
        (bit(), bit(), any::<bool>())
            .prop_map(|(a, b, and)| format!("LD {a}\nA {b}\n{}", if and { "ALD" } else { "OLD" })),
    ];
    let first = prop_oneof![
        bit().prop_map(|b| format!("LD {b}")),
        bit().prop_map(|b| format!("LDN {b}")),
        (byte_in(), byte_in(), 0..6usize).prop_map(|(a, b, r)| {
            let rel = ["=", "<>", "<", "<=", ">", ">="][r];
            format!("LDB{rel} {a}, {b}")
        }),
    ];
    (first, prop::collection::vec(combine, 0..5)).prop_map(|(f, rest)| {
        let mut s = f;
        for r in rest {
            s.push('\n');
            s.push_str(&r);
        }
        s
    })
}

fn action() -> impl Strategy<Value = String> {
    prop_oneof![
        out_bit().prop_map(|b| format!("= {b}")),
        (out_bit(), 1..4u32).prop_map(|(b, n)| format!("S {b}, {n}")),
        (out_bit(), 1..4u32).prop_map(|(b, n)| format!("R {b}, {n}")),
        (word_in(), word()).prop_map(|(a, b)| format!("MOVW {a}, {b}")),
        (dword_in(), dword()).prop_map(|(a, b)| format!("MOVD {a}, {b}")),
        (byte_in(), (0..8u32)).prop_map(|(a, b)| format!("MOVB {a}, MB{b}")),
        (word_in(), word(), 0..3usize)
            .prop_map(|(a, b, k)| format!("{} {a}, {b}", ["+I", "-I", "*I"][k])),
        (dword_in(), dword(), 0..3usize)
            .prop_map(|(a, b, k)| format!("{} {a}, {b}", ["+D", "-D", "*D"][k])),
        word_in().prop_map(|a| format!("MOVW {a}, *MD20")),
        (word_in(), dword(), word()).prop_map(|(a, b, r)| format!("CALL SUB, {a}, {b}, {r}")),
        (dword(), word()).prop_map(|(b, r)| format!("CALL SUB, *MD20, {b}, {r}")),
        (out_bit(), out_bit()).prop_map(|(a, b)| format!("LPS\n= {a}\nLPP\n= {b}")),
    ]
}

fn network() -> impl Strategy<Value = String> {
    (logic(), prop::collection::vec(action(), 1..3)).prop_map(|(l, acts)| {
        let mut s = l;
        for a in acts {
            s.push('\n');
            s.push_str(&a);
        }
        s
    })
}

/// A subroutine with an input, an in-out and an output parameter.
const SUB: &str = "SUBROUTINE_BLOCK SUB:SBR0\nVAR_INPUT\n  a : INT;\nEND_VAR\n\
    VAR_IN_OUT\n  b : DINT;\nEND_VAR\nVAR_OUTPUT\n  r : INT;\nEND_VAR\nBEGIN\n\
    NETWORK 1\nLD SM0.0\nMOVW #a, #r\n+I 7, #r\n+D 1, #b\nEND_SUBROUTINE_BLOCK\n";

fn program() -> impl Strategy<Value = String> {
    prop::collection::vec(network(), 1..8).prop_map(|nets| {
        // MD20 points into M for the pointer moves.
        let mut s = String::from(
            "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\nMOVD &MB40, MD20\n",
        );
        for (k, n) in nets.iter().enumerate() {
            s.push_str(&format!("NETWORK {}\n{n}\n", k + 2));
        }
        s.push_str("END_ORGANIZATION_BLOCK\n");
        s.push_str(SUB);
        s
    })
}

/// CallDepth of the default PLC type (stdlib ManagerFun.xml): MAIN, NEST0.. and SUB
/// nest that deep at most (8 subroutines on the default PLC type).
const CALL_DEPTH: usize = 8;

/// Subroutine `NEST{k}` of a chain of `depth` (SBR1..SBR7): bit logic gated by its INT
/// input, a planned CALL of the next with its own L variables as the arguments (read from
/// and written back into the saved L), math on its in-out and output.
fn nest(k: usize, depth: usize) -> String {
    // The last calls SUB (SBR0, same parameters): MAIN and depth + 1 subroutines deep.
    let callee = if k + 1 < depth {
        format!("NEST{}", k + 1)
    } else {
        "SUB".to_string()
    };
    let call = format!("NETWORK 2\nLDW>= #g, 0\nA SM0.0\nCALL {callee}, #g, #n, #r\n");
    format!(
        "SUBROUTINE_BLOCK NEST{k}:SBR{}\nVAR_INPUT\n  g : INT;\nEND_VAR\n\
         VAR_IN_OUT\n  n : DINT;\nEND_VAR\nVAR_OUTPUT\n  r : INT;\nEND_VAR\n\
         VAR\n  t : INT;\nEND_VAR\nBEGIN\nNETWORK 1\nLDW> #g, 0\nAN M0.{}\nO M1.{}\n\
         = M2.{}\n+D 1, #n\nMOVW {}, #t\n{call}NETWORK 3\nLD SM0.0\n+I #t, #r\n\
         +I {k}, #r\nEND_SUBROUTINE_BLOCK\n",
        k + 1,
        k % 8,
        (k + 3) % 8,
        k % 8,
        k * 3,
    )
}

/// `program()` with a chain of `depth` nested subroutines (MAIN -> NEST0 -> ... ), called
/// from a network of MAIN that also runs some fused bit logic.
fn deep_program() -> impl Strategy<Value = (String, usize)> {
    (program(), 1..CALL_DEPTH).prop_map(|(text, depth)| {
        let call = "NETWORK 90\nLD I0.0\nO I0.1\nAN I0.2\n= M3.0\nCALL NEST0, MW4, MD8, MW12\n";
        let mut s = text.replacen(
            "END_ORGANIZATION_BLOCK",
            &format!("{call}END_ORGANIZATION_BLOCK"),
            1,
        );
        for k in 0..depth {
            s.push_str(&nest(k, depth));
        }
        (s, depth)
    })
}

fn set_inputs(vm: &mut Vm, input: [u8; 4]) {
    common::set(vm, "IB0", u32::from(input[0]));
    common::set(vm, "IB1", u32::from(input[1]));
    common::set(vm, "MB3", u32::from(input[2]));
    common::set(vm, "MW4", u32::from(input[3]) * 257);
}

/// Run a scan through every pause at the breakpoint (each pause continues at once).
fn scan_through_breakpoints(vm: &mut Vm) -> Result<(), gutta_vm::Fault> {
    for _ in 0..1000 {
        match vm.run_scan()? {
            ScanEnd::Paused(_) => vm.debug_run(),
            _ => return Ok(()),
        }
    }
    panic!("a scan paused 1000 times");
}

fn all_memory(vm: &Vm) -> Vec<(u8, Vec<u8>)> {
    vm.target()
        .memory
        .areas
        .iter()
        .map(|a| (a.slot, vm.memory().area(a.slot).unwrap_or(&[]).to_vec()))
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn fast_and_generic_agree(text in program(), inputs in prop::collection::vec(any::<[u8; 4]>(), 1..4)) {
        let mut fast = common::load(&text, VmConfig::default());
        let mut slow = common::load(&text, VmConfig { fast: false, ..VmConfig::default() });
        for (scan, input) in inputs.iter().enumerate() {
            for vm in [&mut fast, &mut slow] {
                common::set(vm, "IB0", u32::from(input[0]));
                common::set(vm, "IB1", u32::from(input[1]));
                common::set(vm, "MB3", u32::from(input[2]));
                common::set(vm, "MW4", u32::from(input[3]) * 257);
                vm.scan().expect("scan");
            }
            prop_assert_eq!(fast.executed_last_scan(), slow.executed_last_scan());
            prop_assert!(all_memory(&fast) == all_memory(&slow), "memory differs after scan {}\n{}", scan, text);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// Deep planned CALLs, a small watchdog and a breakpoint anywhere: the fast side
    /// (paused at its breakpoint and continued) and the reference agree on every byte,
    /// on the instructions executed and on where a watchdog fault happened.
    #[test]
    fn deep_calls_watchdog_and_breakpoints_agree(
        (text, depth) in deep_program(),
        cut in 0..120u64,
        (unit, network, step) in (0..=CALL_DEPTH, 1..12u16, 0..8u16),
        inputs in prop::collection::vec(any::<[u8; 4]>(), 1..4),
    ) {
        // The watchdog at `cut` percent of the first scan's instructions: most cases trip
        // it, anywhere in the scan.
        let mut probe = common::load(&text, VmConfig { fast: false, ..VmConfig::default() });
        set_inputs(&mut probe, inputs[0]);
        probe.scan().expect("scan");
        let watchdog = (probe.executed_last_scan() * cut / 100).max(1);
        let mut fast = common::load(&text, VmConfig { watchdog, ..VmConfig::default() });
        let mut slow = common::load(&text, VmConfig { watchdog, fast: false, ..VmConfig::default() });
        // MAIN, a nested subroutine or SUB (a position that is no instruction is
        // refused: then no breakpoint).
        let function = match unit {
            0 => 0,
            CALL_DEPTH => UnitRef::subroutine(0).page(&fast.target().plc).expect("page"),
            k => UnitRef::subroutine(k.min(depth) as u16).page(&fast.target().plc).expect("page"),
        };
        let _ = fast.set_breakpoint(Some(Position { function, network, step }));
        for (scan, input) in inputs.iter().enumerate() {
            for vm in [&mut fast, &mut slow] {
                set_inputs(vm, *input);
            }
            let (f, s) = (scan_through_breakpoints(&mut fast), slow.scan());
            prop_assert_eq!(&f, &s, "scan {}\n{}", scan, text);
            prop_assert_eq!(fast.fault_position(), slow.fault_position());
            prop_assert_eq!(fast.executed_last_scan(), slow.executed_last_scan());
            prop_assert!(all_memory(&fast) == all_memory(&slow), "memory differs after scan {}\n{}", scan, text);
            if f.is_err() {
                break;
            }
        }
    }
}

/// The decoded forms do run: a program of only fast operations is as fast as its
/// operations, and a slow build of the same program still agrees (one fixed case that
/// covers every fast operation, including the overflow and negative flags).
#[test]
fn every_fast_operation_agrees() {
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\nMOVD -5, MD4\n-D 7, MD4\n\
        MOVW 16#7FFF, MW0\n+I 1, MW0\nMOVB 200, MB8\nMOVR MD4, MD12\n= M2.0\n\
        NETWORK 2\nLDN M2.0\nO I0.0\nON I0.1\nA SM0.0\nAN I0.2\nNOT\nLPS\n= Q0.0\nLRD\n= Q0.1\nLPP\n= Q0.2\n\
        NETWORK 3\nLD I0.0\nLD I0.1\nOLD\nLD SM0.0\nALD\n= Q0.3\n\
        NETWORK 4\nLDW< MW0, 0\nAD<= MD4, -12\nOB> MB8, 100\n= Q0.4\nEND_ORGANIZATION_BLOCK\n";
    let mut fast = common::load(text, VmConfig::default());
    let mut slow = common::load(
        text,
        VmConfig {
            fast: false,
            ..VmConfig::default()
        },
    );
    fast.scan().expect("scan");
    slow.scan().expect("scan");
    assert_eq!(all_memory(&fast), all_memory(&slow));
    assert_eq!(common::read(&fast, "MW0"), 0x8000);
    assert_eq!(common::read(&fast, "SM1.1"), 1, "overflow flag");
    assert_eq!(common::read(&fast, "MD4") as i32, -12);
    assert_eq!(common::read(&fast, "Q0.4"), 1);
}
