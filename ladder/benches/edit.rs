//! Issue 26's speed bar for editing (docs/ladder.md, "Speed of the model"): an edit
//! operation on the ladder model plus rewriting its network in a 10,000-line `.lad`
//! file under 5 ms.
//!
//! The file is the model bench's program of real networks (`corpus_program/mod.rs`),
//! grown until it has 10,000 lines or more, checked on the front end's bench target.
//! What an editor holds is made once: the model (`json::model_of`), an
//! `edit::Editor` over it, and the file's syntax tree (`network_edit::parse`). The edit
//! makes the first contact of the drawn network nearest the middle of MAIN normally
//! closed (`set_mnemonic` `LD` -> `LDN`: NO -> NC, the commonest edit there is).
//!
//! Each step has its own id:
//! - `edit/apply`: `Editor::apply` alone (the network copied, edited, normalised,
//!   validated and written to check it, the undo kept);
//! - `edit/apply_rewrite`: that, then the changed network's lines
//!   (`edit::instruction_lines`) put into the text in place
//!   (`network_edit::replace_network` with the held tree, then `network_edit::apply`):
//!   the bar;
//! - `edit/apply_rewrite_parse`: that, then the new text parsed again, the tree the
//!   next edit needs;
//! - `edit/apply_to_text`: `Editor::apply`, then `edit::apply_to_text`, the library
//!   call a studio makes (it parses the text for each change it writes).
//!
//! Each run edits a fresh copy of the editor, made and dropped outside the timing
//! (`iter_batched_ref`). It asserts, untimed, that the rewritten text checks with no error and that only the
//! edited network's lines changed. `cargo bench -p gutta-ladder --bench edit`;
//! `cargo test --benches` runs each step once.

#![allow(clippy::disallowed_macros, reason = "a bench prints what it measured")]

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use gutta_analysis::network_edit::{self, BlockRef, NetworkRef};
use gutta_catalog::InstructionSet;
use gutta_compiler::check_source;
use gutta_compiler::source::SourceFile;
use gutta_ladder::edit::{
    apply_to_text, instruction_lines, Change, Edit, Editor, ElementPath, Step,
};
use gutta_ladder::json::{model_of, Element, Model, NetworkBody};

#[path = "corpus_program/mod.rs"]
mod corpus_program;

#[path = "../../compiler/benches/scale_program/mod.rs"]
#[allow(dead_code, reason = "only its bench target is used here")]
mod scale_program;

/// The file's size, in lines (at least).
const LINES: usize = 10_000;

fn bench_edit(c: &mut Criterion) {
    let target = scale_program::bench_target();
    let mut networks = 1_000;
    let text = loop {
        let text = corpus_program::generate(networks, &target);
        if text.lines().count() >= LINES {
            break text;
        }
        networks += 250;
    };
    let checked = check_source(SourceFile::new("edit.lad", text.as_str()), Some(&target));
    assert!(!checked.has_errors(), "the program checks clean");
    let set = &checked.target.instructions;
    let model = model_of(&checked, &gutta_ladder::build(&checked));
    let tree = network_edit::parse(&text, false);
    let edit = middle_contact(&model);

    // Untimed: the edit is accepted, the text rewritten checks, only that network
    // changed.
    let mut editor = Editor::new(model.clone(), set);
    let rewritten = apply_rewrite(&mut editor, set, &edit, &text, &tree);
    let checked_again = check_source(
        SourceFile::new("edit.lad", rewritten.as_str()),
        Some(&target),
    );
    assert!(!checked_again.has_errors(), "the edited program checks");
    let changed: Vec<_> = text
        .lines()
        .zip(rewritten.lines())
        .filter(|(a, b)| a != b)
        .collect();
    assert_eq!(changed.len(), 1, "one line changed: {changed:?}");
    assert_eq!(text.lines().count(), rewritten.lines().count());
    println!(
        "edit: {} lines, {networks} networks; {} changes `{}` into `{}`",
        text.lines().count(),
        edit_at(&edit),
        changed[0].0.trim(),
        changed[0].1.trim()
    );

    let fresh = || Editor::new(model.clone(), set);
    c.bench_function("edit/apply", |b| {
        b.iter_batched_ref(
            fresh,
            |editor| black_box(editor.apply(edit.clone()).expect("the edit applies")),
            BatchSize::LargeInput,
        )
    });
    c.bench_function("edit/apply_rewrite", |b| {
        b.iter_batched_ref(
            fresh,
            |editor| black_box(apply_rewrite(editor, set, &edit, &text, &tree)),
            BatchSize::LargeInput,
        )
    });
    c.bench_function("edit/apply_to_text", |b| {
        b.iter_batched_ref(
            fresh,
            |editor| {
                let changes = editor.apply(edit.clone()).expect("the edit applies");
                black_box(apply_to_text(&text, editor.model(), set, &changes).expect("in place"))
            },
            BatchSize::LargeInput,
        )
    });
    c.bench_function("edit/apply_rewrite_parse", |b| {
        b.iter_batched_ref(
            fresh,
            |editor| {
                let text = apply_rewrite(editor, set, &edit, &text, &tree);
                black_box(network_edit::parse(&text, false))
            },
            BatchSize::LargeInput,
        )
    });
}

/// The edit applied and every network it changed rewritten in `text` (tree held).
fn apply_rewrite(
    editor: &mut Editor<'_>,
    set: &InstructionSet,
    edit: &Edit,
    text: &str,
    tree: &gutta_compiler::syntax::ast::Program,
) -> String {
    let changes = editor.apply(edit.clone()).expect("the edit applies");
    let mut edits = Vec::new();
    for change in changes {
        let Change::Lines(at) = change else {
            panic!("an element edit changes lines, not {change:?}");
        };
        let lines = instruction_lines(editor.model(), set, at).expect("the edited network writes");
        let lines: Vec<&str> = lines.iter().map(String::as_str).collect();
        let place = NetworkRef {
            block: BlockRef::Index(at.block),
            network: at.network,
        };
        edits.push(network_edit::replace_network(text, tree, place, &lines).expect("in place"));
    }
    network_edit::apply(text, &edits)
}

/// `set_mnemonic` `LDN` on the first contact (an `LD`) of the drawn network nearest the
/// middle of the first block.
fn middle_contact(model: &Model) -> Edit {
    let networks = &model.blocks[0].networks;
    let middle = networks.len() / 2;
    let first_ld = |rung: &Element| match rung {
        Element::Series { series } => match series.first() {
            Some(Element::Contact { contact, .. }) if contact == "LD" => {
                Some(vec![Step::Series(0)])
            }
            _ => None,
        },
        _ => None,
    };
    let (network, steps) = (middle..networks.len())
        .chain(0..middle)
        .find_map(|n| match &networks[n].body {
            NetworkBody::Rung { rung } => first_ld(rung).map(|steps| (n, steps)),
            NetworkBody::Stl { .. } => None,
        })
        .expect("a drawn network starts with LD");
    let mut at = ElementPath::rung(0, network);
    for step in steps {
        at = at.then(step);
    }
    Edit::SetMnemonic {
        at,
        mnemonic: "LDN".to_string(),
        operands: None,
        inputs: None,
    }
}

fn edit_at(edit: &Edit) -> String {
    match edit {
        Edit::SetMnemonic { at, .. } => at.to_string(),
        other => format!("{other:?}"),
    }
}

criterion_group!(benches, bench_edit);
criterion_main!(benches);
