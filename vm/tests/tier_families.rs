//! The tier's translation on a program of every family it takes, against the
//! interpreter scan by scan (docs/vm-jit.md, "Regions"): timers of each kind, counters,
//! edges, S/R, JMP taken and not, a JMP over a CALL, a JMP whose LBL lies past a record
//! the tier leaves to the interpreter (a conditional END, never powered here: the JMP
//! stays interpreted and a region starts where it lands). Memory is compared whole, hidden state included.
#![cfg(feature = "jit")]

mod common;

use gutta_vm::{TierState, VmConfig};

const PROGRAM: &str = "ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1
LD I0.0
TON T7, 3
= Q0.0
NETWORK 2
LD I0.1
TOF T5, 2
= Q0.1
NETWORK 3
LD I0.2
TONR T6, 4
= Q0.2
NETWORK 4
LD I0.0
LD I0.3
CTU C1, 3
= Q0.3
NETWORK 5
LD I0.1
LD I0.3
CTD C2, 2
= Q0.4
NETWORK 6
LD I0.0
LD I0.1
LD I0.3
CTUD C3, 2
= Q0.5
NETWORK 7
LD I0.2
EU
S M0.0, 3
NETWORK 8
LD I0.1
ED
R M0.1, 9
NETWORK 9
LD I0.3
JMP 1
NETWORK 10
LD SM0.0
+I 1, MW10
CALL S0
NETWORK 11
LBL 1
NETWORK 12
LDN I0.0
JMP 2
NETWORK 13
LD SM0.0
+I 3, MW12
NOT
END
NETWORK 14
LD SM0.0
+I 5, MW14
NETWORK 15
LBL 2
NETWORK 16
LD SM0.0
+I 7, MW16
= Q1.0
A I0.1
= Q1.1
O I0.2
= Q1.2
END_ORGANIZATION_BLOCK
SUBROUTINE_BLOCK S0:SBR0
BEGIN
NETWORK 1
LD SM0.0
+I 1, MW20
LD I0.2
JMP 3
NETWORK 2
LD SM0.0
+I 1, MW22
NETWORK 3
LBL 3
END_SUBROUTINE_BLOCK
";

#[test]
fn every_family_the_tier_takes_agrees_with_the_interpreter_scan_by_scan() {
    let mut interpreted = common::load(
        PROGRAM,
        VmConfig {
            native_after: None,
            ..VmConfig::default()
        },
    );
    let mut compiled = common::load(
        PROGRAM,
        VmConfig {
            native_after: Some(0),
            ..VmConfig::default()
        },
    );
    let regions = match compiled.tier() {
        TierState::Compiled { regions, .. } => *regions,
        other => panic!("not compiled: {other:?}"),
    };
    // MAIN up to the JMP 2 (which stays interpreted: its LBL lies past the END),
    // MAIN from where JMP 2 lands (the runs between, of 2 and 3 instructions, are
    // not worth their entry), and SBR0 whole.
    assert_eq!(regions, 3);
    let i0 = compiled.target().memory.parse_address("IB0").expect("IB0");
    for scan in 0..400u32 {
        // Inputs that hold for a while, so timers run out and edges are rare.
        let inputs = (scan / 7) ^ (scan / 23) ^ (scan / 3 % 2);
        for vm in [&mut interpreted, &mut compiled] {
            vm.write(i0, inputs & 0x0F).expect("IB0");
            vm.scan().expect("scan");
        }
        assert_eq!(
            interpreted.executed_last_scan(),
            compiled.executed_last_scan(),
            "instructions of scan {scan}"
        );
        assert!(
            interpreted.memory() == compiled.memory(),
            "memory after scan {scan}"
        );
    }
}

/// A MAIN longer than a region (1,024 records) made of blocks a JMP skips: the tier cuts
/// it where no jump is open, so every JMP keeps its LBL in its region and the whole scan
/// runs natively (cut blindly at 1,024 records, the JMPs around the cut stayed
/// interpreted and the rest of the unit ran as more, shorter regions).
#[test]
fn a_long_unit_is_cut_where_no_jump_is_open() {
    // 15 records a block, so the 1,024th record lies between a JMP and its LBL.
    let mut text = String::from("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n");
    for k in 0..90 {
        text.push_str(&format!(
            "NETWORK\nLDN I0.{b}\nJMP {k}\nNETWORK\nLD SM0.0\n+I 1, MW{w}\nMOVW MW{w}, MW{v}\n\
             NETWORK\nLDW>= MW{w}, 50\n= M{m}.{b}\nNETWORK\nLBL {k}\nNETWORK\nLD M{m}.{b}\n\
             = Q{q}.{b}\n",
            b = k % 8,
            w = 10 + 2 * (k % 20),
            v = 60 + 2 * (k % 20),
            m = 100 + k / 8,
            q = k / 8 % 2,
        ));
    }
    text.push_str("END_ORGANIZATION_BLOCK\n");
    let mut vms = common::three_engines(VmConfig::default()).map(|c| common::load(&text, c));
    match vms[2].tier() {
        TierState::Compiled { regions, .. } => assert!(*regions >= 2, "{regions} regions"),
        other => panic!("not compiled: {other:?}"),
    }
    let mut executed = 0;
    for scan in 0..60u32 {
        for vm in &mut vms {
            common::set(vm, "IB0", (scan / 5) ^ (scan / 3 % 2));
            vm.scan().expect("scan");
        }
        executed += vms[2].executed_last_scan();
        common::same_as_reference(&vms, scan);
    }
    assert_eq!(
        vms[2].executed_natively(),
        executed,
        "every instruction ran natively"
    );
}

/// A region that starts after a generic record the interpreter runs itself (an EXCH, a
/// box: nothing happens without power flow) is entered. Since escapes (tier.rs) the
/// unpowered EXCH runs inside the region, which then covers all of MAIN; powered, the
/// region returns at it, the interpreter runs it, and the resume region after it is
/// entered.
#[test]
fn a_region_after_a_record_the_fast_path_runs_is_entered() {
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD I0.7\nEXCH MB20, 0\n\
                NETWORK 2\nLD I0.0\nA I0.1\n= Q0.0\nLD SM0.0\n+I 1, MW10\nMOVW MW10, MW12\n\
                +I MW12, MW14\nEND_ORGANIZATION_BLOCK\n";
    let mut vms = common::three_engines(VmConfig::default()).map(|c| common::load(text, c));
    for scan in 0..20u32 {
        for vm in &mut vms {
            // I0.7 (the EXCH's power flow) on every third scan.
            common::set(vm, "IB0", (scan % 4) | if scan % 3 == 0 { 0x80 } else { 0 });
            vm.scan().expect("scan");
        }
        common::same_as_reference(&vms, scan);
    }
    // 9 instructions a scan; natively all 9 on the 13 scans without power flow, and on
    // the 7 with it all but the EXCH (LD I0.7, then the 7 of network 2).
    assert_eq!(vms[0].executed_last_scan(), 9);
    assert_eq!(vms[2].executed_natively(), 13 * 9 + 7 * 8);
}

/// FOR and NEXT stay interpreted (docs/vm-jit.md, "What stays interpreted"), but the
/// loop's body is a region of its own: NEXT sends the interpreter back to the record
/// after FOR, where the region starts, so every iteration runs the body natively.
#[test]
fn a_for_loops_body_runs_natively_on_every_iteration() {
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\nFOR MW2, 1, MW0\n\
                NETWORK 2\nLD SM0.0\n+I 1, MW10\nMOVW MW10, MW12\n+I MW2, MW12\nLDW>= MW12, 40\n\
                = M0.0\nA I0.0\n= Q0.0\nNETWORK 3\nNEXT\nEND_ORGANIZATION_BLOCK\n";
    let mut vms = common::three_engines(VmConfig::default()).map(|c| common::load(text, c));
    let mut iterations = 0;
    for scan in 0..30u32 {
        for vm in &mut vms {
            common::set(vm, "MW0", scan % 7);
            common::set(vm, "IB0", scan % 2);
            vm.scan().expect("scan");
        }
        iterations += u64::from(scan % 7);
        common::same_as_reference(&vms, scan);
    }
    // The body's 8 instructions, natively, on every iteration.
    assert_eq!(vms[2].executed_natively(), iterations * 8);
}

/// ENI and DISI compile (a store of the interrupt enable byte in the flat memory): the
/// MAIN of an S7-200 program that attaches a timed interrupt on the first scan and
/// enables interrupts every scan is one region, and DISI while I0.0 keeps the events
/// pending until the next ENI, on the three engines.
#[test]
fn eni_and_disi_run_inside_a_region() {
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.1\nMOVB 10, SMB10\n\
                ATCH TICK, 10\nNETWORK 2\nLD I0.0\nJMP 1\nNETWORK 3\nENI\nNETWORK 4\nLBL 1\n\
                NETWORK 5\nLD I0.0\nNOT\nJMP 2\nNETWORK 6\nDISI\nNETWORK 7\nLBL 2\nNETWORK 8\n\
                LD I0.1\nA I0.2\n= Q0.0\n+I 1, MW10\nEND_ORGANIZATION_BLOCK\n\
                INTERRUPT_BLOCK TICK:INT1\nBEGIN\nNETWORK 1\nLD SM0.0\nINCW MW20\nEND_INTERRUPT_BLOCK\n";
    let mut vms = common::three_engines(VmConfig {
        scan_ms: 3,
        ..VmConfig::default()
    })
    .map(|c| common::load(text, c));
    let mw20 = vms[0].target().memory.parse_address("MW20").expect("MW20");
    let (mut native, mut ran, mut ticks) = (0, 0, 0);
    for scan in 0..120u32 {
        let before = vms[2].executed_natively();
        let ticks_before = vms[2].read(mw20).expect("MW20");
        for vm in &mut vms {
            // Disabled for a while (I0.0), then enabled, several times.
            common::set(vm, "IB0", u32::from(scan / 10 % 3 == 1) | (scan % 8) << 1);
            vm.scan().expect("scan");
        }
        common::same_as_reference(&vms, scan);
        if scan > 0 {
            native += vms[2].executed_natively() - before;
            ran += vms[2].executed_last_scan();
            ticks += u64::from(vms[2].read(mw20).expect("MW20") - ticks_before);
        }
    }
    assert!(ticks > 20, "the interrupt ran {ticks} times");
    // Every instruction natively, the interrupt routine's 2 too (a unit that compiles
    // whole is a region however short).
    assert_eq!(ran, native);
}
