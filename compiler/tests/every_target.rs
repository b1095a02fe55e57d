//! Every example on every stdlib PLC type it fits: it compiles, and the image passes
//! the format crate's verifier (what the VM will demand). Where it does not fit, the
//! reasons must be the target's limits or memory map, never anything else.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

mod common;

use gutta_catalog::stdlib;
use gutta_compiler::diagnostics::Code;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};

/// Codes that mean "does not fit this PLC type".
const FIT: [Code; 10] = [
    Code::AddressOutOfTarget,
    Code::NoSuchPort,
    Code::ConstantOutOfRange,
    Code::BlockNumberRange,
    Code::TooManyInterrupts,
    Code::TooManySubroutines,
    Code::DataBlockTooLarge,
    Code::ConstPageTooLarge,
    Code::InstructionsTooLarge,
    Code::SystemPageTooLarge,
];

#[test]
fn examples_compile_and_verify_on_every_target_they_fit() {
    let files = common::compiling_programs();
    let mut fitted = 0;
    for path in &files {
        let text = std::fs::read_to_string(path).expect("read");
        for name in stdlib::names() {
            let target = stdlib::shared(name).expect("target");
            let explicit = ExplicitTarget {
                target: target.clone(),
                origin: format!("--plc {name}"),
            };
            let c = compile(
                SourceFile::new(path.display().to_string(), text.clone()),
                Some(&explicit),
            );
            match c.image {
                Some(image) => {
                    fitted += 1;
                    if let Err(e) = gutta_format::verify(&image, &target) {
                        panic!(
                            "{} on {name}: the compiler's image does not verify: {e}",
                            path.display()
                        );
                    }
                }
                None => {
                    let other: Vec<String> = c
                        .checked
                        .diagnostics()
                        .iter()
                        .filter(|d| d.is_error() && !FIT.contains(&d.code))
                        .map(|d| format!("{} {}", d.code.as_str(), d.message))
                        .collect();
                    assert!(
                        other.is_empty(),
                        "{} on {name} fails for reasons other than fit: {other:?}",
                        path.display()
                    );
                }
            }
        }
    }
    assert!(
        fitted >= files.len(),
        "only {fitted} compilations of {} files fit",
        files.len()
    );
}
