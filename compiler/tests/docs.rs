//! docs/diagnostics.md is generated from the code registry; this test fails when they
//! drift apart (`UPDATE_DOCS=1` rewrites the file).

#![allow(
    clippy::disallowed_methods,
    reason = "the docs test reads the generated page and rewrites it on request"
)]

use std::path::Path;

#[test]
fn diagnostics_reference_is_up_to_date() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/diagnostics.md");
    let want = gutta_compiler::diagnostics::reference_markdown();
    if std::env::var_os("UPDATE_DOCS").is_some() {
        std::fs::write(&path, &want).expect("write docs/diagnostics.md");
    }
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(have == want, "docs/diagnostics.md is stale: run `UPDATE_DOCS=1 cargo test -p gutta-compiler --test docs`");
}
