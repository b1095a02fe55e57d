//! Fuzz target of the language server (`gutta_lsp::serve` over an in-memory
//! connection): the input is decoded into an editor session (open, edits with any UTF-16
//! range, requests at any position, malformed requests, live-values configuration and
//! toggles) by the same `session` module the robustness proptest plays
//! (lsp/tests/session/mod.rs). Panics are the bugs it looks for (libFuzzer's hook aborts
//! even under the server's catch_unwind), and the session's rules must hold: every
//! request answered, malformed ones with an error, the server alive to the end and
//! shutting down cleanly. Crashes become regression inputs in lsp/tests/data/fuzz/.
#![no_main]

use libfuzzer_sys::fuzz_target;

#[path = "../../lsp/tests/session/mod.rs"]
mod session;

fuzz_target!(|data: &[u8]| {
    // Long inputs spend the time on one session; the fuzzer learns more from many.
    if data.len() > 4096 {
        return;
    }
    session::run(&session::ops_from_bytes(data));
});
