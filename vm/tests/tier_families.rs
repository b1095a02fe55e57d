//! The tier's translation on a program of every family it takes, against the
//! interpreter scan by scan (docs/vm-jit.md, "Regions"): timers of each kind, counters,
//! edges, S/R, JMP taken and not, a JMP over a CALL, a JMP whose LBL lies past a record
//! the tier leaves to the interpreter (DISI: the JMP stays interpreted and a region
//! starts where it lands). Memory is compared whole, hidden state included.
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
DISI
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
    // MAIN up to the JMP 2 (which stays interpreted: its LBL lies past the DISI),
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
