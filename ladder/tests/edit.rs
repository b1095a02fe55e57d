//! The edit operations on the ladder model (docs/ladder.md, "Editing the model"): paths
//! print and parse as the L codes' JSON paths; each operation's result, in normal form,
//! comes back the same through its program; every refusal is its code at its path with
//! the model unchanged; undo and redo report the networks they change. The issue's
//! "Done when": tests/data/ladder_model/machine.json is built from an empty block by
//! edit operations only, and a sequence of edits on it gives machine_edited.json (the
//! golden file, rewritten with GUTTA_BLESS=1; cli/tests/cc_ladder_json.rs runs it).

#![allow(
    clippy::disallowed_methods,
    reason = "the test reads and blesses the repository's model files"
)]

mod common;

use std::sync::Arc;

use gutta_catalog::{stdlib, Target};
use gutta_ladder::edit::{apply, Change, Edit, Editor, ElementPath, NetworkPath, Place, Step};
use gutta_ladder::json::{program_of, read_model, validate, Element, Model, ModelErrorCode};

use common::edit::round_trip;
use common::root;

fn target() -> Arc<Target> {
    stdlib::shared("CPU-EC20").expect("stdlib target")
}

fn machine() -> Model {
    let text =
        std::fs::read(root().join("tests/data/ladder_model/machine.json")).expect("machine.json");
    read_model(&text).expect("machine.json reads")
}

/// A one-block model whose networks are these rungs (JSON text).
fn model_of_rungs(rungs: &[&str]) -> Model {
    let networks: Vec<String> = rungs
        .iter()
        .map(|r| format!(r#"{{"title": "", "comment": "", "rung": {r}}}"#))
        .collect();
    let text = format!(
        r#"{{"format": "gutta-ladder", "version": 1, "plc": "CPU-EC20", "symbols": [],
  "blocks": [{{"kind": "ORGANIZATION_BLOCK", "name": "MAIN", "id": "OB1", "networks": [{}]}}]}}"#,
        networks.join(", ")
    );
    read_model(text.as_bytes()).expect("the test model reads")
}

fn rung(text: &str) -> Element {
    let model = model_of_rungs(&[text]);
    match &model.blocks[0].networks[0].body {
        gutta_ladder::json::NetworkBody::Rung { rung } => rung.clone(),
        other => panic!("not a rung: {other:?}"),
    }
}

fn path(text: &str) -> ElementPath {
    text.parse().expect("a path")
}

/// `edits` (JSON) applied in order to a model of `rungs`: the first network's rung after
/// them, each accepted edit's network round-tripped through its program.
fn edited(rungs: &[&str], edits: &[&str]) -> Element {
    let target = target();
    let mut model = model_of_rungs(rungs);
    for text in edits {
        let edit = Edit::from_json(text).unwrap_or_else(|e| panic!("{text}: {e}"));
        let changes = apply(&mut model, &target.instructions, &edit)
            .unwrap_or_else(|e| panic!("{text}: {e}"));
        let networks: Vec<(usize, usize)> = changes
            .iter()
            .filter_map(|c| match c {
                Change::Lines(at) | Change::Heading(at) | Change::Inserted(at) => {
                    Some((at.block, at.network))
                }
                _ => None,
            })
            .collect();
        round_trip(&model, &target, false, &networks).unwrap_or_else(|e| panic!("{text}: {e}"));
    }
    match &model.blocks[0].networks[0].body {
        gutta_ladder::json::NetworkBody::Rung { rung } => rung.clone(),
        other => panic!("not a rung: {other:?}"),
    }
}

/// The code and path `edit` is refused with on a model of `rungs`, the model unchanged.
fn refused(rungs: &[&str], edit: &str) -> (ModelErrorCode, String) {
    let target = target();
    let mut model = model_of_rungs(rungs);
    let before = model.clone();
    let edit = Edit::from_json(edit).unwrap_or_else(|e| panic!("{edit}: {e}"));
    let err = apply(&mut model, &target.instructions, &edit).expect_err("refused");
    assert_eq!(model, before, "a refused edit changed the model");
    (err.code, err.path)
}

const LATCH: &str = r#"{"series": [{"contact": "LD", "operands": ["I0.0"]}, {"contact": "LDN", "operands": ["I0.1"]}, {"coil": "=", "operands": ["Q0.0"]}]}"#;
const TWO_OUTPUTS: &str = r#"{"series": [{"contact": "LD", "operands": ["I0.0"]}, {"parallel": [{"coil": "=", "operands": ["Q0.0"]}, {"coil": "=", "operands": ["Q0.1"]}]}]}"#;
const TIMER: &str = r#"{"series": [{"contact": "LD", "operands": ["I0.0"]}, {"box": "TON", "operands": ["T4", "10"], "inputs": []}, {"coil": "=", "operands": ["Q0.0"]}]}"#;
const COUNTER: &str = r#"{"series": [{"contact": "LD", "operands": ["I0.0"]}, {"box": "CTU", "operands": ["C0", "3"], "inputs": [{"contact": "LD", "operands": ["I0.3"]}]}]}"#;

#[test]
fn paths_print_and_parse_as_the_json_paths_of_the_l_codes() {
    let p = ElementPath::rung(0, 2)
        .then(Step::Series(2))
        .then(Step::Input(0))
        .then(Step::Series(0));
    let text = "blocks[0].networks[2].rung.series[2].inputs[0].series[0]";
    assert_eq!(p.to_string(), text);
    assert_eq!(path(text), p);
    assert_eq!(path("blocks[1].networks[0].rung"), ElementPath::rung(1, 0));
    let net: NetworkPath = "blocks[0].networks[3]".parse().expect("a network path");
    assert_eq!(
        net,
        NetworkPath {
            block: 0,
            network: 3
        }
    );
    assert_eq!(net.to_string(), "blocks[0].networks[3]");
    for bad in [
        "",
        "blocks[0]",
        "blocks[0].networks[1]",
        "blocks[0].networks[1].rung.series",
        "blocks[0].networks[1].rung.series[x]",
        "blocks[0].networks[1].rung.series[1]x",
        "blocks[0].networks[1].rung.operands[0]",
    ] {
        let err = bad.parse::<ElementPath>().expect_err(bad);
        assert_eq!(err.code, ModelErrorCode::NoSuchPath, "{bad}");
    }
    assert!("blocks[0].networks[1].rung".parse::<NetworkPath>().is_err());
}

#[test]
fn an_edit_reads_and_writes_its_json_form() {
    let text = r#"{"op": "insert_contact", "at": "blocks[0].networks[1].rung.series[0]", "place": "after", "contact": "LDN", "operands": ["I0.1"]}"#;
    let edit = Edit::from_json(text).expect("an edit");
    assert_eq!(
        edit,
        Edit::InsertContact {
            at: path("blocks[0].networks[1].rung.series[0]"),
            count: 1,
            place: Place::After,
            contact: "LDN".to_string(),
            operands: vec!["I0.1".to_string()],
        }
    );
    assert_eq!(
        edit.to_json(),
        r#"{"op":"insert_contact","at":"blocks[0].networks[1].rung.series[0]","place":"after","contact":"LDN","operands":["I0.1"]}"#
    );
    assert_eq!(Edit::from_json(&edit.to_json()), Ok(edit));
    // Elements inside an edit are read as the model reads them.
    let wrap = r#"{"op": "wrap_parallel", "at": "blocks[0].networks[0].rung.series[0]", "count": 2, "branch": {"series": [{"contact": "LD", "operands": ["M0.0"]}, {"contact": "LD", "operands": ["M0.1"]}]}}"#;
    let edit = Edit::from_json(wrap).expect("an edit");
    assert_eq!(Edit::from_json(&edit.to_json()), Ok(edit));
    for bad in [
        "",
        "[]",
        r#"{"op": "paint", "at": "blocks[0].networks[0].rung"}"#,
        r#"{"op": "delete"}"#,
        r#"{"op": "delete", "at": "blocks[0].networks[0]"}"#,
        r#"{"op": "delete", "at": "blocks[0].networks[0].rung", "colour": 1}"#,
        r#"{"op": "wrap_parallel", "at": "blocks[0].networks[0].rung", "branch": {"wire": 1}}"#,
    ] {
        let err = Edit::from_json(bad).expect_err(bad);
        assert_eq!(err.code, ModelErrorCode::NotAnEdit, "{bad}: {err}");
    }
}

#[test]
fn contacts_go_before_after_and_in_parallel_around_a_selection() {
    let before = edited(
        &[LATCH],
        &[
            r#"{"op": "insert_contact", "at": "blocks[0].networks[0].rung.series[0]", "place": "before", "contact": "LD", "operands": ["I0.5"]}"#,
        ],
    );
    assert_eq!(
        before,
        rung(
            r#"{"series": [{"contact": "LD", "operands": ["I0.5"]}, {"contact": "LD", "operands": ["I0.0"]}, {"contact": "LDN", "operands": ["I0.1"]}, {"coil": "=", "operands": ["Q0.0"]}]}"#
        )
    );
    let after = edited(
        &[LATCH],
        &[
            r#"{"op": "insert_contact", "at": "blocks[0].networks[0].rung.series[0]", "count": 2, "place": "after", "contact": "EU"}"#,
        ],
    );
    assert_eq!(
        after,
        rung(
            r#"{"series": [{"contact": "LD", "operands": ["I0.0"]}, {"contact": "LDN", "operands": ["I0.1"]}, {"contact": "EU", "operands": []}, {"coil": "=", "operands": ["Q0.0"]}]}"#
        )
    );
    // Around two contacts: the run becomes the upper branch.
    let around = edited(
        &[LATCH],
        &[
            r#"{"op": "insert_contact", "at": "blocks[0].networks[0].rung.series[0]", "count": 2, "place": "parallel", "contact": "LD", "operands": ["M0.0"]}"#,
        ],
    );
    assert_eq!(
        around,
        rung(
            r#"{"series": [{"parallel": [{"series": [{"contact": "LD", "operands": ["I0.0"]}, {"contact": "LDN", "operands": ["I0.1"]}]}, {"contact": "LD", "operands": ["M0.0"]}]}, {"coil": "=", "operands": ["Q0.0"]}]}"#
        )
    );
    // Around one branch of a parallel: one more branch, not a parallel in a parallel.
    let third = edited(
        &[LATCH],
        &[
            r#"{"op": "insert_contact", "at": "blocks[0].networks[0].rung.series[0]", "place": "parallel", "contact": "LD", "operands": ["M0.0"]}"#,
            r#"{"op": "insert_contact", "at": "blocks[0].networks[0].rung.series[0].parallel[1]", "place": "parallel", "contact": "LD", "operands": ["M0.1"]}"#,
            r#"{"op": "insert_contact", "at": "blocks[0].networks[0].rung.series[0].parallel[1]", "place": "after", "contact": "LDN", "operands": ["M0.2"]}"#,
        ],
    );
    assert_eq!(
        third,
        rung(
            r#"{"series": [{"parallel": [{"contact": "LD", "operands": ["I0.0"]}, {"series": [{"contact": "LD", "operands": ["M0.0"]}, {"contact": "LDN", "operands": ["M0.2"]}]}, {"contact": "LD", "operands": ["M0.1"]}]}, {"contact": "LDN", "operands": ["I0.1"]}, {"coil": "=", "operands": ["Q0.0"]}]}"#
        )
    );
}

#[test]
fn coils_and_boxes_go_at_a_rung_end_or_as_parallel_outputs() {
    let parallel = edited(
        &[LATCH],
        &[
            r#"{"op": "insert_coil", "at": "blocks[0].networks[0].rung.series[2]", "place": "parallel", "coil": "S", "operands": ["Q0.1", "1"]}"#,
            r#"{"op": "insert_box", "at": "blocks[0].networks[0].rung.series[2].parallel[1]", "place": "parallel", "box": "MOVW", "operands": ["5", "MW0"]}"#,
        ],
    );
    assert_eq!(
        parallel,
        rung(
            r#"{"series": [{"contact": "LD", "operands": ["I0.0"]}, {"contact": "LDN", "operands": ["I0.1"]}, {"parallel": [{"coil": "=", "operands": ["Q0.0"]}, {"coil": "S", "operands": ["Q0.1", "1"]}, {"box": "MOVW", "operands": ["5", "MW0"], "inputs": []}]}]}"#
        )
    );
    // After a box with a power output, at the rung's end; a counter with its reset path.
    let end = edited(
        &[COUNTER],
        &[
            r#"{"op": "insert_coil", "at": "blocks[0].networks[0].rung.series[1]", "place": "after", "coil": "=", "operands": ["Q0.2"]}"#,
            r#"{"op": "insert_box", "at": "blocks[0].networks[0].rung.series[0]", "place": "after", "box": "CTUD", "operands": ["C1", "5"], "inputs": [{"contact": "LD", "operands": ["I0.4"]}, {"contact": "LD", "operands": ["I0.5"]}]}"#,
        ],
    );
    assert_eq!(
        end,
        rung(
            r#"{"series": [{"contact": "LD", "operands": ["I0.0"]}, {"box": "CTUD", "operands": ["C1", "5"], "inputs": [{"contact": "LD", "operands": ["I0.4"]}, {"contact": "LD", "operands": ["I0.5"]}]}, {"box": "CTU", "operands": ["C0", "3"], "inputs": [{"contact": "LD", "operands": ["I0.3"]}]}, {"coil": "=", "operands": ["Q0.2"]}]}"#
        )
    );
}

#[test]
fn a_deleted_element_closes_the_wire_and_the_rung_stays_normal() {
    // A contact out of a series.
    let closed = edited(
        &[LATCH],
        &[r#"{"op": "delete", "at": "blocks[0].networks[0].rung.series[1]"}"#],
    );
    assert_eq!(
        closed,
        rung(
            r#"{"series": [{"contact": "LD", "operands": ["I0.0"]}, {"coil": "=", "operands": ["Q0.0"]}]}"#
        )
    );
    // One of two parallel outputs: the other becomes the rung's end.
    let one_output = edited(
        &[TWO_OUTPUTS],
        &[r#"{"op": "delete", "at": "blocks[0].networks[0].rung.series[1].parallel[0]"}"#],
    );
    assert_eq!(
        one_output,
        rung(
            r#"{"series": [{"contact": "LD", "operands": ["I0.0"]}, {"coil": "=", "operands": ["Q0.1"]}]}"#
        )
    );
    // The contacts of a branch, one by one: the branch goes, then the parallel.
    let branch = edited(
        &[LATCH],
        &[
            r#"{"op": "wrap_parallel", "at": "blocks[0].networks[0].rung.series[0]", "branch": {"series": [{"contact": "LD", "operands": ["M0.0"]}, {"contact": "LD", "operands": ["M0.1"]}]}}"#,
            r#"{"op": "delete", "at": "blocks[0].networks[0].rung.series[0].parallel[1].series[0]"}"#,
            r#"{"op": "delete", "at": "blocks[0].networks[0].rung.series[0].parallel[1]"}"#,
        ],
    );
    assert_eq!(branch, rung(LATCH));
    // A timer between the contacts and the coil.
    let no_timer = edited(
        &[TIMER],
        &[r#"{"op": "delete", "at": "blocks[0].networks[0].rung.series[1]"}"#],
    );
    assert_eq!(
        no_timer,
        rung(
            r#"{"series": [{"contact": "LD", "operands": ["I0.0"]}, {"coil": "=", "operands": ["Q0.0"]}]}"#
        )
    );
}

#[test]
fn operands_and_mnemonics_change_in_place() {
    let changed = edited(
        &[LATCH, TIMER],
        &[
            r#"{"op": "set_mnemonic", "at": "blocks[0].networks[0].rung.series[1]", "mnemonic": "LD"}"#,
            r#"{"op": "set_operands", "at": "blocks[0].networks[0].rung.series[0]", "operands": ["M1.0"]}"#,
            r#"{"op": "set_mnemonic", "at": "blocks[0].networks[0].rung.series[2]", "mnemonic": "S", "operands": ["Q0.0", "2"]}"#,
            r#"{"op": "set_mnemonic", "at": "blocks[0].networks[1].rung.series[1]", "mnemonic": "TOF"}"#,
            r#"{"op": "set_mnemonic", "at": "blocks[0].networks[1].rung.series[0]", "mnemonic": "LDW>=", "operands": ["MW0", "7"]}"#,
        ],
    );
    assert_eq!(
        changed,
        rung(
            r#"{"series": [{"contact": "LD", "operands": ["M1.0"]}, {"contact": "LD", "operands": ["I0.1"]}, {"coil": "S", "operands": ["Q0.0", "2"]}]}"#
        )
    );
    // A counter becomes CTUD with its inputs given.
    let ctud = edited(
        &[COUNTER],
        &[
            r#"{"op": "set_mnemonic", "at": "blocks[0].networks[0].rung.series[1]", "mnemonic": "CTUD", "inputs": [{"contact": "LD", "operands": ["I0.4"]}, {"contact": "LD", "operands": ["I0.3"]}]}"#,
        ],
    );
    assert_eq!(
        ctud,
        rung(
            r#"{"series": [{"contact": "LD", "operands": ["I0.0"]}, {"box": "CTUD", "operands": ["C0", "3"], "inputs": [{"contact": "LD", "operands": ["I0.4"]}, {"contact": "LD", "operands": ["I0.3"]}]}]}"#
        )
    );
}

#[test]
fn illegal_edits_are_refused_with_their_code_and_path() {
    use ModelErrorCode as L;
    let at0 = "blocks[0].networks[0]";
    let cases: Vec<(&[&str], String, L, String)> = vec![
        // A coil in the middle of a series.
        (
            &[LATCH],
            format!(r#"{{"op": "insert_coil", "at": "{at0}.rung.series[0]", "place": "after", "coil": "=", "operands": ["Q0.3"]}}"#),
            L::OutputNotLast,
            format!("{at0}.rung.series[1]"),
        ),
        // A box whose pins do not exist: a wrong operand count, a missing reset input.
        (
            &[LATCH],
            format!(r#"{{"op": "insert_box", "at": "{at0}.rung.series[2]", "place": "parallel", "box": "MOVW", "operands": ["5"]}}"#),
            L::OperandCount,
            format!("{at0}.rung.series[2].parallel[1].operands"),
        ),
        (
            &[LATCH],
            format!(r#"{{"op": "insert_box", "at": "{at0}.rung.series[2]", "place": "parallel", "box": "CTU", "operands": ["C0", "3"]}}"#),
            L::BoxInputs,
            format!("{at0}.rung.series[2].parallel[1].inputs"),
        ),
        (
            &[TIMER],
            format!(r#"{{"op": "set_mnemonic", "at": "{at0}.rung.series[1]", "mnemonic": "TON", "inputs": [{{"contact": "LD", "operands": ["I0.2"]}}]}}"#),
            L::BoxInputs,
            format!("{at0}.rung.series[1].inputs"),
        ),
        // A contact mnemonic that is not a contact, or not in its load form.
        (
            &[LATCH],
            format!(r#"{{"op": "insert_contact", "at": "{at0}.rung.series[0]", "place": "after", "contact": "MOVW", "operands": ["1", "MW0"]}}"#),
            L::WrongElement,
            format!("{at0}.rung.series[1]"),
        ),
        (
            &[LATCH],
            format!(r#"{{"op": "set_mnemonic", "at": "{at0}.rung.series[1]", "mnemonic": "AN"}}"#),
            L::WrongElement,
            format!("{at0}.rung.series[1]"),
        ),
        (
            &[LATCH],
            format!(r#"{{"op": "set_mnemonic", "at": "{at0}.rung.series[1]", "mnemonic": "LDX"}}"#),
            L::UnknownMnemonic,
            format!("{at0}.rung.series[1]"),
        ),
        // `=` -> `S` without the count.
        (
            &[LATCH],
            format!(r#"{{"op": "set_mnemonic", "at": "{at0}.rung.series[2]", "mnemonic": "S"}}"#),
            L::OperandCount,
            format!("{at0}.rung.series[2].operands"),
        ),
        // A path that does not exist.
        (
            &[LATCH],
            format!(r#"{{"op": "delete", "at": "{at0}.rung.series[7]"}}"#),
            L::NoSuchPath,
            format!("{at0}.rung.series[7]"),
        ),
        (
            &[LATCH],
            r#"{"op": "delete", "at": "blocks[0].networks[4].rung"}"#.to_string(),
            L::NoSuchPath,
            "blocks[0].networks[4]".to_string(),
        ),
        (
            &[LATCH],
            format!(r#"{{"op": "delete", "at": "{at0}.rung.series[1]", "count": 5}}"#),
            L::NoSuchPath,
            format!("{at0}.rung.series[1]"),
        ),
        (
            &[LATCH],
            format!(r#"{{"op": "wrap_parallel", "at": "{at0}.rung.series[1]", "count": {}, "branch": {{"contact": "LD", "operands": ["M0.0"]}}}}"#, usize::MAX),
            L::NoSuchPath,
            format!("{at0}.rung.series[1]"),
        ),
        (
            &[LATCH],
            format!(r#"{{"op": "insert_contact", "at": "{at0}.rung.series[0]", "count": 0, "place": "after", "contact": "LD", "operands": ["M0.0"]}}"#),
            L::WrongTarget,
            format!("{at0}.rung.series[0]"),
        ),
        (
            &[LATCH],
            format!(r#"{{"op": "delete", "at": "{at0}.rung.parallel[0]"}}"#),
            L::NoSuchPath,
            format!("{at0}.rung.parallel[0]"),
        ),
        // Operands of a series; a run in a parallel; a box's input deleted on its own.
        (
            &[LATCH],
            format!(r#"{{"op": "set_operands", "at": "{at0}.rung", "operands": []}}"#),
            L::WrongTarget,
            format!("{at0}.rung"),
        ),
        (
            &[TWO_OUTPUTS],
            format!(r#"{{"op": "delete", "at": "{at0}.rung.series[1].parallel[0]", "count": 2}}"#),
            L::WrongTarget,
            format!("{at0}.rung.series[1].parallel[0]"),
        ),
        (
            &[COUNTER],
            format!(r#"{{"op": "delete", "at": "{at0}.rung.series[1].inputs[0]"}}"#),
            L::WrongTarget,
            format!("{at0}.rung.series[1].inputs[0]"),
        ),
        // Deleting the only output, or the whole rung.
        (
            &[LATCH],
            format!(r#"{{"op": "delete", "at": "{at0}.rung.series[2]"}}"#),
            L::LastOutput,
            format!("{at0}.rung.series[2]"),
        ),
        (
            &[LATCH],
            format!(r#"{{"op": "delete", "at": "{at0}.rung"}}"#),
            L::LastOutput,
            format!("{at0}.rung"),
        ),
        // A rung the writer cannot say, or whose first element needs power.
        (
            &[LATCH],
            format!(r#"{{"op": "insert_contact", "at": "{at0}.rung.series[0]", "place": "before", "contact": "NOT"}}"#),
            L::Unwritable,
            format!("{at0}.rung"),
        ),
        (
            &[LATCH],
            format!(r#"{{"op": "delete", "at": "{at0}.rung.series[0]", "count": 2}}"#),
            L::Unwritable,
            format!("{at0}.rung"),
        ),
        (
            &[LATCH],
            format!(r#"{{"op": "insert_box", "at": "{at0}.rung.series[2]", "place": "parallel", "box": "ENI"}}"#),
            L::Unwritable,
            format!("{at0}.rung.series[2].parallel[1]"),
        ),
        // A line break in an operand or a title.
        (
            &[LATCH],
            format!(r#"{{"op": "set_operands", "at": "{at0}.rung.series[0]", "operands": ["I0.0\nI0.1"]}}"#),
            L::Shape,
            format!("{at0}.rung.series[0].operands[0]"),
        ),
        (
            &[LATCH],
            format!(r#"{{"op": "set_network_title", "at": "{at0}", "title": "a\nb"}}"#),
            L::Shape,
            format!("{at0}.title"),
        ),
        (
            &[LATCH],
            r#"{"op": "set_block_title", "block": 0, "title": "a\rb"}"#.to_string(),
            L::Shape,
            "blocks[0].title".to_string(),
        ),
        // Network positions out of range.
        (
            &[LATCH],
            format!(r#"{{"op": "move_network", "at": "{at0}", "to": 1}}"#),
            L::OutOfRange,
            at0.to_string(),
        ),
        (
            &[LATCH],
            r#"{"op": "insert_network", "at": "blocks[0].networks[2]", "network": {"rung": {"series": [{"contact": "LD", "operands": ["I0.0"]}, {"coil": "=", "operands": ["Q0.0"]}]}}}"#.to_string(),
            L::OutOfRange,
            "blocks[0].networks[2]".to_string(),
        ),
        (
            &[LATCH],
            r#"{"op": "delete_network", "at": "blocks[1].networks[0]"}"#.to_string(),
            L::OutOfRange,
            "blocks[1]".to_string(),
        ),
        (
            &[LATCH],
            r#"{"op": "duplicate_network", "at": "blocks[0].networks[1]"}"#.to_string(),
            L::OutOfRange,
            "blocks[0].networks[1]".to_string(),
        ),
        // A new network that is not a rung.
        (
            &[LATCH],
            r#"{"op": "insert_network", "at": "blocks[0].networks[1]", "network": {"rung": {"contact": "LD", "operands": ["I0.0"]}}}"#.to_string(),
            L::NoOutput,
            "blocks[0].networks[1].rung".to_string(),
        ),
    ];
    for (rungs, edit, code, at) in cases {
        assert_eq!(refused(rungs, &edit), (code, at), "{edit}");
    }
}

#[test]
fn undo_and_redo_restore_the_model_and_name_the_changed_networks() {
    let target = target();
    let start = model_of_rungs(&[LATCH, TIMER]);
    let mut editor = Editor::new(start.clone(), &target.instructions);
    assert_eq!(
        editor.undo().expect_err("empty").code,
        ModelErrorCode::NothingToUndo
    );
    let edits = [
        r#"{"op": "set_mnemonic", "at": "blocks[0].networks[1].rung.series[1]", "mnemonic": "TOF"}"#,
        r#"{"op": "duplicate_network", "at": "blocks[0].networks[0]"}"#,
        r#"{"op": "move_network", "at": "blocks[0].networks[2]", "to": 0}"#,
        r#"{"op": "set_network_comment", "at": "blocks[0].networks[0]", "comment": "two\nlines"}"#,
        r#"{"op": "delete_network", "at": "blocks[0].networks[1]"}"#,
        r#"{"op": "set_block_title", "block": 0, "title": "edited"}"#,
    ];
    let expected = [
        vec![Change::Lines(NetworkPath {
            block: 0,
            network: 1,
        })],
        vec![Change::Inserted(NetworkPath {
            block: 0,
            network: 1,
        })],
        vec![Change::Moved {
            block: 0,
            from: 2,
            to: 0,
        }],
        vec![Change::Heading(NetworkPath {
            block: 0,
            network: 0,
        })],
        vec![Change::Deleted(NetworkPath {
            block: 0,
            network: 1,
        })],
        vec![Change::Block(0)],
    ];
    let mut states = vec![start.clone()];
    for (text, want) in edits.iter().zip(&expected) {
        let changes = editor
            .apply(Edit::from_json(text).expect("an edit"))
            .unwrap_or_else(|e| panic!("{text}: {e}"));
        assert_eq!(&changes, want, "{text}");
        validate(editor.model(), &target.instructions).expect("valid");
        program_of(editor.model(), &target.instructions).expect("writable");
        states.push(editor.model().clone());
    }
    // A refused edit is not in the history.
    assert!(editor
        .apply(
            Edit::from_json(r#"{"op": "delete_network", "at": "blocks[0].networks[9]"}"#)
                .expect("an edit")
        )
        .is_err());
    let end = editor.model().clone();
    assert_eq!(end.blocks[0].title.as_deref(), Some("edited"));
    // Undo walks back through every state, naming the inverse changes.
    for (i, want) in expected.iter().enumerate().rev() {
        let changes = editor.undo().expect("undo");
        let inverse: Vec<Change> = want
            .iter()
            .map(|c| match *c {
                Change::Inserted(at) => Change::Deleted(at),
                Change::Deleted(at) => Change::Inserted(at),
                Change::Moved { block, from, to } => Change::Moved {
                    block,
                    from: to,
                    to: from,
                },
                ref other => other.clone(),
            })
            .collect();
        assert_eq!(changes, inverse);
        assert_eq!(editor.model(), &states[i]);
    }
    assert!(!editor.can_undo());
    for state in &states[1..] {
        editor.redo().expect("redo");
        assert_eq!(editor.model(), state);
    }
    assert_eq!(
        editor.redo().expect_err("empty").code,
        ModelErrorCode::NothingToUndo
    );
    // A new edit clears redo.
    editor.undo().expect("undo");
    assert!(editor.can_redo());
    editor
        .apply(
            Edit::from_json(r#"{"op": "set_block_title", "block": 0, "title": null}"#)
                .expect("an edit"),
        )
        .expect("applies");
    assert!(!editor.can_redo());
}

#[test]
fn network_numbers_follow_positions_when_the_block_has_them() {
    let target = target();
    let mut model = model_of_rungs(&[LATCH, TIMER, COUNTER]);
    for (i, n) in model.blocks[0].networks.iter_mut().enumerate() {
        n.number = Some(i as u32 + 1);
    }
    let edit = Edit::from_json(r#"{"op": "move_network", "at": "blocks[0].networks[0]", "to": 2}"#)
        .expect("an edit");
    apply(&mut model, &target.instructions, &edit).expect("applies");
    let numbers: Vec<Option<u32>> = model.blocks[0].networks.iter().map(|n| n.number).collect();
    assert_eq!(numbers, [Some(1), Some(2), Some(3)]);
    round_trip(&model, &target, false, &[(0, 0), (0, 1), (0, 2)]).expect("round trip");
    // A model written without numbers stays without.
    let mut plain = model_of_rungs(&[LATCH]);
    let edit = Edit::from_json(r#"{"op": "duplicate_network", "at": "blocks[0].networks[0]"}"#)
        .expect("an edit");
    apply(&mut plain, &target.instructions, &edit).expect("applies");
    assert!(plain.blocks[0].networks.iter().all(|n| n.number.is_none()));
}

/// The edits that build tests/data/ladder_model/machine.json from an empty MAIN.
const MACHINE_FROM_SCRATCH: &[&str] = &[
    r#"{"op": "set_block_title", "block": 0, "title": "A machine written as a ladder model"}"#,
    // 0: the start/stop latch.
    r#"{"op": "insert_network", "at": "blocks[0].networks[0]", "network": {"title": "start/stop latch", "rung": {"series": [{"contact": "LD", "operands": ["Start"]}, {"coil": "=", "operands": ["Running"]}]}}}"#,
    r#"{"op": "insert_contact", "at": "blocks[0].networks[0].rung.series[0]", "place": "parallel", "contact": "LD", "operands": ["Running"]}"#,
    r#"{"op": "insert_contact", "at": "blocks[0].networks[0].rung.series[0]", "place": "after", "contact": "LDN", "operands": ["Stop"]}"#,
    // 1: a TON with two outputs in parallel.
    r#"{"op": "insert_network", "at": "blocks[0].networks[1]", "network": {"title": "ready 1 s after the start, shown on M0.0 too", "rung": {"series": [{"contact": "LD", "operands": ["Running"]}, {"coil": "=", "operands": ["Ready"]}]}}}"#,
    r#"{"op": "insert_box", "at": "blocks[0].networks[1].rung.series[1]", "place": "before", "box": "TON", "operands": ["T4", "10"]}"#,
    r#"{"op": "insert_coil", "at": "blocks[0].networks[1].rung.series[2]", "place": "parallel", "coil": "=", "operands": ["M0.0"]}"#,
    // 2: a CTU with its reset.
    r#"{"op": "insert_network", "at": "blocks[0].networks[2]", "network": {"title": "count parts, Clear resets", "rung": {"series": [{"contact": "LD", "operands": ["Part"]}, {"coil": "=", "operands": ["Batch"]}]}}}"#,
    r#"{"op": "insert_box", "at": "blocks[0].networks[2].rung.series[0]", "place": "after", "box": "CTU", "operands": ["C0", "3"], "inputs": [{"contact": "LD", "operands": ["Clear"]}]}"#,
    r#"{"op": "delete", "at": "blocks[0].networks[2].rung.series[2]"}"#,
    r#"{"op": "set_network_comment", "at": "blocks[0].networks[2]", "comment": "a batch is three parts"}"#,
    // 3, then 4: the compare on Speed, and a copy of it made into the MOVW box.
    r#"{"op": "insert_network", "at": "blocks[0].networks[3]", "network": {"title": "high speed", "rung": {"series": [{"contact": "LD", "operands": ["Running"]}, {"coil": "=", "operands": ["High"]}]}}}"#,
    r#"{"op": "set_mnemonic", "at": "blocks[0].networks[3].rung.series[0]", "mnemonic": "LDW>=", "operands": ["Speed", "400"]}"#,
    r#"{"op": "duplicate_network", "at": "blocks[0].networks[3]"}"#,
    r#"{"op": "set_network_title", "at": "blocks[0].networks[3]", "title": "speed: 500 while running"}"#,
    r#"{"op": "set_mnemonic", "at": "blocks[0].networks[3].rung.series[0]", "mnemonic": "LD", "operands": ["Running"]}"#,
    r#"{"op": "insert_box", "at": "blocks[0].networks[3].rung.series[0]", "place": "after", "box": "MOVW", "operands": ["500", "Speed"]}"#,
    r#"{"op": "delete", "at": "blocks[0].networks[3].rung.series[2]"}"#,
    // 5, moved to 3: the batch is full.
    r#"{"op": "insert_network", "at": "blocks[0].networks[5]", "network": {"title": "the batch is full", "rung": {"series": [{"contact": "LD", "operands": ["Part"]}, {"coil": "=", "operands": ["Batch"]}]}}}"#,
    r#"{"op": "set_mnemonic", "at": "blocks[0].networks[5].rung.series[0]", "mnemonic": "LDW>=", "operands": ["C0", "3"]}"#,
    r#"{"op": "move_network", "at": "blocks[0].networks[5]", "to": 3}"#,
];

/// The edits that make machine_edited.json of machine.json.
const MACHINE_EDITS: &[&str] = &[
    // Stop becomes a normally closed button: the contact NC -> NO.
    r#"{"op": "set_mnemonic", "at": "blocks[0].networks[0].rung.series[1]", "mnemonic": "LD"}"#,
    // Ready stays on 1 s after the stop instead of coming 1 s after the start.
    r#"{"op": "set_mnemonic", "at": "blocks[0].networks[1].rung.series[1]", "mnemonic": "TOF"}"#,
    r#"{"op": "set_network_title", "at": "blocks[0].networks[1]", "title": "ready while running and 1 s after, shown on M0.0 too"}"#,
    // A second part sensor on I0.4 counts too.
    r#"{"op": "insert_contact", "at": "blocks[0].networks[2].rung.series[0]", "place": "parallel", "contact": "LD", "operands": ["I0.4"]}"#,
    // Speed 300, below the high mark.
    r#"{"op": "set_operands", "at": "blocks[0].networks[4].rung.series[1]", "operands": ["300", "Speed"]}"#,
    r#"{"op": "set_network_title", "at": "blocks[0].networks[4]", "title": "speed: 300 while running"}"#,
    // A low-speed lamp on Q0.4: the high-speed network copied, changed, moved first.
    r#"{"op": "duplicate_network", "at": "blocks[0].networks[5]"}"#,
    r#"{"op": "set_mnemonic", "at": "blocks[0].networks[6].rung.series[0]", "mnemonic": "LDW<"}"#,
    r#"{"op": "set_operands", "at": "blocks[0].networks[6].rung.series[1]", "operands": ["Q0.4"]}"#,
    r#"{"op": "set_network_title", "at": "blocks[0].networks[6]", "title": "low speed"}"#,
    r#"{"op": "move_network", "at": "blocks[0].networks[6]", "to": 0}"#,
];

/// `edits` applied through an `Editor`, each changed network round-tripped.
fn run_edits(start: Model, edits: &[&str]) -> Model {
    let target = target();
    let mut editor = Editor::new(start.clone(), &target.instructions);
    for text in edits {
        let edit = Edit::from_json(text).unwrap_or_else(|e| panic!("{text}: {e}"));
        let changes = editor.apply(edit).unwrap_or_else(|e| panic!("{text}: {e}"));
        let networks: Vec<(usize, usize)> = changes
            .iter()
            .filter_map(|c| match c {
                Change::Lines(at) | Change::Heading(at) | Change::Inserted(at) => {
                    Some((at.block, at.network))
                }
                _ => None,
            })
            .collect();
        round_trip(editor.model(), &target, false, &networks)
            .unwrap_or_else(|e| panic!("{text}: {e}"));
    }
    let end = editor.model().clone();
    while editor.can_undo() {
        editor.undo().expect("undo");
    }
    assert_eq!(editor.model(), &start, "undo of every edit gives the start");
    while editor.can_redo() {
        editor.redo().expect("redo");
    }
    assert_eq!(editor.model(), &end, "redo of every edit gives the end");
    end
}

#[test]
fn the_machine_model_is_built_from_an_empty_block_by_edits_alone() {
    let target = target();
    let machine = machine();
    let mut empty = machine.clone();
    empty.blocks[0].title = None;
    empty.blocks[0].networks.clear();
    let built = run_edits(empty, MACHINE_FROM_SCRATCH);
    assert_eq!(built, machine);
    assert_eq!(
        program_of(&built, &target.instructions).expect("writable"),
        program_of(&machine, &target.instructions).expect("writable")
    );
}

#[test]
fn the_edited_machine_is_the_golden_model() {
    let target = target();
    let edited = run_edits(machine(), MACHINE_EDITS);
    validate(&edited, &target.instructions).expect("valid");
    let golden = root().join("tests/data/ladder_model/machine_edited.json");
    let text = edited.to_json();
    if std::env::var_os("GUTTA_BLESS").is_some_and(|v| v == "1") {
        std::fs::write(&golden, &text).expect("blesses machine_edited.json");
    }
    let want = std::fs::read_to_string(&golden)
        .expect("tests/data/ladder_model/machine_edited.json (GUTTA_BLESS=1 writes it)");
    assert_eq!(text, want, "GUTTA_BLESS=1 rewrites machine_edited.json");
    assert_eq!(read_model(want.as_bytes()).expect("reads"), edited);
}

/// The `.lad` text of `model` with `changes` applied in place, as a studio does
/// (`edit::apply_to_text`).
fn apply_to_text(text: &str, model: &Model, changes: &[Change]) -> String {
    let target = target();
    gutta_ladder::edit::apply_to_text(text, model, &target.instructions, changes)
        .unwrap_or_else(|e| panic!("{changes:?}: {e}"))
}

#[test]
fn the_changes_rewrite_only_their_networks_in_the_lad_text() {
    let target = target();
    let machine = machine();
    let original = program_of(&machine, &target.instructions)
        .expect("writable")
        .replacen("SYMBOLS\n", "SYMBOLS\n  // a comment no edit touches\n", 1);
    let mut editor = Editor::new(machine, &target.instructions);
    let mut text = original.clone();
    for edit in MACHINE_EDITS {
        let changes = editor
            .apply(Edit::from_json(edit).expect("an edit"))
            .unwrap_or_else(|e| panic!("{edit}: {e}"));
        text = apply_to_text(&text, editor.model(), &changes);
    }
    assert!(
        text.contains("SYMBOLS\n  // a comment no edit touches\n"),
        "{text}"
    );
    // The SYMBOLS block and the network the edits left alone keep their bytes.
    let unchanged = "NETWORK 5 // the batch is full\nLDW>=  C0, 3\n=      Batch\n";
    assert!(original.contains("NETWORK 4 // the batch is full\nLDW>=  C0, 3\n=      Batch\n"));
    assert!(text.contains(unchanged), "{text}");
    assert_eq!(
        text[..text.find("ORGANIZATION_BLOCK").expect("a block")],
        original[..original.find("ORGANIZATION_BLOCK").expect("a block")]
    );
    // The rewritten text is the edited model's program, up to the network numbers.
    let written = program_of(editor.model(), &target.instructions).expect("writable");
    assert_eq!(
        text.replace("  // a comment no edit touches\n", ""),
        written
    );
    // Undo back to the start, applying each undo's changes: the original text again,
    // but for the numbers a deleted network leaves (network_edit renumbers no network
    // on a delete: numbers must increase, not be consecutive).
    while editor.can_undo() {
        let changes = editor.undo().expect("undo");
        text = apply_to_text(&text, editor.model(), &changes);
    }
    assert_ne!(text, original);
    assert_eq!(numbered_by_position(&text), original);
}

/// `text` with its `NETWORK n` lines numbered 1, 2, 3... (one block).
fn numbered_by_position(text: &str) -> String {
    let mut n = 0;
    let mut out = String::new();
    for line in text.split_inclusive('\n') {
        match line.strip_prefix("NETWORK ") {
            Some(rest) => {
                n += 1;
                let after = rest.trim_start_matches(|c: char| c.is_ascii_digit());
                out.push_str(&format!("NETWORK {n}{after}"));
            }
            None => out.push_str(line),
        }
    }
    out
}

/// The `ladder_edit` fuzz target's findings: what an edit stores is what the program
/// reads back, so the text rewritten in place stays the model's program.
#[test]
fn blanks_and_line_breaks_in_edits_are_what_the_program_reads_back() {
    let target = target();
    let set = &target.instructions;
    let start = machine();
    let steps = [
        // A title with a blank after it: stored and written trimmed.
        r#"{"op": "set_network_title", "at": "blocks[0].networks[2]", "title": "count parts "}"#,
        // A comment with a lone carriage return: two lines, as the text reads them.
        r#"{"op": "set_network_comment", "at": "blocks[0].networks[2]", "comment": "one\rand two \n\n"}"#,
    ];
    let mut editor = Editor::new(start.clone(), set);
    let mut text = program_of(&start, set).expect("written");
    for step in steps {
        let changes = editor
            .apply(Edit::from_json(step).expect("an edit"))
            .expect("applies");
        text = gutta_ladder::edit::apply_to_text(&text, editor.model(), set, &changes)
            .expect("in place");
        assert_eq!(
            text,
            program_of(editor.model(), set).expect("written"),
            "{step}"
        );
    }
    let net = &editor.model().blocks[0].networks[2];
    assert_eq!(net.title, "count parts");
    assert_eq!(net.comment, "one\nand two");
    assert!(
        text.contains("NETWORK 3 // count parts\n// one\n// and two\nLD     Part\n"),
        "{text}"
    );
    // An empty operand is a missing one, refused at its path; nothing changes.
    let empty = r#"{"op": "insert_coil", "at": "blocks[0].networks[1].rung.series[2].parallel[1]", "place": "parallel", "coil": "S", "operands": ["Q0.5", " "]}"#;
    let before = editor.model().clone();
    let err = editor
        .apply(Edit::from_json(empty).expect("an edit"))
        .expect_err("refused");
    assert_eq!(err.code, ModelErrorCode::OperandCount, "{err}");
    assert!(err.path.ends_with(".operands[1]"), "{err}");
    assert_eq!(editor.model(), &before);
}

/// Found by `edit_props.rs` on tests/data/run/stack_ops.lad network 1: deleting the
/// contact before outputs in parallel would leave them straight on the rail, separate
/// rungs one network's STL cannot say (it wrote `LPS` with nothing loaded). Refused,
/// nothing changed.
#[test]
fn deleting_the_contact_before_parallel_outputs_is_refused() {
    let target = target();
    let branch = |c: &str, q: &str| {
        format!(
            r#"{{"series": [{{"contact": "LD", "operands": ["{c}"]}}, {{"coil": "=", "operands": ["{q}"]}}]}}"#
        )
    };
    let text = format!(
        r#"{{"format": "gutta-ladder", "version": 1, "plc": "CPU-EC20", "symbols": [],
  "blocks": [{{"kind": "ORGANIZATION_BLOCK", "name": "MAIN", "id": "OB1", "networks": [
    {{"title": "", "comment": "", "rung": {{"series": [{{"contact": "LD", "operands": ["I0.0"]}},
      {{"parallel": [{}, {}, {}]}}]}}}}]}}]}}"#,
        branch("I0.1", "Q0.0"),
        branch("I0.2", "Q0.1"),
        branch("I0.3", "Q0.2")
    );
    let model = read_model(text.as_bytes()).expect("reads");
    validate(&model, &target.instructions).expect("valid");
    let mut editor = Editor::new(model.clone(), &target.instructions);
    let err = editor
        .apply(
            Edit::from_json(r#"{"op": "delete", "at": "blocks[0].networks[0].rung.series[0]"}"#)
                .expect("an edit"),
        )
        .expect_err("refused");
    assert_eq!(err.code, ModelErrorCode::Unwritable, "{err}");
    assert_eq!(editor.model(), &model);
}
