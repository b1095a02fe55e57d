//! Code actions over the protocol: did-you-mean replacements, declaring an undefined
//! symbol, adding a missing END_ line; each with the diagnostic it fixes, preferred when
//! it is the only fix.

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
