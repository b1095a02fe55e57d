//! Document symbols (the outline of one file, and of a symbol table) and workspace
//! symbols (every definition of every open program, fuzzy-matched) through the server.
#![allow(clippy::unwrap_used)] // test helpers outside #[test] functions

mod common;

use common::{show_location, uri, ProjectDir, TestServer};
use lsp_types::request::{DocumentSymbolRequest, Request as _, WorkspaceSymbolRequest};
use lsp_types::{
    DocumentSymbol, DocumentSymbolParams, DocumentSymbolResponse, OneOf, PartialResultParams,
    TextDocumentIdentifier, Uri, WorkDoneProgressParams, WorkspaceSymbol, WorkspaceSymbolParams,
};

fn outline(s: &mut TestServer, u: &Uri) -> String {
    let r = s.request::<DocumentSymbolRequest>(DocumentSymbolParams {
        text_document: TextDocumentIdentifier::new(u.clone()),
        work_done_progress_params: WorkDoneProgressParams::default(),
        partial_result_params: PartialResultParams::default(),
    });
    let Some(DocumentSymbolResponse::Nested(items)) = r else {
        panic!("nested document symbols expected, got {r:?}");
    };
    let mut out = String::new();
    render(&items, 0, &mut out);
    out
}

fn render(items: &[DocumentSymbol], depth: usize, out: &mut String) {
    for i in items {
        out.push_str(&format!(
            "{}{:?} {} {} sel {}{}\n",
            "  ".repeat(depth),
            i.kind,
            i.name,
            common::show_range(&i.range),
            common::show_range(&i.selection_range),
            i.detail
                .as_ref()
                .map(|d| format!(" - {d}"))
                .unwrap_or_default()
        ));
        render(i.children.as_deref().unwrap_or(&[]), depth + 1, out);
    }
}

fn workspace(s: &mut TestServer, query: &str, root: Option<&std::path::Path>) -> Vec<String> {
    // The answer's two shapes deserialize alike: read it as the one the server sends.
    let r = s.request_raw(
        WorkspaceSymbolRequest::METHOD,
        serde_json::to_value(WorkspaceSymbolParams {
            query: query.into(),
            work_done_progress_params: WorkDoneProgressParams::default(),
            partial_result_params: PartialResultParams::default(),
        })
        .unwrap(),
    );
    let found: Vec<WorkspaceSymbol> = serde_json::from_value(r.result.unwrap()).unwrap();
    found
        .iter()
        .map(|w| {
            let OneOf::Left(l) = &w.location else {
                panic!("a location expected")
            };
            format!(
                "{:?} {}{} @ {}",
                w.kind,
                w.name,
                w.container_name
                    .as_ref()
                    .map(|c| format!(" in {c}"))
                    .unwrap_or_default(),
                show_location(l, root)
            )
        })
        .collect()
}

const PROGRAM: &str = "PLC_TYPE CPU-EC20\nSYMBOLS\n  Start : I0.0 // 🚀 push button\n  Speed : MW0 : INT\nEND_SYMBOLS\nORGANIZATION_BLOCK MAIN:OB1\nTITLE=Main program\nBEGIN\nNetwork 1 // 启动 latch\nLD     Start\n=      Q0.0\nNetwork 2\nLD     SM0.0\nCALL   ADD3, 1, 2, MW12\nEND_ORGANIZATION_BLOCK\nSUBROUTINE_BLOCK ADD3:SBR0\nVAR_INPUT\n  a : INT;\n  b : INT;\nEND_VAR\nVAR_OUTPUT\n  r : INT;\nEND_VAR\nBEGIN\nNetwork 1 // add\nLD     SM0.0\nMOVW   #a, #r\n+I     #b, #r\nEND_SUBROUTINE_BLOCK\nINTERRUPT_BLOCK TICK:INT1\nBEGIN\nNetwork 1\nLD     SM0.0\n=      M1.0\nEND_INTERRUPT_BLOCK\nDATA_BLOCK INIT:DAT0\nMW22 UINT 6\nEND_DATA_BLOCK\nSYSTEM_BLOCK\nPORT0.BAUD = 9600\nEND_SYSTEM_BLOCK\n";

#[test]
fn the_outline_nests_networks_and_locals_under_their_blocks() {
    let mut s = TestServer::start();
    let u = uri("main.lad");
    s.open(&u, PROGRAM);
    assert_eq!(s.diagnostics_of(&u), &[]);
    insta::assert_snapshot!(outline(&mut s, &u));
}

#[test]
fn a_project_outlines_each_file_and_searches_every_open_program() {
    let p = ProjectDir::new();
    let root = p.root();
    let mut s = TestServer::start();
    let main = p.uri("src/main.lad");
    let table = p.uri("symbols.csv");
    s.open(&main, common::MAIN_LAD);
    s.open_as(&table, "csv", common::SYMBOLS_CSV);
    // A second program: a lone file outside the project.
    let lone = uri("lone.lad");
    s.open(&lone, PROGRAM);
    let mut out = format!("--- main.lad\n{}", outline(&mut s, &main));
    out.push_str(&format!("--- symbols.csv\n{}", outline(&mut s, &table)));
    out.push_str("--- query `mo`\n");
    for line in workspace(&mut s, "mo", Some(&root)) {
        out.push_str(&format!("{line}\n"));
    }
    out.push_str("--- query `st`\n");
    for line in workspace(&mut s, "st", Some(&root)) {
        out.push_str(&format!("{line}\n"));
    }
    insta::assert_snapshot!(out);
    assert_eq!(workspace(&mut s, "zzz", None), Vec::<String>::new());
}
