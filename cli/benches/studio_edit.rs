//! Issue 27's bar for an edit in the studio: an edit to its redrawn rung with
//! diagnostics within 50 ms, on a 1,000-network program. Measured here in Rust through
//! `studio::Session::apply`, what the studio's server calls for each edit: the edit
//! parsed and applied to the model, written into the buffer in place, the buffer
//! checked again and its ladder built, the touched network drawn as SVG, and the
//! model's diagnostics (`json::check`: the compiler's whole pipeline) mapped to their
//! elements.
//!
//! The program is the ladder model bench's program of real networks
//! (ladder/benches/corpus_program), 1,000 networks, in a project in a temporary folder
//! whose gutta.toml names the front end's bench target (compiler/benches/target:
//! program limits a 1,000-network program fits in). The edit makes the first contact
//! of the drawn network nearest the middle of MAIN normally closed (`set_mnemonic`
//! `LD` -> `LDN`); each timed apply is undone untimed, so every run edits the same
//! text. `cargo bench -p gutta-cli --bench studio_edit`; `cargo test -p gutta-cli
//! --bench studio_edit` runs it once.

#![allow(
    clippy::disallowed_macros,
    clippy::disallowed_methods,
    reason = "a bench writes its project and prints what it measured"
)]

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Criterion};
use gutta_cli::studio::Session;
use gutta_compiler::diagnostics::Severity;
use gutta_ladder::json::{Element, Model, NetworkBody};

#[path = "studio_project/mod.rs"]
mod studio_project;

use studio_project::{project, FILE, NETWORKS};

/// `set_mnemonic` `LDN` on the first contact (an `LD`) of the drawn network nearest
/// the middle of MAIN, as JSON.
fn middle_contact(model: &Model) -> String {
    let networks = &model.blocks[0].networks;
    let middle = networks.len() / 2;
    let network = (middle..networks.len())
        .chain(0..middle)
        .find(|&n| match &networks[n].body {
            NetworkBody::Rung {
                rung: Element::Series { series },
            } => {
                matches!(series.first(), Some(Element::Contact { contact, .. }) if contact == "LD")
            }
            _ => false,
        })
        .expect("a drawn network starts with LD");
    format!(
        r#"{{"op": "set_mnemonic", "at": "blocks[0].networks[{network}].rung.series[0]", "mnemonic": "LDN"}}"#
    )
}

fn bench_studio_edit(c: &mut Criterion) {
    let root = project("bench");
    let mut session = Session::open(std::slice::from_ref(&root)).expect("the project opens");
    // MAIN's networks and the subroutines' together.
    let networks: usize = session
        .model(FILE)
        .expect("open")
        .blocks
        .iter()
        .map(|b| b.networks.len())
        .sum();
    assert!(networks >= NETWORKS, "{networks} networks");
    let errors = |d: &[gutta_ladder::json::ModelDiagnostic]| {
        d.iter().filter(|d| d.severity == Severity::Error).count()
    };
    assert_eq!(
        errors(session.diagnostics(FILE).expect("open")),
        0,
        "it checks clean"
    );
    let edit = middle_contact(session.model(FILE).expect("open"));
    let text = session.text(FILE).expect("open").to_string();

    // Untimed: the edit applies, its network is redrawn, the program still checks, and
    // undo gives the text back.
    let update = session.apply(FILE, &edit).expect("the edit applies");
    assert_eq!(update.networks.len(), 1);
    assert!(update.networks[0].svg.contains("class=\"network\""));
    assert_eq!(errors(&update.diagnostics), 0);
    session.undo(FILE).expect("undoes");
    assert_eq!(session.text(FILE).expect("open"), text);
    println!(
        "studio_edit: {networks} networks, {} lines; {edit}",
        text.lines().count()
    );

    c.bench_function("studio/apply", |b| {
        b.iter_custom(|iterations| {
            let mut spent = Duration::ZERO;
            for _ in 0..iterations {
                let start = Instant::now();
                black_box(session.apply(FILE, &edit).expect("the edit applies"));
                spent += start.elapsed();
                session.undo(FILE).expect("undoes");
            }
            spent
        });
    });
    let _ = std::fs::remove_dir_all(&root);
}

criterion_group!(benches, bench_studio_edit);
criterion_main!(benches);
