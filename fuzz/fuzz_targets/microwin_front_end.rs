//! Fuzz target of the Micro/WIN dialect (docs/microwin.md): bytes through the code-page
//! decoder, the dialect's parser and tree pass, the checker and the encoder on CPU-EC20,
//! as one export or (first byte odd) as a program split one block per file with symbol
//! tables. The steps and checks are `compiler/tests/microwin_fuzz/mod.rs`, which
//! `compiler/tests/fuzz_regressions.rs` replays on every crash found.
#![no_main]

use libfuzzer_sys::fuzz_target;

#[path = "../../compiler/tests/microwin_fuzz/mod.rs"]
mod microwin_fuzz;

fuzz_target!(|data: &[u8]| {
    microwin_fuzz::run(data);
});
