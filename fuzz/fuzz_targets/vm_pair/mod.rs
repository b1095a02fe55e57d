//! What the `vm_run` target checks and `vm/tests/fuzz_regressions.rs` replays: a
//! verified image loaded three times (fast operations off, the interpreter's fast
//! operations, and the compiled tier from load) with one input byte in IB0, three scans
//! that must agree on their outcome, instruction count and all memory. No I/O.

use std::sync::Arc;

use gutta_catalog::Target;
use gutta_format::VerifiedImage;
use gutta_vm::{Vm, VmConfig};

/// The compiled VM after three scans in which all three agreed (a disagreement
/// panics), or None when the image does not load.
pub fn scan_both(verified: &VerifiedImage, target: &Arc<Target>, inputs: u8) -> Option<Vm> {
    let config = VmConfig {
        watchdog: 20_000,
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
    for vm in [&mut slow, &mut interpreted, &mut fast] {
        let _ = vm.write(ib0, u32::from(inputs));
    }
    for scan in 0..3 {
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
    }
    Some(fast)
}
