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

// ---- timers, counters, edges, S/R (issue 31) -----------------------------------------

/// A timer: kind, T number (T0-T1 1 ms, T2-T3 10 ms, T4-T15 100 ms on the default PLC
/// type), preset (a literal, a variable, or a pointer: the last stays generic).
fn timer() -> impl Strategy<Value = String> {
    (0..3usize, 0..16u32, preset())
        .prop_map(|(k, n, pt)| format!("{} T{n}, {pt}", ["TON", "TOF", "TONR"][k]))
}

fn preset() -> impl Strategy<Value = String> {
    prop_oneof![
        (-3..40i32).prop_map(|v| v.to_string()),
        Just("0".to_string()),
        Just("32767".to_string()),
        Just("MW60".to_string()),
        Just("MW62".to_string()),
        Just("*MD20".to_string()),
    ]
}

/// Logic that leaves exactly one level on the stack, with timers, counters and edges
/// (each leaves its output on top; `= M10..` records it).
fn stateful_logic() -> impl Strategy<Value = String> {
    let combine = prop_oneof![
        bit().prop_map(|b| format!("A {b}")),
        bit().prop_map(|b| format!("O {b}")),
        timer(),
        timer(),
        (bit(), 0..8u32, preset()).prop_map(|(b, n, pv)| format!("LD {b}\nCTU C{n}, {pv}")),
        (bit(), 0..8u32, preset()).prop_map(|(b, n, pv)| format!("LD {b}\nCTD C{n}, {pv}")),
        (bit(), bit(), 0..8u32, preset())
            .prop_map(|(a, b, n, pv)| format!("LD {a}\nLD {b}\nCTUD C{n}, {pv}")),
        Just("EU".to_string()),
        Just("ED".to_string()),
        (0..16u32).prop_map(|k| format!("= M10.{}\nA M{}.{}", k % 8, 11 + k / 8, k % 8)),
    ];
    (bit(), prop::collection::vec(combine, 1..6)).prop_map(|(first, rest)| {
        let mut s = format!("LD {first}");
        for r in rest {
            s.push('\n');
            s.push_str(&r);
        }
        s
    })
}

fn stateful_action() -> impl Strategy<Value = String> {
    prop_oneof![
        out_bit().prop_map(|b| format!("= {b}")),
        // N from 1 to 20 from any bit: across byte boundaries (the compiler refuses a
        // literal N of 0; a variable N of 0 stays generic, below).
        (0..4u32, 0..8u32, 1..21u32, any::<bool>()).prop_map(|(byte, bit, n, set)| {
            format!("{} M{}.{bit}, {n}", if set { "S" } else { "R" }, 20 + byte)
        }),
        (0..2u32, 0..8u32, 1..12u32).prop_map(|(byte, bit, n)| format!("SI Q{byte}.{bit}, {n}")),
        (0..2u32, 0..8u32, 1..12u32).prop_map(|(byte, bit, n)| format!("RI Q{byte}.{bit}, {n}")),
        // Past the end of M (bytes 0-127): the fault stays the handler's.
        (0..8u32, 1..40u32).prop_map(|(bit, n)| format!("S M126.{bit}, {n}")),
        Just("S M30.0, MB3".to_string()),
        // Generic records the fast path runs itself: INC/DEC, jumps (to labels the
        // program places, forward and backward), and boxes without power flow.
        (0..6usize, 0..4u32).prop_map(|(k, v)| {
            let m = ["INCB", "INCW", "INCD", "DECB", "DECW", "DECD"][k];
            let var = match k % 3 {
                0 => format!("MB{}", 70 + v),
                1 => format!("MW{}", 70 + 2 * v),
                _ => format!("MD{}", 70 + 4 * v),
            };
            format!("{m} {var}")
        }),
        Just("INCW *MD20".to_string()),
        (0..3u32).prop_map(|k| format!("JMP {k}")),
        (0..3u32).prop_map(|k| format!("JMP {k}")),
        Just("/I MW62, MW66".to_string()),
        (0..4u32, 0..4u32).prop_map(|(a, b)| format!("/I MW{}, MW{}", 70 + 2 * a, 70 + 2 * b)),
        (0..4u32, 0..4u32).prop_map(|(a, b)| format!("/D MD{}, MD{}", 70 + 4 * a, 70 + 4 * b)),
        Just("/D -1, MD70".to_string()),
        Just("SWAP MW64".to_string()),
        Just("NOP".to_string()),
        Just("EU\n= M31.0".to_string()),
        timer().prop_map(|t| format!("{t}\n= M31.1")),
    ]
}

fn stateful_program() -> impl Strategy<Value = String> {
    let network = (
        stateful_logic(),
        prop::collection::vec(stateful_action(), 1..3),
    )
        .prop_map(|(l, acts)| {
            let mut s = l;
            for a in acts {
                s.push('\n');
                s.push_str(&a);
            }
            s
        });
    (
        prop::collection::vec(network, 1..8),
        [0..9usize, 0..9, 0..9],
    )
        .prop_map(|(nets, at)| {
            // MD20 points at MW60 (a preset through a pointer).
            let mut s = String::from(
                "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\nMOVD &MB60, MD20\n",
            );
            // LBL 0..2 each in a network of its own, before network `at[k]` (or at the end).
            let mut number = 2;
            for k in 0..=nets.len() {
                for (label, &before) in at.iter().enumerate() {
                    if before.min(nets.len()) == k {
                        s.push_str(&format!("NETWORK {number}\nLBL {label}\n"));
                        number += 1;
                    }
                }
                if let Some(n) = nets.get(k) {
                    s.push_str(&format!("NETWORK {number}\n{n}\n"));
                    number += 1;
                }
            }
            s.push_str("END_ORGANIZATION_BLOCK\n");
            s
        })
}

/// A start value for a timer or counter: at and around the limits, or small.
fn cell_value() -> impl Strategy<Value = u32> {
    prop_oneof![
        Just(0u32),
        Just(32767),
        Just(32766),
        Just(0x8000),
        Just(0x8001),
        Just(0xFFFF),
        0..50u32,
    ]
}

/// The bytes after the areas: timers', counters' and edges' hidden state.
fn hidden(vm: &Vm) -> Vec<u8> {
    vm.memory().hidden().to_vec()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(192))]

    /// Timers (every kind, every resolution, preset literal, variable and through a
    /// pointer), counters (from their limits, reset and load), EU/ED and S/R/SI/RI (N 0
    /// to 20 across bytes, past the area's end) run by the interpreter's fast operations
    /// and by the handlers agree after every scan on every byte of memory, on the hidden
    /// state, on the instructions executed and on faults, with any scan time, across a
    /// reset.
    #[test]
    fn stateful_operations_agree(
        text in stateful_program(),
        scan_ms in prop_oneof![Just(1u32), Just(3), Just(10), Just(55), Just(250), 0..2000u32],
        cells in prop::collection::vec(cell_value(), 24),
        inputs in prop::collection::vec((any::<[u8; 3]>(), -3..40i32, -3..40i32), 1..40),
        reset_at in 0..60usize,
    ) {
        // A backward jump may loop: the watchdog ends it, at the same instruction.
        let base = VmConfig { scan_ms, native_after: None, watchdog: 5000, ..VmConfig::default() };
        let mut fast = common::load(&text, base);
        let mut slow = common::load(&text, VmConfig { fast: false, ..base });
        for vm in [&mut fast, &mut slow] {
            for (k, &v) in cells.iter().enumerate() {
                let cell = if k < 16 { format!("T{k}") } else { format!("C{}", k - 16) };
                common::set(vm, &cell, v);
            }
        }
        for (scan, &(bits, w0, w1)) in inputs.iter().enumerate() {
            for vm in [&mut fast, &mut slow] {
                if scan == reset_at {
                    vm.reset();
                }
                common::set(vm, "IB0", u32::from(bits[0]));
                common::set(vm, "IB1", u32::from(bits[1]));
                common::set(vm, "MB3", u32::from(bits[2]) % 24);
                common::set(vm, "MW60", w0 as u16 as u32);
                common::set(vm, "MW62", w1 as u16 as u32);
            }
            let (f, s) = (fast.scan(), slow.scan());
            prop_assert_eq!(&f, &s, "scan {}\n{}", scan, text);
            prop_assert_eq!(fast.fault_position(), slow.fault_position());
            prop_assert_eq!(fast.executed_last_scan(), slow.executed_last_scan());
            prop_assert!(all_memory(&fast) == all_memory(&slow), "memory differs after scan {}\n{}", scan, text);
            prop_assert!(hidden(&fast) == hidden(&slow), "hidden state differs after scan {}\n{}", scan, text);
            if f.is_err() {
                break;
            }
        }
    }
}

/// Run `text` on the fast path and the handlers `scans` times with `inputs(scan)` set
/// before each scan; both agree after each; returns the fast VM.
fn agree(
    text: &str,
    scan_ms: u32,
    scans: usize,
    inputs: impl Fn(usize) -> Vec<(&'static str, u32)>,
) -> Vm {
    let base = VmConfig {
        scan_ms,
        native_after: None,
        ..VmConfig::default()
    };
    let mut fast = common::load(text, base);
    let mut slow = common::load(
        text,
        VmConfig {
            fast: false,
            ..base
        },
    );
    for scan in 0..scans {
        for vm in [&mut fast, &mut slow] {
            for (var, v) in inputs(scan) {
                common::set(vm, var, v);
            }
        }
        assert_eq!(fast.scan(), slow.scan(), "scan {scan}");
        assert_eq!(fast.executed_last_scan(), slow.executed_last_scan());
        assert_eq!(all_memory(&fast), all_memory(&slow), "scan {scan}");
        assert_eq!(hidden(&fast), hidden(&slow), "scan {scan}");
    }
    fast
}

/// Every timer kind at every resolution, the preset a literal and a variable, with a
/// scan time that leaves remainders (7 ms): the fast path runs them (no generic record
/// left) and agrees with the handlers scan by scan; the values are those of the
/// semantics (a 1 ms timer counts 7 per scan, a 10 ms one 7 per 10 ms).
#[test]
fn timers_agree_at_every_resolution() {
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n\
        NETWORK 1\nLD I0.0\nTON T0, 50\n= Q0.0\nLD I0.0\nTON T2, MW60\n= Q0.1\n\
        LD I0.0\nTON T4, 3\n= Q0.2\n\
        NETWORK 2\nLD I0.1\nTOF T1, 30\n= Q0.3\nLD I0.1\nTOF T3, MW60\n= Q0.4\n\
        LD I0.1\nTOF T5, 2\n= Q0.5\n\
        NETWORK 3\nLD I0.2\nTONR T6, MW62\n= Q0.6\nLD I0.2\nTONR T7, 0\n= Q0.7\n\
        NETWORK 4\nLDN I0.2\nTON T8, -1\n= Q1.0\nEND_ORGANIZATION_BLOCK\n";
    let fast = agree(text, 7, 60, |scan| {
        vec![
            ("I0.0", u32::from((scan / 20) % 2 == 0)),
            ("I0.1", u32::from(scan < 5 || (30..33).contains(&scan))),
            ("I0.2", u32::from(scan % 7 < 4)),
            ("MW60", 12),
            ("MW62", 5),
        ]
    });
    assert_eq!(fast.generic_records(), Vec::<(String, usize)>::new());
    // I0.0 went 1 (0-19), 0 (20-39), 1 (40-59): 20 scans of 7 ms, the first starts.
    assert_eq!(common::read(&fast, "T0"), 19 * 7);
    assert_eq!(common::read(&fast, "T2"), 19 * 7 / 10);
    assert_eq!(common::read(&fast, "Q0.0"), 1);
}

/// Counters at their limits, reset and load, presets literal and variable; EU/ED on
/// rising and falling inputs; S/R across byte boundaries (N 1 to 16; a literal 0 the
/// compiler refuses).
#[test]
fn counters_edges_and_set_bits_agree() {
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n\
        NETWORK 1\nLD I0.0\nLD I0.1\nCTU C0, 5\n= Q0.0\n\
        LD I0.0\nLD I0.1\nCTD C1, MW60\n= Q0.1\n\
        LD I0.0\nLD I0.2\nLD I0.1\nCTUD C2, MW60\n= Q0.2\n\
        LD I0.2\nLD I0.1\nCTUD C3, -32768\n= Q0.3\n\
        NETWORK 2\nLD I0.0\nEU\n= Q1.0\nLD I0.0\nED\n= Q1.1\n\
        NETWORK 3\nLD I0.3\nS M0.6, 5\nR M2.3, 13\nS M5.0, 1\nR M6.7, 1\n\
        NETWORK 4\nLDN I0.3\nR M0.7, 3\nS M2.0, 16\nSI Q1.6, 2\nRI Q1.7, 1\n\
        END_ORGANIZATION_BLOCK\n";
    let base = VmConfig {
        native_after: None,
        ..VmConfig::default()
    };
    let probe = common::load(text, base);
    assert_eq!(probe.generic_records(), Vec::<(String, usize)>::new());
    let fast = agree(text, 10, 40, |scan| {
        let mut v = vec![
            ("I0.0", u32::from(scan % 2 == 0)),
            ("I0.1", u32::from(scan % 11 == 10)),
            ("I0.2", u32::from(scan % 3 == 0)),
            ("I0.3", u32::from(scan % 4 < 2)),
            ("MW60", 3),
        ];
        if scan == 0 {
            // At the limits: CTU at max, CTUD at min.
            v.extend([("C0", 32767), ("C2", 0x8001), ("C3", 0x8000)]);
        }
        v
    });
    // Reset at scan 32; I0.0 rose at 34, 36 and 38 since.
    assert_eq!(common::read(&fast, "C0"), 3);
}

/// Generic records the fast path runs itself: INC/DEC at the edges of their ranges
/// and /I, /D by zero, of MIN by -1 and of negatives (each one's SM1 flags copied
/// after it), LBL and NOP, a forward JMP over networks and
/// a box without power flow; both engines agree and count the same instructions.
#[test]
fn quick_generic_records_agree() {
    let mut text = String::from("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\n");
    let cases = [
        ("INCW", "MW0", "16#FFFF"),
        ("DECW", "MW2", "1"),
        ("INCW", "MW4", "32767"),
        ("DECW", "MW6", "-32768"),
        ("INCD", "MD8", "-1"),
        ("DECD", "MD12", "-2147483648"),
        ("INCB", "MB16", "255"),
        ("DECB", "MB17", "0"),
        ("DECB", "MB18", "1"),
        ("/I 0,", "MW20", "7"),
        ("/I -1,", "MW22", "-32768"),
        ("/I -3,", "MW24", "7"),
        ("/D 2,", "MD28", "-2147483647"),
        ("/D -1,", "MD32", "-2147483648"),
        ("/D 5,", "MD36", "3"),
    ];
    for (k, (m, var, start)) in cases.iter().enumerate() {
        let mov = match var.as_bytes()[1] {
            b'W' => "MOVW",
            b'D' => "MOVD",
            _ => "MOVB",
        };
        text.push_str(&format!(
            "{mov} {start}, {var}\n{m} {var}\nMOVB SMB1, MB{}\n",
            60 + k
        ));
    }
    text.push_str(
        "NETWORK 2\nLD I0.0\nJMP 1\nNETWORK 3\nLD SM0.0\nINCW MW40\nNOP\n\
         NETWORK 4\nLBL 1\nNETWORK 5\nLDN SM0.0\nSWAP MW50\nINCW MW52\n\
         NETWORK 6\nLD SM0.0\nINCW MW46\nEND_ORGANIZATION_BLOCK\n",
    );
    let fast = agree(&text, 10, 4, |scan| {
        vec![("I0.0", u32::from(scan % 2 == 1))]
    });
    // Only the box reaches its handler (with power flow; here it has none).
    assert_eq!(fast.generic_records(), vec![("SWAP".to_string(), 1)]);
    // MW40 counted in the scans I0.0 was 0 (0 and 2), MW46 in every scan.
    assert_eq!(common::read(&fast, "MW40"), 2);
    assert_eq!(common::read(&fast, "MW46"), 4);
    assert_eq!(
        common::read(&fast, "MB62"),
        0b110,
        "32767 + 1: overflow, negative"
    );
    assert_eq!(common::read(&fast, "MB69"), 0b1000, "division by zero");
    assert_eq!(common::read(&fast, "MB70"), 0b0010, "-32768 / -1");
}
