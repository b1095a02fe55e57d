//! The generic families the compiled tier takes (`vm/src/tier_generic.rs`: word logic,
//! INC/DEC, /I /D MUL DIV, shifts and rotates, conversions, REAL math, SQRT and
//! compares, MOVx of an address, SWAP, LDS, NOP) against their handlers in `ops/`:
//! random programs using every one, run by the reference semantics (`fast` off), the
//! interpreter and compiled at load, with random inputs (REAL bit patterns included:
//! NaN, infinities) over many scans; memory, instruction count and outcome agree after
//! every scan. And a MAIN made of them compiles whole (one region): every mnemonic here
//! is compiled, none splits the unit.
#![cfg(feature = "jit")]

mod common;

use gutta_vm::{TierState, Vm, VmConfig};
use proptest::prelude::*;

/// Every mnemonic the tier takes from `tier_generic`, with placeholders.
const STATEMENTS: &[&str] = &[
    "ANDB {b}, {b2}",
    "ANDW {w}, {w2}",
    "ANDD {d}, {d2}",
    "ORB {b}, {b2}",
    "ORW {w}, {w2}",
    "ORD {d}, {d2}",
    "XORB {b}, {b2}",
    "XORW {w}, {w2}",
    "XORD {d}, {d2}",
    "INVB {b2}",
    "INVW {w2}",
    "INVD {d2}",
    "INCB {b2}",
    "INCW {w2}",
    "INCD {d2}",
    "DECB {b2}",
    "DECW {w2}",
    "DECD {d2}",
    "/I {w}, {w2}",
    "/D {d}, {d2}",
    "MUL {w}, {d2}",
    "DIV {w}, {d2}",
    "SRB {b2}, {n}",
    "SRW {w2}, {n}",
    "SRD {d2}, {n}",
    "SLB {b2}, {n}",
    "SLW {w2}, {n}",
    "SLD {d2}, {n}",
    "RRB {b2}, {n}",
    "RRW {w2}, {n}",
    "RRD {d2}, {n}",
    "RLB {b2}, {n}",
    "RLW {w2}, {n}",
    "RLD {d2}, {n}",
    "BTI {b}, {w2}",
    "ITB {w}, {b2}",
    "ITD {w}, {d2}",
    "DTI {d}, {w2}",
    "DTR {d}, {r2}",
    "ROUND {r}, {d2}",
    "TRUNC {r}, {d2}",
    "BCDI {w2}",
    "IBCD {w2}",
    "SEG {b}, {b2}",
    "DECO {b}, {w2}",
    "ENCO {w}, {b2}",
    "+R {r}, {r2}",
    "-R {r}, {r2}",
    "*R {r}, {r2}",
    "/R {r}, {r2}",
    "SQRT {r}, {r2}",
    "AR= {r}, {r2}",
    "OR<> {r}, {r2}",
    "AR< {r}, {r2}",
    "OR<= {r}, {r2}",
    "AR> {r}, {r2}",
    "OR>= {r}, {r2}",
    "LDR< {r}, {r2}\nOLD",
    "LDR>= {r}, {r2}\nALD",
    "MOVD &MB50, {d2}",
    "SWAP {w2}",
    "LD {bit}\nLDS 1\nALD\nOLD",
    "LDS 0\nALD",
    "NOP",
    "= {out}",
    "AN {bit}",
    "LPS\nAN {bit}\n= {out}\nLPP",
];

const BITS: &[&str] = &[
    "I0.0", "I0.5", "I1.2", "M0.0", "M1.3", "SM1.0", "SM1.1", "SM1.3",
];
const OUTS: &[&str] = &["M0.0", "M1.3", "Q0.1", "M3.0"];
const BYTES: &[&str] = &["MB8", "IB1", "MB2", "200", "0"];
const BYTES_OUT: &[&str] = &["MB8", "MB2", "MB9"];
const WORDS: &[&str] = &[
    "MW0", "MW2", "MW4", "IW0", "16#7FFF", "-32768", "0", "-1", "16#1234",
];
const WORDS_OUT: &[&str] = &["MW0", "MW2", "MW4", "MW6"];
const DWORDS: &[&str] = &["MD10", "MD14", "MD60", "2147483647", "-7", "0"];
const DWORDS_OUT: &[&str] = &["MD10", "MD14", "MD20"];
const REALS: &[&str] = &["MD60", "MD64", "MD68", "2.5", "-0.5", "0.0", "3.0E+9"];
const REALS_OUT: &[&str] = &["MD60", "MD64"];
const COUNTS: &[&str] = &[
    "MB8", "MB9", "0", "1", "7", "8", "9", "16", "17", "33", "255",
];

#[allow(clippy::too_many_arguments)]
fn fill(s: &str, picks: [&str; 10]) -> String {
    let [bit, out, b, b2, w, w2, d, d2, r, r2] = picks;
    s.replace("{bit}", bit)
        .replace("{out}", out)
        .replace("{b2}", b2)
        .replace("{b}", b)
        .replace("{w2}", w2)
        .replace("{w}", w)
        .replace("{d2}", d2)
        .replace("{d}", d)
        .replace("{r2}", r2)
        .replace("{r}", r)
}

fn statement() -> impl Strategy<Value = String> {
    (
        prop::sample::select(STATEMENTS),
        (
            prop::sample::select(BITS),
            prop::sample::select(OUTS),
            prop::sample::select(BYTES),
            prop::sample::select(BYTES_OUT),
            prop::sample::select(WORDS),
        ),
        (
            prop::sample::select(WORDS_OUT),
            prop::sample::select(DWORDS),
            prop::sample::select(DWORDS_OUT),
            prop::sample::select(REALS),
            prop::sample::select(REALS_OUT),
        ),
        prop::sample::select(COUNTS),
    )
        .prop_map(|(s, (bit, out, b, b2, w), (w2, d, d2, r, r2), n)| {
            fill(s, [bit, out, b, b2, w, w2, d, d2, r, r2]).replace("{n}", n)
        })
}

fn program() -> impl Strategy<Value = String> {
    let network = (
        prop::sample::select(BITS),
        any::<bool>(),
        prop::collection::vec(statement(), 1..8),
    );
    prop::collection::vec(network, 1..10).prop_map(|nets| {
        let mut s = String::from("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n");
        for (k, (first, inverted, body)) in nets.iter().enumerate() {
            let ld = if *inverted { "LDN" } else { "LD" };
            s.push_str(&format!("NETWORK {}\n{ld} {first}\n", k + 1));
            for st in body {
                s.push_str(st);
                s.push('\n');
            }
        }
        s.push_str("END_ORGANIZATION_BLOCK\n");
        s
    })
}

/// The three engines, loaded.
fn load3(text: &str) -> [Vm; 3] {
    common::three_engines(VmConfig::default()).map(|c| common::load(text, c))
}

/// Inputs of one scan: IB0, IB1, MW0, MD68 (a REAL's bits), MD10.
type Inputs = (u8, u8, u16, u32, u32);

/// Run all three over `inputs` (one scan each); they must agree after each.
fn agree(text: &str, inputs: &[Inputs]) -> Result<(), TestCaseError> {
    let mut vms = load3(text);
    prop_assert!(
        matches!(vms[2].tier(), TierState::Compiled { .. }),
        "compiled at load: {:?}\n{}",
        vms[2].tier(),
        text
    );
    for (scan, &(i0, i1, w, real, d)) in inputs.iter().enumerate() {
        let mut outcomes = Vec::new();
        for vm in &mut vms {
            common::set(vm, "IB0", u32::from(i0));
            common::set(vm, "IB1", u32::from(i1));
            if scan % 3 == 0 {
                common::set(vm, "MW0", u32::from(w));
                common::set(vm, "MD68", real);
                common::set(vm, "MD10", d);
            }
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
                common::areas(vm) == common::areas(&vms[0]),
                "memory differs after scan {} (VM {})\n{}",
                scan,
                k,
                text
            );
        }
    }
    Ok(())
}

/// A REAL's bits: mostly ordinary values, sometimes NaN, infinities, zeros, halves.
fn real_bits() -> impl Strategy<Value = u32> {
    prop_oneof![
        any::<u32>(),
        (-1000i32..1000).prop_map(|k| (k as f32 * 0.5).to_bits()),
        prop::sample::select(vec![
            f32::NAN.to_bits(),
            0xFFC0_0000,
            f32::INFINITY.to_bits(),
            f32::NEG_INFINITY.to_bits(),
            (-0.0f32).to_bits(),
            2_147_483_648f32.to_bits(),
            (-2_147_483_648f32).to_bits(),
        ]),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn generic_families_agree_on_three_engines(
        text in program(),
        inputs in prop::collection::vec(
            (any::<u8>(), any::<u8>(), any::<u16>(), real_bits(), any::<u32>()),
            1..24,
        ),
    ) {
        agree(&text, &inputs)?;
    }
}

/// A MAIN of every mnemonic, each with plain operands: one region (a mnemonic the tier
/// did not take would cut MAIN in two), and the three engines agree on it.
#[test]
fn a_main_of_every_generic_family_compiles_whole() {
    let mut text = String::from("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\n");
    for s in STATEMENTS {
        let line = fill(
            s,
            [
                "I0.0", "M3.0", "MB8", "MB9", "MW0", "MW2", "MD10", "MD14", "MD60", "MD64",
            ],
        )
        .replace("{n}", "MB8");
        text.push_str(&line);
        text.push('\n');
    }
    text.push_str("END_ORGANIZATION_BLOCK\n");
    let vms = load3(&text);
    assert!(
        matches!(vms[2].tier(), TierState::Compiled { regions: 1, .. }),
        "{:?}",
        vms[2].tier()
    );
    let inputs: Vec<Inputs> = (0..40u32)
        .map(|k| {
            (
                k as u8,
                (k * 7) as u8,
                (k * 2_731) as u16,
                (k as f32 * 1.25 - 20.0).to_bits(),
                k.wrapping_mul(0x9E37_79B9),
            )
        })
        .collect();
    agree(&text, &inputs).expect("the three engines agree");
}
