//! Random step lists (every Step, Calls of later functions with L inside the memory,
//! random layouts) compiled and run against the reference interpreter, and the replay
//! of every input the fuzzer found (`tests/data/fuzz/`), both through `jit_fuzz`.

#![allow(
    clippy::disallowed_methods,
    reason = "the replay reads the fuzzer's finds from tests/data/fuzz"
)]

use proptest::prelude::*;

mod jit_fuzz;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn compiled_code_agrees_with_the_reference(data in proptest::collection::vec(any::<u8>(), 0..700)) {
        jit_fuzz::check_bytes(&data);
    }

    /// Only valid programs (first byte below 0xC0): every one must compile.
    #[test]
    fn valid_programs_compile_and_agree(first in 0u8..0xC0, rest in proptest::collection::vec(any::<u8>(), 0..700)) {
        let mut data = vec![first];
        data.extend(rest);
        let case = jit_fuzz::decode(&data);
        prop_assert!(!case.loose);
        jit_fuzz::check_case(&case);
    }
}

#[test]
fn the_fuzzers_finds_still_agree() {
    let dir = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/fuzz"));
    let mut replayed = 0;
    for entry in std::fs::read_dir(dir).expect("tests/data/fuzz") {
        let path = entry.expect("a directory entry").path();
        if path.extension().is_some_and(|e| e == "bin") {
            jit_fuzz::check_bytes(&std::fs::read(&path).expect("a fuzz input"));
            replayed += 1;
        }
    }
    // The directory always holds at least the seed below (an empty input).
    assert!(replayed >= 1, "no inputs in {}", dir.display());
}
