//! Rename over the protocol: prepareRename's range and placeholder, edits in every file
//! of a two-file project (the symbol table's cell included), refusals with their reason.

mod common;

use common::{at, find, redact, ProjectDir, TestServer, MAIN_LAD, MOTOR_LAD};
use lsp_types::request::{PrepareRenameRequest, Rename};
use lsp_types::{Position, RenameParams, WorkspaceEdit};

fn rename(s: &mut TestServer, u: &lsp_types::Uri, p: Position, new: &str) -> lsp_server::Response {
    let params = RenameParams {
        text_document_position: at(u, p.line, p.character),
        new_name: new.into(),
        work_done_progress_params: Default::default(),
    };
    s.request_raw(
        <Rename as lsp_types::request::Request>::METHOD,
        serde_json::to_value(params).expect("params"),
    )
}

/// The edits sorted by file and position, for a stable snapshot.
fn sorted(edit: &WorkspaceEdit) -> Vec<(String, Vec<lsp_types::TextEdit>)> {
    let mut files: Vec<_> = edit
        .changes
        .iter()
        .flatten()
        .map(|(u, e)| {
            let mut e = e.clone();
            e.sort_by_key(|e| (e.range.start.line, e.range.start.character));
            (u.as_str().to_string(), e)
        })
        .collect();
    files.sort_by(|a, b| a.0.cmp(&b.0));
    files
}

#[test]
fn a_symbol_of_the_table_is_renamed_in_every_file() {
    let p = ProjectDir::new();
    let mut s = TestServer::start();
    let announced = &s.initialize_result["capabilities"]["renameProvider"]["prepareProvider"];
    assert_eq!(announced, &serde_json::Value::Bool(true));
    let main = p.uri("src/main.lad");
    let motor = p.uri("src/motor.lad");
    s.open(&main, MAIN_LAD);
    s.open(&motor, MOTOR_LAD);
    let lamp = find(MAIN_LAD, "Lamp", 0, 1);
    let prepared = s.request::<PrepareRenameRequest>(at(&main, lamp.line, lamp.character));
    insta::assert_snapshot!("prepare_lamp", redact(&prepared, &[&p.root()]));
    let motor_use = find(MOTOR_LAD, "Motor\n", 0, 0);
    let r = rename(&mut s, &motor, motor_use, "Drive");
    let edit: WorkspaceEdit =
        serde_json::from_value(r.result.expect("an edit")).expect("a WorkspaceEdit");
    insta::assert_snapshot!("motor_to_drive", redact(&sorted(&edit), &[&p.root()]));
    // The subroutine, renamed from its CALL in the other file.
    let call = find(MAIN_LAD, "MOTOR,", 0, 2);
    let r = rename(&mut s, &main, call, "Drive2");
    let edit: WorkspaceEdit =
        serde_json::from_value(r.result.expect("an edit")).expect("a WorkspaceEdit");
    insta::assert_snapshot!("block_to_drive2", redact(&sorted(&edit), &[&p.root()]));
}

#[test]
fn refusals_say_why() {
    let p = ProjectDir::new();
    let mut s = TestServer::start();
    let main = p.uri("src/main.lad");
    s.open(&main, MAIN_LAD);
    let start = find(MAIN_LAD, "Start", 0, 1);
    let mut reasons = Vec::new();
    for new in ["Lamp", "MW10", "END_VAR", "9lives", "MOTOR"] {
        let r = rename(&mut s, &main, start, new);
        let e = r.error.expect("refused");
        reasons.push(format!("{new}: {}", e.message));
    }
    let lbl = find(MAIN_LAD, "BEGIN", 0, 1);
    let prepared = s.request_raw(
        <PrepareRenameRequest as lsp_types::request::Request>::METHOD,
        serde_json::to_value(at(&main, lbl.line, lbl.character)).expect("params"),
    );
    reasons.push(format!(
        "BEGIN: {}",
        prepared.error.expect("refused").message
    ));
    insta::assert_snapshot!(reasons.join("\n"));
}
