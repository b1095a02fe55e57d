//! The ladder model as JSON (docs/ladder.md, "The model as JSON"): every program of the
//! census corpora written as JSON reads back to the same model and validates against its
//! PLC type; each fault of a bad model is its L code at its JSON path; the L codes'
//! registry and docs/ladder.md's table agree.

#![allow(
    clippy::disallowed_methods,
    reason = "the test reads the repository's programs and docs"
)]

mod common;

use gutta_catalog::stdlib;
use gutta_compiler::source::{is_microwin, SourceFile, MARKER};
use gutta_compiler::{check_source, ExplicitTarget};
use gutta_ladder::json::{
    model_of, program_of, read_model, validate, Element, Model, ModelErrorCode, NetworkBody,
};

use common::{checked_file, files, root};

#[test]
fn every_program_round_trips_through_json_and_validates() {
    let sets = common::CORPORA;
    let mut failures = Vec::new();
    let mut rungs = 0;
    for (dir, exts) in sets {
        for path in files(dir, exts) {
            let checked = checked_file(&path);
            if checked.has_errors() {
                continue;
            }
            let ladder = gutta_ladder::build(&checked);
            let model = model_of(&checked, &ladder);
            let text = model.to_json();
            match read_model(text.as_bytes()) {
                Ok(back) if back == model => {}
                Ok(_) => failures.push(format!("{}: read back differs", path.display())),
                Err(e) => failures.push(format!("{}: {e}", path.display())),
            }
            if let Err(e) = validate(&model, &checked.target.instructions) {
                failures.push(format!("{}: {e}", path.display()));
            }
            for block in &model.blocks {
                let kinds = ["ORGANIZATION_BLOCK", "SUBROUTINE_BLOCK", "INTERRUPT_BLOCK"];
                if !kinds.contains(&block.kind.as_str()) {
                    failures.push(format!("{}: block kind {}", path.display(), block.kind));
                }
            }
            rungs += model
                .blocks
                .iter()
                .flat_map(|b| &b.networks)
                .filter(|n| matches!(n.body, NetworkBody::Rung { .. }))
                .count();
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(rungs > 300, "only {rungs} rungs");
}

/// Model -> program text -> compiled -> model again: the same model, for every program
/// of the corpora whose model the test above reads back.
#[test]
fn every_model_written_as_a_program_builds_the_same_model() {
    let sets = common::CORPORA;
    let mut failures = Vec::new();
    let mut programs_written = 0;
    for (dir, exts) in sets {
        for path in files(dir, exts) {
            let checked = checked_file(&path);
            if checked.has_errors() {
                continue;
            }
            let model = model_of(&checked, &gutta_ladder::build(&checked));
            let text = match program_of(&model, &checked.target.instructions) {
                Ok(text) => text,
                Err(e) => {
                    failures.push(format!("{}: {e}", path.display()));
                    continue;
                }
            };
            let explicit = ExplicitTarget {
                target: checked.target.clone(),
                origin: "the model's plc".to_string(),
            };
            // The model does not record the dialect: a Micro/WIN export's program is
            // compiled as one again (its marker first), as its operands are written.
            let original = std::fs::read_to_string(&path).unwrap_or_default();
            let text = if is_microwin(&path.display().to_string(), &original) {
                format!("{MARKER}\n{text}")
            } else {
                text
            };
            let name = format!("{} (written)", path.display());
            let again = check_source(SourceFile::new(name, text.clone()), Some(&explicit));
            if again.has_errors() {
                let first = again.diagnostics().first().map(|d| d.message.clone());
                failures.push(format!(
                    "{}: the written program does not compile: {first:?}\n{text}",
                    path.display()
                ));
                continue;
            }
            let back = without_lines(model_of(&again, &gutta_ladder::build(&again)));
            let model = without_lines(model);
            if back != model {
                let diff = first_difference(&model.to_json(), &back.to_json());
                failures.push(format!("{}: the model differs: {diff}", path.display()));
            }
            programs_written += 1;
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(programs_written > 50, "only {programs_written} programs");
}

/// The model with the source lines in its STL networks' reasons (`at line 12`) blanked:
/// the written program has its own line numbers.
fn without_lines(mut model: Model) -> Model {
    for net in model.blocks.iter_mut().flat_map(|b| &mut b.networks) {
        if let NetworkBody::Stl { reason, .. } = &mut net.body {
            let mut out = String::new();
            let mut rest = reason.as_str();
            while let Some(at) = rest.find("at line ") {
                out.push_str(&rest[..at + "at line ".len()]);
                rest =
                    rest[at + "at line ".len()..].trim_start_matches(|c: char| c.is_ascii_digit());
                out.push('_');
            }
            out.push_str(rest);
            *reason = out;
        }
    }
    model
}

/// The first line where two texts differ, both sides.
fn first_difference(a: &str, b: &str) -> String {
    a.lines()
        .zip(b.lines())
        .enumerate()
        .find(|(_, (x, y))| x != y)
        .map_or_else(
            || "in length".to_string(),
            |(i, (x, y))| format!("line {}: `{x}` became `{y}`", i + 1),
        )
}

#[test]
fn contacts_are_written_in_their_load_form() {
    let checked = common::checked(&common::main_with(
        "NETWORK 1\nLD I0.0\nAN I0.1\nOW>= MW2, 5\n= Q0.0",
    ));
    let model = model_of(&checked, &gutta_ladder::build(&checked));
    let NetworkBody::Rung { rung } = &model.blocks[0].networks[0].body else {
        panic!("not a rung");
    };
    let mut contacts = Vec::new();
    collect_contacts(rung, &mut contacts);
    assert_eq!(contacts, ["LD", "LDN", "LDW>="]);
}

fn collect_contacts(e: &Element, out: &mut Vec<String>) {
    match e {
        Element::Series { series: list } | Element::Parallel { parallel: list } => {
            list.iter().for_each(|e| collect_contacts(e, out))
        }
        Element::Contact { contact, .. } => out.push(contact.clone()),
        Element::Coil { .. } => {}
        Element::Box { inputs, .. } => inputs.iter().for_each(|e| collect_contacts(e, out)),
    }
}

/// A model of one network whose rung is `rung` (JSON text).
fn model_with(rung: &str) -> String {
    format!(
        r#"{{"format": "gutta-ladder", "version": 1, "plc": "CPU-EC20", "symbols": [],
  "blocks": [{{"kind": "ORGANIZATION_BLOCK", "name": "MAIN", "id": "OB1", "networks": [
    {{"title": "", "comment": "", "rung": {{"series": [{{"contact": "LD", "operands": ["I0.0"]}}, {{"coil": "=", "operands": ["Q0.0"]}}]}}}},
    {{"title": "", "comment": "", "rung": {rung}}}]}}]}}"#
    )
}

/// The code and path `text` is refused with, read and validated on the default target.
fn refusal(text: &str) -> (ModelErrorCode, String) {
    let target = stdlib::default_target().expect("stdlib");
    let err = read_model(text.as_bytes())
        .and_then(|m| validate(&m, &target.instructions))
        .expect_err("refused");
    (err.code, err.path)
}

#[test]
fn a_good_model_validates() {
    let target = stdlib::default_target().expect("stdlib");
    let text = model_with(
        r#"{"series": [{"parallel": [{"contact": "LD", "operands": ["I0.1"]}, {"contact": "LDN", "operands": ["M0.0"]}]},
            {"box": "TON", "operands": ["T37", "100"], "inputs": []},
            {"parallel": [{"coil": "=", "operands": ["Q0.1"]}, {"series": [{"contact": "LD", "operands": ["I0.2"]}, {"coil": "S", "operands": ["Q0.2", "1"]}]}]}]}"#,
    );
    let model = read_model(text.as_bytes()).expect("reads");
    validate(&model, &target.instructions).expect("valid");
}

#[test]
fn each_fault_has_its_code_and_json_path() {
    use ModelErrorCode as C;
    let rung = |r: &str| model_with(r);
    let cases: Vec<(String, ModelErrorCode, &str)> = vec![
        ("{\"format\": ".to_string(), C::NotJson, ""),
        ("[1, 2]".to_string(), C::Shape, ""),
        (
            r#"{"format": "gutta-svg", "version": 1}"#.to_string(),
            C::UnknownFormat,
            "format",
        ),
        (
            r#"{"format": "gutta-ladder", "version": 2}"#.to_string(),
            C::LaterVersion,
            "version",
        ),
        (
            r#"{"format": "gutta-ladder", "version": 1, "plc": "CPU-EC20"}"#.to_string(),
            C::Shape,
            "blocks",
        ),
        (
            rung(
                r#"{"series": [{"contact": "LDX", "operands": ["I0.0"]}, {"coil": "=", "operands": ["Q0.0"]}]}"#,
            ),
            C::UnknownMnemonic,
            "blocks[0].networks[1].rung.series[0]",
        ),
        (
            rung(
                r#"{"series": [{"contact": "AN", "operands": ["I0.0"]}, {"coil": "=", "operands": ["Q0.0"]}]}"#,
            ),
            C::WrongElement,
            "blocks[0].networks[1].rung.series[0]",
        ),
        (
            rung(
                r#"{"series": [{"contact": "LD", "operands": ["I0.0"]}, {"coil": "S", "operands": ["Q0.0"]}]}"#,
            ),
            C::OperandCount,
            "blocks[0].networks[1].rung.series[1].operands",
        ),
        (
            rung(
                r#"{"series": [{"contact": "LD", "operands": ["I0.0"]}, {"coil": "S", "operands": ["Q0.0", " "]}]}"#,
            ),
            C::OperandCount,
            "blocks[0].networks[1].rung.series[1].operands[1]",
        ),
        (
            rung(
                r#"{"series": [{"contact": "LD", "operands": ["I0.0"]}, {"coil": "=", "operands": ["Q0.0"]}, {"contact": "LD", "operands": ["I0.1"]}]}"#,
            ),
            C::OutputNotLast,
            "blocks[0].networks[1].rung.series[1]",
        ),
        (
            rung(
                r#"{"series": [{"contact": "LD", "operands": ["I0.0"]}, {"contact": "LDN", "operands": ["I0.1"]}]}"#,
            ),
            C::NoOutput,
            "blocks[0].networks[1].rung",
        ),
        (
            rung(
                r#"{"series": [{"contact": "LD", "operands": ["I0.0"]}, {"parallel": [{"coil": "=", "operands": ["Q0.0"]}, {"contact": "LD", "operands": ["I0.1"]}]}]}"#,
            ),
            C::NoOutput,
            "blocks[0].networks[1].rung.series[1].parallel[1]",
        ),
        (
            rung(
                r#"{"series": [{"contact": "LD", "operands": [7]}, {"coil": "=", "operands": ["Q0.0"]}]}"#,
            ),
            C::Shape,
            "blocks[0].networks[1].rung.series[0].operands[0]",
        ),
        (
            rung(
                r#"{"series": [{"contact": "LD", "operands": ["I0.0"]}, {"box": "CTU", "operands": ["C1", "5"], "inputs": []}]}"#,
            ),
            C::BoxInputs,
            "blocks[0].networks[1].rung.series[1].inputs",
        ),
        (
            rung(
                r#"{"series": [{"contact": "LD", "operands": ["I0.0"]}, {"box": "CTU", "operands": ["C1", "5"], "inputs": [{"coil": "=", "operands": ["Q0.0"]}]}]}"#,
            ),
            C::OutputNotLast,
            "blocks[0].networks[1].rung.series[1].inputs[0]",
        ),
        (
            r#"{"format": "gutta-ladder", "version": 0}"#.to_string(),
            C::Shape,
            "version",
        ),
        (
            format!("{}{}", "[".repeat(10_000), "]".repeat(10_000)),
            C::NotJson,
            "",
        ),
        (
            rung(r#"{"series": [{"wire": 1}]}"#),
            C::Shape,
            "blocks[0].networks[1].rung.series[0]",
        ),
    ];
    let mut wrong = Vec::new();
    for (text, code, path) in cases {
        let got = refusal(&text);
        if got != (code, path.to_string()) {
            wrong.push(format!(
                "{text}\n  want {code} at {path:?}, got {} at {:?}",
                got.0, got.1
            ));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn the_codes_are_numbered_explained_and_documented() {
    let doc = std::fs::read_to_string(root().join("docs/ladder.md")).expect("docs/ladder.md");
    for (i, code) in ModelErrorCode::ALL.iter().enumerate() {
        assert_eq!(code.as_str(), format!("L{:04}", i + 1));
        assert_eq!(
            ModelErrorCode::parse(&code.as_str().to_lowercase()),
            Some(*code)
        );
        assert!(!code.explanation().is_empty());
        let row = format!("| {} | {} |", code.as_str(), code.summary());
        assert!(doc.contains(&row), "docs/ladder.md lacks the row `{row}`");
    }
}

/// A valid model's program: each rung as the writer's canonical STL, the blocks'
/// keywords and their END_ keywords around them.
#[test]
fn a_valid_model_is_written_as_canonical_stl() {
    let target = stdlib::default_target().expect("stdlib");
    let text = model_with(
        r#"{"series": [{"parallel": [{"contact": "LD", "operands": ["I0.1"]}, {"contact": "LDN", "operands": ["M0.0"]}]},
            {"box": "TON", "operands": ["T37", "100"], "inputs": []},
            {"parallel": [{"coil": "=", "operands": ["Q0.1"]}, {"series": [{"contact": "LD", "operands": ["I0.2"]}, {"coil": "S", "operands": ["Q0.2", "1"]}]}]}]}"#,
    );
    let model = read_model(text.as_bytes()).expect("reads");
    let program = program_of(&model, &target.instructions).expect("written");
    let lines: Vec<&str> = program.lines().collect();
    let from = lines
        .iter()
        .position(|l| *l == "NETWORK 2")
        .expect("network 2");
    assert_eq!(
        lines[from..],
        [
            "NETWORK 2",
            "LD     I0.1",
            "ON     M0.0",
            "TON    T37, 100",
            "=      Q0.1",
            "A      I0.2",
            "S      Q0.2, 1",
            "END_ORGANIZATION_BLOCK",
        ],
        "{program}"
    );
    assert!(program.starts_with("PLC_TYPE CPU-EC20\n"), "{program}");
    assert!(program.contains("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\n"));
}

/// A valid rung STL cannot say: L0013 at the rung's JSON path.
#[test]
fn a_rung_the_writer_refuses_is_l0013_at_its_path() {
    let target = stdlib::default_target().expect("stdlib");
    let text = model_with(
        r#"{"series": [{"contact": "NOT", "operands": []}, {"coil": "=", "operands": ["Q0.1"]}]}"#,
    );
    let model = read_model(text.as_bytes()).expect("reads");
    validate(&model, &target.instructions).expect("valid");
    let err = program_of(&model, &target.instructions).expect_err("refused");
    assert_eq!(err.code, ModelErrorCode::Unwritable);
    assert_eq!(err.path, "blocks[0].networks[1].rung");
}

/// The power rules (L0013 from `validate`): a rung's STL must mean what it draws.
#[test]
fn a_rung_whose_stl_would_mean_something_else_is_l0013_at_the_element() {
    let target = stdlib::default_target().expect("stdlib");
    let set = &target.instructions;
    let ld = |x: &str| format!(r#"{{"contact": "LD", "operands": ["{x}"]}}"#);
    let ton = r#"{"box": "TON", "operands": ["T37", "100"], "inputs": []}"#;
    let not = r#"{"contact": "NOT", "operands": []}"#;
    let coil = r#"{"coil": "=", "operands": ["Q0.1"]}"#;
    let refused = [
        // A timer in a parallel path after I0.1: STL would time I0.2 alone.
        (
            format!(
                r#"{{"series": [{}, {{"parallel": [{{"series": [{}, {ton}]}}, {}]}}, {coil}]}}"#,
                ld("I0.1"),
                ld("I0.2"),
                ld("I0.3")
            ),
            "blocks[0].networks[1].rung.series[1].parallel[0].series[1]",
        ),
        // NOT in a parallel path after I0.1: STL would invert I0.2 alone.
        (
            format!(
                r#"{{"series": [{}, {{"parallel": [{}, {{"series": [{}, {not}]}}]}}, {coil}]}}"#,
                ld("I0.1"),
                ld("I0.3"),
                ld("I0.2")
            ),
            "blocks[0].networks[1].rung.series[1].parallel[1].series[1]",
        ),
        // The same inside an output branch (after LPS).
        (
            format!(
                r#"{{"series": [{}, {{"parallel": [{{"series": [{{"parallel": [{}, {{"series": [{}, {not}]}}]}}, {coil}]}}, {{"coil": "=", "operands": ["Q0.2"]}}]}}]}}"#,
                ld("I0.1"),
                ld("I0.3"),
                ld("I0.2")
            ),
            "blocks[0].networks[1].rung.series[1].parallel[0].series[0].parallel[1].series[1]",
        ),
        // Paths ending in boxes in parallel, followed by a coil: a path, not outputs
        // (the ladder_edit property test's finding on power_flow.lad network 7).
        (
            format!(
                r#"{{"series": [{}, {{"parallel": [{{"series": [{}, {ton}]}}, {{"series": [{}, {{"box": "TONR", "operands": ["T6", "50"], "inputs": []}}]}}]}}, {coil}]}}"#,
                ld("I0.0"),
                ld("I2.1"),
                ld("I2.2")
            ),
            "blocks[0].networks[1].rung.series[1].parallel[0].series[1]",
        ),
        // Outputs in parallel straight from the rail: separate rungs.
        (
            format!(
                r#"{{"parallel": [{{"series": [{}, {coil}]}}, {{"series": [{}, {{"coil": "=", "operands": ["Q0.2"]}}]}}]}}"#,
                ld("I0.1"),
                ld("I0.2")
            ),
            "blocks[0].networks[1].rung",
        ),
        // A coil first on the rail, and a box that runs without power flow in a rung.
        (
            format!(r#"{{"series": [{coil}]}}"#),
            "blocks[0].networks[1].rung.series[0]",
        ),
        (
            format!(
                r#"{{"series": [{}, {{"box": "ENI", "operands": [], "inputs": []}}]}}"#,
                ld("I0.1")
            ),
            "blocks[0].networks[1].rung.series[1]",
        ),
    ];
    for (rung, path) in refused {
        let model = read_model(model_with(&rung).as_bytes()).expect("reads");
        let err = validate(&model, set).expect_err(&rung);
        assert_eq!(
            (err.code, err.path.as_str()),
            (ModelErrorCode::Unwritable, path),
            "{rung}: {err}"
        );
    }
    // At the start of the rung a parallel path starts at the rail: the timer times
    // I0.2 alone, as drawn, and the written STL says so.
    let rung = format!(
        r#"{{"series": [{{"parallel": [{{"series": [{}, {ton}]}}, {}]}}, {}, {coil}]}}"#,
        ld("I0.2"),
        ld("I0.3"),
        ld("I0.1")
    );
    let model = read_model(model_with(&rung).as_bytes()).expect("reads");
    validate(&model, set).expect("valid");
    let program = program_of(&model, set).expect("written");
    assert!(
        program.contains("LD     I0.2\nTON    T37, 100\nO      I0.3\nA      I0.1\n="),
        "{program}"
    );
}

/// What cannot become source lines is L0002 at its path when the program is written.
#[test]
fn a_block_kind_or_a_line_break_the_program_cannot_hold_is_l0002() {
    let target = stdlib::default_target().expect("stdlib");
    let written = |text: String| {
        let model = read_model(text.as_bytes()).expect("reads");
        let err = program_of(&model, &target.instructions).expect_err("refused");
        (err.code, err.path)
    };
    let good = r#"{"series": [{"contact": "LD", "operands": ["I0.1"]}, {"coil": "=", "operands": ["Q0.1"]}]}"#;
    let kind = model_with(good).replace("ORGANIZATION_BLOCK", "FUNCTION_BLOCK");
    assert_eq!(
        written(kind),
        (ModelErrorCode::Shape, "blocks[0].kind".to_string())
    );
    let broken = model_with(&good.replace("I0.1", "I0.1\\nLD I0.2"));
    assert_eq!(
        written(broken),
        (
            ModelErrorCode::Shape,
            "blocks[0].networks[1].rung.series[0].operands[0]".to_string()
        )
    );
}
