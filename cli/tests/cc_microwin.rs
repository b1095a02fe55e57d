//! `gutta-cc` reading Micro/WIN exports (docs/microwin.md) through the real binary: a
//! GBK `.awl` with CRLF and a Windows-1252 tab-separated symbol table compile, with the
//! note on the code pages and the S7-200 interrupt placement after the summary (`-o`,
//! `--check`) and at the top of `--emit listing`; a `.lad` without the marker stays
//! strictly UTF-8.

mod common;

use common::{cc, stderr, stdout};

use std::path::PathBuf;

/// A fresh directory for this test.
fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gutta-cc-microwin-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("creates the scratch directory");
    dir
}

const MAIN: &str = "ORGANIZATION_BLOCK 主程序:OB1\nTITLE=程序注释\nBEGIN\nNetwork 1 \t\n\
LD\tFirst_Scan_On\nATCH\t中断程序_0:INT0, 10\nENI\nNetwork 2\nLD\tAlways_On\n=\tLampe\n\
END_ORGANIZATION_BLOCK\nINTERRUPT_BLOCK 中断程序_0:INT0\nBEGIN\nNetwork 1\nLD\tAlways_On\n\
INCW\tMW0\nEND_INTERRUPT_BLOCK\nINTERRUPT_BLOCK INT_1:INT1\nBEGIN\nNetwork 1\n\
END_INTERRUPT_BLOCK\n";

#[test]
fn a_gbk_export_and_a_windows_1252_table_compile_with_the_placement_shown() {
    let dir = scratch("gbk");
    let source = dir.join("主程序.awl");
    let crlf = MAIN.replace('\n', "\r\n");
    let (gbk, _, bad) = encoding_rs::GBK.encode(&crlf);
    assert!(!bad);
    std::fs::write(&source, &gbk).expect("writes the export");
    let table = dir.join("symbols.txt");
    // `Lampe<TAB>Q0.0<TAB>Lampe über der Tür` in Windows-1252.
    let mut row = b"Lampe\tQ0.0\tLampe ".to_vec();
    row.extend_from_slice(&[0xFC, b'b', b'e', b'r', b' ', 0x96, b'\r', b'\n']);
    std::fs::write(&table, &row).expect("writes the table");
    let image = dir.join("image");
    let args = [
        source.to_str().expect("path"),
        "--symbols",
        table.to_str().expect("path"),
        "-o",
        image.to_str().expect("path"),
        "--emit",
        "listing",
    ];
    let o = cc(&args);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("主程序.awl is not UTF-8; read as GBK"),
        "{err}"
    );
    assert!(
        err.contains("symbols.txt is not UTF-8; read as Windows-1252"),
        "{err}"
    );
    let placement =
        "S7-200 interrupts: 中断程序_0 (INT0) -> INT1; INT_1 (INT1) empty, not attached: dropped";
    assert!(err.contains(placement), "{err}");
    let out = stdout(&o);
    assert!(out.starts_with(&format!("// {placement}\n")), "{out}");
    let check = cc(&[args[0], args[1], args[2], "--check"]);
    assert!(stderr(&check).contains(placement), "{}", stderr(&check));
}

#[test]
fn a_lad_file_without_the_marker_must_be_utf8() {
    let dir = scratch("lad");
    let source = dir.join("main.lad");
    std::fs::write(&source, [b'/', b'/', b' ', 0xFC, b'\n']).expect("writes");
    let o = cc(&[source.to_str().expect("path"), "--check"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("is not UTF-8 text"), "{}", stderr(&o));
}
