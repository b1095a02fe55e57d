//! The fixes diagnostics carry for editors: every did-you-mean in the error corpus (and
//! in a program with one typo of each kind) carries exactly one fix, and applying it
//! writes the text the help line shows and clears that diagnostic; every unclosed block
//! carries the END_ line that closes it.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

mod common;

use common::{lad_files, root};
use gutta_compiler::diagnostics::{Code, Diagnostic};
use gutta_compiler::source::SourceFile;
use gutta_compiler::{check_source, CheckedFile};

fn check(text: &str) -> CheckedFile {
    check_source(SourceFile::new("t.lad", text), None)
}

fn apply(text: &str, d: &Diagnostic) -> String {
    let mut out = text.to_string();
    let mut edits = d.fixes[0].edits.clone();
    edits.sort_by_key(|(s, _)| s.start);
    for (span, new) in edits.iter().rev() {
        out.replace_range(span.range(), new);
    }
    out
}

/// Every did-you-mean of `text` has one fix, writing what the help shows, after which
/// no diagnostic of that code starts there. Returns how many were checked.
fn did_you_means_apply(name: &str, text: &str) -> usize {
    let checked = check(text);
    let mut count = 0;
    for d in checked.diagnostics() {
        let Some(shown) = d
            .help
            .as_deref()
            .and_then(|h| h.strip_prefix("did you mean `"))
            .and_then(|h| h.strip_suffix("`?"))
        else {
            continue;
        };
        count += 1;
        assert_eq!(d.fixes.len(), 1, "{name}: {d:?}");
        let (span, new) = &d.fixes[0].edits[0];
        assert!(
            shown.ends_with(new.as_str()),
            "{name}: `{new}` for `{shown}`"
        );
        let fixed = check(&apply(text, d));
        assert!(
            !fixed
                .diagnostics()
                .iter()
                .any(|e| e.code == d.code && e.primary.span.start == span.start),
            "{name}: {:?} remains after its fix",
            d.code
        );
    }
    count
}

#[test]
fn one_typo_of_each_kind() {
    let text = "PLC_TYPE CPUEC20\nSYMBOLS\n  Start : I0.0\n  Temp : MD8 : RAEL\nEND_SYMBOLS\n\
        ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD Strat\nMOWV MW0, MW2\nCALL ADD4\nEND_ORGANIZATION_BLOCK\n\
        SUBROUTINE_BLOCK ADD3:SBR0\nVAR_INPUT\n  count : INTT;\n  value : INT;\nEND_VAR\nBEGIN\nNETWORK 1\n\
        LD SM0.0\nMOVW #valeu, MW4\nEND_SUBROUTINE_BLOCK\n\
        SYSTEM_BLOCK\n  PORT0.BUAD = 9600\n  PASWORD = \"1\"\nEND_SYSTEM_BLOCK\n";
    assert_eq!(did_you_means_apply("typos", text), 9);
}

#[test]
fn every_did_you_mean_of_the_error_corpus() {
    let mut count = 0;
    for path in lad_files(&root().join("tests/data/check/err")) {
        let text = std::fs::read_to_string(&path).expect("read");
        // Files that choose a PLC type by `// plc:` are checked with the default here;
        // the fixes do not depend on it.
        count += did_you_means_apply(&path.display().to_string(), &text);
    }
    assert!(count > 0, "the corpus has did-you-means");
}

#[test]
fn an_unclosed_block_gets_its_end_line() {
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD I0.0\n= Q0.0\n\
        SUBROUTINE_BLOCK S:SBR0\nVAR_INPUT\n  a : INT;\nBEGIN\nNETWORK 1\nLD I0.0";
    let mut text = text.to_string();
    for _ in 0..3 {
        let checked = check(&text);
        let Some(d) = checked
            .diagnostics()
            .iter()
            .find(|d| d.code == Code::UnterminatedBlock)
        else {
            break;
        };
        assert_eq!(d.fixes.len(), 1, "{d:?}");
        text = apply(&text, d);
    }
    assert!(
        !check(&text)
            .diagnostics()
            .iter()
            .any(|d| d.code == Code::UnterminatedBlock),
        "{text}"
    );
    assert!(text.contains("= Q0.0\nEND_ORGANIZATION_BLOCK\nSUBROUTINE_BLOCK"));
    assert!(text.ends_with("LD I0.0\nEND_SUBROUTINE_BLOCK\n"), "{text}");
}

/// A misspelt END_ keyword is one diagnostic, whose one fix writes the keyword over the
/// word: the line is replaced, not followed by a second END_ line. (That this fix is
/// also the editor's one quick fix is gutta-analysis's tests/fixes.rs.)
#[test]
fn a_misspelt_end_is_replaced_not_added() {
    let text =
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD I0.0\n= Q0.0\nEND_ORGANISATION_BLOCK\n";
    let checked = check(text);
    let [d] = checked.diagnostics() else {
        panic!("one diagnostic: {:?}", checked.diagnostics());
    };
    assert_eq!(d.code, Code::MisspeltEnd);
    assert_eq!(
        d.help.as_deref(),
        Some("did you mean `END_ORGANIZATION_BLOCK`?")
    );
    let word = text.find("END_ORGANISATION_BLOCK").expect("word");
    assert_eq!(
        d.primary.span.range(),
        word..word + "END_ORGANISATION_BLOCK".len()
    );

    let fixed = apply(text, d);
    assert_eq!(fixed, text.replace("ORGANISATION", "ORGANIZATION"));
    assert!(check(&fixed).diagnostics().is_empty(), "{fixed}");
}
