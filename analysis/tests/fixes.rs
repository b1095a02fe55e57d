//! The quick fixes the editor offers are the fixes diagnostics carry (the fixes
//! themselves are gutta-compiler's tests/fixes.rs).

use gutta_analysis::actions::code_actions;
use gutta_compiler::check_source;
use gutta_compiler::diagnostics::Code;
use gutta_compiler::source::SourceFile;

/// A misspelt END_ keyword's one fix is also the editor's one quick fix, preferred,
/// writing the keyword over the word.
#[test]
fn a_misspelt_end_has_one_preferred_quick_fix() {
    let text =
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD I0.0\n= Q0.0\nEND_ORGANISATION_BLOCK\n";
    let checked = check_source(SourceFile::new("t.lad", text), None);
    let [d] = checked.diagnostics() else {
        panic!("one diagnostic: {:?}", checked.diagnostics());
    };
    assert_eq!(d.code, Code::MisspeltEnd);

    let actions = code_actions(&checked, d.primary.span);
    assert_eq!(actions.len(), 1, "{actions:?}");
    assert!(actions[0].preferred);
    assert_eq!(actions[0].title, "Replace with `END_ORGANIZATION_BLOCK`");
    assert_eq!(
        actions[0].edits,
        vec![(d.primary.span, "END_ORGANIZATION_BLOCK".to_string())]
    );
}
