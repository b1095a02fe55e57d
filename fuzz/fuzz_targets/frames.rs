//! Fuzz target of the protocol core (`gutta-protocol`): arbitrary bytes through both RTU
//! splitters, the TCP splitter, every decoder, the page reassembler and the master. The
//! checks are `protocol/tests/frames_fuzz/mod.rs`, shared with the crate's replay of
//! the fuzzer's finds (`protocol/tests/fuzz_regressions.rs`); a failed check or a
//! panic is the bug it looks for.
#![no_main]

use libfuzzer_sys::fuzz_target;

#[path = "../../protocol/tests/frames_fuzz/mod.rs"]
mod frames_fuzz;

fuzz_target!(|data: &[u8]| {
    frames_fuzz::check_bytes(data);
});
