//! What the `vm_run` target checks and `vm/tests/fuzz_regressions.rs` replays: a
//! verified image loaded three times (fast operations off, the interpreter's fast
//! operations, and the compiled tier from load), `SCANS` scans of 25 ms (timers of every
//! resolution finish) with IB0 from the input byte, rotated every few scans, that must
//! agree on their outcome, instruction count and all memory (hidden state included). No
//! I/O. The bases the mutations start from: the format tests' full program (every
//! operand kind) or `plant.lad` (the families real programs are made of).

use std::sync::{Arc, OnceLock};

use gutta_catalog::Target;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_format::{Image, VerifiedImage};
use gutta_vm::{Vm, VmConfig};

/// Scans each image runs.
pub const SCANS: u32 = 40;

/// The plant base: timers of each kind and resolution, counters, edges, S/R, compares,
/// JMP/LBL, CALL with parameters, FOR/NEXT, conversions and shifts.
pub fn plant_image(target: &Arc<Target>) -> &'static Image {
    static IMAGE: OnceLock<Image> = OnceLock::new();
    IMAGE.get_or_init(|| {
        let explicit = ExplicitTarget {
            target: Arc::clone(target),
            origin: "fuzz".into(),
        };
        let c = compile(
            SourceFile::new("plant.lad", include_str!("plant.lad")),
            Some(&explicit),
        );
        c.image.unwrap_or_else(|| {
            panic!(
                "plant.lad compiles: {:?}",
                c.checked
                    .diagnostics()
                    .iter()
                    .filter(|d| d.is_error())
                    .collect::<Vec<_>>()
            )
        })
    })
}

/// The base of an input whose first byte is `inputs`: the plant when its top bit is set
/// (also I0.7), else the full program (so inputs found before the plant keep their
/// meaning).
pub fn base<'a>(full: &'a Image, target: &Arc<Target>, inputs: u8) -> &'a Image {
    if inputs & 0x80 != 0 {
        plant_image(target)
    } else {
        full
    }
}

/// The compiled VM after the scans in which all three agreed (a disagreement panics),
/// or None when the image does not load.
pub fn scan_both(verified: &VerifiedImage, target: &Arc<Target>, inputs: u8) -> Option<Vm> {
    let config = VmConfig {
        watchdog: 20_000,
        scan_ms: 25,
        ..VmConfig::default()
    };
    let load = |fast, native_after| {
        Vm::new(
            verified.clone(),
            Arc::clone(target),
            VmConfig {
                fast,
                native_after,
                ..config
            },
        )
    };
    let (Ok(mut slow), Ok(mut interpreted), Ok(mut fast)) =
        (load(false, None), load(true, None), load(true, Some(0)))
    else {
        return None;
    };
    let ib0 = target.memory.parse_address("IB0").expect("IB0 exists");
    for scan in 0..SCANS {
        let input = u32::from(inputs.rotate_left(scan / 5));
        for vm in [&mut slow, &mut interpreted, &mut fast] {
            let _ = vm.write(ib0, input);
        }
        let reference = (
            slow.scan(),
            slow.executed_last_scan(),
            slow.fault_position(),
        );
        for (name, vm) in [("interpreted", &mut interpreted), ("compiled", &mut fast)] {
            let outcome = (vm.scan(), vm.executed_last_scan(), vm.fault_position());
            assert_eq!(
                outcome, reference,
                "scan {scan}: {name} and generic agree on the outcome"
            );
            assert_eq!(
                vm.memory(),
                slow.memory(),
                "scan {scan}: {name} and generic agree on memory"
            );
        }
        if reference.0.is_err() {
            break;
        }
    }
    Some(fast)
}
