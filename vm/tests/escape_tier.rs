//! Escapes (docs/vm-jit.md, "Escapes"): boxes the compiled tier keeps interpreted (EXCH,
//! ATCH, DTCH, CEVNT) sit inside a region; without power flow the region runs over them,
//! with power flow it returns there, the interpreter runs the box and goes on in the
//! resume region after it. Three engines (reference, interpreter, compiled at load)
//! on programs whose boxes are powered on some scans and not on others, with attached
//! interrupts that then fire: memory, count and outcome agree after every scan. An
//! escape as a region's first and last record, two in a row, one inside a JMP's span;
//! the AN2002 master runs natively but for its powered EXCH boxes; random MAINs of
//! boxes among compiled statements and forward JMPs.
#![cfg(feature = "jit")]

mod common;

use gutta_vm::{TierState, Vm, VmConfig};

/// MAIN: timed interrupt 0 (event 10, period SMB10 from IB3) attached to A or detached
/// from the inputs, event 11 to B on the first scan only; EXCH powered by I0.3; two
/// boxes in a row (ATCH then CEVNT on I1.1); a DTCH inside a JMP's span (jumped over
/// while I0.4); ENI every scan and DISI when I1.4 (Flow Always: compiled as a store of
/// the interrupt enable byte), an ATCH (on I1.2) right after ENI; an EXCH as MAIN's
/// last record.
const PROGRAM: &str = "
ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1
LD     SM0.0
MOVB   IB3, SMB10
MOVB   IB3, SMB11
A      I0.0
=      M0.0
NETWORK 2
LD     I1.0
ATCH   A, 10
LD     SM0.1
ATCH   B, 11
LD     I0.1
A      I0.2
=      Q0.1
+I     1, MW10
NETWORK 3
LD     I0.3
EXCH   MB20, 0
NETWORK 4
LD     I1.1
ATCH   A, 10
CEVNT  10
LD     I0.5
=      Q0.2
INCW   MW12
NETWORK 5
LD     I0.4
JMP    1
NETWORK 6
LD     I0.6
DTCH   10
=      Q0.3
INCW   MW14
NETWORK 7
LBL    1
NETWORK 8
LD     I0.7
AN     I1.0
=      Q0.4
+I     3, MW16
LD     I1.2
ENI
ATCH   B, 11
NETWORK 9
LD     I1.3
A      I0.0
=      Q0.5
+I     5, MW18
NETWORK 10
LDN    I1.4
JMP    2
NETWORK 11
DISI
NETWORK 12
LBL    2
NETWORK 13
LD     I1.5
O      I0.0
A      I0.1
=      Q0.6
+I     7, MW30
LD     I1.6
EXCH   MB50, 0
END_ORGANIZATION_BLOCK

INTERRUPT_BLOCK A:INT1
BEGIN
NETWORK 1
LD     SM0.0
INCW   MW40
MOVW   MW40, MW42
LD     I0.0
DTCH   11
END_INTERRUPT_BLOCK

INTERRUPT_BLOCK B:INT2
BEGIN
NETWORK 1
LD     SM0.0
INCW   MW44
END_INTERRUPT_BLOCK
";

/// A small deterministic generator of the inputs (xorshift).
struct Inputs(u32);

impl Inputs {
    fn next(&mut self) -> u32 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.0 = x;
        x
    }
}

fn three(text: &str) -> [Vm; 3] {
    common::three_engines(VmConfig {
        scan_ms: 7,
        ..VmConfig::default()
    })
    .map(|c| common::load(text, c))
}

/// Scan the three VMs `scans` times with inputs from `inputs` (IB0, IB1 each scan;
/// IB3 1..=20 ms); they must agree after every scan. Returns the compiled VM's native
/// count and the total count.
fn agree(vms: &mut [Vm; 3], scans: u32, seed: u32) -> (u64, u64) {
    let mut inputs = Inputs(seed);
    let mut total = 0;
    for scan in 0..scans {
        let (ib0, ib1, ib3) = (
            inputs.next() & 0xFF,
            inputs.next() & 0xFF,
            1 + inputs.next() % 20,
        );
        let mut outcomes = Vec::new();
        for vm in vms.iter_mut() {
            common::set(vm, "IB0", ib0);
            common::set(vm, "IB1", ib1);
            common::set(vm, "IB3", ib3);
            outcomes.push((vm.run_scan(), vm.executed_last_scan(), vm.fault_position()));
        }
        for k in 1..3 {
            assert_eq!(
                outcomes[k], outcomes[0],
                "scan {scan} (seed {seed}), VM {k}"
            );
            assert!(
                common::areas(&vms[k]) == common::areas(&vms[0])
                    && vms[k].memory() == vms[0].memory(),
                "memory after scan {scan} (seed {seed}), VM {k}"
            );
        }
        total += vms[0].executed_last_scan();
    }
    (vms[2].executed_natively(), total)
}

#[test]
fn boxes_powered_on_some_scans_agree_in_three_engines() {
    for seed in [1, 0x9E37_79B9, 0xDEAD_BEEF, 12345, 777] {
        let mut vms = three(PROGRAM);
        assert!(
            matches!(vms[2].tier(), TierState::Compiled { .. }),
            "{:?}",
            vms[2].tier()
        );
        let (native, total) = agree(&mut vms, 300, seed);
        // The interrupt routines ran (A counts MW40).
        assert!(common::read(&vms[0], "MW40") > 0, "routine A never ran");
        // Most of it natively: the boxes are powered half the time here, and they,
        // ENI/DISI, the interrupt routines (5 instructions: not worth a region) and
        // the records around them that no region is worth covering stay interpreted.
        assert!(
            native * 10 >= total * 6,
            "natively {native} of {total} (seed {seed})"
        );
    }
}

/// Unpowered boxes: all of MAIN natively (interpreted only interrupt routine B, whose
/// 2 instructions are too few for a region); with every box powered, the five boxes
/// interpreted, and after them at most the short runs no resume region covers.
#[test]
fn powered_boxes_run_interpreted_and_the_rest_natively() {
    let mut vms = three(PROGRAM);
    for vm in &mut vms {
        common::set(vm, "IB3", 10);
        vm.scan().expect("first scan");
    }
    let before = vms[2].executed_natively();
    for vm in &mut vms {
        // No box powered; no jump.
        common::set(vm, "IB0", 0);
        common::set(vm, "IB1", 0);
        vm.scan().expect("scan");
    }
    let executed = vms[2].executed_last_scan();
    let quiet = executed - (vms[2].executed_natively() - before);
    assert_eq!(executed, vms[0].executed_last_scan());
    let before = vms[2].executed_natively();
    for vm in &mut vms {
        // Every box powered (I0.3 EXCH, I1.1 ATCH+CEVNT, I0.6 DTCH, I1.6 EXCH), no jump;
        // I1.0 off (no ATCH there), I1.2 off (no ATCH after ENI).
        common::set(vm, "IB0", 0b0100_1000);
        common::set(vm, "IB1", 0b0101_0010);
        vm.scan().expect("scan");
    }
    let executed_powered = vms[2].executed_last_scan();
    let powered = executed_powered - (vms[2].executed_natively() - before);
    assert_eq!(executed_powered, vms[0].executed_last_scan());
    assert!(common::areas(&vms[2]) == common::areas(&vms[0]));
    assert!(
        quiet <= 2,
        "unpowered: {quiet} of {executed} interpreted (routine B's 2 at most)"
    );
    assert!(
        (5..=5 + 12).contains(&powered),
        "powered: {powered} of {executed_powered} interpreted (the five boxes and at most 12 more)"
    );
}

/// The AN2002 master (examples/an2002_sample3_master.lad, polling on, no port): its
/// EXCH boxes no longer split MAIN; only the scans that queue the exchanges (T4 done)
/// run the two EXCH interpreted.
#[test]
fn the_an2002_master_runs_natively_but_for_its_powered_exch() {
    let text = include_str!("../../examples/an2002_sample3_master.lad");
    let mut vms = three(text);
    let mut total = 0;
    for scan in 0..2_000u32 {
        for vm in &mut vms {
            common::set(vm, "I0.1", 1);
            vm.scan().expect("scan");
        }
        assert_eq!(
            vms[2].executed_last_scan(),
            vms[0].executed_last_scan(),
            "scan {scan}"
        );
        assert!(vms[2].memory() == vms[0].memory(), "scan {scan}");
        total += vms[0].executed_last_scan();
    }
    let native = vms[2].executed_natively();
    // A pulse every 200 ms at 7 ms scans: about one scan in 30 runs two EXCH powered.
    assert!(native * 100 >= total * 99, "natively {native} of {total}");
    assert!(native < total, "the powered EXCH ran interpreted");
}

/// One network of a random program: its LD input, its statements, and whether a JMP
/// from it (to the label before network `to`) is taken on its LD's input instead.
#[derive(Debug, Clone)]
struct Network {
    input: (u8, u8),
    statements: Vec<usize>,
    jump_to: Option<usize>,
}

/// Statements after a network's LD: contacts, coils, math, and the boxes that become
/// escapes (`{k}`: the network's number, so words differ).
const STATEMENTS: &[&str] = &[
    "A      I1.{b}",
    "AN     I0.{b}",
    "=      Q0.{b}",
    "+I     1, MW{k}",
    "INCW   MW{k}",
    "EXCH   MB20, 0",
    "ATCH   A, 10",
    "ATCH   B, 11",
    "DTCH   10",
    "DTCH   11",
    "CEVNT  10",
    "EXCH   MB50, 0",
];

fn network(count: usize) -> impl proptest::strategy::Strategy<Value = Network> {
    use proptest::prelude::*;
    (
        (0u8..2, 0u8..8),
        proptest::collection::vec(0..STATEMENTS.len(), 1..5),
        proptest::option::weighted(0.2, 0..count),
    )
        .prop_map(|(input, statements, jump_to)| Network {
            input,
            statements,
            jump_to,
        })
}

/// MAIN: the period of event 10 from IB3, ENI, then the networks; a network's JMP goes
/// to a label before a later network (none when `to` is not a later one).
fn program(networks: &[Network]) -> String {
    let mut text = String::from(
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\nMOVB IB3, SMB10\n\
         MOVB IB3, SMB11\nNETWORK 2\nENI\n",
    );
    let mut labels = std::collections::BTreeSet::new();
    for (k, n) in networks.iter().enumerate() {
        if labels.contains(&k) {
            text.push_str(&format!("NETWORK\nLBL {k}\n"));
        }
        text.push_str(&format!("NETWORK\nLD I{}.{}\n", n.input.0, n.input.1));
        for &s in &n.statements {
            let b = (k + s) % 8;
            text.push_str(
                &STATEMENTS[s]
                    .replace("{b}", &b.to_string())
                    .replace("{k}", &(60 + 2 * (k % 20)).to_string()),
            );
            text.push('\n');
        }
        if let Some(to) = n.jump_to.filter(|&to| to > k && to < networks.len()) {
            text.push_str(&format!("NETWORK\nLD I1.{}\nJMP {to}\n", k % 8));
            labels.insert(to);
        }
    }
    text.push_str(
        "END_ORGANIZATION_BLOCK\n\
         INTERRUPT_BLOCK A:INT1\nBEGIN\nNETWORK 1\nLD SM0.0\nINCW MW40\nEND_INTERRUPT_BLOCK\n\
         INTERRUPT_BLOCK B:INT2\nBEGIN\nNETWORK 1\nLD SM0.0\nINCW MW42\nEND_INTERRUPT_BLOCK\n",
    );
    text
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(48))]

    /// Random MAINs of networks whose boxes (EXCH, ATCH, DTCH, CEVNT) sit among
    /// compiled statements, some inside forward JMPs' spans, on the three engines for
    /// 60 scans of random inputs: memory, count and outcome equal after every scan.
    #[test]
    fn random_programs_with_boxes_agree(
        networks in proptest::collection::vec(network(24), 1..24),
        seed in 1u32..u32::MAX,
    ) {
        let text = program(&networks);
        let mut vms = three(&text);
        proptest::prop_assert!(
            matches!(vms[2].tier(), TierState::Compiled { .. } | TierState::Interpreted),
            "{:?}",
            vms[2].tier()
        );
        agree(&mut vms, 60, seed);
    }
}
