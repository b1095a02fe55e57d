//! Rendered diagnostics with their source, as a user sees them (no colour, ASCII):
//! one insta snapshot per file in tests/data/render/. A change in wording or layout
//! shows as a reviewed snapshot diff.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

use std::path::Path;

use gutta_compiler::check_source;
use gutta_compiler::diagnostics::render::{render, RenderStyle};
use gutta_compiler::source::SourceFile;

#[test]
fn rendered_diagnostics() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/render");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("render dir")
        .map(|e| e.expect("entry").path())
        .collect();
    files.sort();
    assert!(files.len() >= 5);
    for path in files {
        let name = path
            .file_stem()
            .and_then(|s| s.to_str())
            .expect("name")
            .to_string();
        let text = std::fs::read_to_string(&path).expect("read");
        let checked = check_source(SourceFile::new(format!("{name}.lad"), text), None);
        assert!(
            !checked.diagnostics().is_empty(),
            "{name} gives no diagnostic"
        );
        let rendered = render(&checked.file, checked.diagnostics(), RenderStyle::PLAIN);
        insta::assert_snapshot!(name, rendered);
    }
}
