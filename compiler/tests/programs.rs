//! Programs in several files and symbol tables. The corpus tests/data/check/programs/NAME/
//! holds one program each: its .lad sources (in name order), its tables (.csv, .tsv) and
//! `expected`, one `FILE:LINE CODE` per diagnostic (empty: the program compiles). The
//! other tests pin exact human and JSON output across files, the program's symbols and
//! its source map.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

mod common;

use std::path::Path;

use common::root;
use gutta_compiler::diagnostics::json::to_json_lines;
use gutta_compiler::diagnostics::render::{render, RenderStyle};
use gutta_compiler::source::SourceFile;
use gutta_compiler::{check_program, check_source, compile_program, CheckedFile, ProgramSources};

fn load(dir: &Path) -> ProgramSources {
    let mut paths: Vec<_> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("dir entry").path())
        .collect();
    paths.sort();
    let mut program = ProgramSources::default();
    for path in paths {
        let name = path
            .file_name()
            .expect("a file name")
            .to_string_lossy()
            .into_owned();
        let bytes = std::fs::read(&path).expect("read");
        let file = SourceFile::from_bytes(&name, bytes).expect("UTF-8");
        match path.extension().and_then(|x| x.to_str()) {
            // A Micro/WIN data block export is a source under its .txt name.
            Some("lad" | "txt") => program.sources.push(file),
            Some("csv" | "tsv") => program.symbol_tables.push(file),
            _ => {}
        }
    }
    program
}

/// `FILE:LINE CODE` of every diagnostic, sorted.
fn located(c: &CheckedFile) -> Vec<String> {
    let mut out: Vec<String> = c
        .diagnostics()
        .iter()
        .map(|d| {
            let at = c.file.locate(&c.index, d.primary.span.start as usize);
            format!("{}:{} {}", at.file, at.line, d.code.as_str())
        })
        .collect();
    out.sort();
    out
}

fn program(files: &[(&str, &str)]) -> ProgramSources {
    let mut p = ProgramSources::default();
    for (name, text) in files {
        let file = SourceFile::new(*name, *text);
        if name.ends_with(".lad") {
            p.sources.push(file);
        } else {
            p.symbol_tables.push(file);
        }
    }
    p
}

#[test]
fn program_corpus() {
    let base = root().join("tests/data/check/programs");
    let mut dirs: Vec<_> = std::fs::read_dir(&base)
        .expect("the programs corpus")
        .map(|e| e.expect("dir entry").path())
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    assert!(dirs.len() >= 3, "programs are missing");
    for dir in dirs {
        let expected_text = std::fs::read_to_string(dir.join("expected")).expect("expected");
        let mut expected: Vec<String> = expected_text
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty() && !l.starts_with('#'))
            .map(String::from)
            .collect();
        expected.sort();
        let compiled = compile_program(load(&dir), None);
        let got = located(&compiled.checked);
        assert_eq!(
            got,
            expected,
            "{}:\n{}",
            dir.display(),
            render(
                &compiled.checked.file,
                compiled.checked.diagnostics(),
                RenderStyle::PLAIN
            )
        );
        assert_eq!(
            compiled.image.is_some(),
            expected.is_empty(),
            "{}",
            dir.display()
        );
    }
}

#[test]
fn one_source_is_the_single_file_pipeline() {
    let text =
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD I0.0\n= Q0.9\nEND_ORGANIZATION_BLOCK";
    let alone = check_source(SourceFile::new("m.lad", text), None);
    let program = check_program(ProgramSources::single(SourceFile::new("m.lad", text)), None);
    assert!(!program.file.is_joined());
    assert_eq!(program.diagnostics(), alone.diagnostics());
    assert_eq!(
        to_json_lines(&program.file, &program.index, program.diagnostics()),
        to_json_lines(&alone.file, &alone.index, alone.diagnostics())
    );
}

const A: &str = "SYMBOLS\n  Start : I0.0\nEND_SYMBOLS\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD Start\n= Q0.0\nEND_ORGANIZATION_BLOCK\n";
const B: &str = "// b\nSYMBOLS\n  START : I0.1\nEND_SYMBOLS";

#[test]
fn a_duplicate_in_another_file_shows_both_places() {
    let c = check_program(program(&[("a.lad", A), ("b.lad", B)]), None);
    let human = render(&c.file, c.diagnostics(), RenderStyle::PLAIN);
    assert_eq!(
        human,
        "[E0203] Error: symbol `START` is declared twice\n   \
         ,-[ b.lad:3:3 ]\n   \
         |\n \
         3 |   START : I0.1\n   \
         |   ^^|^^  \n   \
         |     `---- here\n   \
         |\n   \
         |-[ a.lad:2:3 ]\n   \
         |\n \
         2 |   Start : I0.0\n   \
         |   ^^|^^  \n   \
         |     `---- first declared here\n\
         ---'\n"
    );
    let json = to_json_lines(&c.file, &c.index, c.diagnostics());
    assert_eq!(
        json,
        "{\"code\":\"E0203\",\"severity\":\"error\",\"message\":\"symbol `START` is declared twice\",\
         \"file\":\"b.lad\",\"line\":3,\"column\":3,\"end_line\":3,\"end_column\":8,\"help\":null,\
         \"start_offset\":15,\"end_offset\":20,\"labels\":[{\"file\":\"a.lad\",\"line\":2,\"column\":3,\
         \"end_line\":2,\"end_column\":8,\"message\":\"first declared here\"}]}\n"
    );
}

#[test]
fn a_table_duplicate_points_into_the_table_and_the_source() {
    let table = "Symbol,Address,Comment\r\nLamp,Q0.1,\r\nstart,I0.2,\r\n";
    let c = check_program(program(&[("a.lad", A), ("io.csv", table)]), None);
    let json = to_json_lines(&c.file, &c.index, c.diagnostics());
    assert_eq!(json.lines().count(), 1, "{json}");
    assert!(
        json.contains("\"file\":\"io.csv\",\"line\":3,\"column\":1,"),
        "{json}"
    );
    assert!(
        json.contains("\"labels\":[{\"file\":\"a.lad\",\"line\":2,\"column\":3,"),
        "{json}"
    );
}

#[test]
fn an_unclosed_block_is_reported_at_its_own_files_end() {
    let open = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD I0.0\n= Q0.0";
    let sbr = "SUBROUTINE_BLOCK S:SBR0\nBEGIN\nNETWORK 1\nLD I0.1\n= Q0.1\nEND_SUBROUTINE_BLOCK\n";
    let c = check_program(program(&[("a.lad", open), ("b.lad", sbr)]), None);
    // (W0203: SBR0 is never called.)
    assert_eq!(located(&c), ["a.lad:1 E0105", "b.lad:1 W0203"]);
    let d = &c.diagnostics()[0];
    let end = c.file.locate(&c.index, d.secondary[0].span.start as usize);
    assert_eq!((end.file, end.line, end.column), ("a.lad", 5, 7));
    let human = render(&c.file, c.diagnostics(), RenderStyle::PLAIN);
    assert!(human.contains("[ a.lad:1:1 ]"), "{human}");
    assert!(!human.contains("b.lad:5"), "{human}");
}

#[test]
fn plc_types_must_agree_and_may_start_any_file() {
    let a = "PLC_TYPE CPU-EC20\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD I0.0\n= Q0.0\nEND_ORGANIZATION_BLOCK\n";
    let same = "PLC_TYPE cpu-ec20\nSYMBOLS\n  X : M0.0\nEND_SYMBOLS\n";
    let c = check_program(program(&[("a.lad", a), ("b.lad", same)]), None);
    assert_eq!(located(&c), Vec::<String>::new());
    let other = "PLC_TYPE EC30-EK51\n";
    let c = check_program(program(&[("a.lad", a), ("b.lad", other)]), None);
    assert_eq!(located(&c), ["b.lad:1 E0112"]);
    let human = render(&c.file, c.diagnostics(), RenderStyle::PLAIN);
    assert!(
        human.contains("this file names PLC type EC30-EK51, another file CPU-EC20"),
        "{human}"
    );
    assert!(
        human.contains("[ a.lad:1:10 ]") && human.contains("CPU-EC20 named here"),
        "{human}"
    );
    // Only in the second file: the program's type all the same.
    let c = check_program(
        program(&[("b.lad", "SYMBOLS\nEND_SYMBOLS\n"), ("a.lad", a)]),
        None,
    );
    assert_eq!((located(&c), c.target.name()), (vec![], "CPU-EC20"));
}

#[test]
fn main_is_defined_once_across_files() {
    let main =
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD I0.0\n= Q0.0\nEND_ORGANIZATION_BLOCK\n";
    let c = check_program(program(&[("a.lad", main), ("b.lad", main)]), None);
    // (W0201: Q0.0 is written twice.)
    assert_eq!(located(&c), ["b.lad:1 E0207", "b.lad:5 W0201"]);
    let sbr = "SUBROUTINE_BLOCK S:SBR0\nBEGIN\nNETWORK 1\nLD I0.1\n= Q0.1\nEND_SUBROUTINE_BLOCK\n";
    let c = check_program(program(&[("a.lad", sbr), ("b.lad", sbr)]), None);
    assert_eq!(
        located(&c),
        [
            "a.lad:1 E0408",
            "a.lad:1 W0203",
            "b.lad:1 E0207",
            "b.lad:1 W0203",
            "b.lad:5 W0201"
        ]
    );
}

#[test]
fn symbols_of_the_program_include_tables_with_types_and_origins() {
    let compiled = compile_program(
        load(&root().join("tests/data/check/programs/two_files_ok")),
        None,
    );
    let symbols = compiled.checked.symbols();
    let row = |name: &str| {
        let s = symbols
            .get(name)
            .unwrap_or_else(|| panic!("{name} is declared"));
        (
            s.address.as_str(),
            s.data_type.as_deref(),
            s.comment.as_str(),
            s.origin.as_str(),
        )
    };
    assert_eq!(row("start"), ("I0.0", None, "start button", "a.lad:4"));
    assert_eq!(
        row("Speed"),
        ("MW10", Some("INT"), "typed symbol", "a.lad:5")
    );
    assert_eq!(
        row("Lamp"),
        ("Q0.0", None, "the \"green\" lamp", "symbols.csv:2")
    );
    assert_eq!(row("Temp"), ("MD8", Some("REAL"), "tank", "symbols.csv:3"));
    assert_eq!(
        row("Setpoint"),
        ("MW12", Some("INT"), "pasted from Micro/WIN", "pasted.tsv:1")
    );
    assert_eq!(symbols.symbols.len(), 5);
    let map = compiled.source_map().expect("a map");
    assert_eq!(map.symbols, symbols);
}

#[test]
fn the_source_map_names_each_instructions_file() {
    let compiled = compile_program(
        load(&root().join("tests/data/check/programs/two_files_ok")),
        None,
    );
    let map = compiled.source_map().expect("a map");
    assert_eq!(
        (map.file.as_str(), map.files.clone()),
        ("a.lad", vec!["a.lad".to_string(), "b.lad".to_string()])
    );
    let b = map.resolve_line("b.lad:6").expect("ok").expect("a line");
    assert_eq!(
        (
            map.file_of(b.instruction),
            b.instruction.line,
            b.instruction.text.as_str()
        ),
        ("b.lad", 6, "MOVR   1.5, Temp")
    );
    let a = map.resolve_line("a.lad:11").expect("ok").expect("a line");
    assert_eq!(
        (
            map.file_of(a.instruction),
            a.instruction.line,
            a.instruction.text.as_str()
        ),
        ("a.lad", 11, "LD     Start")
    );
    assert!(map
        .resolve_line("11")
        .is_err_and(|e| e.contains("a.lad, b.lad")));
    let json = map.to_json();
    assert_eq!(gutta_format::SourceMap::from_json(&json), Ok(map));
}

#[test]
fn the_listing_names_the_files() {
    let compiled = compile_program(
        load(&root().join("tests/data/check/programs/two_files_ok")),
        None,
    );
    let lowered = compiled.lowered.as_ref().expect("lowered");
    let text = gutta_compiler::encode::listing(
        lowered,
        &compiled.checked.file,
        &compiled.checked.index,
        "CPU-EC20",
    );
    assert!(
        text.starts_with("; listing of a.lad, b.lad, pasted.tsv, symbols.csv for CPU-EC20"),
        "{text}"
    );
    assert!(text.contains("; file b.lad\n"), "{text}");
    assert!(text.contains("    6  MOVR   1.5, Temp\n"), "{text}");
}
