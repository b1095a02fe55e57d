//! The native transcriptions do what the VM does: the programs compiled for
//! EC30-EKSTM32-XC and run in the VM, and transcribed and run natively, from the same
//! changing inputs, leave I, Q, M and the math flags (SMB1) byte-identical after every
//! scan (the conveyor plant and the mixing station: T, C and SMB0 too, over thousands
//! of scans of virtual time). Without this the benchmark's native figure would mean nothing.

use std::sync::Arc;

use gutta_bench_native::{
    Memory, Plant, BIT_LOGIC, CONVEYOR, CONVEYOR_STATIONS, MIXED, MIXING, MIXING_STATIONS,
};
use gutta_catalog::{stdlib, Target};
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_vm::{Vm, VmConfig};

const TARGET: &str = "EC30-EKSTM32-XC";
const SCANS: u32 = 5;

fn load(text: &str, config: VmConfig) -> (Vm, Arc<Target>) {
    let target = stdlib::shared(TARGET).expect("target");
    let explicit = ExplicitTarget {
        target: Arc::clone(&target),
        origin: "test".into(),
    };
    let c = compile(SourceFile::new("agree.lad", text), Some(&explicit));
    let image = c
        .image
        .unwrap_or_else(|| panic!("does not compile: {:?}", c.checked.diagnostics()));
    let verified = gutta_format::verify(&image, &target).expect("verifies");
    let vm = Vm::new(verified, Arc::clone(&target), config).expect("loads");
    (vm, target)
}

/// Write a byte (`IB3`) or word (`MW6`) in both memories.
fn set(vm: &mut Vm, target: &Target, native: &mut Memory, var: &str, value: u32) {
    let a = target.memory.parse_address(var).expect("address");
    vm.write(a, value).expect("write");
    let area = match &var[..1] {
        "I" => &mut native.i[..],
        "M" => &mut native.m[..],
        _ => panic!("set {var}"),
    };
    let at = a.offset as usize;
    let bytes = value.to_le_bytes();
    let n = a.width.bytes() as usize;
    area[at..at + n].copy_from_slice(&bytes[..n]);
}

fn vm_area<'a>(vm: &'a Vm, target: &Target, name: &str) -> &'a [u8] {
    let slot = target.memory.area(name).expect("area").slot;
    vm.memory().area(slot).expect("area in VM memory")
}

/// Different inputs every scan: I bytes, M bits the bit program reads, and INT words
/// (MW0..MW30) and MD40 spread over the range, so compares go both ways and *I
/// overflows.
fn stimulate(scan: u32, vm: &mut Vm, target: &Target, native: &mut Memory) {
    for byte in 0..4 {
        let v = (0x5A ^ (scan * 37 + byte * 11)) & 0xFF;
        set(vm, target, native, &format!("IB{byte}"), v);
    }
    for byte in 0..16 {
        let v = (0xC3 ^ (scan * 29 + byte * 7)) & 0xFF;
        set(vm, target, native, &format!("MB{byte}"), v);
    }
    for k in 0..16u32 {
        let v = (k * 4099 + scan * 7919) % 65536;
        set(vm, target, native, &format!("MW{}", k * 2), v);
    }
    set(vm, target, native, "MD40", 0x7FFF_FFF0 + scan * 3);
}

/// The VM interpreted and compiled at load (docs/vm-jit.md; gutta-vm's default feature
/// `jit`).
fn configs() -> [VmConfig; 2] {
    [None, Some(0)].map(|native_after| VmConfig {
        native_after,
        ..VmConfig::default()
    })
}

fn agree(text: &str, scan: fn(&mut Memory)) {
    for config in configs() {
        agree_with(text, scan, config);
    }
}

fn agree_with(text: &str, scan: fn(&mut Memory), config: VmConfig) {
    let (mut vm, target) = load(text, config);
    if config.native_after == Some(0) {
        assert!(
            matches!(vm.tier(), gutta_vm::TierState::Compiled { .. }),
            "compiled: {:?}",
            vm.tier()
        );
    }
    let mut native = Memory::default();
    let mut changed = 0;
    for n in 0..SCANS {
        stimulate(n, &mut vm, &target, &mut native);
        let before = native.clone();
        vm.scan().expect("scan");
        scan(&mut native);
        changed += usize::from(before != native);
        for (name, bytes) in [
            ("I", &native.i[..]),
            ("Q", &native.q[..]),
            ("M", &native.m[..]),
        ] {
            let vm_bytes = vm_area(&vm, &target, name);
            if let Some(at) = (0..bytes.len()).find(|&k| vm_bytes[k] != bytes[k]) {
                panic!(
                    "scan {n}: {name}B{at} is {:#04x} in the VM and {:#04x} native",
                    vm_bytes[at], bytes[at]
                );
            }
            assert_eq!(vm_bytes.len(), bytes.len(), "{name} size");
        }
        assert_eq!(
            vm_area(&vm, &target, "SM")[1],
            native.sm[1],
            "scan {n}: SMB1 (math flags)"
        );
    }
    assert_eq!(changed, SCANS as usize, "every scan changes memory");
}

#[test]
fn bit_logic_agrees_with_the_vm() {
    agree(BIT_LOGIC, gutta_bench_native::bit_logic_scan);
    agree(BIT_LOGIC, gutta_bench_native::bit_logic_scan_fenced);
}

#[test]
fn mixed_agrees_with_the_vm() {
    agree(MIXED, gutta_bench_native::mixed_scan);
    agree(MIXED, gutta_bench_native::mixed_scan_fenced);
}

#[test]
fn both_programs_take_both_branches() {
    // A transcription that skips box instructions or never overflows would still agree
    // on a program that never exercises them: check the stimulus does.
    let (mut vm, target) = load(MIXED, VmConfig::default());
    let mut native = Memory::default();
    stimulate(0, &mut vm, &target, &mut native);
    gutta_bench_native::mixed_scan(&mut native);
    let b_words: Vec<i16> = (32..64)
        .step_by(2)
        .map(|k| gutta_bench_native::word(&native.m, k))
        .collect();
    assert!(b_words.iter().any(|&w| w >= 100) && b_words.iter().any(|&w| w < 100));
    assert_ne!(native.m[64..96], [0; 32], "the subroutine's results arrive");
}

#[test]
fn memory_sizes_match_the_catalog() {
    let target = stdlib::shared(TARGET).expect("target");
    let size = |name: &str| target.memory.area(name).expect("area").size as usize;
    assert_eq!(size("I"), gutta_bench_native::I_BYTES);
    assert_eq!(size("Q"), gutta_bench_native::Q_BYTES);
    assert_eq!(size("M"), gutta_bench_native::M_BYTES);
    assert_eq!(size("SM"), gutta_bench_native::SM_BYTES);
    assert_eq!(
        u32::from(target.instructions.logic_stack_depth),
        gutta_bench_native::LOGIC_STACK_DEPTH
    );
}

/// The conveyor plant's inputs at scan `n`: every start button pressed now and then,
/// stop buttons of a changing few stations held for a while, the acknowledge buttons
/// pressed and released every 40 scans.
fn plant_inputs(n: u32) -> [u8; 15] {
    let mut bytes = [0u8; 15];
    for (k, byte) in bytes.iter_mut().enumerate() {
        let k = k as u32;
        *byte = match k / 5 {
            0 => {
                if n % 400 < 3 {
                    0xFF
                } else {
                    0
                }
            }
            1 => {
                if (n / 150 + k * 3).is_multiple_of(4) {
                    0x5A_u32.rotate_left(n / 150 % 8) as u8
                } else {
                    0
                }
            }
            _ => {
                if (n / 40) % 2 == 1 {
                    0xFF
                } else {
                    0
                }
            }
        };
    }
    bytes
}

#[test]
fn conveyor_agrees_with_the_vm() {
    for config in configs() {
        let (mut vm, target) = load(CONVEYOR, config);
        let mut plant = Plant::new(config.scan_ms);
        let (mut alarms_set, mut alarms_cleared, mut batches, mut skipped, mut totals) =
            (0, 0, 0, 0, 0);
        for n in 0..3000u32 {
            set_inputs(&mut vm, &target, &mut plant, &plant_inputs(n));
            let before = plant.clone();
            vm.scan().expect("scan");
            gutta_bench_native::conveyor_scan(&mut plant);
            same_areas(&vm, &target, &plant, config, n);
            // What the scan did, so the run is known to reach every family.
            for k in 0..CONVEYOR_STATIONS {
                let b = 100 + 16 * k;
                let was = |bit: u32| gutta_bench_native::bit(&before.mem.m, b, bit);
                let now = |bit: u32| gutta_bench_native::bit(&plant.mem.m, b, bit);
                alarms_set += usize::from(!was(2) && now(2));
                alarms_cleared += usize::from(was(2) && !now(2));
                batches += usize::from(now(4));
                skipped += usize::from(!now(0));
                totals += usize::from(now(3));
            }
        }
        assert!(alarms_set > 40, "EU and S: {alarms_set}");
        assert!(alarms_cleared > 40, "ED and R: {alarms_cleared}");
        assert!(
            batches > 40,
            "CTU to its preset, the compare, the reset: {batches}"
        );
        assert!(skipped > 1000, "the JMP taken: {skipped}");
        assert!(totals > 1000, "the batch total past its limit: {totals}");
        assert!(plant.t.iter().any(|&b| b != 0), "timers running at the end");
    }
}

/// IB0.. of the VM and of the native plant set to `bytes`.
fn set_inputs(vm: &mut Vm, target: &Target, plant: &mut Plant, bytes: &[u8]) {
    for (k, &v) in bytes.iter().enumerate() {
        let a = target
            .memory
            .parse_address(&format!("IB{k}"))
            .expect("address");
        vm.write(a, u32::from(v)).expect("write");
        plant.mem.i[k] = v;
    }
}

/// The VM's I, Q, M, T, C and SMB0..1 against the plant's, after scan `n`.
fn same_areas(vm: &Vm, target: &Target, plant: &Plant, config: VmConfig, n: u32) {
    for (name, bytes) in [
        ("I", &plant.mem.i[..]),
        ("Q", &plant.mem.q[..]),
        ("M", &plant.mem.m[..]),
        ("T", &plant.t[..]),
        ("C", &plant.c[..]),
        ("SM", &plant.mem.sm[..2]),
    ] {
        let vm_bytes = vm_area(vm, target, name);
        if let Some(at) = (0..bytes.len()).find(|&k| vm_bytes[k] != bytes[k]) {
            panic!(
                "{config:?} scan {n}: {name}B{at} is {:#04x} in the VM and {:#04x} native",
                vm_bytes[at], bytes[at]
            );
        }
    }
}

/// The mixing station's inputs at scan `n`: start buttons (IB0..IB2) pressed for a
/// few scans every 97 and, rotating, held; acknowledge buttons (IB3..IB5) pressed and
/// released every 70 scans.
fn mixing_inputs(n: u32) -> [u8; 6] {
    let start = if n % 97 < 4 {
        0xFF
    } else {
        0x0F_u32.rotate_left(n / 500 % 8) as u8
    };
    let ack = if (n / 70) % 2 == 1 { 0xFF } else { 0 };
    [start, start, start, ack, ack, ack]
}

#[test]
fn mixing_agrees_with_the_vm() {
    for config in configs() {
        let (mut vm, target) = load(MIXING, config);
        let mut plant = Plant::new(config.scan_ms);
        let (mut batches, mut slow, mut cleared, mut run_on, mut stopped, mut scaled) =
            (0, 0, 0, 0, 0, 0);
        for n in 0..3000u32 {
            set_inputs(&mut vm, &target, &mut plant, &mixing_inputs(n));
            let before = plant.clone();
            vm.scan().expect("scan");
            gutta_bench_native::mixing_scan(&mut plant);
            same_areas(&vm, &target, &plant, config, n);
            // What the scan did, so the run is known to reach every family.
            for k in 0..MIXING_STATIONS {
                let b = 800 + 24 * k;
                let now = |bit: u32| gutta_bench_native::bit(&plant.mem.m, b, bit);
                let was = |bit: u32| gutta_bench_native::bit(&before.mem.m, b, bit);
                let counted = gutta_bench_native::word(&plant.c, 2 * (40 + k));
                batches += usize::from(counted > gutta_bench_native::word(&before.c, 2 * (40 + k)));
                slow += usize::from(!was(4) && now(4));
                cleared += usize::from(now(7));
                let agitator = gutta_bench_native::bit(&plant.mem.q, 10 + k / 8, (k % 8) as u32);
                let agitated = gutta_bench_native::bit(&before.mem.q, 10 + k / 8, (k % 8) as u32);
                run_on += usize::from(agitator && !now(1));
                stopped += usize::from(agitated && !agitator);
                scaled += usize::from(gutta_bench_native::dword(&plant.mem.m, b + 16) > 0);
            }
        }
        assert!(batches > 100, "fill, mix, drain, CTUD up: {batches}");
        assert!(slow > 100, "TONR past its preset: {slow}");
        assert!(cleared > 20, "CTUD done and reset: {cleared}");
        assert!(run_on > 1000, "TOF running the agitator on: {run_on}");
        assert!(stopped > 100, "TOF's delay over: {stopped}");
        assert!(scaled > 1000, "ITD, DTR, *R, TRUNC: {scaled}");
    }
}
