//! Inputs the `frames` fuzz target (fuzz/fuzz_targets/frames.rs) found, replayed through
//! the target's own checks (`frames_fuzz/mod.rs`). Adding a regression means adding a
//! file to protocol/tests/data/fuzz/frames/ (the fuzzer's input as it is).

#![allow(
    clippy::disallowed_methods,
    clippy::disallowed_types,
    reason = "the replay reads the fuzzer's finds from tests/data/fuzz"
)]

mod frames_fuzz;

#[test]
fn frames_finds_replay_clean() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fuzz/frames");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("protocol/tests/data/fuzz/frames")
        .map(|e| e.expect("a directory entry").path())
        .collect();
    files.sort();
    assert!(
        !files.is_empty(),
        "no regression inputs in {}",
        dir.display()
    );
    for path in files {
        let data = std::fs::read(&path).expect("a regression input");
        frames_fuzz::check_bytes(&data);
    }
}
