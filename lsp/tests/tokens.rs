//! textDocument/semanticTokens/full and /range over the in-process server, decoded
//! back into `line:column text type modifiers` lines through the announced legend.

mod common;

use common::{uri, TestServer};
use lsp_types::request::{SemanticTokensFullRequest, SemanticTokensRangeRequest};
use lsp_types::{
    Position, Range, SemanticTokens, SemanticTokensParams, SemanticTokensRangeParams,
    SemanticTokensRangeResult, SemanticTokensResult, TextDocumentIdentifier,
};
use serde_json::Value;

const TEXT: &str = "PLC_TYPE CPU-EC20\nSYMBOLS\n  启动 : I0.0 // start\n  Speed : MW10 : INT\nEND_SYMBOLS\nSUBROUTINE_BLOCK ADD:SBR0\nVAR_INPUT\n  a : INT;\nEND_VAR\nBEGIN\nNETWORK 1 // add\nLD     启动\nMOVW   #a, Speed\n+I     3, AQW0\nLDW>=  C2, -5\nJMP    1\nLBL    1\nEND_SUBROUTINE_BLOCK\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD     SM0.0\nCALL   ADD, T3\nEND_ORGANIZATION_BLOCK\nDATA_BLOCK D:DAT0\n  MW22 UINT 6\nEND_DATA_BLOCK\nSYSTEM_BLOCK\n  PASSWORD = \"1234\"\nEND_SYSTEM_BLOCK\n";

/// Tokens of `TEXT` as lines, through the legend the server announced.
fn decode(s: &TestServer, tokens: &SemanticTokens) -> Vec<String> {
    decode_in(s, tokens, TEXT)
}

fn decode_in(s: &TestServer, tokens: &SemanticTokens, text: &str) -> Vec<String> {
    let legend = &s.initialize_result["capabilities"]["semanticTokensProvider"]["legend"];
    let names = |key: &str| -> Vec<String> {
        legend[key]
            .as_array()
            .into_iter()
            .flatten()
            .filter_map(Value::as_str)
            .map(str::to_string)
            .collect()
    };
    let (types, modifiers) = (names("tokenTypes"), names("tokenModifiers"));
    let lines: Vec<&str> = text.lines().collect();
    let (mut line, mut col) = (0u32, 0u32);
    tokens
        .data
        .iter()
        .map(|t| {
            if t.delta_line > 0 {
                col = 0;
            }
            line += t.delta_line;
            col += t.delta_start;
            let units: Vec<u16> = lines[line as usize].encode_utf16().collect();
            let text = String::from_utf16_lossy(&units[col as usize..(col + t.length) as usize]);
            let mods: Vec<&str> = (0..modifiers.len())
                .filter(|b| t.token_modifiers_bitset & (1 << b) != 0)
                .map(|b| modifiers[b].as_str())
                .collect();
            format!(
                "{}:{} {text} {} {}",
                line + 1,
                col,
                types[t.token_type as usize],
                mods.join("+")
            )
        })
        .collect()
}

#[test]
fn full_document_tokens_by_kind_and_area() {
    let mut s = TestServer::start();
    let u = uri("main.lad");
    s.open(&u, TEXT);
    let Some(SemanticTokensResult::Tokens(tokens)) =
        s.request::<SemanticTokensFullRequest>(SemanticTokensParams {
            text_document: TextDocumentIdentifier::new(u.clone()),
            work_done_progress_params: Default::default(),
            partial_result_params: Default::default(),
        })
    else {
        panic!("no tokens");
    };
    insta::assert_snapshot!(decode(&s, &tokens).join("\n"));
}

#[test]
fn a_range_gives_its_lines_only() {
    let mut s = TestServer::start();
    let u = uri("main.lad");
    s.open(&u, TEXT);
    let Some(SemanticTokensRangeResult::Tokens(tokens)) =
        s.request::<SemanticTokensRangeRequest>(SemanticTokensRangeParams {
            text_document: TextDocumentIdentifier::new(u.clone()),
            range: Range::new(Position::new(11, 0), Position::new(13, 0)),
            work_done_progress_params: Default::default(),
            partial_result_params: Default::default(),
        })
    else {
        panic!("no tokens");
    };
    assert_eq!(
        decode(&s, &tokens),
        [
            "12:0 LD function ",
            "12:7 启动 variable symbolic+input",
            "13:0 MOVW function ",
            "13:8 a parameter ",
            "13:11 Speed variable symbolic+memory",
        ]
    );
}

#[test]
fn project_files_and_symbol_tables_get_their_own_tokens() {
    let p = common::ProjectDir::new();
    let mut s = TestServer::start();
    let motor = p.uri("src/motor.lad");
    let table = p.uri("symbols.csv");
    s.open(&motor, common::MOTOR_LAD);
    s.open(&table, common::SYMBOLS_CSV);
    let mut shown = Vec::new();
    for (u, text) in [(&motor, common::MOTOR_LAD), (&table, common::SYMBOLS_CSV)] {
        let Some(SemanticTokensResult::Tokens(tokens)) =
            s.request::<SemanticTokensFullRequest>(SemanticTokensParams {
                text_document: TextDocumentIdentifier::new(u.clone()),
                work_done_progress_params: Default::default(),
                partial_result_params: Default::default(),
            })
        else {
            panic!("no tokens");
        };
        shown.extend(decode_in(&s, &tokens, text));
    }
    insta::assert_snapshot!(shown.join("\n"));
}
