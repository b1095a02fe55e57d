//! What the `vm_run` target checks and `vm/tests/fuzz_regressions.rs` replays: a
//! verified image loaded twice (fast operations on and off) with one input byte in IB0,
//! three scans that must agree on their outcome and on all memory. No I/O.

use std::sync::Arc;

use gutta_catalog::Target;
use gutta_format::VerifiedImage;
use gutta_vm::{Vm, VmConfig};

/// The fast and the generic VM after three scans that agreed (a disagreement panics),
/// or None when the image does not load.
pub fn scan_both(verified: &VerifiedImage, target: &Arc<Target>, inputs: u8) -> Option<Vm> {
    let config = VmConfig {
        watchdog: 20_000,
        ..VmConfig::default()
    };
    let load = |fast| {
        Vm::new(
            verified.clone(),
            Arc::clone(target),
            VmConfig { fast, ..config },
        )
    };
    let (Ok(mut fast), Ok(mut slow)) = (load(true), load(false)) else {
        return None;
    };
    let ib0 = target.memory.parse_address("IB0").expect("IB0 exists");
    for vm in [&mut fast, &mut slow] {
        let _ = vm.write(ib0, u32::from(inputs));
    }
    for scan in 0..3 {
        let (a, b) = (fast.scan(), slow.scan());
        assert_eq!(a, b, "scan {scan}: fast and generic agree on the outcome");
        assert_eq!(
            fast.memory(),
            slow.memory(),
            "scan {scan}: fast and generic agree on memory"
        );
    }
    Some(fast)
}
