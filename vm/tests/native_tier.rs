//! The compiled tier (docs/vm-jit.md) against the interpreter and the reference
//! semantics: random programs of the families real programs are made of (bit logic and
//! the logic stack, SM bits, edges, timers of every kind and resolution, counters, S/R
//! and their immediate forms, compares, moves, math, conversions, shifts and word logic
//! of every width, JMP/LBL forward over blocks and backward in a loop that ends, an SCR
//! sequence, FOR/NEXT, CALLs of subroutines that compile whole, of one with a generic
//! instruction and of one with parameters of every kind, pointers), run three ways:
//! `fast` off (every instruction through `ops/`), the interpreter (`native_after: None`)
//! and compiled at load (`native_after: Some(0)`), for 30 scans and more of inputs held a
//! few scans each, at scan times of 1 to 30 ms. Memory (every area and the hidden state
//! after them), the instruction count and the outcome must agree after every scan; the
//! watchdog, CallDepth and breakpoints must land on the same instruction.
//! `PROPTEST_CASES` overrides the number of cases.
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

/// Statements a network may hold after its first LD. A `{name}` is replaced by an operand
/// of the list `name` (see `Operands`), chosen with the statement; `{body}` (FOR) by
/// one of `FOR_BODY`.
const STATEMENTS: &[&str] = &[
    // Bit logic and the logic stack.
    "A {bit}",
    "AN {bit}",
    "O {bit}",
    "ON {bit}",
    "NOT",
    "= {out}",
    "AW> {cell}, 1",
    "OW<= {cell}, 2",
    "LPS\n= {out}\nLPP",
    "LPS\nA {bit}\n= {out}\nLRD\nAN {bit2}\n= {out2}\nLPP",
    "LD {bit}\nOLD",
    "LD {bit}\nALD",
    "LD {bit}\nLDS 1\nOLD\nALD",
    "LDN {bit}\nLD {bit2}\nLDS 2\nALD\nOLD\nALD",
    // Edges: several instances may watch the same input.
    "EU",
    "ED",
    "EU\n= {out}",
    "LD {bit}\nED\nOLD",
    // Timers of each kind and resolution, preset literal or in a word.
    "TON {ton}, {pt}",
    "TOF {tof}, {pt}",
    "TONR {tonr}, {pt}",
    "TON {ton}, {pt}\n= {out}",
    "TOF {tof}, {pt}\nAW< {cell}, 3\n= {out}",
    "MOVW 0, {cell}",
    // Counters, with reset/load from inputs.
    "LD {bit}\nCTU {cu}, {pv}",
    "LD {bit}\nCTD {cd}, {pv}",
    "LD {bit}\nLD {bit2}\nCTUD {cud}, {pv}",
    "AW>= {cell}, {pv}",
    // S/R and their immediate forms, N crossing bytes or from a byte.
    "S {sr}, {n}",
    "R {sr}, {n}",
    "SI {q}, {n}",
    "RI {q}, {n}",
    "S {out}, 2",
    "R {out}, 1",
    // Compares of every width, combined.
    "AB= {b}, 7",
    "AB<> {b}, {bb}",
    "OB>= {b}, {bb}",
    "LDB< {b}, {bb}\nALD",
    "AW>= {w}, {ww}",
    "OW< {w}, {ww}",
    "LDW<> {w}, {ww}\nOLD",
    "AD= {d}, {dd}",
    "OD< {d}, {dd}",
    "LDD> {d}, {dd}\nALD",
    "AR< {r}, {rr}",
    "OR>= {r}, {rr}",
    "LDR= {r}, {rr}\nOLD",
    "LDR<> {r}, {rr}\nALD",
    // Moves, math, conversions, shifts, INC/DEC, word logic of every width.
    "MOVB {b}, {bo}",
    "MOVW {w}, {wo}",
    "MOVD {d}, {do}",
    "MOVR {r}, {ro}",
    "MOVW {w}, *MD20",
    "SWAP {wo}",
    "+I {w}, {wo}",
    "-I 1000, {wo}",
    "-I {w}, {wo}",
    "*I {w}, {wo}",
    "/I {w}, {wo}",
    "+D {d}, {do}",
    "-D {d}, {do}",
    "*D {d}, {do}",
    "/D {d}, {do}",
    "+R {r}, {ro}",
    "-R {r}, {ro}",
    "*R {r}, {ro}",
    "/R {r}, {ro}",
    "SQRT {r}, {ro}",
    "MUL {w}, {do}",
    "DIV {w}, {do}",
    "INCB {bo}",
    "DECB {bo}",
    "INCW {wo}",
    "DECW {wo}",
    "INCD {do}",
    "DECD {do}",
    "BTI {b}, {wo}",
    "ITB {w}, {bo}",
    "ITD {w}, {do}",
    "DTI {d}, {wo}",
    "DTR {d}, {ro}",
    "ROUND {r}, {do}",
    "TRUNC {r}, {do}",
    "ANDB {b}, {bo}",
    "ORB {b}, {bo}",
    "XORB {b}, {bo}",
    "INVB {bo}",
    "ANDW {w}, {wo}",
    "ORW {w}, {wo}",
    "XORW {w}, {wo}",
    "INVW {wo}",
    "ANDD {d}, {do}",
    "ORD {d}, {do}",
    "XORD {d}, {do}",
    "INVD {do}",
    "SLB {bo}, {sh}",
    "SRB {bo}, {sh}",
    "RLB {bo}, {sh}",
    "RRB {bo}, {sh}",
    "SLW {wo}, {sh}",
    "SRW {wo}, {sh}",
    "RLW {wo}, {sh}",
    "RRW {wo}, {sh}",
    "SLD {do}, {sh}",
    "SRD {do}, {sh}",
    "RLD {do}, {sh}",
    "RRD {do}, {sh}",
    // CALLs: whole subroutines, one with a generic instruction, one with parameters of
    // every kind (literal arguments too).
    "CALL LEAF, {w}, {wo}",
    "CALL MID, {w}, {do}",
    "CALL SLOW, {w}",
    "CALL PARAMS, {bit}, {b}, {w}, {d}, {r}, {wo}, {do}, {out}",
    // FOR/NEXT, literal and variable bounds, nested.
    "FOR MW64, 1, {fe}\n{body}\nNEXT",
    "FOR MW64, {fe}, 2\n{body}\nNEXT\n= {out}",
    "FOR MW64, 1, 2\nFOR MW66, 1, {fe}\n{body}\nNEXT\n{body}\nNEXT",
    "LD {bit}\nCTU C3, 4",
];

/// What a FOR loop's body holds (no FOR: its index words are the loop's).
const FOR_BODY: &[&str] = &[
    "INCW {wo}",
    "+I {w}, {wo}",
    "EU\n= {out}",
    "TON {ton}, {pt}",
    "LD {bit}\nCTU {cu}, {pv}",
    "S {sr}, {n}",
    "CALL PARAMS, {bit}, {b}, {w}, {d}, {r}, {wo}, {do}, {out}",
    "*R {r}, {ro}",
    "AW> {w}, {ww}\n= {out}",
];

const BITS: &[&str] = &[
    "I0.0", "I0.5", "I1.2", "M0.0", "M1.3", "M2.7", "Q0.1", "M6.2", "SM0.0", "SM0.1", "SM0.5",
    "SM1.0", "SM1.1", "SM1.2", "SM1.3",
];
const OUTS: &[&str] = &["M0.0", "M1.3", "M2.7", "Q0.1", "Q0.4", "M3.0"];
const WORDS: &[&str] = &[
    "MW0", "MW2", "MW4", "IW0", "16#7FFF", "-32768", "3", "T4", "C0",
];
const WORDS_OUT: &[&str] = &["MW0", "MW2", "MW4", "MW6"];
const DWORDS: &[&str] = &["MD10", "MD14", "2147483647", "-7", "100000"];
const DWORDS_OUT: &[&str] = &["MD10", "MD14"];
const BYTES: &[&str] = &["MB8", "IB1", "200", "MB74"];
const BYTES_OUT: &[&str] = &["MB8", "MB9"];
const REALS: &[&str] = &["MD56", "MD60", "1.5", "-2.25", "MD10", "1.0E+10"];
const REALS_OUT: &[&str] = &["MD56", "MD60"];
/// S/R starts: bits whose N (up to 20) crosses bytes.
const SR_BITS: &[&str] = &["M5.3", "M6.0", "M7.7", "Q0.5", "M2.7"];
const Q_BITS: &[&str] = &["Q0.0", "Q0.6", "Q1.3"];
/// N of S/R: 1..20 literal, or MB74 (set from the inputs, 0..20).
const COUNTS: &[&str] = &["1", "2", "3", "7", "8", "9", "13", "16", "17", "20", "MB74"];
const SHIFTS: &[&str] = &["0", "1", "3", "8", "15", "17", "33", "MB9"];
/// Timer presets: small literals, or MW72 (set from the inputs, 0..15).
const PRESETS: &[&str] = &["0", "1", "2", "3", "5", "12", "MW72"];
/// FOR bounds: small literals, or MW68 (set from the inputs, 0..3).
const FOR_ENDS: &[&str] = &["0", "1", "3", "MW68"];
/// Timer and counter cells read as words (their bits are what their boxes leave on the
/// logic stack), and written (TONR's reset).
const CELLS: &[&str] = &["T0", "T2", "T4", "T6", "T8", "T9", "C0", "C2", "C4", "C5"];
const CTU: &[&str] = &["C0", "C1"];
const CTD: &[&str] = &["C2"];
const CTUD: &[&str] = &["C4", "C5"];

/// Timer numbers per kind. CPU-EC20: T0-T1 count 1 ms, T2-T3 10 ms, T4-T15 100 ms; a
/// layout (0..3) gives the 1 ms and 10 ms timers to different kinds, so over the cases
/// every kind runs at every resolution. T9 is PARAMS' TON.
fn timer_numbers(layout: u8) -> [Vec<&'static str>; 3] {
    let mut kinds: [Vec<&'static str>; 3] = [vec!["T4", "T9"], vec!["T5", "T6"], vec!["T7", "T8"]];
    for (k, fast) in [["T0", "T2"], ["T1", "T3"]].iter().enumerate() {
        let kind = (usize::from(layout) + k) % 3;
        kinds[kind].extend(fast);
    }
    kinds
}

/// The subroutines: LEAF and MID compile whole (MID calls LEAF: depth 2), SLOW has a
/// generic instruction (so a CALL of it ends a region).
const SUBROUTINES: &str = "SUBROUTINE_BLOCK LEAF:SBR0\nVAR_INPUT\n  a : INT;\nEND_VAR\n\
    VAR_OUTPUT\n  r : INT;\nEND_VAR\nBEGIN\nNETWORK 1\nLD SM0.0\nMOVW #a, #r\n+I 7, #r\n\
    LDW> #a, 100\n= M4.0\nEND_SUBROUTINE_BLOCK\n\
    SUBROUTINE_BLOCK MID:SBR1\nVAR_INPUT\n  a : INT;\nEND_VAR\nVAR_IN_OUT\n  b : DINT;\nEND_VAR\n\
    BEGIN\nNETWORK 1\nLD SM0.0\n+D 1, #b\nCALL LEAF, #a, MW30\nAN M4.0\n= M4.1\nEND_SUBROUTINE_BLOCK\n\
    SUBROUTINE_BLOCK SLOW:SBR2\nVAR_INPUT\n  a : INT;\nEND_VAR\nBEGIN\nNETWORK 1\nLD SM0.0\n\
    INCW MW40\nMOVW #a, MW42\nEND_SUBROUTINE_BLOCK\n";

/// A subroutine with parameters of every kind (BOOL, BYTE, WORD, DWORD, REAL in; INT
/// in-out; DINT and BOOL out) and a timer, an edge, a compare and a forward jump.
const PARAMS: &str = "SUBROUTINE_BLOCK PARAMS:SBR3\nVAR_INPUT\n  en : BOOL;\n  y : BYTE;\n\
    w : WORD;\n  d : DWORD;\n  r : REAL;\nEND_VAR\nVAR_IN_OUT\n  io : INT;\nEND_VAR\n\
    VAR_OUTPUT\n  o : DINT;\n  q : BOOL;\nEND_VAR\nBEGIN\nNETWORK 1\nLD #en\nTON T9, 3\n= #q\n\
    NETWORK 2\nLD SM0.0\n+I #w, #io\nITD #io, #o\n+D #d, #o\nMOVB #y, MB80\n\
    NETWORK 3\nLDB> #y, 100\nJMP 1\nNETWORK 4\nLD SM0.0\nINCW MW82\n\
    NETWORK 5\nLBL 1\nLDR> #r, 1.0\nEU\nINCW MW84\nEND_SUBROUTINE_BLOCK\n";

/// A statement to be filled in: its template and the seeds choosing its operands.
#[derive(Debug, Clone)]
struct Template {
    text: &'static str,
    seeds: Vec<u16>,
}

fn template(list: &'static [&'static str]) -> impl Strategy<Value = Template> {
    (
        prop::sample::select(list),
        prop::collection::vec(any::<u16>(), 24),
    )
        .prop_map(|(text, seeds)| Template { text, seeds })
}

/// Fill `t` in: each placeholder takes the next seed.
fn fill(t: &Template, timers: &[Vec<&'static str>; 3]) -> String {
    let mut out = String::new();
    let mut rest = t.text;
    let mut seeds = t.seeds.iter().cycle();
    while let Some(open) = rest.find('{') {
        out.push_str(&rest[..open]);
        let close = open + rest[open..].find('}').expect("a closed placeholder");
        let name = &rest[open + 1..close];
        let seed = usize::from(*seeds.next().expect("seeds"));
        let list: &[&str] = match name {
            "bit" | "bit2" => BITS,
            "out" | "out2" => OUTS,
            "w" | "ww" => WORDS,
            "wo" => WORDS_OUT,
            "d" | "dd" => DWORDS,
            "do" => DWORDS_OUT,
            "b" | "bb" => BYTES,
            "bo" => BYTES_OUT,
            "r" | "rr" => REALS,
            "ro" => REALS_OUT,
            "sr" => SR_BITS,
            "q" => Q_BITS,
            "n" => COUNTS,
            "sh" => SHIFTS,
            "pt" | "pv" => PRESETS,
            "fe" => FOR_ENDS,
            "cell" => CELLS,
            "cu" => CTU,
            "cd" => CTD,
            "cud" => CTUD,
            "ton" => &timers[0],
            "tof" => &timers[1],
            "tonr" => &timers[2],
            "body" => FOR_BODY,
            other => panic!("no operand list {other}"),
        };
        let chosen = list[seed % list.len()];
        if name == "body" {
            let inner = Template {
                text: chosen,
                seeds: t.seeds.iter().rev().copied().collect(),
            };
            out.push_str(&fill(&inner, timers));
        } else {
            out.push_str(chosen);
        }
        rest = &rest[close + 1..];
    }
    out.push_str(rest);
    out
}

/// A network: its first contact (inverted or not) and its statements.
type Network = (&'static str, bool, Vec<Template>);

/// What MAIN is made of: networks, a forward JMP over networks (timers, CALLs, ...
/// inside), or a loop of a backward JMP that ends after three rounds.
#[derive(Debug, Clone)]
enum Item {
    Network(Network),
    Skip(&'static str, Vec<Network>),
    Loop(Vec<Network>),
}

fn network() -> impl Strategy<Value = Network> {
    (
        prop::sample::select(BITS),
        any::<bool>(),
        prop::collection::vec(template(STATEMENTS), 1..6),
    )
}

fn item() -> impl Strategy<Value = Item> {
    prop_oneof![
        6 => network().prop_map(Item::Network),
        1 => (prop::sample::select(BITS), prop::collection::vec(network(), 1..3))
            .prop_map(|(bit, nets)| Item::Skip(bit, nets)),
        1 => prop::collection::vec(network(), 1..3).prop_map(Item::Loop),
    ]
}

/// An SCR sequence of two steps (S0.x are MB96's bits, as in the Micro/WIN dialect): step 0 goes
/// to step 1 on `to1`, step 1 back on `to0`, and leaves its segment early on `cut`.
#[derive(Debug, Clone)]
struct Sequence {
    to1: &'static str,
    to0: &'static str,
    cut: &'static str,
    steps: [Vec<Network>; 2],
}

fn sequence() -> impl Strategy<Value = Option<Sequence>> {
    prop::option::of(
        (
            prop::sample::select(BITS),
            prop::sample::select(BITS),
            prop::sample::select(BITS),
            prop::collection::vec(network(), 1..3),
            prop::collection::vec(network(), 1..3),
        )
            .prop_map(|(to1, to0, cut, a, b)| Sequence {
                to1,
                to0,
                cut,
                steps: [a, b],
            }),
    )
}

/// Assembles MAIN's text, numbering networks and labels.
struct Writer<'a> {
    text: String,
    networks: usize,
    labels: u8,
    timers: &'a [Vec<&'static str>; 3],
}

impl Writer<'_> {
    fn start(&mut self, head: &str) {
        self.networks += 1;
        self.text
            .push_str(&format!("NETWORK {}\n{head}\n", self.networks));
    }

    fn network(&mut self, (first, inverted, body): &Network) {
        let ld = if *inverted { "LDN" } else { "LD" };
        self.start(&format!("{ld} {first}"));
        for t in body {
            let s = fill(t, self.timers);
            self.text.push_str(&s);
            self.text.push('\n');
        }
    }

    fn item(&mut self, item: &Item) {
        match item {
            Item::Network(n) => self.network(n),
            Item::Skip(bit, nets) => {
                self.labels += 1;
                let label = self.labels;
                self.start(&format!("LD {bit}\nJMP {label}"));
                for n in nets {
                    self.network(n);
                }
                self.start(&format!("LBL {label}"));
            }
            Item::Loop(nets) => {
                self.labels += 1;
                let label = self.labels;
                self.start("LD SM0.0\nMOVW 0, MW70");
                self.start(&format!("LBL {label}\nLD SM0.0\nINCW MW70"));
                for n in nets {
                    self.network(n);
                }
                self.start(&format!("LDW< MW70, 3\nJMP {label}"));
            }
        }
    }

    /// The sequence as the Micro/WIN dialect compiles it (docs/microwin.md, "Sequence
    /// control relays": `LSCR S0.k` is `LDN M96.k` `JMP l` `NOT`, `SCRT` a set and a
    /// reset, `CSCRE` `JMP l`, `SCRE` `LBL l`): the VM never sees SCR itself, and the
    /// dialect's stricter checks (one preset per timer whose bit is read) would refuse
    /// most random programs.
    fn sequence(&mut self, s: &Sequence) {
        self.start("LD SM0.1\nS M96.0, 1");
        for (k, step) in s.steps.iter().enumerate() {
            let label = 200 + k;
            self.start(&format!("LDN M96.{k}\nJMP {label}\nNOT"));
            for n in step {
                self.network(n);
            }
            let (to, next) = if k == 0 { (s.to1, 1) } else { (s.to0, 0) };
            self.start(&format!("LD {to}\nS M96.{next}, 1\nR M96.{k}, 1"));
            if k == 1 {
                self.start(&format!("LD {}\nJMP {label}", s.cut));
                self.start("LD SM0.0\nINCW MW86");
            }
            self.start(&format!("LBL {label}"));
        }
    }
}

/// A random program: MAIN of networks, jumps and loops (and an SCR sequence), and the
/// subroutines.
fn main_block() -> impl Strategy<Value = String> {
    (prop::collection::vec(item(), 1..9), sequence(), 0..3u8).prop_map(
        |(items, sequence, layout)| {
            let timers = timer_numbers(layout);
            let mut w = Writer {
                text: String::new(),
                networks: 0,
                labels: 0,
                timers: &timers,
            };
            w.start("LD SM0.0\nMOVD &MB50, MD20");
            // Every cell the statements read is driven by a timer or counter.
            let drive = |kind: &str, list: &[&str], pt: &str| {
                list.iter()
                    .map(|t| format!("{kind} {t}, {pt}\n"))
                    .collect::<String>()
            };
            w.start(&format!(
                "LD I0.3\n{}{}{}",
                drive("TON", &timers[0], "4"),
                drive("TOF", &timers[1], "MW72"),
                drive("TONR", &timers[2], "6")
            ));
            w.start("LD I0.4\nLD I0.6\nCTU C0, 3");
            w.start("LD I1.0\nLD I0.6\nCTU C1, MW72");
            w.start("LD I0.4\nLD I1.1\nCTD C2, 2");
            w.start("LD I0.4\nLD I1.0\nLD I0.6\nCTUD C4, 5");
            w.start("LD I1.1\nLD I0.4\nLD I1.0\nCTUD C5, MW72");
            for item in &items {
                w.item(item);
            }
            if let Some(s) = &sequence {
                w.sequence(s);
            }
            format!(
                "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n{}END_ORGANIZATION_BLOCK\n\
                 {SUBROUTINES}{PARAMS}",
                w.text
            )
        },
    )
}

/// Scans' inputs: each held for a few scans (timers need time), at least 30 scans.
fn scan_inputs() -> impl Strategy<Value = Vec<[u8; 3]>> {
    prop::collection::vec((any::<[u8; 3]>(), 1..12usize), 3..8).prop_map(|held| {
        let mut scans: Vec<[u8; 3]> = held
            .iter()
            .flat_map(|(input, n)| std::iter::repeat_n(*input, *n))
            .collect();
        while scans.len() < 30 {
            let last = *scans.last().expect("inputs");
            scans.push(last);
        }
        scans
    })
}

/// Run all three for `inputs` scans; they must agree after each: the outcome, the
/// instruction count, the fault's position and all memory (hidden state included).
fn agree(text: &str, config: VmConfig, inputs: &[[u8; 3]]) -> Result<[Vm; 3], TestCaseError> {
    let mut vms = common::three_engines(config).map(|c| common::load(text, c));
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
            common::set(vm, "MW68", u32::from(input[2] & 3));
            common::set(vm, "MW72", u32::from(input[1] & 15));
            common::set(vm, "MB74", u32::from(input[0] % 21));
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
                common::areas(vm) == common::areas(&vms[0]) && vm.memory() == vms[0].memory(),
                "memory differs after scan {} (VM {})\n{}",
                scan,
                k,
                text
            );
        }
    }
    Ok(vms)
}

/// Scan times: timers of every resolution see whole units, remainders and several
/// units a scan.
const SCAN_MS: &[u32] = &[1, 7, 10, 30];

/// `PROPTEST_CASES` when set, else `default`.
#[allow(
    clippy::disallowed_methods,
    reason = "a test reads proptest's own variable"
)]
fn cases(default: u32) -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default);
    ProptestConfig::with_cases(cases)
}

proptest! {
    #![proptest_config(cases(160))]

    #[test]
    fn compiled_interpreted_and_reference_agree(
        text in main_block(),
        inputs in scan_inputs(),
        scan_ms in prop::sample::select(SCAN_MS),
    ) {
        agree(&text, VmConfig { watchdog: 10_000_000, scan_ms, ..VmConfig::default() }, &inputs)?;
    }

    /// A small watchdog trips inside what would be a region: the compiled tier must
    /// leave it to the interpreter, which trips on the same instruction.
    #[test]
    fn the_watchdog_trips_on_the_same_instruction(
        text in main_block(),
        watchdog in 1..120u64,
    ) {
        agree(&text, VmConfig { watchdog, ..VmConfig::default() }, &[[1, 2, 3], [4, 5, 6], [4, 5, 6]])?;
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
    assert_eq!(common::areas(&native), common::areas(&reference));
    // Everything ran natively (`Vm::executed_natively`, what the benchmark reports).
    assert_eq!(
        native.executed_natively(),
        3 * native.executed_last_scan(),
        "every instruction of the three scans in compiled code"
    );
    assert_eq!(reference.executed_natively(), 0);
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

/// CALLs nested as deep as CallDepth (8) allows run natively (MAIN and S0..S7 are
/// regions, each unit compiling whole, however short; the chain runs as native calls)
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
        matches!(vms[2].tier(), TierState::Compiled { regions: 9, .. }),
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
    assert_eq!(common::areas(&native), common::areas(&reference));
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
            assert!(
                common::areas(&vms[1]) == common::areas(&vms[0])
                    && common::areas(&vms[2]) == common::areas(&vms[0])
            );
        }
    }
}
