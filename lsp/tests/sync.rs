//! Text sync through the server: full and incremental changes with UTF-16 positions
//! (CJK, emoji, CRLF) reach the analysis, and the protocol's edges (unknown methods,
//! bad params, cancel, shutdown) answer as LSP says.
#![allow(clippy::unwrap_used)] // test helpers outside #[test] functions

mod common;

use common::{find, uri, TestServer};
use lsp_types::{Range, TextDocumentContentChangeEvent};
use serde_json::json;

const PROGRAM: &str = "ORGANIZATION_BLOCK MAIN:OB1\r\nBEGIN\r\nNetwork 1 // 启动 🚀 lamp\r\nLD     I0.0\r\n=      Q0.0\r\nEND_ORGANIZATION_BLOCK\r\n";

fn codes(server: &TestServer, u: &lsp_types::Uri) -> Vec<String> {
    server
        .diagnostics_of(u)
        .iter()
        .map(|d| match &d.code {
            Some(lsp_types::NumberOrString::String(s)) => s.clone(),
            other => format!("{other:?}"),
        })
        .collect()
}

#[test]
fn incremental_edits_after_cjk_and_emoji_land_where_the_client_put_them() {
    let mut s = TestServer::start();
    let u = uri("main.lad");
    s.open(&u, PROGRAM);
    assert_eq!(codes(&s, &u), Vec::<String>::new());
    // Insert a bad instruction right after "lamp" on the emoji line: UTF-16 columns.
    let after_lamp = find(PROGRAM, "lamp", 0, 4);
    s.change(
        &u,
        2,
        vec![TextDocumentContentChangeEvent {
            range: Some(Range::new(after_lamp, after_lamp)),
            range_length: None,
            text: "\r\nLDX    Start".into(),
        }],
    );
    let d = s.diagnostics_of(&u).to_vec();
    assert!(!d.is_empty(), "the inserted line is reported");
    // The first diagnostic sits on the inserted line (line 3), at column 0 or later.
    assert_eq!(d[0].range.start.line, 3);
    // Replace "LDX" by "LD " (a valid instruction again).
    let start = lsp_types::Position::new(3, 0);
    let end = lsp_types::Position::new(3, 3);
    s.change(
        &u,
        3,
        vec![TextDocumentContentChangeEvent {
            range: Some(Range::new(start, end)),
            range_length: None,
            text: "LD ".into(),
        }],
    );
    let still: Vec<String> = codes(&s, &u);
    // `Start` is still undeclared; the mnemonic error is gone.
    assert_ne!(still, codes_of(&d));
    // A full replacement clears everything.
    s.replace(&u, 4, PROGRAM);
    assert_eq!(codes(&s, &u), Vec::<String>::new());
    assert_eq!(s.publish_counts[u.as_str()], 4, "one publish per change");
    s.shutdown().unwrap();
}

fn codes_of(d: &[lsp_types::Diagnostic]) -> Vec<String> {
    d.iter().map(|d| format!("{:?}", d.code)).collect()
}

#[test]
fn unknown_requests_bad_params_and_cancel_answer_as_lsp_says() {
    let mut s = TestServer::start();
    let r = s.request_raw("gutta/nothing", json!({}));
    assert_eq!(
        r.error.unwrap().code,
        lsp_server::ErrorCode::MethodNotFound as i32
    );
    // Cancel and unknown notifications are ignored; the server lives on.
    s.notify_raw("$/cancelRequest", json!({"id": 1}));
    s.notify_raw("gutta/unknown", json!(null));
    // A notification with malformed params does not kill the server either.
    s.notify_raw("textDocument/didOpen", json!({"textDocument": 5}));
    s.sync();
    // Changes to a document that is not open are dropped.
    s.replace(&uri("never-opened.lad"), 2, "x");
    assert!(s.diagnostics.is_empty());
    s.shutdown().unwrap();
}

#[test]
fn initialize_announces_incremental_sync() {
    let s = TestServer::start();
    let sync = &s.initialize_result["capabilities"]["textDocumentSync"];
    assert_eq!(sync["change"], json!(2));
    assert_eq!(sync["openClose"], json!(true));
    assert_eq!(
        s.initialize_result["serverInfo"]["name"],
        json!("gutta-lsp")
    );
}

#[test]
fn closing_a_lone_file_clears_its_diagnostics() {
    let mut s = TestServer::start();
    let u = uri("bad.lad");
    s.open(&u, "LDX I0.0\n");
    assert!(!s.diagnostics_of(&u).is_empty());
    s.close(&u);
    assert!(s.diagnostics_of(&u).is_empty());
}
