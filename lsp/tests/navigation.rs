//! Hover, go to definition, references and document highlight through the server: in
//! one file (with CRLF and non-ASCII text before the positions), and across the files
//! of a project on disk, into its CSV symbol table.
#![allow(clippy::unwrap_used)] // test helpers outside #[test] functions

mod common;

use common::{at, find, show_location, show_range, uri, ProjectDir, TestServer};
use lsp_types::request::{DocumentHighlightRequest, GotoDefinition, HoverRequest, References};
use lsp_types::{
    DocumentHighlightParams, GotoDefinitionParams, GotoDefinitionResponse, HoverContents,
    HoverParams, PartialResultParams, Position, ReferenceContext, ReferenceParams, Uri,
    WorkDoneProgressParams,
};

const LONE: &str = "// 启动 🚀 demo\r\nSYMBOLS\r\n  Start : I0.0 // 按钮 push button\r\n  Lamp  : Q0.0\r\nEND_SYMBOLS\r\nORGANIZATION_BLOCK MAIN:OB1\r\nBEGIN\r\nNetwork 1 // 🚀 latch\r\nLD     Start\r\nO      M0.0\r\n=      M0.0\r\nJMP    4\r\nCALL   ADD3, 2, 3, MW12\r\nLBL    4\r\nLD     M0.0\r\n=      Lamp\r\nEND_ORGANIZATION_BLOCK\r\nSUBROUTINE_BLOCK ADD3:SBR0\r\nVAR_INPUT\r\n  a : INT; // 🚀 first\r\n  b : INT;\r\nEND_VAR\r\nVAR_OUTPUT\r\n  r : INT;\r\nEND_VAR\r\nBEGIN\r\nNetwork 1\r\nLD     SM0.0\r\nMOVW   #a, #r\r\n+I     #b, #r\r\nEND_SUBROUTINE_BLOCK\r\nDATA_BLOCK INIT:DAT0\r\nMW22 UINT 6\r\nEND_DATA_BLOCK\r\n";

fn hover_text(s: &mut TestServer, u: &Uri, p: Position) -> String {
    let h = s.request::<HoverRequest>(HoverParams {
        text_document_position_params: at(u, p.line, p.character),
        work_done_progress_params: WorkDoneProgressParams::default(),
    });
    match h {
        Some(h) => {
            let HoverContents::Markup(m) = h.contents else {
                panic!("markdown hover expected")
            };
            format!("[{}]\n{}", show_range(&h.range.unwrap()), m.value)
        }
        None => "(none)".into(),
    }
}

fn definition(s: &mut TestServer, u: &Uri, p: Position, root: Option<&std::path::Path>) -> String {
    let d = s.request::<GotoDefinition>(GotoDefinitionParams {
        text_document_position_params: at(u, p.line, p.character),
        work_done_progress_params: WorkDoneProgressParams::default(),
        partial_result_params: PartialResultParams::default(),
    });
    match d {
        Some(GotoDefinitionResponse::Scalar(l)) => show_location(&l, root),
        other => format!("{other:?}"),
    }
}

fn references(
    s: &mut TestServer,
    u: &Uri,
    p: Position,
    declaration: bool,
    root: Option<&std::path::Path>,
) -> Vec<String> {
    s.request::<References>(ReferenceParams {
        text_document_position: at(u, p.line, p.character),
        work_done_progress_params: WorkDoneProgressParams::default(),
        partial_result_params: PartialResultParams::default(),
        context: ReferenceContext {
            include_declaration: declaration,
        },
    })
    .unwrap_or_default()
    .iter()
    .map(|l| show_location(l, root))
    .collect()
}

#[test]
fn hovers_in_one_file_explain_every_kind_of_item() {
    let mut s = TestServer::start();
    let u = uri("main.lad");
    s.open(&u, LONE);
    assert_eq!(s.diagnostics_of(&u), &[]);
    let places = [
        ("mnemonic", find(LONE, "MOVW", 0, 2)),
        ("symbol use", find(LONE, "Start", 1, 3)),
        ("symbol declaration", find(LONE, "Start", 0, 0)),
        ("address", find(LONE, "M0.0", 0, 1)),
        ("block", find(LONE, "ADD3", 0, 4)),
        ("local", find(LONE, "#r", 0, 1)),
        ("label", find(LONE, "LBL    4", 0, 7)),
        ("data block", find(LONE, "INIT", 0, 1)),
        ("nothing", find(LONE, "BEGIN", 0, 1)),
    ];
    let mut out = String::new();
    for (what, p) in places {
        out.push_str(&format!("=== {what}\n{}\n\n", hover_text(&mut s, &u, p)));
    }
    insta::assert_snapshot!(out);
}

#[test]
fn definition_references_and_highlight_in_one_file() {
    let mut s = TestServer::start();
    let u = uri("main.lad");
    s.open(&u, LONE);
    let mut out = Vec::new();
    for (what, p) in [
        ("Start", find(LONE, "Start", 1, 2)),
        ("JMP 4", find(LONE, "JMP    4", 0, 7)),
        ("CALL ADD3", find(LONE, "ADD3", 0, 0)),
        ("#b", find(LONE, "#b", 0, 1)),
    ] {
        out.push(format!("{what} -> {}", definition(&mut s, &u, p, None)));
        out.push(format!(
            "  refs: {}",
            references(&mut s, &u, p, true, None).join(", ")
        ));
        out.push(format!(
            "  refs without declaration: {}",
            references(&mut s, &u, p, false, None).len()
        ));
    }
    let highlights = s
        .request::<DocumentHighlightRequest>(DocumentHighlightParams {
            text_document_position_params: {
                let r = find(LONE, "#r", 1, 1);
                at(&u, r.line, r.character)
            },
            work_done_progress_params: WorkDoneProgressParams::default(),
            partial_result_params: PartialResultParams::default(),
        })
        .unwrap_or_default();
    for h in highlights {
        out.push(format!(
            "highlight #r {} {:?}",
            show_range(&h.range),
            h.kind
        ));
    }
    // A direct address: every operand naming it, written where `=` writes it.
    let m = find(LONE, "M0.0", 1, 1);
    out.push(format!(
        "M0.0 refs: {}",
        references(&mut s, &u, m, true, None).join(", ")
    ));
    let highlights = s
        .request::<DocumentHighlightRequest>(DocumentHighlightParams {
            text_document_position_params: at(&u, m.line, m.character),
            work_done_progress_params: WorkDoneProgressParams::default(),
            partial_result_params: PartialResultParams::default(),
        })
        .unwrap_or_default();
    for h in highlights {
        out.push(format!(
            "highlight M0.0 {} {:?}",
            show_range(&h.range),
            h.kind
        ));
    }
    // Nothing at a keyword.
    out.push(format!(
        "BEGIN -> {}",
        definition(&mut s, &u, find(LONE, "BEGIN", 0, 0), None)
    ));
    insta::assert_snapshot!(out.join("\n"));
}

#[test]
fn definitions_cross_files_and_reach_the_csv_row() {
    let p = ProjectDir::new();
    let root = p.root();
    let mut s = TestServer::start();
    let main = p.uri("src/main.lad");
    let motor = p.uri("src/motor.lad");
    let table = p.uri("symbols.csv");
    s.open(&main, common::MAIN_LAD);
    s.open(&motor, common::MOTOR_LAD);
    let mut out = Vec::new();
    let motor_use = find(common::MOTOR_LAD, "Motor", 0, 2);
    out.push(format!(
        "Motor -> {}",
        definition(&mut s, &motor, motor_use, Some(&root))
    ));
    let call = find(common::MAIN_LAD, "MOTOR", 0, 1);
    out.push(format!(
        "CALL MOTOR -> {}",
        definition(&mut s, &main, call, Some(&root))
    ));
    let start = find(common::MAIN_LAD, "Start", 0, 0);
    out.push(format!(
        "Start -> {}",
        definition(&mut s, &main, start, Some(&root))
    ));
    out.push(format!(
        "Start refs: {}",
        references(&mut s, &main, start, true, Some(&root)).join(", ")
    ));
    out.push(format!(
        "hover Lamp:\n{}",
        hover_text(&mut s, &main, find(common::MAIN_LAD, "Lamp", 0, 0))
    ));
    // The table itself, opened: its rows are definitions with references in the sources.
    s.open_as(&table, "csv", common::SYMBOLS_CSV);
    let row = find(common::SYMBOLS_CSV, "Motor", 0, 1);
    out.push(format!(
        "csv Motor refs: {}",
        references(&mut s, &table, row, true, Some(&root)).join(", ")
    ));
    out.push(format!(
        "csv Motor hover:\n{}",
        hover_text(&mut s, &table, row)
    ));
    insta::assert_snapshot!(out.join("\n"));
}

#[test]
fn positions_stay_right_in_a_crlf_file_with_emoji_of_a_project() {
    let p = ProjectDir::new();
    let root = p.root();
    let mut s = TestServer::start();
    let main = p.uri("src/main.lad");
    s.open(&main, common::MAIN_LAD);
    // The editor's text (CRLF, emoji and CJK before the names) wins over the disk's.
    let text = common::MAIN_LAD
        .replace("// start the motor", "// 🚀 启动 the motor 🚀")
        .replace("LD     Start", "LD     Start // 🚀🚀")
        .replace('\n', "\r\n");
    s.replace(&main, 2, &text);
    assert_eq!(s.diagnostics_of(&main), &[]);
    let lamp = find(&text, "Lamp", 0, 2);
    let refs = references(&mut s, &main, lamp, true, Some(&root));
    assert_eq!(refs, ["symbols.csv 2:0-2:4", "src/main.lad 5:7-5:11"]);
    let start = find(&text, "Start", 0, 5);
    assert_eq!(
        definition(&mut s, &main, start, Some(&root)),
        "symbols.csv 1:0-1:5"
    );
    // Past the end of a line: the line's end, which is no name.
    assert_eq!(
        definition(&mut s, &main, Position::new(3, 400), Some(&root)),
        "None"
    );
}

/// A timer, its symbol and its constant preset explain the timer: kind, resolution on
/// the target (CPU-EC20: T4 counts 100 ms) and the preset as a duration.
#[test]
fn a_timer_hover_gives_its_resolution_and_the_preset_as_a_duration() {
    let text = "SYMBOLS\n  Delay : T4 // 按钮 dwell\nEND_SYMBOLS\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLD     I0.0\nTON    Delay, 150\nLDW>=  T4, 20\n=      Q0.0\nEND_ORGANIZATION_BLOCK\n";
    let mut s = TestServer::start();
    let u = uri("main.lad");
    s.open(&u, text);
    assert_eq!(s.diagnostics_of(&u), &[]);
    let line = "**TON** (on-delay timer) `Delay` (`T4`): counts 100 ms; preset 150 = 15.0 s";
    let preset = hover_text(&mut s, &u, find(text, "150", 0, 1));
    assert_eq!(preset, format!("[7:14-7:17]\n{line}"));
    for (needle, n) in [("Delay", 0), ("Delay", 1), ("T4", 1)] {
        let h = hover_text(&mut s, &u, find(text, needle, n, 1));
        assert!(h.ends_with(&format!("\n\n{line}")), "{needle} #{n}: {h}");
    }
    assert_eq!(hover_text(&mut s, &u, find(text, "20", 0, 1)), "(none)");
}
