//! The analysis API the language server will adapt: definitions, references and hover
//! with byte spans, from text alone.

use gutta_analysis::Analysis;
use gutta_compiler::check::DefKind;

const PROGRAM: &str = "SYMBOLS\n  Start : I0.0 // push button\nEND_SYMBOLS\n\
ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLD Start\nCALL ADD3, MW10, MW12\nNetwork 2\nLD Start\nMOVW 16#0E01, MW20\nEND_ORGANIZATION_BLOCK\n\
SUBROUTINE_BLOCK ADD3:SBR0\nVAR_INPUT\n  a : INT;\nEND_VAR\nVAR_OUTPUT\n  r : INT;\nEND_VAR\nBEGIN\nNetwork 1\nLD SM0.0\nMOVW #a, #r\nEND_SUBROUTINE_BLOCK\n";

fn at(text: &str, needle: &str, nth: usize) -> usize {
    text.match_indices(needle)
        .nth(nth)
        .map(|(i, _)| i)
        .unwrap_or_else(|| panic!("no {needle} #{nth}"))
}

#[test]
fn definitions_references_and_hover() {
    let a = Analysis::new("p.lad", PROGRAM, None);
    assert!(a.diagnostics().is_empty(), "{:?}", a.diagnostics());
    let kinds: Vec<DefKind> = a.definitions().iter().map(|d| d.kind).collect();
    assert!(
        kinds.contains(&DefKind::Symbol)
            && kinds.contains(&DefKind::Unit)
            && kinds.contains(&DefKind::Local)
    );

    // A use of `Start` leads to its definition and to both uses.
    let use_at = at(PROGRAM, "Start", 1);
    let def = a.definition_at(use_at + 2).expect("definition of Start");
    assert_eq!((def.name.as_str(), def.kind), ("Start", DefKind::Symbol));
    assert_eq!(&PROGRAM[def.span.range()], "Start");
    let refs = a.references_at(use_at);
    assert_eq!(refs.len(), 3, "definition and two uses");
    assert!(refs.iter().all(|s| &PROGRAM[s.range()] == "Start"));

    // CALL ADD3 refers to the subroutine; #a to the local.
    let call = at(PROGRAM, "ADD3", 0);
    assert_eq!(a.definition_at(call).map(|d| d.kind), Some(DefKind::Unit));
    let local = at(PROGRAM, "#a", 0) + 1;
    let d = a.definition_at(local).expect("local");
    assert!(
        d.detail.contains("INT") && d.detail.contains("LW0"),
        "{}",
        d.detail
    );

    // Hover: an instruction's summary, an address with its Modbus reference, a symbol.
    let (_, text) = a.hover(at(PROGRAM, "MOVW", 0)).expect("hover on MOVW");
    assert!(text.contains("MOVW"), "{text}");
    let (span, text) = a.hover(at(PROGRAM, "MW20", 0) + 1).expect("hover on MW20");
    assert_eq!(&PROGRAM[span.range()], "MW20");
    assert!(text.contains("400019"), "{text}");
    let (_, text) = a.hover(use_at).expect("hover on Start");
    assert!(text.contains("push button"), "{text}");
}

#[test]
fn broken_text_still_gives_answers() {
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLD Lamp\nMOVW MB0,\n";
    let a = Analysis::new("b.lad", text, None);
    assert!(a.diagnostics().len() >= 2);
    for d in a.diagnostics() {
        assert!(d.primary.span.end as usize <= text.len());
    }
    assert!(a.hover(at(text, "LD", 0)).is_some());
}
