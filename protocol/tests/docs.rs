//! docs/protocol.md's function table is generated from the function registry
//! (`registry::reference_markdown`); this test fails when they drift apart
//! (`UPDATE_DOCS=1` rewrites the table between the markers).

#![allow(
    clippy::disallowed_methods,
    clippy::disallowed_types,
    reason = "tests read and write their data files"
)]

use std::path::Path;

const BEGIN: &str = "<!-- functions: generated from protocol/src/registry.rs -->\n";
const END: &str = "<!-- end functions -->";

#[test]
fn function_table_is_up_to_date() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/protocol.md");
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    let (Some(begin), Some(end)) = (have.find(BEGIN), have.find(END)) else {
        panic!(
            "docs/protocol.md lacks the markers `{}` and `{END}`",
            BEGIN.trim()
        );
    };
    let want = format!(
        "{}{BEGIN}{}{}",
        &have[..begin],
        gutta_protocol::registry::reference_markdown(),
        &have[end..]
    );
    if std::env::var_os("UPDATE_DOCS").is_some() {
        std::fs::write(&path, &want).expect("write docs/protocol.md");
    }
    assert!(
        have == want,
        "docs/protocol.md's function table is stale: regenerate with `UPDATE_DOCS=1 cargo test -p gutta-protocol --test docs`"
    );
}
