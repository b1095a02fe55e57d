//! Fuzz target of gutta-jit: bytes decode to a layout, functions of steps (Calls among
//! them), memory and a logic stack (`jit/tests/jit_fuzz/mod.rs`, shared with the crate's
//! tests); what compiles must run exactly as `gutta_jit::reference` does (memory, stack,
//! count), what is refused must be a program the decoder made loose. A crash is a
//! difference, a reference panic (an access `compile` let through) or a hang.
#![no_main]

use libfuzzer_sys::fuzz_target;

#[path = "../../jit/tests/jit_fuzz/mod.rs"]
mod jit_fuzz;

fuzz_target!(|data: &[u8]| {
    jit_fuzz::check_bytes(data);
});
