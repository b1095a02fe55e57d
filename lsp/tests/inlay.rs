//! textDocument/inlayHint over the in-process server: symbol addresses, Modbus
//! references and timer presets as durations, in a lone file and across a project's
//! files and symbol table, and the `initializationOptions.inlayHints` switch.

mod common;

use common::{uri, TestServer};
use lsp_types::request::InlayHintRequest;
use lsp_types::{
    InitializeParams, InlayHintLabel, InlayHintParams, Position, Range, TextDocumentIdentifier, Uri,
};

const TEXT: &str = "SYMBOLS\n  Start : I0.0 // go\n  Speed : MW20\nEND_SYMBOLS\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD     Start\nMOVW   Speed, MW30\n=      Q0.0\nEND_ORGANIZATION_BLOCK\n";

fn hints(s: &mut TestServer, u: &Uri) -> Vec<String> {
    let answer = s.request::<InlayHintRequest>(InlayHintParams {
        text_document: TextDocumentIdentifier::new(u.clone()),
        range: Range::new(Position::new(0, 0), Position::new(100, 0)),
        work_done_progress_params: Default::default(),
    });
    answer
        .unwrap_or_default()
        .iter()
        .map(|h| {
            let label = match &h.label {
                InlayHintLabel::String(s) => s.clone(),
                InlayHintLabel::LabelParts(parts) => {
                    parts.iter().map(|p| p.value.as_str()).collect()
                }
            };
            format!(
                "{}:{} {label:?} {:?}",
                h.position.line + 1,
                h.position.character,
                h.kind
            )
        })
        .collect()
}

#[test]
fn symbol_uses_show_addresses_and_words_their_modbus_register() {
    let mut s = TestServer::start();
    let u = uri("main.lad");
    s.open(&u, TEXT);
    insta::assert_snapshot!(hints(&mut s, &u).join("\n"));
}

#[test]
fn symbols_of_a_project_table_show_their_address_in_every_file() {
    let p = common::ProjectDir::new();
    let mut s = TestServer::start();
    let motor = p.uri("src/motor.lad");
    s.open(&motor, common::MOTOR_LAD);
    assert_eq!(hints(&mut s, &motor), ["8:12 \": Q0.1\" Some(Type)"]);
}

#[test]
fn initialization_options_turn_hints_off() {
    let start = |options: serde_json::Value| {
        TestServer::start_with(InitializeParams {
            initialization_options: Some(options),
            ..InitializeParams::default()
        })
    };
    let u = uri("main.lad");
    let mut off = start(serde_json::json!({ "inlayHints": false }));
    off.open(&u, TEXT);
    assert_eq!(hints(&mut off, &u), Vec::<String>::new());
    let mut no_modbus = start(serde_json::json!({ "inlayHints": { "modbus": false } }));
    no_modbus.open(&u, TEXT);
    assert_eq!(
        hints(&mut no_modbus, &u),
        ["8:12 \": I0.0\" Some(Type)", "9:12 \": MW20\" Some(Type)"]
    );
}

#[test]
fn a_timer_preset_shows_its_duration_unless_turned_off() {
    // CPU-EC20: T4 counts 100 ms, T2 10 ms; a preset in memory has no duration.
    let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD     I0.0\nTON    T4, 100\nTONR   T2, 6150\nTOF    T5, MW10\nEND_ORGANIZATION_BLOCK\n";
    let u = uri("main.lad");
    let only_timers =
        serde_json::json!({ "inlayHints": { "modbus": false, "symbolAddresses": false } });
    let mut s = TestServer::start_with(InitializeParams {
        initialization_options: Some(only_timers),
        ..InitializeParams::default()
    });
    s.open(&u, text);
    assert_eq!(
        hints(&mut s, &u),
        [
            "5:14 \"10.0 s\" Some(Parameter)",
            "6:15 \"1 min 1.50 s\" Some(Parameter)"
        ]
    );
    let off = serde_json::json!({ "inlayHints": { "modbus": false, "timerDurations": false } });
    let mut s = TestServer::start_with(InitializeParams {
        initialization_options: Some(off),
        ..InitializeParams::default()
    });
    s.open(&u, text);
    assert_eq!(hints(&mut s, &u), Vec::<String>::new());
}

#[test]
fn visible_operands_are_the_live_values_hook() {
    let u = uri("main.lad");
    let mut docs = gutta_lsp::documents::Documents::default();
    docs.open(
        u.clone(),
        gutta_lsp::documents::Document {
            text: TEXT.to_string(),
            version: 1,
            language_id: "gutta".into(),
        },
    );
    let mut ws = gutta_lsp::workspace::Workspace::default();
    ws.opened(&docs, &u);
    let program = ws.program_of(&u).expect("analysed");
    let shown: Vec<String> = gutta_lsp::handlers::inlay::visible_operands(
        program,
        &u,
        Range::new(Position::new(7, 0), Position::new(10, 0)),
    )
    .iter()
    .map(|(r, a)| {
        format!(
            "{}:{}-{} {}",
            r.start.line + 1,
            r.start.character,
            r.end.character,
            program.checked.target.memory.format_address(a)
        )
    })
    .collect();
    assert_eq!(
        shown,
        ["8:7-12 I0.0", "9:7-12 MW20", "9:14-18 MW30", "10:7-11 Q0.0"]
    );
}
