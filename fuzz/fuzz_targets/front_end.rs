//! Fuzz target of the whole front end: arbitrary bytes (lossily decoded) through
//! `check_source`, then both diagnostic renderers. Panics are the bugs it looks for; it
//! also asserts that every span it gets back lies inside the text on char boundaries.
#![no_main]

use std::sync::OnceLock;

use gutta_catalog::stdlib;
use gutta_compiler::diagnostics::json::to_json_lines;
use gutta_compiler::diagnostics::render::{render, RenderStyle};
use gutta_compiler::source::{SourceFile, Span};
use gutta_compiler::{check_source, ExplicitTarget};
use libfuzzer_sys::fuzz_target;

/// The default target, loaded once: loading it per input (as `check_source(.., None)`
/// does) would dominate the run. `PLC_TYPE` lines then take the W0204 path.
fn default_target() -> &'static ExplicitTarget {
    static TARGET: OnceLock<ExplicitTarget> = OnceLock::new();
    TARGET.get_or_init(|| ExplicitTarget {
        target: stdlib::shared(stdlib::DEFAULT).expect("the embedded default target loads"),
        origin: "the fuzzer".to_string(),
    })
}

fn assert_span(text: &str, span: Span, what: &str) {
    let (start, end) = (span.start as usize, span.end as usize);
    assert!(
        start <= end && end <= text.len(),
        "{what} span {start}..{end} outside text of {} bytes",
        text.len()
    );
    assert!(
        text.is_char_boundary(start) && text.is_char_boundary(end),
        "{what} span {start}..{end} not on char boundaries"
    );
}

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data).into_owned();
    let checked = check_source(SourceFile::new("fuzz.lad", text), Some(default_target()));
    let text = checked.file.text.as_str();
    for d in checked.diagnostics() {
        assert_span(text, d.primary.span, "primary");
        for s in &d.secondary {
            assert_span(text, s.span, "secondary");
        }
    }
    for def in &checked.output.definitions {
        assert_span(text, def.span, "definition");
    }
    for r in &checked.output.references {
        assert_span(text, r.span, "reference");
    }
    let rendered = render(&checked.file, checked.diagnostics(), RenderStyle::PLAIN);
    let json = to_json_lines(&checked.file, &checked.index, checked.diagnostics());
    assert_eq!(json.lines().count(), checked.diagnostics().len());
    assert!(checked.diagnostics().is_empty() || !rendered.is_empty());
});
