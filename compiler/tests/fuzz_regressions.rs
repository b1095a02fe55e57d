//! Inputs the fuzzer (fuzz/fuzz_targets/front_end.rs) crashed on, replayed through the
//! same steps: every file in tests/data/fuzz/ checks on the default target without a
//! panic, with every span inside the text, and renders as text and JSON. The inputs of
//! `microwin_front_end` (tests/data/fuzz/microwin/) go through that target's own steps,
//! `microwin_fuzz::run`, the very code the target runs. Adding a regression means
//! adding a file. Also keeps fuzz/front_end.dict in step with the
//! instruction set. No fuzzing here: the fuzzer itself runs with `cargo fuzz`.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

mod microwin_fuzz;

use std::path::{Path, PathBuf};

use gutta_catalog::stdlib;
use gutta_compiler::diagnostics::json::to_json_lines;
use gutta_compiler::diagnostics::render::{render, RenderStyle};
use gutta_compiler::diagnostics::Code;
use gutta_compiler::source::{PartKind, SourceFile, Span};
use gutta_compiler::{check_source, CheckedFile, ExplicitTarget};

fn default_target() -> ExplicitTarget {
    ExplicitTarget {
        target: stdlib::shared(stdlib::DEFAULT).expect("the embedded default target loads"),
        origin: "the fuzzer".to_string(),
    }
}

fn span_ok(text: &str, span: Span) -> bool {
    let (start, end) = (span.start as usize, span.end as usize);
    start <= end && end <= text.len() && text.is_char_boundary(start) && text.is_char_boundary(end)
}

/// What the fuzz target does with one input; panics where the fuzzer would crash.
fn replay(name: &str, bytes: &[u8], target: &ExplicitTarget) -> CheckedFile {
    let text = String::from_utf8_lossy(bytes).into_owned();
    let checked = check_source(SourceFile::new(name, text), Some(target));
    let text = checked.file.text.as_str();
    for d in checked.diagnostics() {
        assert!(
            span_ok(text, d.primary.span),
            "{name}: primary span of {d:?}"
        );
        for s in &d.secondary {
            assert!(span_ok(text, s.span), "{name}: secondary span of {d:?}");
        }
    }
    for def in &checked.output.definitions {
        assert!(span_ok(text, def.span), "{name}: span of {def:?}");
    }
    for r in &checked.output.references {
        assert!(span_ok(text, r.span), "{name}: span of {r:?}");
    }
    let rendered = render(&checked.file, checked.diagnostics(), RenderStyle::PLAIN);
    assert_eq!(
        checked.diagnostics().is_empty(),
        rendered.is_empty(),
        "{name}"
    );
    let json = to_json_lines(&checked.file, &checked.index, checked.diagnostics());
    assert_eq!(json.lines().count(), checked.diagnostics().len(), "{name}");
    checked
}

fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fuzz")
}

/// The files of a directory, sorted.
fn files_in(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    files
}

/// Crashes of `microwin_front_end` (fuzz/fuzz_targets/microwin_front_end.rs), replayed
/// by the code the target runs; and, so that the target's steps are known to accept a
/// real export, the Micro/WIN corpus as single exports (first byte 0) and the program
/// exported one block per file as a split input (first byte 1, parts joined by NUL).
#[test]
fn microwin_fuzz_crashes_stay_fixed() {
    let crashes = files_in(&data_dir().join("microwin"));
    assert!(
        !crashes.is_empty(),
        "no regression inputs in tests/data/fuzz/microwin"
    );
    for path in crashes {
        let bytes = std::fs::read(&path).expect("readable regression input");
        let result = std::panic::catch_unwind(|| microwin_fuzz::run(&bytes));
        assert!(result.is_ok(), "{} panics", path.display());
    }
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/microwin");
    for path in files_in(&corpus) {
        if path.extension().is_some_and(|x| x == "txt") {
            // A data block export: the sixth part of a split input, after its program
            // and four empty parts (CPU-EC20 has no V: refused, never a panic).
            let mut input = vec![1];
            input.extend(std::fs::read(corpus.join("data_block_program.awl")).expect("program"));
            input.extend([0; 5]);
            input.extend(std::fs::read(&path).expect("corpus file"));
            let compiled = microwin_fuzz::run(&input);
            let kinds: Vec<PartKind> = compiled
                .checked
                .file
                .parts()
                .iter()
                .map(|p| p.kind)
                .collect();
            assert!(
                kinds.contains(&PartKind::DataBlockTab),
                "{}: {kinds:?}",
                path.display()
            );
            continue;
        }
        let mut input = vec![0];
        input.extend(std::fs::read(&path).expect("corpus file"));
        let compiled = microwin_fuzz::run(&input);
        assert!(compiled.checked.microwin.is_some(), "{}", path.display());
    }
    let split = corpus.join("split_program");
    let mut input = vec![1];
    for (i, name) in [
        "MAIN.awl",
        "SBR_0.awl",
        "INT_0.awl",
        "symbols.csv",
        "symbols_gbk.txt",
    ]
    .iter()
    .enumerate()
    {
        if i > 0 {
            input.push(0);
        }
        input.extend(std::fs::read(split.join(name)).expect("split program file"));
    }
    let compiled = microwin_fuzz::run(&input);
    assert!(
        compiled.image.is_some(),
        "{:?}",
        compiled.checked.diagnostics()
    );
}

#[test]
fn fuzz_crashes_stay_fixed() {
    let mut files: Vec<PathBuf> = std::fs::read_dir(data_dir())
        .expect("tests/data/fuzz exists")
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no regression inputs in tests/data/fuzz");
    let target = default_target();
    for path in files {
        let bytes = std::fs::read(&path).expect("readable regression input");
        let name = path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        replay(&name, &bytes, &target);
    }
}

/// The first crash: `MB44444444444444444430` saturates the byte number, and the range
/// check overflowed. Such addresses are simply outside the area.
#[test]
fn huge_address_numbers_are_outside_the_area() {
    let target = default_target();
    let name = "address_offset_overflow_operand.lad";
    let bytes = std::fs::read(data_dir().join(name)).expect("regression input");
    let checked = replay(name, &bytes, &target);
    let outside: Vec<&str> = checked
        .diagnostics()
        .iter()
        .filter(|d| d.code == Code::AddressOutOfTarget)
        .map(|d| checked.file.slice(d.primary.span))
        .collect();
    assert_eq!(
        outside,
        ["M99999999999999999999.0", "MW444444444444444444444"]
    );

    let name = "address_offset_overflow_data_row.lad";
    let bytes = std::fs::read(data_dir().join(name)).expect("regression input");
    let checked = replay(name, &bytes, &target);
    assert!(checked
        .diagnostics()
        .iter()
        .any(|d| d.code == Code::AddressOutOfTarget
            && checked.file.slice(d.primary.span) == "MB44444444444444444430"));
}

/// Entries of a libFuzzer dictionary: the quoted values, unescaped.
fn dictionary_entries(text: &str) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    for line in text.lines().map(str::trim) {
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let Some(start) = line.find('"') else {
            continue;
        };
        let quoted = &line.as_bytes()[start + 1..line.len() - 1];
        let mut value = Vec::new();
        let mut i = 0;
        while i < quoted.len() {
            match quoted[i] {
                b'\\' if quoted.get(i + 1) == Some(&b'x') => {
                    let hex = std::str::from_utf8(&quoted[i + 2..i + 4]).expect("hex escape");
                    value.push(u8::from_str_radix(hex, 16).expect("hex escape"));
                    i += 4;
                }
                b'\\' => {
                    value.push(quoted[i + 1]);
                    i += 2;
                }
                b => {
                    value.push(b);
                    i += 1;
                }
            }
        }
        out.push(value);
    }
    out
}

#[test]
fn dictionary_lists_every_mnemonic_and_keyword() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fuzz/front_end.dict");
    let text = std::fs::read_to_string(&path).expect("fuzz/front_end.dict");
    let entries = dictionary_entries(&text);
    let has = |word: &str| entries.iter().any(|e| e.as_slice() == word.as_bytes());
    let target = default_target().target;
    let missing: Vec<&str> = target
        .instructions
        .names()
        .map(|(name, _)| name)
        .filter(|name| !has(name))
        .collect();
    assert!(
        missing.is_empty(),
        "fuzz/front_end.dict lacks mnemonics {missing:?}"
    );
    let keywords = entries
        .iter()
        .filter_map(|e| std::str::from_utf8(e).ok())
        .filter(|w| gutta_compiler::syntax::is_reserved(w))
        .count();
    assert!(
        keywords >= 21,
        "only {keywords} block keywords in the dictionary"
    );
}

/// The first crash of `microwin_front_end`: in a program of two files, an undefined
/// symbol's "also used here" label in the second file, after Chinese text there, made
/// ariadne slice inside a character (it took a char offset for a byte offset). The label
/// now renders at its file, line and column.
#[test]
fn a_label_in_another_file_after_chinese_text_renders() {
    let bytes = std::fs::read(data_dir().join("microwin/split_render_cr_gbk.bin"))
        .expect("regression input");
    let compiled = microwin_fuzz::run(&bytes);
    let c = &compiled.checked;
    let undefined: Vec<_> = c
        .diagnostics()
        .iter()
        .filter(|d| d.code == Code::UndefinedSymbol)
        .cloned()
        .collect();
    assert_eq!(undefined.len(), 1, "{:?}", c.diagnostics());
    let text = render(&c.file, &undefined, RenderStyle::PLAIN);
    assert!(text.contains("[ MAIN.awl:2:3 ]"), "{text}");
    assert!(text.contains("[ SBR_0.awl:2:3 ]"), "{text}");
    assert!(text.contains("also used here"), "{text}");
}
