//! Fuzz target of the ladder model's edit operations as the studio sends them
//! (docs/ladder.md, "Editing the model"): the input's lines, each an edit in its JSON
//! form (`gutta_ladder::edit::Edit::from_json`) or `undo` / `redo`, applied by an
//! `edit::Editor` to one of the repository's models (the first byte chooses
//! tests/data/ladder_model/machine.json or machine_edited.json). It must never panic;
//! a refused edit leaves the model as it was; after every step the model validates, is
//! written as a program, and every network a change names writes its lines; the step's
//! changes are written into the program's text in place (`edit::apply_to_text`), which
//! stays the model's program but for network numbers (a deleted network leaves a gap);
//! the program at the end goes through the compiler's check; undoing every step gives the
//! model it started from.
#![no_main]

use std::sync::{Arc, OnceLock};

use gutta_catalog::{stdlib, Target};
use gutta_compiler::check_source;
use gutta_compiler::source::SourceFile;
use gutta_ladder::edit::{apply_to_text, instruction_lines, Change, Edit, Editor};
use gutta_ladder::json::{program_of, read_model, validate, Model};
use libfuzzer_sys::fuzz_target;

const MODELS: [&str; 2] = [
    include_str!("../../tests/data/ladder_model/machine.json"),
    include_str!("../../tests/data/ladder_model/machine_edited.json"),
];

/// The default target, loaded once (the models are CPU-EC20's).
fn default_target() -> &'static Arc<Target> {
    static TARGET: OnceLock<Arc<Target>> = OnceLock::new();
    TARGET
        .get_or_init(|| stdlib::shared(stdlib::DEFAULT).expect("the embedded default target loads"))
}

/// The models, read once.
fn models() -> &'static [Model; 2] {
    static READ: OnceLock<[Model; 2]> = OnceLock::new();
    READ.get_or_init(|| MODELS.map(|m| read_model(m.as_bytes()).expect("the model reads")))
}

fn holds(model: &Model, changes: &[Change]) {
    let set = &default_target().instructions;
    validate(model, set).expect("an edited model validates");
    program_of(model, set).expect("an edited model is written");
    for change in changes {
        if let Change::Lines(at) | Change::Heading(at) | Change::Inserted(at) = change {
            instruction_lines(model, set, *at).expect("a changed network writes its lines");
        }
    }
}

/// `text` with every `NETWORK n` line's number left out.
fn unnumbered(text: &str) -> String {
    text.lines()
        .map(|l| match l.strip_prefix("NETWORK ") {
            Some(rest) => {
                let rest = rest.trim_start_matches(|c: char| c.is_ascii_digit());
                format!("NETWORK{rest}")
            }
            None => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n")
}

fuzz_target!(|data: &[u8]| {
    let Some((&which, rest)) = data.split_first() else {
        return;
    };
    let start = &models()[usize::from(which % 2)];
    let set = &default_target().instructions;
    let mut editor = Editor::new(start.clone(), set);
    let mut text = program_of(start, set).expect("the model is written");
    let input = String::from_utf8_lossy(rest);
    for line in input.lines().take(64) {
        let before = editor.model().clone();
        let result = match line.trim() {
            "undo" => editor.undo(),
            "redo" => editor.redo(),
            json => match Edit::from_json(json) {
                Ok(edit) => editor.apply(edit),
                Err(_) => continue,
            },
        };
        match result {
            Ok(changes) => {
                holds(editor.model(), &changes);
                text = apply_to_text(&text, editor.model(), set, &changes)
                    .expect("the changes go into the text the model was written as");
                let written = program_of(editor.model(), set).expect("written");
                assert_eq!(unnumbered(&text), unnumbered(&written), "after {line}");
            }
            Err(_) => assert_eq!(editor.model(), &before, "a refused step changes nothing"),
        }
    }
    let program = program_of(editor.model(), set).expect("the model is written");
    check_source(SourceFile::new("edited.lad", program), None);
    while editor.can_undo() {
        editor.undo().expect("an edit undoes");
    }
    assert_eq!(editor.model(), start, "undoing every edit gives the start");
});
