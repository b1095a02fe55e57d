//! The Micro/WIN corpus (tests/data/microwin, docs/microwin.md): every file is read as
//! `gutta-cc` reads a Micro/WIN export (`SourceFile::from_code_page_bytes`) and must be
//! in the code page its `// encoding: NAME` line names (UTF-8 without one), give exactly
//! the diagnostics its lines announce (`// error: E0115`), compile to an image when it
//! announces no error, and show the interrupt placement (and event translation) its
//! `// summary:` line gives.
//! The VM side (system symbols, a remapped interrupt running) is tests/data/run's
//! `microwin_*.lad`.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

mod common;

use std::path::PathBuf;

use common::{actual, expected, root};
use gutta_compiler::compile;
use gutta_compiler::source::{SourceEncoding, SourceFile};
use gutta_compiler::syntax::microwin;

fn corpus() -> Vec<PathBuf> {
    let dir = root().join("tests/data/microwin");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("dir entry").path())
        .filter(|p| {
            p.extension()
                .is_some_and(|x| x.eq_ignore_ascii_case("awl") || x == "lad")
        })
        .collect();
    files.sort();
    files
}

/// The value of a `// KEY: value` line, if the file has one.
fn directive<'t>(text: &'t str, key: &str) -> Option<&'t str> {
    text.lines()
        .find_map(|l| l.trim().strip_prefix("//")?.trim().strip_prefix(key))
        .and_then(|rest| rest.strip_prefix(':'))
        .map(str::trim)
}

#[test]
fn every_export_reads_checks_and_compiles_as_announced() {
    let files = corpus();
    assert!(files.len() >= 8, "the Micro/WIN corpus is missing files");
    let mut failures = Vec::new();
    let mut encodings = Vec::new();
    for path in files {
        let bytes = std::fs::read(&path).expect("read corpus file");
        let crlf = bytes.windows(2).any(|w| w == b"\r\n");
        let (file, encoding) = SourceFile::from_code_page_bytes(path.display().to_string(), bytes);
        encodings.push((encoding, crlf));
        let want_encoding = directive(&file.text, "encoding").unwrap_or("UTF-8");
        if encoding.as_str() != want_encoding {
            failures.push(format!(
                "{}: read as {}, announced {want_encoding}",
                path.display(),
                encoding.as_str()
            ));
        }
        let compiled = compile(file, None);
        let c = &compiled.checked;
        let want = expected(&c.file.text);
        if actual(c) != want {
            let got: Vec<String> = c
                .diagnostics()
                .iter()
                .map(|d| {
                    let line = c
                        .index
                        .line_col(&c.file.text, d.primary.span.start as usize)
                        .line;
                    format!("line {line}: {} {}", d.code.as_str(), d.message)
                })
                .collect();
            failures.push(format!(
                "{}: expected {want:?}, got:\n  {}",
                path.display(),
                got.join("\n  ")
            ));
        }
        let announces_error = want.keys().any(|(_, code)| code.starts_with('E'));
        if compiled.image.is_none() != announces_error {
            failures.push(format!(
                "{}: image {}, errors announced: {announces_error}",
                path.display(),
                compiled.image.is_some()
            ));
        }
        let summary = c.microwin_summary();
        if summary.as_deref() != directive(&c.file.text, "summary") {
            failures.push(format!("{}: summary {summary:?}", path.display()));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    for (encoding, crlf) in [
        (SourceEncoding::Utf8, false),
        (SourceEncoding::Gbk, true),
        (SourceEncoding::Windows1252, true),
    ] {
        assert!(
            encodings.contains(&(encoding, crlf)),
            "no corpus file in {} with CRLF {crlf}",
            encoding.as_str()
        );
    }
}

#[test]
fn code_pages_decode_as_documented() {
    let utf8 = "主程序 °".as_bytes().to_vec();
    assert_eq!(
        gutta_compiler::source::decode_code_page(utf8).1,
        SourceEncoding::Utf8
    );
    // 主程序 in GBK
    let (text, encoding) =
        gutta_compiler::source::decode_code_page(vec![0xD6, 0xF7, 0xB3, 0xCC, 0xD0, 0xF2]);
    assert_eq!((text.as_str(), encoding), ("主程序", SourceEncoding::Gbk));
    // `° ` is no GBK pair: Windows-1252
    let (text, encoding) = gutta_compiler::source::decode_code_page(vec![b'5', 0xB0, b' ', 0x96]);
    assert_eq!(
        (text.as_str(), encoding),
        ("5° –", SourceEncoding::Windows1252)
    );
}

#[test]
fn a_lad_file_without_the_marker_is_not_in_the_dialect() {
    assert!(!microwin::is_microwin(
        "main.lad",
        "ORGANIZATION_BLOCK MAIN:OB1\n"
    ));
    assert!(microwin::is_microwin(
        "MAIN.AWL",
        "ORGANIZATION_BLOCK MAIN:OB1\n"
    ));
}

/// A misspelt Micro/WIN system name in an export gets a did-you-mean to the name (and its
/// quick fix), as a misspelt symbol does.
#[test]
fn a_misspelt_system_name_suggests_the_micro_win_name() {
    let text = "ORGANIZATION_BLOCK MAIN:OB1\r\nBEGIN\r\nNetwork 1\r\nLD     Alway_On\r\n=      Q0.0\r\nEND_ORGANIZATION_BLOCK\r\n";
    let compiled = compile(SourceFile::new("main.awl", text), None);
    let diags = compiled.checked.diagnostics();
    assert_eq!(diags.len(), 1, "{diags:#?}");
    assert_eq!(diags[0].code.as_str(), "E0202");
    assert_eq!(diags[0].help.as_deref(), Some("did you mean `Always_On`?"));
    assert_eq!(diags[0].fixes.len(), 1, "the replacement as a fix");
}
