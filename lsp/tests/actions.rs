//! Code actions over the protocol: did-you-mean replacements, declaring an undefined
//! symbol at a free address of the width its use needs, adding a missing END_ line,
//! E0302's address of the right width; each with the diagnostic it fixes, preferred
//! when it is the only fix.

mod common;

use common::{find, redact, uri, TestServer};
use lsp_types::request::CodeActionRequest;
use lsp_types::{
    CodeActionContext, CodeActionOrCommand, CodeActionParams, Range, TextDocumentIdentifier,
};

fn actions(s: &mut TestServer, u: &lsp_types::Uri, range: Range) -> Vec<String> {
    let answer = s.request::<CodeActionRequest>(CodeActionParams {
        text_document: TextDocumentIdentifier::new(u.clone()),
        range,
        context: CodeActionContext::default(),
        work_done_progress_params: Default::default(),
        partial_result_params: Default::default(),
    });
    answer
        .into_iter()
        .flatten()
        .map(|a| match a {
            CodeActionOrCommand::CodeAction(a) => {
                let code = a
                    .diagnostics
                    .as_ref()
                    .and_then(|d| d.first())
                    .and_then(|d| d.code.clone());
                format!(
                    "{} (preferred: {:?}, fixes {:?})\n{}",
                    a.title,
                    a.is_preferred,
                    code,
                    redact(&a.edit, &[])
                )
            }
            other => panic!("a code action, not {other:?}"),
        })
        .collect()
}

#[test]
fn quick_fixes_for_typos_undefined_symbols_and_missing_ends() {
    let text = "SYMBOLS\n  Start : I0.0\nEND_SYMBOLS\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD     Strat\nMOWV   MW0, MW2\n=      Pump\n";
    let mut s = TestServer::start();
    let kinds = &s.initialize_result["capabilities"]["codeActionProvider"]["codeActionKinds"];
    assert_eq!(kinds, &serde_json::json!(["quickfix"]));
    let u = uri("main.lad");
    s.open(&u, text);
    let on = |needle: &str| {
        let p = find(text, needle, 0, 1);
        Range::new(p, p)
    };
    insta::assert_snapshot!(
        "typo_of_a_symbol",
        actions(&mut s, &u, on("Strat")).join("\n")
    );
    insta::assert_snapshot!(
        "typo_of_a_mnemonic",
        actions(&mut s, &u, on("MOWV")).join("\n")
    );
    insta::assert_snapshot!("undeclared", actions(&mut s, &u, on("Pump")).join("\n"));
    insta::assert_snapshot!(
        "missing_end",
        actions(&mut s, &u, on("ORGANIZATION")).join("\n")
    );
    assert!(actions(&mut s, &u, on("BEGIN")).is_empty());
}

/// E0302 on a direct address: the address of the wanted width at the same byte, the
/// diagnostic's only fix (preferred); none for a symbol or a bit.
#[test]
fn a_width_mismatch_gets_the_address_of_the_right_width() {
    let text = "SYMBOLS\n  Small : MB6\nEND_SYMBOLS\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD     I0.0\nMOVW   MB4, MW20\nMOVW   Small, MW22\nMOVW   M0.0, MW24\nEND_ORGANIZATION_BLOCK\n";
    let mut s = TestServer::start();
    let u = uri("main.lad");
    s.open(&u, text);
    let on = |needle: &str| {
        let p = find(text, needle, 0, 1);
        Range::new(p, p)
    };
    let fixes = actions(&mut s, &u, on("MB4"));
    assert_eq!(fixes.len(), 1, "{fixes:?}");
    assert!(
        fixes[0].starts_with("Replace `MB4` with `MW4` (the word at the same byte) (preferred: Some(true), fixes Some(String(\"E0302\")))"),
        "{fixes:?}"
    );
    assert!(fixes[0].contains("\"newText\": \"MW4\""), "{fixes:?}");
    assert!(actions(&mut s, &u, on("Small,")).is_empty());
    assert!(actions(&mut s, &u, on("M0.0")).is_empty());
}

/// A misspelt END_ keyword: one quick fix, replacing the word (not adding a second END_
/// line), for the one diagnostic of the line.
#[test]
fn misspelt_end_is_replaced() {
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD     I0.0\n=      Q0.0\nEND_ORGANISATION_BLOCK\n";
    let mut s = TestServer::start();
    let u = uri("main.lad");
    s.open(&u, text);
    let p = find(text, "END_ORGANISATION", 0, 3);
    let found = actions(&mut s, &u, Range::new(p, p));
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(
        found[0].starts_with(
            "Replace with `END_ORGANIZATION_BLOCK` (preferred: Some(true), fixes Some(String(\"E0116\")))"
        ),
        "{}",
        found[0]
    );
    insta::assert_snapshot!("misspelt_end", found.join("\n"));
}
