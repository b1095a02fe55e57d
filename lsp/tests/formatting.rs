//! The formatter over the repository's programs (examples/, tests/data/**): idempotent,
//! and the formatted text compiles to the same image (or the same diagnostic codes)
//! as the text it came from, also after its blanks were shuffled by proptest. The
//! in-process `textDocument/formatting` tests follow. Reads files; changes none.

mod common;

use std::path::{Path, PathBuf};

use common::{uri, TestServer};

use gutta_analysis::format::{format, format_edits};
use gutta_compiler::source::SourceFile;
use lsp_types::request::{Formatting, RangeFormatting};
use lsp_types::{
    DocumentFormattingParams, DocumentRangeFormattingParams, FormattingOptions, Position, Range,
    TextDocumentIdentifier,
};
use proptest::prelude::*;

fn corpus() -> Vec<(String, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut files = Vec::new();
    for dir in ["examples", "tests/data"] {
        collect(&root.join(dir), &mut files);
    }
    files.sort();
    let read: Vec<(String, String)> = files
        .into_iter()
        .filter_map(|p| {
            let text = std::fs::read_to_string(&p).ok()?;
            Some((p.display().to_string(), text))
        })
        .collect();
    assert!(
        read.len() > 50,
        "the corpus went missing: {} files",
        read.len()
    );
    read
}

fn collect(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            collect(&p, out);
        } else if p.extension().is_some_and(|x| x == "lad") {
            out.push(p);
        }
    }
}

/// What a text compiles to: its image, or its diagnostic codes when it has none.
fn meaning(name: &str, text: &str) -> Result<gutta_format::Image, Vec<String>> {
    let compiled = gutta_compiler::compile(SourceFile::new(name, text), None);
    match compiled.image {
        Some(image) => Ok(image),
        None => Err(compiled
            .checked
            .diagnostics()
            .iter()
            .map(|d| d.code.as_str().to_string())
            .collect()),
    }
}

/// Formats `text` if it parses; checks idempotence and meaning. Whether it was formatted.
fn holds(name: &str, text: &str) -> bool {
    let Ok(once) = format(text) else {
        return false;
    };
    assert_eq!(
        format(&once).as_deref(),
        Ok(once.as_str()),
        "{name}: not idempotent"
    );
    let mut edited = text.to_string();
    for e in format_edits(text).unwrap_or_default().iter().rev() {
        edited.replace_range(e.span.range(), &e.text);
    }
    assert_eq!(
        edited, once,
        "{name}: the line edits are not the formatted text"
    );
    assert_eq!(
        meaning(name, text),
        meaning(name, &once),
        "{name}: meaning changed"
    );
    true
}

#[test]
fn every_program_formats_idempotently_to_the_same_image() {
    let corpus = corpus();
    let formatted = corpus.iter().filter(|(n, t)| holds(n, t)).count();
    // Only the programs of the syntax-error corpus are refused.
    assert!(
        formatted * 10 > corpus.len() * 8,
        "{formatted} of {}",
        corpus.len()
    );
}

/// `text` with its layout shuffled: indentation, the gap after a line's first token,
/// trailing blanks and runs of blank lines, from `noise`. Never inside a comment or string.
fn shuffle(text: &str, noise: &[u8]) -> String {
    let (mut out, text) = match text.strip_prefix('\u{FEFF}') {
        Some(rest) => ("\u{FEFF}".to_string(), rest),
        None => (String::new(), text),
    };
    for (i, line) in text.split_inclusive('\n').enumerate() {
        let n = noise.get(i % noise.len().max(1)).copied().unwrap_or(0);
        let (body, end) = match line.strip_suffix('\n') {
            Some(b) => (b, "\n"),
            None => (line, ""),
        };
        let trimmed = body.trim_start();
        out.push_str(&" ".repeat((n & 3) as usize));
        let first_gap = trimmed.find([' ', '\t']);
        let title = trimmed.to_ascii_uppercase().starts_with("TITLE");
        match first_gap {
            Some(g) if !trimmed.starts_with("//") && !trimmed[..g].contains('"') && !title => {
                let rest = trimmed[g..].trim_start();
                out.push_str(&trimmed[..g]);
                out.push_str(&" ".repeat(1 + ((n >> 2) & 7) as usize));
                out.push_str(rest);
            }
            _ => out.push_str(trimmed),
        }
        if n & 0x20 != 0 && !title && !trimmed.contains("//") {
            out.push_str("   ");
        }
        out.push_str(end);
        // Blank lines the formatter keeps (one of a run) stay; a run grows.
        if n & 0x40 != 0 && trimmed.is_empty() {
            out.push('\n');
        }
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, failure_persistence: None, ..ProptestConfig::default() })]
    #[test]
    fn shuffled_layouts_format_to_the_same_program(
        pick in any::<prop::sample::Index>(),
        noise in prop::collection::vec(any::<u8>(), 1..40),
    ) {
        let corpus = corpus();
        let (name, text) = &corpus[pick.index(corpus.len())];
        let shuffled = shuffle(text, &noise);
        if holds(name, &shuffled) {
            // The shuffle does not reach the layout the formatter chose.
            prop_assert_eq!(format(&shuffled), format(text));
        }
    }
}

fn format_request(s: &mut TestServer, u: &lsp_types::Uri) -> Option<Vec<lsp_types::TextEdit>> {
    s.request::<Formatting>(DocumentFormattingParams {
        text_document: TextDocumentIdentifier::new(u.clone()),
        options: FormattingOptions::default(),
        work_done_progress_params: Default::default(),
    })
}

#[test]
fn the_server_answers_one_edit_of_the_changed_lines() {
    let mut s = TestServer::start();
    let u = uri("main.lad");
    let text = "// a program\r\nSYMBOLS\r\nStart:I0.0 // go\r\n  Lamp : Q0.0\r\nEND_SYMBOLS\r\nORGANIZATION_BLOCK MAIN:OB1\r\nBEGIN\r\nNetwork 1 // latch\r\nLD Start\r\nO   Lamp   // hold\r\n=  Lamp\r\nEND_ORGANIZATION_BLOCK\r\n";
    s.open(&u, text);
    insta::assert_snapshot!(common::redact(&format_request(&mut s, &u), &[]));
    // The edit applied is the formatted text; formatted text needs no edits.
    let edits = format_request(&mut s, &u).unwrap_or_default();
    let (start, end) = gutta_lsp::documents::byte_range(text, edits[0].range);
    let formatted = format!("{}{}{}", &text[..start], edits[0].new_text, &text[end..]);
    assert_eq!(format(text).as_deref(), Ok(formatted.as_str()));
    s.replace(&u, 2, &formatted);
    assert_eq!(format_request(&mut s, &u), Some(vec![]));
}

#[test]
fn a_text_with_syntax_errors_is_left_alone() {
    let mut s = TestServer::start();
    let u = uri("broken.lad");
    s.open(
        &u,
        "ORGANIZATION_BLOCK MAIN\nBEGIN\nNETWORK 1\nLD ?\nEND_ORGANIZATION_BLOCK\n",
    );
    assert_eq!(format_request(&mut s, &u), None);
    let logged = s.received("window/logMessage");
    assert!(
        logged
            .iter()
            .any(|n| n.params.to_string().contains("line 4")),
        "{logged:?}"
    );
}

#[test]
fn the_layout_example_of_the_docs_is_formatted() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/language.md");
    let docs = std::fs::read_to_string(path).unwrap_or_default();
    let example = docs
        .split("## 14. Layout")
        .nth(1)
        .and_then(|s| s.split("```\n").nth(1))
        .unwrap_or_default();
    assert!(example.contains("Network 1"), "the example went missing");
    assert_eq!(format(example).as_deref(), Ok(example));
    assert!(
        meaning("layout.lad", example).is_ok(),
        "the example compiles"
    );
}

#[test]
fn range_formatting_edits_only_the_lines_of_the_range() {
    let mut s = TestServer::start();
    let u = uri("main.lad");
    let text = "ORGANIZATION_BLOCK MAIN\nBEGIN\nNETWORK 1\nLD   I0.0\n=  Q0.0\nNETWORK 2\nLD   I0.1\n=  Q0.1\nEND_ORGANIZATION_BLOCK\n";
    s.open(&u, text);
    let edits = s.request::<RangeFormatting>(DocumentRangeFormattingParams {
        text_document: TextDocumentIdentifier::new(u.clone()),
        range: Range::new(Position::new(6, 0), Position::new(6, 4)),
        options: FormattingOptions::default(),
        work_done_progress_params: Default::default(),
    });
    let shown: Vec<String> = edits
        .unwrap_or_default()
        .iter()
        .map(|e| {
            format!(
                "{}:{}-{}:{} {:?}",
                e.range.start.line,
                e.range.start.character,
                e.range.end.line,
                e.range.end.character,
                e.new_text
            )
        })
        .collect();
    assert_eq!(shown, ["6:0-6:9 \"LD     I0.1\""]);
}
