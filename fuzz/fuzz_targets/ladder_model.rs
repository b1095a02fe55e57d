//! Fuzz target of the ladder model reader (docs/ladder.md, "The model as JSON"):
//! arbitrary bytes through `gutta_ladder::json::read_model` and, when they read,
//! `validate` against the default target's instruction set. It must never panic; every
//! refusal is an L code whose path is empty or starts with a field of the format.
#![no_main]

use std::sync::{Arc, OnceLock};

use gutta_catalog::{stdlib, Target};
use gutta_ladder::json::{read_model, validate};
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
                return;
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
