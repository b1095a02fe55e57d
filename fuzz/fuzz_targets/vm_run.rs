//! Fuzz target of the VM: byte mutations of a valid image (the format tests' full
//! program, every operand kind; or, when the first byte's top bit is set, the plant of
//! vm_pair/plant.lad: timers, counters, edges, S/R, jumps, CALL with parameters, FOR,
//! conversions) that still verify are loaded and run on the three engines (fast
//! operations off, on, and compiled at load) through 40 scans, then a breakpoint and
//! single steps. Panics and hangs are the bugs it looks for; faults are fine (they are
//! typed errors). The engines must also agree on memory, the count and the fault.
#![no_main]

use gutta_format::verify;
use gutta_vm::{Position, Step};
use libfuzzer_sys::fuzz_target;

mod shared;
mod vm_pair;

use shared::{base_image, default_target, mutate};

fuzz_target!(|data: &[u8]| {
    let Some((&inputs, rest)) = data.split_first() else {
        return;
    };
    let mut image = vm_pair::base(base_image(), default_target(), inputs).clone();
    mutate(&mut image, rest, false);
    let Ok(verified) = verify(&image, default_target()) else {
        return;
    };
    let Some(mut fast) = vm_pair::scan_both(&verified, default_target(), inputs) else {
        return;
    };
    // Debugging on whatever survived: a breakpoint on MAIN's first networks, steps.
    let _ = fast.set_breakpoint(Some(Position {
        function: 0,
        network: u16::from(inputs % 4),
        step: u16::from(inputs >> 6),
    }));
    let _ = fast.scan();
    let _ = fast.debug_stop();
    for k in 0..8u8 {
        let step = [Step::In, Step::Over, Step::Out][usize::from(k % 3)];
        let _ = fast.debug_step(step);
        let _ = fast.debug_state();
    }
    fast.debug_run();
    let _ = fast.scan();
});
