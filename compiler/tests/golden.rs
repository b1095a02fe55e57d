//! Golden images: every example and every clean test program has an insta snapshot of
//! its pages (hex, 16 bytes a row, with the page's length and CRC) followed by the
//! image's disassembly as the decoded view. Any change in encoding shows as a reviewed
//! snapshot diff (`cargo insta review`, or INSTA_UPDATE=always to accept).

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

mod common;

use std::path::Path;

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_format::{crc16, disasm};

fn golden_text(path: &Path) -> String {
    let rel = path.strip_prefix(common::root()).unwrap_or(path);
    let text = std::fs::read_to_string(path).expect("read");
    let explicit = text
        .lines()
        .next()
        .and_then(|l| l.trim().strip_prefix("// plc:"))
        .map(|n| ExplicitTarget {
            target: stdlib::shared(n.trim()).expect("stdlib target"),
            origin: format!("--plc {}", n.trim()),
        });
    let compiled = compile(
        SourceFile::new(rel.display().to_string(), text),
        explicit.as_ref(),
    );
    let image = compiled.image.unwrap_or_else(|| {
        panic!(
            "{} does not compile: {:?}",
            rel.display(),
            compiled.checked.diagnostics().first()
        )
    });
    let mut out = format!("{} for {}\n", rel.display(), image.plc_type);
    for (id, bytes) in &image.pages {
        out.push_str(&format!(
            "\n== {} ({} bytes, crc 0x{:04X})\n",
            id.file_name(),
            bytes.len(),
            crc16(bytes)
        ));
        for (i, row) in bytes.chunks(16).enumerate() {
            let hex: Vec<String> = row.iter().map(|b| format!("{b:02X}")).collect();
            out.push_str(&format!("{:04X}  {}\n", i * 16, hex.join(" ")));
        }
    }
    let d = disasm::disassemble_with_errors(&image, &compiled.checked.target);
    assert!(d.errors.is_empty(), "{}: {:?}", rel.display(), d.errors);
    out.push_str("\n== decoded\n");
    out.push_str(&d.text);
    out
}

#[test]
fn golden_images() {
    let files = common::compiling_programs();
    assert!(files.len() >= 25, "programs are missing");
    for path in files {
        let name = path
            .file_stem()
            .and_then(|s| s.to_str())
            .expect("name")
            .to_string();
        let dir = path
            .parent()
            .and_then(|p| p.file_name())
            .and_then(|s| s.to_str())
            .unwrap_or("x")
            .to_string();
        insta::assert_snapshot!(format!("{dir}__{name}"), golden_text(&path));
    }
}
