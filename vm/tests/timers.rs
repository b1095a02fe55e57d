//! Timers and counters: programs compiled by gutta-cc and run on the VM, checked
//! against the ManagerFun.xml descriptions of TON, TOF, TONR, CTU, CTD and CTUD.

mod common;

use common::{read, set};
use gutta_vm::{Vm, VmConfig};

fn vm_for(code: &str) -> Vm {
    vm_with(code, VmConfig::default())
}

fn vm_with(code: &str, config: VmConfig) -> Vm {
    let text = format!("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n{code}\nEND_ORGANIZATION_BLOCK\n");
    common::load(&text, config)
}

fn int(vm: &Vm, var: &str) -> i16 {
    read(vm, var) as u16 as i16
}

fn scans(vm: &mut Vm, n: usize) {
    for _ in 0..n {
        vm.scan().expect("scan");
    }
}

#[test]
fn ton_is_done_two_seconds_after_in_came_on() {
    let mut vm = vm_for("NETWORK 1\nLD I0.0\nTON T4, 20\n= Q0.0");
    scans(&mut vm, 5);
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "T4")), (0, 0));
    set(&mut vm, "I0.0", 1);
    // The first scan with IN = 1 starts the timer at virtual time t0.
    let t0 = vm.clock_ms();
    scans(&mut vm, 1);
    assert_eq!(int(&vm, "T4"), 0, "starts counting at the first execution");
    scans(&mut vm, 199);
    // The last scan ran at t0 + 1990 ms.
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "T4")), (0, 19));
    assert_eq!(vm.clock_ms() - t0, 2000);
    scans(&mut vm, 1);
    // This scan ran at t0 + 2000 ms: exactly 2 s.
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "T4")), (1, 20));
    scans(&mut vm, 100);
    assert_eq!(
        (read(&vm, "Q0.0"), int(&vm, "T4")),
        (1, 30),
        "keeps counting"
    );
    set(&mut vm, "I0.0", 0);
    scans(&mut vm, 1);
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "T4")), (0, 0), "IN off resets");
}

#[test]
fn ton_stops_at_32767_and_pt_zero_is_done_at_once() {
    let mut vm =
        vm_for("NETWORK 1\nLD I0.0\nTON T0, 0\n= Q0.0\nNETWORK 2\nLD I0.0\nTON T4, 5\n= Q0.1");
    set(&mut vm, "I0.0", 1);
    scans(&mut vm, 1);
    assert_eq!(read(&vm, "Q0.0"), 1, "PT 0 is done as soon as IN is 1");
    set(&mut vm, "T0", 32760);
    scans(&mut vm, 1);
    assert_eq!(int(&vm, "T0"), 32767, "a 1 ms timer stops at 32767");
    scans(&mut vm, 3);
    assert_eq!(int(&vm, "T0"), 32767);
    // A program may write the current value.
    set(&mut vm, "T4", 10);
    scans(&mut vm, 1);
    assert_eq!(read(&vm, "Q0.1"), 1);
}

#[test]
fn a_10_ms_timer_and_scan_times_that_do_not_divide_the_unit() {
    let mut vm = vm_for("NETWORK 1\nLD I0.0\nTON T2, 100\n= Q0.0");
    set(&mut vm, "I0.0", 1);
    scans(&mut vm, 101);
    assert_eq!(
        (read(&vm, "Q0.0"), int(&vm, "T2")),
        (1, 100),
        "1 s at 10 ms"
    );

    // 7 ms scans on a 100 ms timer: the uncounted remainder is kept, no drift.
    let mut vm = vm_with(
        "NETWORK 1\nLD I0.0\nTON T4, 20\n= Q0.0",
        VmConfig {
            scan_ms: 7,
            ..VmConfig::default()
        },
    );
    set(&mut vm, "I0.0", 1);
    scans(&mut vm, 1 + 285);
    // 285 * 7 = 1995 ms.
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "T4")), (0, 19));
    scans(&mut vm, 1);
    // 286 * 7 = 2002 ms.
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "T4")), (1, 20));
}

#[test]
fn tof_holds_the_output_for_pt_after_in_went_off() {
    let mut vm = vm_for("NETWORK 1\nLD I0.0\nTOF T5, 30\n= Q0.0");
    scans(&mut vm, 3);
    assert_eq!(read(&vm, "Q0.0"), 0, "not armed after entering RUN");
    set(&mut vm, "I0.0", 1);
    scans(&mut vm, 1);
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "T5")), (1, 0));
    set(&mut vm, "I0.0", 0);
    scans(&mut vm, 1);
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "T5")), (1, 0));
    scans(&mut vm, 299);
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "T5")), (1, 29));
    scans(&mut vm, 1);
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "T5")), (0, 30), "3 s after");
    scans(&mut vm, 50);
    assert_eq!(
        (read(&vm, "Q0.0"), int(&vm, "T5")),
        (0, 30),
        "stops at PT, T unchanged once disarmed"
    );
    // IN on again resets and re-arms; a short pulse restarts the delay.
    set(&mut vm, "I0.0", 1);
    scans(&mut vm, 1);
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "T5")), (1, 0));
    set(&mut vm, "I0.0", 0);
    scans(&mut vm, 101);
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "T5")), (1, 10));
    set(&mut vm, "I0.0", 1);
    scans(&mut vm, 1);
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "T5")), (1, 0));
}

#[test]
fn tonr_accumulates_and_is_reset_by_writing_the_value() {
    let mut vm = vm_for("NETWORK 1\nLD I0.0\nTONR T6, 10\n= Q0.0\nNETWORK 2\nLD I0.1\nMOVW 0, T6");
    set(&mut vm, "I0.0", 1);
    scans(&mut vm, 61);
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "T6")), (0, 6));
    set(&mut vm, "I0.0", 0);
    scans(&mut vm, 20);
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "T6")), (0, 6), "retains");
    set(&mut vm, "I0.0", 1);
    scans(&mut vm, 41);
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "T6")), (1, 10));
    set(&mut vm, "I0.0", 0);
    scans(&mut vm, 5);
    assert_eq!(read(&vm, "Q0.0"), 1, "done whatever IN is");
    set(&mut vm, "I0.1", 1);
    scans(&mut vm, 1);
    // TONR ran before the MOVW in this scan; the next scan sees 0.
    assert_eq!(int(&vm, "T6"), 0);
    scans(&mut vm, 1);
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "T6")), (0, 0));
}

#[test]
fn tonr_drops_the_fraction_when_in_goes_off() {
    let mut vm = vm_for("NETWORK 1\nLD I0.0\nTONR T6, 10\n= Q0.0");
    // Runs of 9 scans (80 ms counted each) never complete a 100 ms unit.
    for _ in 0..5 {
        set(&mut vm, "I0.0", 1);
        scans(&mut vm, 9);
        set(&mut vm, "I0.0", 0);
        scans(&mut vm, 1);
    }
    assert_eq!(int(&vm, "T6"), 0);
}

#[test]
fn the_current_value_can_be_compared() {
    let mut vm = vm_for("NETWORK 1\nLD I0.0\nTON T4, 50\nNETWORK 2\nLDW>= T4, 2\n= Q0.1");
    set(&mut vm, "I0.0", 1);
    scans(&mut vm, 20);
    assert_eq!((read(&vm, "Q0.1"), int(&vm, "T4")), (0, 1));
    scans(&mut vm, 1);
    assert_eq!((read(&vm, "Q0.1"), int(&vm, "T4")), (1, 2));
}

#[test]
fn ctu_counts_rising_edges_up_to_pv_and_r_resets() {
    let mut vm = vm_for("NETWORK 1\nLD I0.0\nLD I0.1\nCTU C0, 3\n= Q0.0");
    let pulse = |vm: &mut Vm| {
        set(vm, "I0.0", 1);
        scans(vm, 2);
        set(vm, "I0.0", 0);
        scans(vm, 2);
    };
    pulse(&mut vm);
    pulse(&mut vm);
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "C0")), (0, 2));
    pulse(&mut vm);
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "C0")), (1, 3));
    pulse(&mut vm);
    assert_eq!(
        (read(&vm, "Q0.0"), int(&vm, "C0")),
        (1, 4),
        "counts past PV"
    );
    // R resets; an edge of CU while R is on is consumed.
    set(&mut vm, "I0.1", 1);
    set(&mut vm, "I0.0", 1);
    scans(&mut vm, 1);
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "C0")), (0, 0));
    set(&mut vm, "I0.1", 0);
    scans(&mut vm, 1);
    assert_eq!(int(&vm, "C0"), 0, "CU was already on");
    // The counter maximum.
    set(&mut vm, "I0.0", 0);
    set(&mut vm, "C0", 32767);
    pulse(&mut vm);
    assert_eq!(int(&vm, "C0"), 32767);
}

#[test]
fn an_input_already_on_in_the_first_scan_counts_once() {
    let mut vm = vm_for("NETWORK 1\nLD I0.0\nLD I0.1\nCTU C0, 3\n= Q0.0");
    set(&mut vm, "I0.0", 1);
    scans(&mut vm, 5);
    assert_eq!(int(&vm, "C0"), 1);
}

#[test]
fn ctd_counts_down_from_pv() {
    let mut vm = vm_for("NETWORK 1\nLD I0.0\nLD I0.1\nCTD C1, 3\n= Q0.0");
    scans(&mut vm, 1);
    assert_eq!(
        (read(&vm, "Q0.0"), int(&vm, "C1")),
        (1, 0),
        "never loaded: 0, done"
    );
    set(&mut vm, "I0.1", 1);
    scans(&mut vm, 1);
    set(&mut vm, "I0.1", 0);
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "C1")), (0, 3));
    for expected in [2, 1, 0, 0] {
        set(&mut vm, "I0.0", 1);
        scans(&mut vm, 1);
        set(&mut vm, "I0.0", 0);
        scans(&mut vm, 1);
        assert_eq!(int(&vm, "C1"), expected);
    }
    assert_eq!(read(&vm, "Q0.0"), 1);
}

#[test]
fn ctud_counts_both_ways_within_its_limits() {
    let mut vm = vm_for("NETWORK 1\nLD I0.0\nLD I0.1\nLD I0.2\nCTUD C2, 2\n= Q0.0");
    let pulse = |vm: &mut Vm, input: &str| {
        set(vm, input, 1);
        scans(vm, 1);
        set(vm, input, 0);
        scans(vm, 1);
    };
    pulse(&mut vm, "I0.0");
    pulse(&mut vm, "I0.0");
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "C2")), (1, 2));
    pulse(&mut vm, "I0.1");
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "C2")), (0, 1));
    // Both edges in one execution leave C unchanged.
    set(&mut vm, "I0.0", 1);
    set(&mut vm, "I0.1", 1);
    scans(&mut vm, 1);
    assert_eq!(int(&vm, "C2"), 1);
    set(&mut vm, "I0.0", 0);
    set(&mut vm, "I0.1", 0);
    scans(&mut vm, 1);
    pulse(&mut vm, "I0.1");
    pulse(&mut vm, "I0.1");
    assert_eq!(int(&vm, "C2"), -1, "goes below 0");
    // Limits.
    set(&mut vm, "C2", (-32768i16) as u16 as u32);
    pulse(&mut vm, "I0.1");
    assert_eq!(int(&vm, "C2"), -32768);
    set(&mut vm, "C2", 32767);
    pulse(&mut vm, "I0.0");
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "C2")), (1, 32767));
    // R resets.
    set(&mut vm, "I0.2", 1);
    scans(&mut vm, 1);
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "C2")), (0, 0));
}

#[test]
fn counters_leave_one_level_with_the_done_state() {
    // CTU consumes CU and R and pushes done: ALD combines it with the level below.
    let mut vm = vm_for("NETWORK 1\nLD I0.3\nLD I0.0\nLD I0.1\nCTU C0, 1\nALD\n= Q0.0");
    set(&mut vm, "I0.0", 1);
    scans(&mut vm, 1);
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "C0")), (0, 1));
    set(&mut vm, "I0.3", 1);
    scans(&mut vm, 1);
    assert_eq!(read(&vm, "Q0.0"), 1);
}

#[test]
fn reset_clears_the_hidden_timer_state() {
    let mut vm = vm_for("NETWORK 1\nLD I0.0\nTONR T6, 10\n= Q0.0");
    set(&mut vm, "I0.0", 1);
    scans(&mut vm, 6);
    vm.reset();
    set(&mut vm, "I0.0", 1);
    scans(&mut vm, 1);
    assert_eq!(int(&vm, "T6"), 0, "fresh start after reset");
    scans(&mut vm, 10);
    assert_eq!(int(&vm, "T6"), 1);
}

#[test]
fn a_1_ms_timer_counts_the_scan_time() {
    let mut vm = vm_for("NETWORK 1\nLD I0.0\nTON T1, 25\n= Q0.0");
    set(&mut vm, "I0.0", 1);
    scans(&mut vm, 3);
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "T1")), (0, 20));
    scans(&mut vm, 1);
    assert_eq!((read(&vm, "Q0.0"), int(&vm, "T1")), (1, 30));
}
