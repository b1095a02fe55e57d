//! Checks on the model (docs/ladder.md, "Checks on the model"): every kind of compiler
//! diagnostic lands on the part of the model that caused it (a contact, a coil, a box,
//! a symbol row, a variable, a network, the parallel an `ALD`/`OLD`/`LPS` writes), the
//! structural L codes come first, and over the corpora every diagnostic of every
//! program's model names a part of the model; with every contact's operand renamed to a
//! symbol nobody defines, each undefined-symbol error is at exactly that contact.
//! Models the `ladder_model_arbitrary` fuzz target found wrong are kept here too.

#![allow(
    clippy::disallowed_methods,
    clippy::disallowed_macros,
    reason = "the corpus test reads the repository's programs and prints its census"
)]

mod common;

use std::collections::BTreeMap;

use gutta_catalog::stdlib;
use gutta_compiler::diagnostics::Severity;
use gutta_compiler::ExplicitTarget;
use gutta_ladder::json::{
    check, model_of, names_a_part, read_model, written_program, Element, Model, ModelCheck,
    ModelDiagnostic, NetworkBody,
};

use common::{checked_file, files};

/// The default target, named as the model's `plc` names it.
fn ec20() -> ExplicitTarget {
    ExplicitTarget {
        target: stdlib::shared("CPU-EC20").expect("stdlib"),
        origin: "the model's plc".to_string(),
    }
}

fn contact(mnemonic: &str, operands: &[&str]) -> String {
    format!(r#"{{"contact": "{mnemonic}", "operands": {operands:?}}}"#)
}

fn coil(mnemonic: &str, operands: &[&str]) -> String {
    format!(r#"{{"coil": "{mnemonic}", "operands": {operands:?}}}"#)
}

fn boxed(mnemonic: &str, operands: &[&str], inputs: &[String]) -> String {
    format!(
        r#"{{"box": "{mnemonic}", "operands": {operands:?}, "inputs": [{}]}}"#,
        inputs.join(", ")
    )
}

fn series(parts: &[String]) -> String {
    format!(r#"{{"series": [{}]}}"#, parts.join(", "))
}

fn parallel(parts: &[String]) -> String {
    format!(r#"{{"parallel": [{}]}}"#, parts.join(", "))
}

/// A network of `rung`.
fn net(rung: &str) -> String {
    format!(r#"{{"title": "", "comment": "", "rung": {rung}}}"#)
}

/// A model of `symbols` (JSON list items) and blocks (JSON objects).
fn model(symbols: &[&str], blocks: &[String]) -> Model {
    let text = format!(
        r#"{{"format": "gutta-ladder", "version": 1, "plc": "CPU-EC20", "symbols": [{}], "blocks": [{}]}}"#,
        symbols.join(", "),
        blocks.join(", ")
    );
    read_model(text.as_bytes()).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// MAIN with `networks`.
fn main_block(networks: &[String]) -> String {
    format!(
        r#"{{"kind": "ORGANIZATION_BLOCK", "name": "MAIN", "id": "OB1", "networks": [{}]}}"#,
        networks.join(", ")
    )
}

/// A model of MAIN with one network per rung.
fn main_model(symbols: &[&str], rungs: &[String]) -> Model {
    let networks: Vec<String> = rungs.iter().map(|r| net(r)).collect();
    model(symbols, &[main_block(&networks)])
}

/// The one diagnostic of `checked` with `code`; the check's diagnostics all name parts.
fn only(model: &Model, checked: &ModelCheck, code: &str) -> ModelDiagnostic {
    for d in &checked.diagnostics {
        assert!(names_a_part(model, &d.path), "{d} names nothing");
    }
    let with: Vec<&ModelDiagnostic> = checked
        .diagnostics
        .iter()
        .filter(|d| d.code == code)
        .collect();
    assert_eq!(with.len(), 1, "{:#?}", checked.diagnostics);
    with[0].clone()
}

/// A latch whose second contact names an undefined symbol.
#[test]
fn an_undefined_symbol_is_at_its_contact() {
    let m = main_model(
        &[],
        &[series(&[
            contact("LD", &["I0.0"]),
            contact("LDN", &["Stopp"]),
            coil("=", &["Q0.0"]),
        ])],
    );
    let checked = check(&m, &ec20());
    assert!(checked.has_errors());
    let d = only(&m, &checked, "E0202");
    assert_eq!(d.path, "blocks[0].networks[0].rung.series[1]");
    assert_eq!(d.severity, Severity::Error);
    assert!(d.message.contains("Stopp"), "{d}");
}

#[test]
fn a_bad_operand_of_a_coil_is_at_the_coil() {
    // Inputs are read-only for programs.
    let m = main_model(
        &[],
        &[series(&[
            contact("LD", &["I0.0"]),
            parallel(&[coil("=", &["Q0.0"]), coil("=", &["I0.1"])]),
        ])],
    );
    let checked = check(&m, &ec20());
    let d = only(&m, &checked, "E0308");
    assert_eq!(d.path, "blocks[0].networks[0].rung.series[1].parallel[1]");
}

#[test]
fn a_timer_box_with_a_wrong_timer_is_at_the_box() {
    // A counter's number where TON takes a timer's, behind a contact and before a coil.
    let m = main_model(
        &[],
        &[series(&[
            contact("LD", &["I0.0"]),
            boxed("TON", &["C5", "100"], &[]),
            coil("=", &["Q0.0"]),
        ])],
    );
    let checked = check(&m, &ec20());
    let errors: Vec<&ModelDiagnostic> = checked
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .collect();
    assert_eq!(errors.len(), 1, "{:#?}", checked.diagnostics);
    assert_eq!(errors[0].path, "blocks[0].networks[0].rung.series[1]");
    assert!(errors[0].code.starts_with("E03"), "{}", errors[0]);
}

#[test]
fn a_symbol_row_with_a_bad_address_is_at_its_row() {
    let m = main_model(
        &[
            r#"{"name": "Start", "address": "I0.0"}"#,
            r#"{"name": "Stop", "address": "I0.1"}"#,
            r#"{"name": "Motor", "address": "Q0.0"}"#,
            r#"{"name": "Lamp", "address": "Q99.9"}"#,
        ],
        &[series(&[contact("LD", &["Start"]), coil("=", &["Motor"])])],
    );
    let checked = check(&m, &ec20());
    let errors: Vec<&ModelDiagnostic> = checked
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .collect();
    assert_eq!(errors.len(), 1, "{:#?}", checked.diagnostics);
    assert_eq!(errors[0].path, "symbols[3]");
}

#[test]
fn a_call_to_a_missing_subroutine_is_at_the_call() {
    let m = main_model(
        &[],
        &[series(&[
            contact("LD", &["SM0.0"]),
            boxed("CALL", &["FILL"], &[]),
        ])],
    );
    let checked = check(&m, &ec20());
    let d = only(&m, &checked, "E0206");
    assert_eq!(d.path, "blocks[0].networks[0].rung.series[1]");
}

#[test]
fn a_warning_is_at_its_coil_with_a_note_at_the_other_one() {
    let m = main_model(
        &[],
        &[
            series(&[contact("LD", &["I0.0"]), coil("=", &["Q0.0"])]),
            series(&[contact("LD", &["I0.1"]), coil("=", &["Q0.0"])]),
        ],
    );
    let checked = check(&m, &ec20());
    assert!(!checked.has_errors(), "{:#?}", checked.diagnostics);
    let d = only(&m, &checked, "W0201");
    assert_eq!(d.severity, Severity::Warning);
    assert_eq!(d.path, "blocks[0].networks[1].rung.series[1]");
    let notes: Vec<&str> = d.notes.iter().map(|n| n.path.as_str()).collect();
    assert_eq!(notes, ["blocks[0].networks[0].rung.series[1]"]);
    let json = checked.to_json();
    assert!(json.contains(r#""severity": "warning""#), "{json}");
    assert!(json.contains(r#""code": "W0201""#), "{json}");
}

#[test]
fn a_structural_fault_is_its_l_code_and_stops_the_check() {
    let m = main_model(
        &[],
        &[series(&[
            contact("LD", &["I0.0", "I0.1"]),
            contact("LDN", &["Undefined"]),
            coil("=", &["Q0.0"]),
        ])],
    );
    let checked = check(&m, &ec20());
    assert_eq!(checked.diagnostics.len(), 1, "{:#?}", checked.diagnostics);
    let d = &checked.diagnostics[0];
    assert_eq!(d.code, "L0007");
    assert_eq!(d.path, "blocks[0].networks[0].rung.series[0].operands");
    assert!(checked.program.is_none());
    assert!(names_a_part(&m, &d.path));
    // A rung the writer cannot say (NOT first) is L0013, also before the compiler.
    let m = main_model(&[], &[series(&[contact("NOT", &[]), coil("=", &["Q0.0"])])]);
    let checked = check(&m, &ec20());
    assert_eq!(checked.diagnostics[0].code, "L0013");
    assert!(checked.has_errors());
}

#[test]
fn a_diagnostic_without_a_line_is_at_the_whole_model() {
    let sbr = r#"{"kind": "SUBROUTINE_BLOCK", "name": "FILL", "id": "SBR0", "networks": []}"#;
    let m = model(&[], &[sbr.to_string()]);
    let checked = check(&m, &ec20());
    let d = only(&m, &checked, "E0408");
    assert_eq!(d.path, "");
}

#[test]
fn variables_networks_and_stl_lines_are_their_own_parts() {
    let sbr = r#"{"kind": "SUBROUTINE_BLOCK", "name": "FILL", "id": "SBR0",
        "VAR_INPUT": [{"name": "level", "type": "WORD"}],
        "VAR": [{"name": "tmp", "type": "WORDY"}],
        "networks": [
          {"title": "", "comment": "", "stl": ["LD     SM0.0", "MOVW   #level, QW9999"], "reason": "as written"}]}"#;
    let main = main_block(&[net(&series(&[
        contact("LD", &["SM0.0"]),
        boxed("CALL", &["FILL", "MW0"], &[]),
    ]))]);
    let m = model(&[], &[main, sbr.to_string()]);
    let checked = check(&m, &ec20());
    let at: BTreeMap<String, String> = checked
        .diagnostics
        .iter()
        .map(|d| (d.code.clone(), d.path.clone()))
        .collect();
    assert_eq!(
        at.get("E0213").map(String::as_str),
        Some("blocks[1].VAR[0]"),
        "{:#?}",
        checked.diagnostics
    );
    let stl_error = checked
        .diagnostics
        .iter()
        .find(|d| d.path.starts_with("blocks[1].networks[0]"))
        .unwrap_or_else(|| panic!("{:#?}", checked.diagnostics));
    assert_eq!(stl_error.path, "blocks[1].networks[0].stl[1]");
}

/// The source map itself: each line of a rung with parallels in series and in
/// parallel, and outputs split with LPS/LRD/LPP, at its element or its `parallel`.
#[test]
fn stack_lines_are_at_the_parallel_they_write() {
    let rung = series(&[
        contact("LD", &["I0.0"]),
        parallel(&[
            series(&[contact("LD", &["I0.1"]), contact("LD", &["I0.2"])]),
            contact("LD", &["I0.3"]),
            series(&[contact("LD", &["I0.4"]), contact("LDN", &["I0.5"])]),
        ]),
        parallel(&[
            series(&[contact("LD", &["I1.0"]), coil("=", &["Q0.0"])]),
            series(&[contact("LD", &["I1.1"]), coil("=", &["Q0.1"])]),
            series(&[contact("LD", &["I1.2"]), coil("=", &["Q0.2"])]),
        ]),
    ]);
    let m = main_model(&[], &[rung]);
    let set = &ec20().target.instructions;
    let written = written_program(&m, set).expect("writes");
    let r = "blocks[0].networks[0].rung.series";
    let lines: Vec<(String, String)> = written
        .text
        .lines()
        .zip(&written.paths)
        .skip_while(|(l, _)| !l.starts_with("NETWORK"))
        .map(|(l, p)| {
            let short = p.strip_prefix(r).map_or(p.clone(), |s| format!("~{s}"));
            (l.split_whitespace().next().unwrap_or("").to_string(), short)
        })
        .collect();
    let want = [
        ("NETWORK", "blocks[0].networks[0]"),
        ("LD", "~[0]"),
        ("LD", "~[1].parallel[0].series[0]"),
        ("A", "~[1].parallel[0].series[1]"),
        ("O", "~[1].parallel[1]"),
        ("LD", "~[1].parallel[2].series[0]"),
        ("AN", "~[1].parallel[2].series[1]"),
        ("OLD", "~[1]"),
        ("ALD", "~[1]"),
        ("LPS", "~[2]"),
        ("A", "~[2].parallel[0].series[0]"),
        ("=", "~[2].parallel[0].series[1]"),
        ("LRD", "~[2]"),
        ("A", "~[2].parallel[1].series[0]"),
        ("=", "~[2].parallel[1].series[1]"),
        ("LPP", "~[2]"),
        ("A", "~[2].parallel[2].series[0]"),
        ("=", "~[2].parallel[2].series[1]"),
        ("END_ORGANIZATION_BLOCK", "blocks[0]"),
    ];
    let want: Vec<(String, String)> = want
        .iter()
        .map(|(l, p)| (l.to_string(), p.to_string()))
        .collect();
    assert_eq!(lines, want);
    assert_eq!(written.text.lines().count(), written.paths.len());
    assert_eq!(written.paths[0], "plc");
    for p in &written.paths {
        assert!(names_a_part(&m, p), "{p}");
    }
}

#[test]
fn paths_that_name_nothing_are_told_apart() {
    let m = main_model(
        &[r#"{"name": "Start", "address": "I0.0"}"#],
        &[series(&[contact("LD", &["Start"]), coil("=", &["Q0.0"])])],
    );
    for good in [
        "",
        "plc",
        "symbols[0]",
        "blocks[0]",
        "blocks[0].networks[0].rung.series[1]",
        "blocks[0].networks[0].rung.series[0].operands[0]",
    ] {
        assert!(names_a_part(&m, good), "{good}");
    }
    for bad in [
        "symbols[1]",
        "blocks[1]",
        "blocks[0].networks[0].rung.series[2]",
        "blocks[0].networks[0].rung.parallel[0]",
        "blocks[0].VAR[0]",
        "blocks[x]",
        "nothing",
    ] {
        assert!(!names_a_part(&m, bad), "{bad}");
    }
}

/// Every contact with operands, its JSON path and a mutable handle on its first operand.
fn contacts_mut<'a>(e: &'a mut Element, path: String, out: &mut Vec<(String, &'a mut String)>) {
    match e {
        Element::Series { series: list } => {
            for (i, x) in list.iter_mut().enumerate() {
                contacts_mut(x, format!("{path}.series[{i}]"), out);
            }
        }
        Element::Parallel { parallel: list } => {
            for (i, x) in list.iter_mut().enumerate() {
                contacts_mut(x, format!("{path}.parallel[{i}]"), out);
            }
        }
        Element::Contact { operands, .. } => {
            if let Some(first) = operands.first_mut() {
                out.push((path, first));
            }
        }
        Element::Coil { .. } => {}
        Element::Box { inputs, .. } => {
            for (i, x) in inputs.iter_mut().enumerate() {
                contacts_mut(x, format!("{path}.inputs[{i}]"), out);
            }
        }
    }
}

/// Over every program of the corpora: the model's check maps every compiler diagnostic
/// (none lost) to a part of the model; and with every contact's first operand renamed
/// to a symbol nobody defines (`Undefined_7`), the undefined-symbol error of each name
/// is at exactly its contact.
#[test]
fn every_corpus_diagnostic_maps_to_a_part_of_the_model() {
    let mut failures = Vec::new();
    let (mut programs, mut diagnostics, mut contacts) = (0, 0, 0);
    for (dir, exts) in common::CORPORA {
        for path in files(dir, exts) {
            let checked = checked_file(&path);
            if checked.has_errors() {
                continue;
            }
            let target = ExplicitTarget {
                target: checked.target.clone(),
                origin: "the model's plc".to_string(),
            };
            let mut model = model_of(&checked, &gutta_ladder::build(&checked));
            let name = path.display();
            let result = check(&model, &target);
            let Some(written) = &result.program else {
                failures.push(format!("{name}: {:?}", result.diagnostics));
                continue;
            };
            let compiled = gutta_compiler::compile(
                gutta_compiler::source::SourceFile::new("model.lad", written.text.clone()),
                Some(&target),
            );
            if compiled.checked.diagnostics().len() != result.diagnostics.len() {
                failures.push(format!("{name}: diagnostics lost"));
            }
            for d in &result.diagnostics {
                diagnostics += 1;
                let paths = std::iter::once(&d.path).chain(d.notes.iter().map(|n| &n.path));
                for p in paths {
                    if !names_a_part(&model, p) {
                        failures.push(format!("{name}: {d} at `{p}`, which names nothing"));
                    }
                }
            }
            // Every contact's operand undefined, each at its own contact.
            let mut expected = BTreeMap::new();
            for (b, block) in model.blocks.iter_mut().enumerate() {
                for (n, net) in block.networks.iter_mut().enumerate() {
                    if let NetworkBody::Rung { rung } = &mut net.body {
                        let mut found = Vec::new();
                        contacts_mut(rung, format!("blocks[{b}].networks[{n}].rung"), &mut found);
                        for (at, operand) in found {
                            let symbol = format!("Undefined_{}", expected.len());
                            *operand = symbol.clone();
                            expected.insert(symbol, at);
                        }
                    }
                }
            }
            contacts += expected.len();
            let result = check(&model, &target);
            for (symbol, at) in &expected {
                let found = result
                    .diagnostics
                    .iter()
                    .find(|d| d.code == "E0202" && d.message.contains(&format!("`{symbol}`")));
                match found {
                    Some(d) if &d.path == at => {}
                    Some(d) => failures.push(format!("{name}: {symbol} at {} not {at}", d.path)),
                    None => failures.push(format!("{name}: no E0202 for {symbol} ({at})")),
                }
            }
            programs += 1;
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(programs > 50, "only {programs} programs");
    assert!(contacts > 300, "only {contacts} contacts");
    println!("{programs} models checked: {diagnostics} diagnostics, {contacts} contacts renamed");
}

/// Another PLC type than the model's `plc` (`--plc`): W0204 at `plc`, still valid.
#[test]
fn another_target_than_the_models_plc_is_a_warning_at_plc() {
    let m = main_model(
        &[],
        &[series(&[contact("LD", &["I0.0"]), coil("=", &["Q0.0"])])],
    );
    let other = ExplicitTarget {
        target: stdlib::shared("CPU-EC20-M3").expect("stdlib"),
        origin: "--plc CPU-EC20-M3".to_string(),
    };
    let checked = check(&m, &other);
    assert!(!checked.has_errors(), "{:#?}", checked.diagnostics);
    let d = only(&m, &checked, "W0204");
    assert_eq!(d.path, "plc");
    assert!(d.message.contains("--plc CPU-EC20-M3"), "{d}");
}
