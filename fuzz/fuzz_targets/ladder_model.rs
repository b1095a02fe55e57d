//! Fuzz target of the ladder model reader (docs/ladder.md, "The model as JSON"):
//! arbitrary bytes through `gutta_ladder::json::read_model` and, when they read,
//! `validate` against the default target's instruction set and, when it validates,
//! `program_of` (the model written as a program) and the compiler's `check_source` on
//! that program. It must never panic; every refusal is an L code whose path is empty or
//! starts with a field of the format. (`validate` alone does not check operands'
//! areas and types: that a model which validates compiles is `json::check`'s promise,
//! held by the `ladder_model_arbitrary` target.)
#![no_main]

use std::sync::{Arc, OnceLock};

use gutta_catalog::{stdlib, Target};
use gutta_compiler::check_source;
use gutta_compiler::source::SourceFile;
use gutta_ladder::json::{program_of, read_model, validate};
use libfuzzer_sys::fuzz_target;

/// The default target, loaded once.
fn default_target() -> &'static Arc<Target> {
    static TARGET: OnceLock<Arc<Target>> = OnceLock::new();
    TARGET
        .get_or_init(|| stdlib::shared(stdlib::DEFAULT).expect("the embedded default target loads"))
}

fuzz_target!(|data: &[u8]| {
    let refused = match read_model(data) {
        Ok(model) => match validate(&model, &default_target().instructions) {
            Ok(()) => {
                // A model that reads writes back as JSON that reads to the same model.
                let again = read_model(model.to_json().as_bytes()).expect("its own JSON reads");
                assert_eq!(again, model);
                match program_of(&model, &default_target().instructions) {
                    Ok(text) => {
                        check_source(SourceFile::new("model.lad", text), None);
                        return;
                    }
                    Err(e) => e,
                }
            }
            Err(e) => e,
        },
        Err(e) => e,
    };
    let first = refused.path.split(['.', '[']).next().unwrap_or("");
    assert!(
        ["", "format", "version", "plc", "symbols", "blocks"].contains(&first),
        "{refused}"
    );
});
