//! textDocument/foldingRange over the in-process server: blocks, VAR sections,
//! networks and comment runs as line ranges.

mod common;

use common::{uri, TestServer};
use lsp_types::request::FoldingRangeRequest;
use lsp_types::{FoldingRangeParams, TextDocumentIdentifier};

#[test]
fn blocks_sections_networks_and_comments_fold() {
    let mut s = TestServer::start();
    let u = uri("main.lad");
    s.open(
        &u,
        "// blink\n// two lines\nSYMBOLS\n  Start : I0.0\nEND_SYMBOLS\n\nORGANIZATION_BLOCK MAIN:OB1\nVAR\n  t : INT;\nEND_VAR\nBEGIN\nNETWORK 1 // latch\nLD     Start\n=      Q0.0\nNETWORK 2\nLD     SM0.5\n=      Q0.1\nEND_ORGANIZATION_BLOCK\n\nSYSTEM_BLOCK\n  PORT0.BAUD = 9600\nEND_SYSTEM_BLOCK\n",
    );
    let ranges = s.request::<FoldingRangeRequest>(FoldingRangeParams {
        text_document: TextDocumentIdentifier::new(u.clone()),
        work_done_progress_params: Default::default(),
        partial_result_params: Default::default(),
    });
    let shown: Vec<String> = ranges
        .unwrap_or_default()
        .iter()
        .map(|r| format!("{}..{} {:?}", r.start_line, r.end_line, r.kind))
        .collect();
    insta::assert_snapshot!(shown.join("\n"));
}
