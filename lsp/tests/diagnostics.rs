//! Diagnostics as published: code, severity, message with help, related information
//! for secondary labels, the code's documentation link, source "gutta".
#![allow(clippy::unwrap_used)] // test helpers outside #[test] functions

mod common;

use common::{redact, uri, TestServer};

#[test]
fn a_lone_file_publishes_codes_help_and_docs_links() {
    let mut s = TestServer::start();
    let u = uri("main.lad");
    s.open(
        &u,
        "SYMBOLS\n  Start : I0.0\n  Start : I0.1\nEND_SYMBOLS\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLDX    Strat\n=      Q0.0\nEND_ORGANIZATION_BLOCK\n",
    );
    insta::assert_snapshot!(redact(&s.diagnostics_of(&u), &[]));
}

#[test]
fn a_change_in_one_project_file_republishes_every_file() {
    let p = common::ProjectDir::new();
    let mut s = TestServer::start();
    let main = p.uri("src/main.lad");
    let motor = p.uri("src/motor.lad");
    let table = p.uri("symbols.csv");
    s.open(&main, common::MAIN_LAD);
    // Every file of the program is published, clean ones with empty lists.
    for u in [&main, &motor, &table] {
        assert_eq!(s.diagnostics_of(u), &[], "{}", u.as_str());
    }
    // Break the table's symbol `Motor` from main.lad's side: nothing; from the
    // subroutine's: rename the use, so motor.lad reports it.
    s.open(&motor, common::MOTOR_LAD);
    s.replace(
        &motor,
        2,
        &common::MOTOR_LAD.replace("=      Motor", "=      Motr"),
    );
    assert_eq!(s.diagnostics_of(&main), &[]);
    insta::assert_snapshot!(redact(&s.diagnostics_of(&motor), &[&p.root()]));
    // A duplicate symbol between main.lad's SYMBOLS and the table: the diagnostic
    // lands in one file and points into the other.
    let with_symbols = format!("SYMBOLS\n  Lamp : Q0.2\nEND_SYMBOLS\n{}", common::MAIN_LAD);
    s.replace(&main, 2, &with_symbols);
    insta::assert_snapshot!(
        "duplicate_across_files",
        redact(
            &[
                ("main", s.diagnostics_of(&main)),
                ("table", s.diagnostics_of(&table))
            ],
            &[&p.root()]
        )
    );
    // Closing both: the program is dropped, every file cleared.
    s.close(&main);
    s.close(&motor);
    for u in [&main, &motor, &table] {
        assert_eq!(s.diagnostics_of(u), &[], "{}", u.as_str());
    }
}

#[test]
fn files_changed_on_disk_reach_the_programs_that_hold_them() {
    let p = common::ProjectDir::new();
    let mut s = TestServer::start_watching();
    s.sync();
    let registered: Vec<&str> = s
        .server_requests
        .iter()
        .map(|r| r.method.as_str())
        .collect();
    assert_eq!(registered, ["client/registerCapability"]);
    let main = p.uri("src/main.lad");
    let motor = p.uri("src/motor.lad");
    let table = p.uri("symbols.csv");
    s.open(&main, common::MAIN_LAD);
    assert_eq!(s.diagnostics_of(&motor), &[]);
    // The table loses `Motor` on disk: motor.lad (not open) now misuses the name.
    std::fs::write(
        p.root().join("symbols.csv"),
        common::SYMBOLS_CSV.replace("Motor,Q0.1,main drive\n", ""),
    )
    .unwrap();
    s.files_changed(&[&table]);
    // (`Motor` then names the block MOTOR: names are case-insensitive.)
    let messages: Vec<_> = s
        .diagnostics_of(&motor)
        .iter()
        .map(|d| d.message.clone())
        .collect();
    assert_eq!(messages.len(), 1, "{messages:?}");
    assert!(messages[0].contains("subroutine"), "{messages:?}");
    // gutta.toml drops motor.lad: main.lad calls a block that is gone, motor.lad is
    // no longer part of a program and is cleared.
    std::fs::write(
        p.root().join("gutta.toml"),
        "[program]\nsources = [\"src/main.lad\"]\nsymbols = [\"symbols.csv\"]\n",
    )
    .unwrap();
    s.files_changed(&[&p.uri("gutta.toml")]);
    assert_eq!(s.diagnostics_of(&motor), &[]);
    let codes: Vec<_> = s
        .diagnostics_of(&main)
        .iter()
        .map(|d| d.code.clone())
        .collect();
    assert!(
        codes.contains(&Some(lsp_types::NumberOrString::String("E0206".into()))),
        "{codes:?}"
    );
}

#[test]
fn a_broken_gutta_toml_is_shown_once_and_the_file_is_analysed_alone() {
    let dir = tempfile::tempdir().unwrap();
    let root = std::fs::canonicalize(dir.path()).unwrap();
    std::fs::write(
        root.join("gutta.toml"),
        "[program]\nsourcs = [\"main.lad\"]\n",
    )
    .unwrap();
    std::fs::write(root.join("main.lad"), "LDX I0.0\n").unwrap();
    let mut s = TestServer::start();
    let main = common::file_uri(&root.join("main.lad"));
    s.open(&main, "LDX I0.0\n");
    s.replace(&main, 2, "LDX I0.1\n");
    let shown = s.received("window/showMessage");
    assert_eq!(shown.len(), 1, "one warning, not one per change");
    let message = shown[0].params["message"].as_str().unwrap();
    assert!(message.contains("gutta.toml"), "{message}");
    assert!(!s.diagnostics_of(&main).is_empty(), "analysed alone");
}

/// A change in one file of a project changes what the other files show (tokens, inlay
/// hints): a client that supports the refresh requests gets them after the change; a
/// lone file does not cause them, nor does a client without the support.
#[test]
fn a_project_change_asks_the_client_to_refresh_tokens_and_hints() {
    let p = common::ProjectDir::new();
    let capabilities = lsp_types::ClientCapabilities {
        workspace: Some(lsp_types::WorkspaceClientCapabilities {
            semantic_tokens: Some(lsp_types::SemanticTokensWorkspaceClientCapabilities {
                refresh_support: Some(true),
            }),
            inlay_hint: Some(lsp_types::InlayHintWorkspaceClientCapabilities {
                refresh_support: Some(true),
            }),
            ..Default::default()
        }),
        ..Default::default()
    };
    let mut s = TestServer::start_with(lsp_types::InitializeParams {
        capabilities,
        ..Default::default()
    });
    let main = p.uri("src/main.lad");
    s.open(&main, common::MAIN_LAD);
    s.replace(&main, 2, &format!("{}\n", common::MAIN_LAD));
    s.sync();
    let methods: Vec<&str> = s
        .server_requests
        .iter()
        .map(|r| r.method.as_str())
        .collect();
    assert!(
        methods.contains(&"workspace/semanticTokens/refresh"),
        "{methods:?}"
    );
    assert!(
        methods.contains(&"workspace/inlayHint/refresh"),
        "{methods:?}"
    );

    let mut plain = TestServer::start();
    plain.open(&main, common::MAIN_LAD);
    plain.replace(&main, 2, &format!("{}\n", common::MAIN_LAD));
    plain.sync();
    let refreshes = plain
        .server_requests
        .iter()
        .filter(|r| r.method.ends_with("/refresh"))
        .count();
    assert_eq!(refreshes, 0, "a client without refresh support gets none");
}

/// A symbol table saved by a Chinese Windows (GBK) is read as gutta-cc reads it: its
/// symbols resolve in the project's sources, and it has no diagnostics of its own.
#[test]
fn a_gbk_symbol_table_on_disk_is_read_in_its_code_page() {
    let p = common::ProjectDir::new();
    // `启动,I0.0,按钮` in GBK (启 C6F4, 动 B6AF, 按 B0B4, 钮 C5A5): not UTF-8.
    let mut csv = b"Symbol,Address,Comment\n".to_vec();
    csv.extend([0xC6, 0xF4, 0xB6, 0xAF]);
    csv.extend(b",I0.0,");
    csv.extend([0xB0, 0xB4, 0xC5, 0xA5]);
    csv.extend(b"\nLamp,Q0.0,indicator\nMotor,Q0.1,main drive\n");
    assert!(String::from_utf8(csv.clone()).is_err());
    std::fs::write(p.root().join("symbols.csv"), csv).expect("writes the table");
    let mut s = TestServer::start();
    let main = p.uri("src/main.lad");
    s.open(
        &main,
        &common::MAIN_LAD.replace("LD     Start", "LD     启动"),
    );
    assert_eq!(
        s.diagnostics_of(&main),
        &[],
        "启动 comes from the GBK table"
    );
    assert_eq!(s.diagnostics_of(&p.uri("symbols.csv")), &[]);
    let warnings = s.received("window/showMessage");
    assert!(
        warnings.is_empty(),
        "no warning about the table: {warnings:?}"
    );
}
