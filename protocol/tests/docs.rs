//! docs/protocol.md's function table is generated from the function registry
//! (`registry::reference_markdown`), its Modbus function and frame-length tables from
//! the Modbus function registry (`modbus_registry`); these tests fail when they drift
//! apart (`UPDATE_DOCS=1` rewrites the tables between their markers).

#![allow(
    clippy::disallowed_methods,
    clippy::disallowed_types,
    reason = "tests read and write their data files"
)]

use std::path::Path;
use std::sync::Mutex;

/// The tests rewrite one file: one at a time.
static DOCS: Mutex<()> = Mutex::new(());

/// Checks (or with `UPDATE_DOCS`, rewrites) the text between `begin` and `end`.
fn check_generated(begin_marker: &str, end_marker: &str, generated: &str, what: &str) {
    let _one_at_a_time = DOCS.lock().unwrap_or_else(|e| e.into_inner());
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/protocol.md");
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    let (Some(begin), Some(end)) = (have.find(begin_marker), have.find(end_marker)) else {
        panic!(
            "docs/protocol.md lacks the markers `{}` and `{end_marker}`",
            begin_marker.trim()
        );
    };
    let want = format!(
        "{}{begin_marker}{generated}{}",
        &have[..begin],
        &have[end..]
    );
    if std::env::var_os("UPDATE_DOCS").is_some() {
        std::fs::write(&path, &want).expect("write docs/protocol.md");
    }
    assert!(
        have == want,
        "docs/protocol.md's {what} is stale: regenerate with `UPDATE_DOCS=1 cargo test -p gutta-protocol --test docs`"
    );
}

#[test]
fn function_table_is_up_to_date() {
    check_generated(
        "<!-- functions: generated from protocol/src/registry.rs -->\n",
        "<!-- end functions -->",
        &gutta_protocol::registry::reference_markdown(),
        "function table",
    );
}

#[test]
fn modbus_tables_are_up_to_date() {
    check_generated(
        "<!-- modbus functions: generated from protocol/src/modbus_registry.rs -->\n",
        "<!-- end modbus functions -->",
        &gutta_protocol::modbus_registry::reference_markdown(),
        "Modbus function table",
    );
    check_generated(
        "<!-- modbus frame lengths: generated from protocol/src/modbus_registry.rs -->\n",
        "<!-- end modbus frame lengths -->",
        &gutta_protocol::modbus_registry::splitter_markdown(),
        "frame length table",
    );
}
