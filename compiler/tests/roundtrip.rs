//! Round trip of the disassembler over every example and clean test program (and, for
//! the Micro/WIN layout, every program of the run corpus): compile, disassemble
//! (`gutta_format::disasm`, as `stl` or `awl`), compile the text again, and require the
//! same pages, byte for byte, and the same text from the second image.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

mod common;

use std::path::Path;

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, Compiled, ExplicitTarget};
use gutta_format::disasm::{disassemble_as, Format};
use gutta_format::Image;

fn build(name: &str, text: String, explicit: Option<&ExplicitTarget>) -> Compiled {
    compile(SourceFile::new(name, text), explicit)
}

/// Which pages differ, and the first differing byte of each.
fn page_diff(a: &Image, b: &Image) -> String {
    let mut out = Vec::new();
    for id in a.pages.keys().chain(b.pages.keys()) {
        let (x, y) = (a.pages.get(id), b.pages.get(id));
        if x == y || out.iter().any(|(i, _)| i == id) {
            continue;
        }
        let what = match (x, y) {
            (Some(x), Some(y)) => {
                let at = x
                    .iter()
                    .zip(y)
                    .position(|(p, q)| p != q)
                    .unwrap_or(x.len().min(y.len()));
                format!(
                    "first difference at byte {at} (lengths {} and {})",
                    x.len(),
                    y.len()
                )
            }
            (Some(_), None) => "missing after the round trip".to_string(),
            _ => "only after the round trip".to_string(),
        };
        out.push((*id, what));
    }
    out.iter()
        .map(|(id, what)| format!("    {}: {what}", id.file_name()))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The round trip of one program through `format`; `Err` says precisely what went wrong.
fn round_trip(path: &Path, format: Format) -> Result<(), String> {
    let text = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
    let first = text.lines().next().unwrap_or("").trim().to_string();
    let explicit = first.strip_prefix("// plc:").map(|name| ExplicitTarget {
        target: stdlib::shared(name.trim()).expect("stdlib target"),
        origin: format!("--plc {}", name.trim()),
    });
    let original = build(&path.display().to_string(), text, explicit.as_ref());
    let Some(image) = original.image else {
        return Err("does not compile".to_string());
    };
    let target = original.checked.target.clone();
    let dis = disassemble_as(&image, &target, format);
    if !dis.errors.is_empty() {
        let list: Vec<String> = dis.errors.iter().map(|e| format!("    {e}")).collect();
        return Err(format!("disassembly errors:\n{}", list.join("\n")));
    }
    // Micro/WIN's layout is read back as what it is, an export (a `.awl` file).
    let (name, crlf) = match format {
        Format::Stl => ("dis.lad", false),
        Format::Awl => ("dis.awl", true),
    };
    if crlf && dis.text.replace("\r\n", "").contains('\n') {
        return Err("a line does not end in CRLF".to_string());
    }
    let again = build(name, dis.text.clone(), None);
    let Some(image2) = again.image else {
        let diags: Vec<String> = again
            .checked
            .diagnostics()
            .iter()
            .map(|d| {
                let start = (d.primary.span.start as usize).min(dis.text.len());
                let line = dis.text.get(..start).unwrap_or("").lines().count();
                format!("    line {line}: {:?} {}", d.code, d.message)
            })
            .collect();
        return Err(format!(
            "the disassembly does not compile:\n{}\n--- text ---\n{}",
            diags.join("\n"),
            dis.text
        ));
    };
    if image2.pages != image.pages {
        return Err(format!(
            "the disassembly compiles to other pages:\n{}\n--- text ---\n{}",
            page_diff(&image, &image2),
            dis.text
        ));
    }
    let dis2 = disassemble_as(&image2, &target, format);
    let body = |t: &str| t.lines().skip(1).map(str::to_string).collect::<Vec<_>>();
    if body(&dis2.text) != body(&dis.text) {
        return Err("disassembling the second image gives other text".to_string());
    }
    Ok(())
}

#[test]
fn every_example_and_clean_program_round_trips() {
    let files = common::compiling_programs();
    assert!(files.len() > 20, "found only {} programs", files.len());
    let failures: Vec<String> = files
        .iter()
        .filter_map(|p| {
            round_trip(p, Format::Stl)
                .err()
                .map(|e| format!("{}: {e}", p.display()))
        })
        .collect();
    assert!(
        failures.is_empty(),
        "{} of {} programs do not round-trip:\n{}",
        failures.len(),
        files.len(),
        failures.join("\n\n")
    );
}

/// `gutta-cc dis --format awl`: the Micro/WIN layout, read back as a `.awl` export
/// (S7-200 interrupt numbers and all), compiles to the same pages for every example,
/// clean check program and run-corpus program.
#[test]
fn every_program_round_trips_through_the_micro_win_layout() {
    let mut files = common::compiling_programs();
    files.extend(common::lad_files(&common::root().join("tests/data/run")));
    assert!(files.len() > 100, "found only {} programs", files.len());
    let failures: Vec<String> = files
        .iter()
        .filter_map(|p| {
            round_trip(p, Format::Awl)
                .err()
                .map(|e| format!("{}: {e}", p.display()))
        })
        .collect();
    assert!(
        failures.is_empty(),
        "{} of {} programs do not round-trip through awl:\n{}",
        failures.len(),
        files.len(),
        failures.join("\n\n")
    );
}
