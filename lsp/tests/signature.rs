//! Signature help over the protocol: the instruction's operands with role and types,
//! the active operand by comma position, a CALL's subroutine parameters.

mod common;

use common::{at, find, redact, uri, TestServer};
use lsp_types::request::SignatureHelpRequest;
use lsp_types::{SignatureHelp, SignatureHelpParams};

const PROGRAM: &str = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\nMOVW   MW0, MW2\nCALL   ADD3, 5, \nEND_ORGANIZATION_BLOCK\n\
SUBROUTINE_BLOCK ADD3:SBR0\nVAR_INPUT\n  a : INT; // first\nEND_VAR\nVAR_OUTPUT\n  r : INT;\nEND_VAR\nBEGIN\nNETWORK 1\nLD SM0.0\nEND_SUBROUTINE_BLOCK\n";

fn help(s: &mut TestServer, u: &lsp_types::Uri, needle: &str, shift: u32) -> Option<SignatureHelp> {
    s.request::<SignatureHelpRequest>(SignatureHelpParams {
        context: None,
        text_document_position_params: {
            let p = find(PROGRAM, needle, 0, shift);
            at(u, p.line, p.character)
        },
        work_done_progress_params: Default::default(),
    })
}

#[test]
fn operands_roles_types_and_the_active_one() {
    let mut s = TestServer::start();
    assert!(s.initialize_result["capabilities"]["signatureHelpProvider"].is_object());
    let u = uri("main.lad");
    s.open(&u, PROGRAM);
    insta::assert_snapshot!("movw_second", redact(&help(&mut s, &u, "MW2", 1), &[]));
    let first = help(&mut s, &u, "MW0,", 1).expect("signature help");
    assert_eq!(first.active_parameter, Some(0));
    insta::assert_snapshot!("call_parameters", redact(&help(&mut s, &u, "5, ", 3), &[]));
    assert_eq!(help(&mut s, &u, "LD SM0.0", 1), None, "not in operands");
}
