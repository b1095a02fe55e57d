//! `gutta-cc ladder ... -o OUT.json` and `gutta-cc ladder MODEL.json` through the real
//! binary (docs/ladder.md, "The model as JSON"): every example's model validates against
//! docs/ladder-model.schema.json; the section's example is what the CLI prints for its
//! program; a bad model is refused with its L code and JSON path, exit 2, nothing
//! written; a good one is written as a program that compiles (to stdout with `-o -`),
//! and a model written from scratch runs as its tests expect, and so does that model
//! after a sequence of edit operations (machine_edited.json); a rung the writer cannot
//! say is L0013; every L code explains.

mod common;

use std::path::Path;

use common::{cc, examples, root, stderr, stdout};
use gutta_ladder::json::ModelErrorCode;

fn schema() -> jsonschema::Validator {
    let text = std::fs::read_to_string(root().join("docs/ladder-model.schema.json"))
        .expect("docs/ladder-model.schema.json");
    let schema: serde_json::Value = serde_json::from_str(&text).expect("the schema is JSON");
    jsonschema::validator_for(&schema).expect("the schema is a JSON Schema")
}

#[test]
fn every_example_model_validates_against_the_schema() {
    let validator = schema();
    let dir = common::scratch("ladder-json-schema");
    let mut failures = Vec::new();
    for example in examples() {
        let out = dir.join("model.json");
        let run = cc(&[
            "ladder",
            example.to_str().expect("utf-8 path"),
            "-o",
            out.to_str().expect("utf-8 path"),
        ]);
        assert!(
            run.status.success(),
            "{}: {}",
            example.display(),
            stderr(&run)
        );
        let text = std::fs::read_to_string(&out).expect("the model was written");
        let value: serde_json::Value = serde_json::from_str(&text).expect("the model is JSON");
        for error in validator.iter_errors(&value) {
            failures.push(format!(
                "{}: {} at {}",
                example.display(),
                error,
                error.instance_path
            ));
        }
        // Stdout carries the same bytes.
        let piped = cc(&["ladder", example.to_str().expect("utf-8 path"), "-o", "-"]);
        assert_eq!(stdout(&piped), text, "{}", example.display());
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The body of the first fenced block of `lang` after `heading` in `doc`.
fn fenced(doc: &str, heading: &str, lang: &str) -> String {
    let section = &doc[doc.find(heading).expect("the heading")..];
    let open = format!("```{lang}\n");
    let start = section.find(&open).expect("the block") + open.len();
    let end = section[start..].find("```").expect("the block's end") + start;
    section[start..end].to_string()
}

#[test]
fn the_docs_example_is_what_the_cli_prints() {
    let doc = std::fs::read_to_string(root().join("docs/ladder.md")).expect("docs/ladder.md");
    let heading = "## The model as JSON";
    let source = fenced(&doc, heading, "stl");
    let json = fenced(&doc, heading, "json");
    let dir = common::scratch("ladder-json-docs");
    let program = dir.join("motor.lad");
    std::fs::write(&program, source).expect("writes the program");
    let run = cc(&["ladder", program.to_str().expect("utf-8 path"), "-o", "-"]);
    assert!(run.status.success(), "{}", stderr(&run));
    assert_eq!(stdout(&run), json);
    let value: serde_json::Value = serde_json::from_str(&json).expect("JSON");
    assert!(schema().is_valid(&value));
}

/// `gutta-cc ladder MODEL -o OUT` on `text`: (exit code, stderr), and whether OUT exists.
fn read_back(tag: &str, text: &str, out: &str) -> (Option<i32>, String, bool) {
    let dir = common::scratch(&format!("ladder-json-{tag}"));
    let model = dir.join("model.json");
    std::fs::write(&model, text).expect("writes the model");
    let out = if out == "-" {
        "-".to_string()
    } else {
        dir.join(out).display().to_string()
    };
    let run = cc(&["ladder", model.to_str().expect("utf-8 path"), "-o", &out]);
    assert!(
        stdout(&run).is_empty(),
        "nothing on stdout: {}",
        stdout(&run)
    );
    (run.status.code(), stderr(&run), Path::new(&out).exists())
}

#[test]
fn a_bad_model_is_refused_with_its_code_and_path() {
    let coil_first = r#"{"format": "gutta-ladder", "version": 1, "plc": "CPU-EC20", "symbols": [],
      "blocks": [{"kind": "ORGANIZATION_BLOCK", "name": "MAIN", "id": "OB1", "networks": [
        {"title": "", "comment": "", "rung": {"series": [{"coil": "=", "operands": ["Q0.0"]}, {"contact": "LD", "operands": ["I0.0"]}]}}]}]}"#;
    let (code, err, written) = read_back("coil", coil_first, "out.lad");
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("L0008 at blocks[0].networks[0].rung.series[0]"),
        "{err}"
    );
    assert!(err.contains("gutta-cc explain L0008"), "{err}");
    assert!(!written);

    let (code, err, _) = read_back("json", "{\"format\": ", "-");
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("L0001"), "{err}");

    let plc = coil_first.replace("CPU-EC20", "CPU-NONE");
    let (code, err, _) = read_back("plc", &plc, "-");
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("L0010 at plc"), "{err}");

    let unknown = coil_first.replace(r#""coil": "=""#, r#""coil": "=X""#);
    let (code, err, _) = read_back("mnemonic", &unknown, "-");
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("L0005 at blocks[0].networks[0].rung.series[0]"),
        "{err}"
    );
}

#[test]
fn a_good_model_is_written_as_a_program_that_compiles() {
    let example = root().join("examples/blink.lad");
    let run = cc(&["ladder", example.to_str().expect("utf-8 path"), "-o", "-"]);
    let model_json = stdout(&run);
    let dir = common::scratch("ladder-json-writer");
    let model = dir.join("model.json");
    std::fs::write(&model, &model_json).expect("writes the model");
    let lad = dir.join("blink.lad");
    let run = cc(&[
        "ladder",
        model.to_str().expect("utf-8 path"),
        "-o",
        lad.to_str().expect("utf-8 path"),
    ]);
    assert!(run.status.success(), "{}", stderr(&run));
    assert!(stdout(&run).is_empty(), "{}", stdout(&run));
    assert!(
        stderr(&run).contains("written as STL into"),
        "{}",
        stderr(&run)
    );
    let text = std::fs::read_to_string(&lad).expect("the program was written");
    assert!(text.contains("ORGANIZATION_BLOCK MAIN:OB1"), "{text}");
    assert!(text.contains("SUBROUTINE_BLOCK ADD3:SBR0"), "{text}");
    let check = cc(&["--check", lad.to_str().expect("utf-8 path")]);
    assert!(check.status.success(), "{}\n{text}", stderr(&check));

    // `-o -`: the same text on stdout.
    let piped = cc(&["ladder", model.to_str().expect("utf-8 path"), "-o", "-"]);
    assert!(piped.status.success(), "{}", stderr(&piped));
    assert_eq!(stdout(&piped), text);
}

/// tests/data/ladder_model/machine.json, written by hand as a model (a start/stop latch,
/// a TON with outputs in parallel, a CTU with its reset, compare contacts, a MOVW box),
/// becomes machine.lad and passes machine.gtest on the VM.
#[test]
fn a_model_written_from_scratch_runs_as_expected() {
    let data = root().join("tests/data/ladder_model");
    let dir = common::scratch("ladder-json-machine");
    for name in ["machine.json", "machine.gtest"] {
        std::fs::copy(data.join(name), dir.join(name)).expect("copies the test data");
    }
    let lad = dir.join("machine.lad");
    let run = cc(&[
        "ladder",
        dir.join("machine.json").to_str().expect("utf-8 path"),
        "-o",
        lad.to_str().expect("utf-8 path"),
    ]);
    assert!(run.status.success(), "{}", stderr(&run));
    let test = cc(&[
        "test",
        dir.join("machine.gtest").to_str().expect("utf-8 path"),
    ]);
    assert!(
        test.status.success(),
        "{}{}\n{}",
        stdout(&test),
        stderr(&test),
        std::fs::read_to_string(&lad).unwrap_or_default()
    );
    assert!(
        stdout(&test).contains("4 passed, 0 failed"),
        "{}",
        stdout(&test)
    );
}

/// tests/data/ladder_model/machine_edited.json, machine.json after a sequence of edit
/// operations (ladder/tests/edit.rs: Stop NC -> NO, TON -> TOF, a contact in parallel,
/// a MOVW operand, a network duplicated, changed and moved), becomes its program and
/// passes machine_edited.gtest, whose tests are the edits' new behaviour.
#[test]
fn the_edited_model_runs_as_its_edits_say() {
    let data = root().join("tests/data/ladder_model");
    let dir = common::scratch("ladder-json-machine-edited");
    for name in ["machine_edited.json", "machine_edited.gtest"] {
        std::fs::copy(data.join(name), dir.join(name)).expect("copies the test data");
    }
    let lad = dir.join("machine_edited.lad");
    let run = cc(&[
        "ladder",
        dir.join("machine_edited.json")
            .to_str()
            .expect("utf-8 path"),
        "-o",
        lad.to_str().expect("utf-8 path"),
    ]);
    assert!(run.status.success(), "{}", stderr(&run));
    let test = cc(&[
        "test",
        dir.join("machine_edited.gtest")
            .to_str()
            .expect("utf-8 path"),
    ]);
    assert!(
        test.status.success(),
        "{}{}\n{}",
        stdout(&test),
        stderr(&test),
        std::fs::read_to_string(&lad).unwrap_or_default()
    );
    assert!(
        stdout(&test).contains("4 passed, 0 failed"),
        "{}",
        stdout(&test)
    );
}

#[test]
fn a_rung_the_writer_cannot_say_is_l0013() {
    let not_first = r#"{"format": "gutta-ladder", "version": 1, "plc": "CPU-EC20", "symbols": [],
      "blocks": [{"kind": "ORGANIZATION_BLOCK", "name": "MAIN", "id": "OB1", "networks": [
        {"title": "", "comment": "", "rung": {"series": [{"contact": "NOT", "operands": []}, {"coil": "=", "operands": ["Q0.0"]}]}}]}]}"#;
    let (code, err, written) = read_back("not-first", not_first, "out.lad");
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("L0013 at blocks[0].networks[0].rung"), "{err}");
    assert!(err.contains("gutta-cc explain L0013"), "{err}");
    assert!(!written);
}

#[test]
fn every_model_code_explains() {
    for code in ModelErrorCode::ALL {
        let run = cc(&["explain", code.as_str()]);
        assert!(run.status.success(), "{}", code.as_str());
        let out = stdout(&run);
        assert!(out.contains(code.summary()), "{out}");
        assert!(out.contains(code.explanation()), "{out}");
    }
}

/// A model of MAIN whose networks are `rungs` (JSON elements).
fn main_model(rungs: &[&str]) -> String {
    let networks: Vec<String> = rungs
        .iter()
        .map(|r| format!(r#"{{"title": "", "comment": "", "rung": {r}}}"#))
        .collect();
    format!(
        r#"{{"format": "gutta-ladder", "version": 1, "plc": "CPU-EC20", "symbols": [],
      "blocks": [{{"kind": "ORGANIZATION_BLOCK", "name": "MAIN", "id": "OB1", "networks": [{}]}}]}}"#,
        networks.join(", ")
    )
}

/// An undefined symbol on a contact and an input written by a coil: both compiler
/// errors are printed at their elements, exit 2, nothing written.
#[test]
fn compiler_errors_of_a_model_are_refused_at_their_elements() {
    let model = main_model(&[
        r#"{"series": [{"contact": "LD", "operands": ["I0.0"]}, {"contact": "LDN", "operands": ["Stopp"]}, {"coil": "=", "operands": ["Q0.0"]}]}"#,
        r#"{"series": [{"contact": "LD", "operands": ["I0.1"]}, {"coil": "=", "operands": ["I0.2"]}]}"#,
    ]);
    for out in ["out.lad", "-"] {
        let (code, err, written) = read_back("compiler-errors", &model, out);
        assert_eq!(code, Some(2), "{err}");
        assert!(
            err.contains("model.json: E0202 at blocks[0].networks[0].rung.series[1]: "),
            "{err}"
        );
        assert!(
            err.contains("model.json: E0308 at blocks[0].networks[1].rung.series[1]: "),
            "{err}"
        );
        assert_eq!(err.matches("gutta-cc: error:").count(), 2, "{err}");
        assert!(err.contains("  hint: "), "{err}");
        assert!(out == "-" || !written, "{out} was written");
    }
}

/// A warning (an output written twice) is printed at its coil; the program is written.
#[test]
fn warnings_of_a_model_are_printed_and_the_program_written() {
    let model = main_model(&[
        r#"{"series": [{"contact": "LD", "operands": ["I0.0"]}, {"coil": "=", "operands": ["Q0.0"]}]}"#,
        r#"{"series": [{"contact": "LD", "operands": ["I0.1"]}, {"coil": "=", "operands": ["Q0.0"]}]}"#,
    ]);
    let (code, err, written) = read_back("warning", &model, "out.lad");
    assert_eq!(code, Some(0), "{err}");
    assert!(
        err.contains("gutta-cc: warning: ")
            && err.contains("model.json: W0201 at blocks[0].networks[1].rung.series[1]: "),
        "{err}"
    );
    assert!(written);
}

/// `--message-format json`: each diagnostic one object on stdout with its file, path,
/// code and severity, then the fatal error object; nothing written.
#[test]
fn model_diagnostics_as_json_lines() {
    let model = main_model(&[
        r#"{"series": [{"contact": "LD", "operands": ["I0.0"]}, {"contact": "LDN", "operands": ["Stopp"]}, {"coil": "=", "operands": ["Q0.0"]}]}"#,
    ]);
    let dir = common::scratch("ladder-json-message-format");
    let path = dir.join("model.json");
    std::fs::write(&path, &model).expect("writes the model");
    let out = dir.join("out.lad");
    let run = cc(&[
        "--message-format",
        "json",
        "ladder",
        path.to_str().expect("utf-8 path"),
        "-o",
        out.to_str().expect("utf-8 path"),
    ]);
    assert_eq!(run.status.code(), Some(2), "{}", stderr(&run));
    let objects: Vec<serde_json::Value> = stdout(&run)
        .lines()
        .map(|l| serde_json::from_str(l).expect("one JSON object per line"))
        .collect();
    assert_eq!(objects.len(), 2, "{}", stdout(&run));
    assert_eq!(objects[0]["code"], "E0202");
    assert_eq!(objects[0]["severity"], "error");
    assert_eq!(objects[0]["path"], "blocks[0].networks[0].rung.series[1]");
    assert_eq!(objects[0]["file"], path.display().to_string());
    assert_eq!(objects[1]["type"], "error");
    assert_eq!(objects[1]["kind"], "program");
    assert!(stderr(&run).is_empty(), "{}", stderr(&run));
    assert!(!out.exists());
}
