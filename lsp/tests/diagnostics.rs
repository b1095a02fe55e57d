//! Diagnostics as published: code, severity, message with help, related information
//! for secondary labels, the code's documentation link, source "gutta".

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
