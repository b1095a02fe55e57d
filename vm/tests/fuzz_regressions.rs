//! Inputs the `vm_run` fuzz target (fuzz/fuzz_targets/vm_run.rs) found, replayed as it
//! replays them: byte edits of the format tests' full program or of the plant
//! (vm_pair/plant.lad; the first byte's top bit picks it); an image that verifies runs
//! on the generic semantics, the interpreter and the compiled tier, which must agree on
//! every scan's outcome and count and on all memory. The unmutated plant replays too. Adding a regression means adding a file to
//! vm/tests/data/fuzz/vm_run/ (and, when the fix was in the verifier, a row below).

#![allow(
    clippy::disallowed_methods,
    clippy::disallowed_types,
    reason = "tests read their data files"
)]

#[path = "../../fuzz/fuzz_targets/shared/mod.rs"]
mod shared;
#[path = "../../fuzz/fuzz_targets/vm_pair/mod.rs"]
mod vm_pair;

use std::path::Path;

use gutta_format::{verify, VerifyCode};
use shared::{base_image, default_target, mutate};

/// Files whose image the verifier must refuse, with the code: the bug was that it
/// verified.
const REFUSED: &[(&str, VerifyCode)] = &[
    // SBR0's output moved onto LD0, over both parameters before it: the planned CALL
    // and the general CALL copied the parameters in different orders and disagreed.
    (
        "call_parameters_sharing_l.bin",
        VerifyCode::OverlappingLocals,
    ),
];

/// What a replay did: refused by the verifier (with its code), or ran.
fn replay(data: &[u8]) -> Result<(), VerifyCode> {
    let Some((&inputs, rest)) = data.split_first() else {
        return Ok(());
    };
    let mut image = vm_pair::base(base_image(), default_target(), inputs).clone();
    mutate(&mut image, rest, false);
    let verified = verify(&image, default_target()).map_err(|e| e.code())?;
    vm_pair::scan_both(&verified, default_target(), inputs);
    Ok(())
}

/// The plant base itself verifies and runs alike on the three engines (an input of one
/// byte with the top bit: no edits).
#[test]
fn the_plant_base_runs_alike() {
    for inputs in [0x80, 0xFF, 0xA5] {
        assert_eq!(replay(&[inputs]), Ok(()));
    }
    let verified = verify(vm_pair::plant_image(default_target()), default_target())
        .expect("the plant verifies");
    let vm = vm_pair::scan_both(&verified, default_target(), 0xC3).expect("loads");
    assert!(vm.scans() >= u64::from(vm_pair::SCANS), "ran every scan");
}

#[test]
fn vm_run_finds_replay_clean() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fuzz/vm_run");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("vm/tests/data/fuzz/vm_run")
        .map(|e| e.expect("a directory entry").path())
        .collect();
    files.sort();
    assert!(
        !files.is_empty(),
        "no regression inputs in {}",
        dir.display()
    );
    for path in files {
        let name = path
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or_default();
        let data = std::fs::read(&path).expect("a regression input");
        let outcome = replay(&data);
        if let Some((_, code)) = REFUSED.iter().find(|(file, _)| *file == name) {
            assert_eq!(outcome, Err(*code), "{name}");
        }
    }
}
