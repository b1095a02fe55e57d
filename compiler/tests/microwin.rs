//! The Micro/WIN corpus (tests/data/microwin, docs/microwin.md): every file is read as
//! `gutta-cc` reads a Micro/WIN export (`SourceFile::from_code_page_bytes`) and must be
//! in the code page its `// encoding: NAME` line names (UTF-8 without one), give exactly
//! the diagnostics its lines announce (`// error: E0115`), compile to an image when it
//! announces no error, and show the interrupt placement (and event translation) its
//! `// summary:` line gives. The corpus covers every code page with both line ends, and
//! docs/microwin.md lists every file; the program exported one block per file
//! (tests/data/microwin/split_program) compiles as one. The VM side (system symbols, a
//! remapped interrupt running) is tests/data/run's `microwin_*` programs and
//! cli/tests/cc_microwin_split.rs. Data block exports (`data_block_*.txt`, docs/microwin.md
//! "Data block exports") are read as gutta-cc reads a source (known by their
//! `DATA_BLOCK_TAB` line, in their code page) and compiled with the program their
//! `// program: FILE` line names, for the target of their `// plc: NAME` line (the
//! default without one); their inline expectations are on their own lines.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

mod common;

use std::path::PathBuf;

use common::{actual, expected, root};
use gutta_compiler::microwin;
use gutta_compiler::source::{PartKind, SourceEncoding, SourceFile};
use gutta_compiler::{compile, compile_program, ExplicitTarget, ProgramSources};

/// The corpus files with one of these extensions, sorted.
fn files_with(extensions: &[&str]) -> Vec<PathBuf> {
    let dir = root().join("tests/data/microwin");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("dir entry").path())
        .filter(|p| {
            p.extension()
                .and_then(|x| x.to_str())
                .is_some_and(|x| extensions.iter().any(|e| x.eq_ignore_ascii_case(e)))
        })
        .collect();
    files.sort();
    files
}

/// The exports of programs: `.awl` files and `.lad` files with or without the marker.
fn corpus() -> Vec<PathBuf> {
    files_with(&["awl", "lad"])
}

/// The data block exports.
fn data_blocks() -> Vec<PathBuf> {
    files_with(&["txt"])
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
    for path in files {
        let bytes = std::fs::read(&path).expect("read corpus file");
        let (file, encoding) = SourceFile::from_code_page_bytes(path.display().to_string(), bytes);
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
}

/// docs/microwin.md, "Data block exports": each `data_block_*.txt` is known as a data
/// block export by its header under its `.txt` name, read in the code page it announces,
/// and compiled with the program it names gives exactly the diagnostics its own lines
/// announce (none in the program), and an image when it announces no error.
#[test]
fn every_data_block_export_compiles_with_its_program_as_announced() {
    let files = data_blocks();
    assert!(files.len() >= 5, "the data block exports are missing");
    let mut failures = Vec::new();
    for path in files {
        let name = path
            .file_name()
            .and_then(|n| n.to_str())
            .expect("a name")
            .to_string();
        let bytes = std::fs::read(&path).expect("read corpus file");
        let (file, encoding) =
            SourceFile::from_program_file_bytes(&name, bytes, false).expect("a code page");
        let want_encoding = directive(&file.text, "encoding").unwrap_or("UTF-8");
        if encoding.as_str() != want_encoding {
            failures.push(format!(
                "{name}: read as {}, announced {want_encoding}",
                encoding.as_str()
            ));
        }
        let want = expected(&file.text);
        let program_name = directive(&file.text, "program")
            .unwrap_or_else(|| panic!("{name} has no `// program:` line"))
            .to_string();
        let explicit = directive(&file.text, "plc").map(|plc| ExplicitTarget {
            target: gutta_catalog::stdlib::shared(plc).expect("a stdlib target"),
            origin: format!("--plc {plc}"),
        });
        let program_bytes = std::fs::read(root().join("tests/data/microwin").join(&program_name))
            .expect("the program file");
        let (program_file, _) = SourceFile::from_code_page_bytes(&program_name, program_bytes);
        let mut program = ProgramSources::default();
        program.sources.push(file);
        program.sources.push(program_file);
        let compiled = compile_program(program, explicit.as_ref());
        let c = &compiled.checked;
        let kinds: Vec<(String, PartKind)> = c
            .file
            .parts()
            .into_iter()
            .map(|p| (p.name, p.kind))
            .collect();
        assert_eq!(
            kinds,
            [
                (program_name.clone(), PartKind::Source),
                (name.clone(), PartKind::DataBlockTab)
            ]
        );
        let mut got = std::collections::BTreeMap::new();
        let mut described = Vec::new();
        for d in c.diagnostics() {
            let at = c.file.locate(&c.index, d.primary.span.start as usize);
            described.push(format!(
                "{}:{}: {} {}",
                at.file,
                at.line,
                d.code.as_str(),
                d.message
            ));
            let key = if at.file == name { at.line } else { 0 };
            *got.entry((key, d.code.as_str().to_string())).or_insert(0) += 1;
        }
        if got != want {
            failures.push(format!(
                "{name}: expected {want:?}, got:\n  {}",
                described.join("\n  ")
            ));
        }
        let announces_error = want.keys().any(|(_, code)| code.starts_with('E'));
        if compiled.image.is_none() != announces_error {
            failures.push(format!(
                "{name}: image {}, errors announced: {announces_error}",
                compiled.image.is_some()
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The values of a data block export land in the image's data pages as data blocks of
/// the next free numbers, each value at its address: what `DATA_BLOCK` rows of the same
/// values give (the VM reads them in cli/tests/cc_data_block_export.rs).
#[test]
fn a_data_block_export_is_the_same_data_as_data_block_rows() {
    let program =
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\n= Q0.0\nEND_ORGANIZATION_BLOCK\n";
    let export = "DATA_BLOCK_TAB DB1\r\nBEGIN\r\nVB20 7, 'A'\r\nVW28 -2\r\nVD32 1.5\r\nVB40 \"Hi\"\r\nEND_DATA_BLOCK_TAB\r\n";
    let rows = "DATA_BLOCK DB0:DAT0\n  MB0 BYTE 1\nEND_DATA_BLOCK\nDATA_BLOCK DB1:DAT1\n  VB20 BYTE 7\n  VB21 BYTE 65\n  VW28 WORD -2\n  VD32 REAL 1.5\n  VB40 BYTE 2\n  VB41 BYTE 72\n  VB42 BYTE 105\nEND_DATA_BLOCK\n";
    let target = ExplicitTarget {
        target: gutta_catalog::stdlib::shared("EC30-EKSTM32-XC").expect("target"),
        origin: "--plc EC30-EKSTM32-XC".into(),
    };
    let image = |files: &[(&str, &str)]| {
        let mut program = ProgramSources::default();
        for (name, text) in files {
            program.sources.push(SourceFile::new(*name, *text));
        }
        let compiled = compile_program(program, Some(&target));
        let d: Vec<String> = compiled
            .checked
            .diagnostics()
            .iter()
            .map(|d| d.message.clone())
            .collect();
        assert!(d.is_empty(), "{d:?}");
        compiled.image.expect("an image")
    };
    // DAT0 is the program's own; the export takes DAT1, the next free number.
    let with_export = image(&[
        ("DB1.txt", export),
        (
            "main.lad",
            &format!("{program}DATA_BLOCK DB0:DAT0\n  MB0 BYTE 1\nEND_DATA_BLOCK\n"),
        ),
    ]);
    let with_rows = image(&[("main.lad", &format!("{program}{rows}"))]);
    assert!(
        with_export.pages == with_rows.pages,
        "the data pages differ"
    );
}

/// An export with more values than a data block holds fills the next data blocks.
#[test]
fn a_long_data_block_export_fills_several_data_blocks() {
    let program =
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD SM0.0\n= Q0.0\nEND_ORGANIZATION_BLOCK\n";
    let values: Vec<String> = (0..40).map(|v| v.to_string()).collect();
    let export = format!(
        "DATA_BLOCK_TAB\nMB0 {}\nEND_DATA_BLOCK_TAB\n",
        values.join(", ")
    );
    let mut sources = ProgramSources::default();
    sources.sources.push(SourceFile::new("main.lad", program));
    sources
        .sources
        .push(SourceFile::new("db.txt", export.as_str()));
    // CPU-EC20: 16 rows per data block, so 40 values are DAT0..DAT2.
    let checked = gutta_compiler::check_program(sources.clone(), None);
    assert!(
        checked.diagnostics().is_empty(),
        "{:?}",
        checked.diagnostics()
    );
    let program_out = checked.output.program.expect("checked");
    let blocks: Vec<(u32, String, usize)> = program_out
        .data_blocks
        .iter()
        .map(|d| (d.number, d.name.clone(), d.items.len()))
        .collect();
    assert_eq!(
        blocks,
        [
            (0, "DAT0".into(), 16),
            (1, "DAT1".into(), 16),
            (2, "DAT2".into(), 8)
        ]
    );
    // EC30-EKSTM32-XC: 16 data blocks of 128 rows hold 2048 values; the 2049th needs
    // DAT16 (E0413).
    let values: Vec<String> = (0..2049).map(|v| (v % 200).to_string()).collect();
    let export = format!(
        "DATA_BLOCK_TAB big\nVB0 {}\nEND_DATA_BLOCK_TAB\n",
        values.join(", ")
    );
    sources.sources[1] = SourceFile::new("db.txt", export.as_str());
    let target = ExplicitTarget {
        target: gutta_catalog::stdlib::shared("EC30-EKSTM32-XC").expect("target"),
        origin: "--plc EC30-EKSTM32-XC".into(),
    };
    let codes: Vec<&str> = gutta_compiler::check_program(sources, Some(&target))
        .diagnostics()
        .iter()
        .map(|d| d.code.as_str())
        .collect();
    assert_eq!(codes, ["E0413"]);
}

/// The code page of a corpus file as its bytes show it: a UTF-8 BOM, valid UTF-8, or
/// else what `decode_code_page` makes of it (GBK or Windows-1252, which the corpus test
/// checks against the file's `// encoding:` line).
fn code_page(bytes: &[u8]) -> &'static str {
    if bytes.starts_with(&[0xEF, 0xBB, 0xBF]) {
        return "UTF-8 with BOM";
    }
    match gutta_compiler::source::decode_code_page(bytes.to_vec()).1 {
        SourceEncoding::Utf8 => "UTF-8",
        SourceEncoding::Gbk => "GBK",
        SourceEncoding::Windows1252 => "Windows-1252",
    }
}

/// The line ends of a file: "CRLF" when every line feed follows a carriage return, "LF"
/// when there is no carriage return at all, else None (mixed, or a lone CR, which the
/// dialect does not read as a line end).
fn line_ends(bytes: &[u8]) -> Option<&'static str> {
    let lf = bytes.iter().filter(|&&b| b == b'\n').count();
    let cr = bytes.iter().filter(|&&b| b == b'\r').count();
    let crlf = bytes.windows(2).filter(|w| w == b"\r\n").count();
    match (cr, crlf) {
        (0, _) if lf > 0 => Some("LF"),
        (cr, crlf) if cr == crlf && crlf == lf && lf > 0 => Some("CRLF"),
        _ => None,
    }
}

/// docs/microwin.md, "The corpus": every code page a Micro/WIN export comes in appears
/// with both line ends, and no file mixes them.
#[test]
fn the_corpus_covers_every_code_page_and_line_end() {
    let mut files = corpus();
    files.extend(data_blocks());
    let split = root().join("tests/data/microwin/split_program");
    files.extend(
        std::fs::read_dir(&split)
            .unwrap_or_else(|e| panic!("{}: {e}", split.display()))
            .map(|e| e.expect("dir entry").path())
            .filter(|p| p.extension().is_some_and(|x| x != "md") && !p.ends_with("EXPECTED")),
    );
    let mut seen = std::collections::BTreeSet::new();
    let mut mixed = Vec::new();
    for path in &files {
        let bytes = std::fs::read(path).expect("read corpus file");
        match line_ends(&bytes) {
            Some(ends) => {
                seen.insert((code_page(&bytes), ends));
            }
            None => mixed.push(path.display().to_string()),
        }
    }
    assert!(mixed.is_empty(), "mixed or lone-CR line ends: {mixed:?}");
    let mut missing = Vec::new();
    for page in ["UTF-8 with BOM", "UTF-8", "GBK", "Windows-1252"] {
        for ends in ["CRLF", "LF"] {
            if !seen.contains(&(page, ends)) {
                missing.push(format!("{page} with {ends}"));
            }
        }
    }
    assert!(missing.is_empty(), "no corpus file in {missing:?}");
    let docs = std::fs::read_to_string(root().join("docs/microwin.md")).expect("docs/microwin.md");
    let undocumented: Vec<String> = corpus()
        .iter()
        .chain(&data_blocks())
        .filter_map(|p| p.file_name()?.to_str().map(|n| format!("`{n}`")))
        .filter(|n| !docs.contains(n.as_str()))
        .collect();
    assert!(
        undocumented.is_empty(),
        "docs/microwin.md, \"The corpus\", lacks {undocumented:?}"
    );
}

#[test]
fn line_ends_and_code_pages_are_told_apart() {
    assert_eq!(line_ends(b"a\r\nb\r\n"), Some("CRLF"));
    assert_eq!(line_ends(b"a\nb\n"), Some("LF"));
    assert_eq!(line_ends(b"a\r\nb\n"), None);
    assert_eq!(line_ends(b"a\rb\r"), None);
    assert_eq!(code_page(b"\xEF\xBB\xBFLD"), "UTF-8 with BOM");
    assert_eq!(code_page("主".as_bytes()), "UTF-8");
    assert_eq!(code_page(&[0xD6, 0xF7]), "GBK");
    assert_eq!(code_page(&[0xFC, b':']), "Windows-1252");
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

/// docs/microwin.md, "One block per file": tests/data/microwin/split_program holds a
/// program exported block by block (MAIN, SBR_0 and INT_0 in their own files, in GBK and
/// UTF-8) with a MicroWIN SMART CSV table and a Micro/WIN tab-separated table in GBK;
/// its `EXPECTED` file names them. Read as gutta-cc reads them (each in its code page)
/// they compile as one program without a diagnostic, INT_0 placed on GUTTA's INT1 and
/// the subroutine kept as SBR0. (The VM run is cli/tests/cc_microwin_split.rs.)
#[test]
fn a_program_split_one_block_per_file_compiles() {
    let dir = root().join("tests/data/microwin/split_program");
    let expected = std::fs::read_to_string(dir.join("EXPECTED")).expect("EXPECTED");
    let read = |name: &str| {
        let bytes = std::fs::read(dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        SourceFile::from_code_page_bytes(name, bytes)
    };
    let names = |key: &str| -> Vec<String> {
        directive(&expected, key)
            .unwrap_or_else(|| panic!("EXPECTED has no `// {key}:` line"))
            .split_whitespace()
            .map(str::to_string)
            .collect()
    };
    let mut program = gutta_compiler::ProgramSources::default();
    let mut encodings = Vec::new();
    for name in names("files") {
        let (file, encoding) = read(&name);
        encodings.push((name, encoding.as_str()));
        program.sources.push(file);
    }
    for name in names("tables") {
        let (file, encoding) = read(&name);
        encodings.push((name, encoding.as_str()));
        program.symbol_tables.push(file);
    }
    let pages: Vec<&str> = encodings.iter().map(|(_, e)| *e).collect();
    assert_eq!(
        pages,
        ["GBK", "GBK", "UTF-8", "UTF-8", "GBK"],
        "{encodings:?}"
    );
    let compiled = gutta_compiler::compile_program(program, None);
    let c = &compiled.checked;
    let diagnostics: Vec<String> = c
        .diagnostics()
        .iter()
        .map(|d| format!("{} {}", d.code.as_str(), d.message))
        .collect();
    assert!(diagnostics.is_empty(), "{diagnostics:#?}");
    assert!(compiled.image.is_some());
    assert_eq!(c.target.name(), "CPU-EC20");
    assert_eq!(
        c.microwin
            .as_ref()
            .and_then(|m| microwin::interrupt_summary(&m.interrupt_placements))
            .as_deref(),
        directive(&expected, "summary")
    );
    let blocks: Vec<String> = c
        .ast
        .units
        .iter()
        .map(|u| {
            let (n, _) = u.header.number.expect("numbered block");
            format!(
                "{} {}{}",
                c.file.slice(u.header.name),
                n.prefix.as_str(),
                n.number
            )
        })
        .collect();
    assert_eq!(blocks, ["主程序 OB1", "子程序_0 SBR0", "中断程序_0 INT1"]);
    let symbols = c.symbols();
    let origin = |name: &str| {
        symbols
            .get(name)
            .map(|s| s.origin.clone())
            .unwrap_or_else(|| panic!("no symbol {name}"))
    };
    assert_eq!(origin("电机"), "symbols.csv:3");
    assert_eq!(origin("中断计数"), "symbols_gbk.txt:2");
}

/// The way back keeps empty blocks: an image with an empty subroutine nothing calls and
/// an empty interrupt routine nothing attaches, written as a Micro/WIN export by
/// `gutta-cc dis --format awl`, compiles back to the same pages. Its `// timer-boxes:
/// gutta` line says the text is no Micro/WIN export with templates to drop.
#[test]
fn empty_blocks_of_an_image_survive_the_way_back() {
    use gutta_format::disasm::{disassemble_as, Format};
    let text =
        "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD I0.0\n= Q0.0\nEND_ORGANIZATION_BLOCK\n\
SUBROUTINE_BLOCK LEER:SBR0\nBEGIN\nNETWORK 1\nEND_SUBROUTINE_BLOCK\n\
INTERRUPT_BLOCK STILL:INT1\nBEGIN\nNETWORK 1\nEND_INTERRUPT_BLOCK\n";
    let first = compile(SourceFile::new("empty.lad", text), None);
    let image = first.image.expect("the GUTTA program compiles");
    let dis = disassemble_as(&image, &first.checked.target, Format::Awl);
    assert!(dis.errors.is_empty(), "{:?}", dis.errors);
    assert!(
        dis.text.contains("SUBROUTINE_BLOCK SBR_0:SBR0"),
        "{}",
        dis.text
    );
    let back = compile(SourceFile::new("dis.awl", dis.text.clone()), None);
    let again = back
        .image
        .unwrap_or_else(|| panic!("{:?}\n{}", back.checked.diagnostics(), dis.text));
    assert_eq!(
        again.pages.keys().collect::<Vec<_>>(),
        image.pages.keys().collect::<Vec<_>>()
    );
    assert!(again.pages == image.pages, "the pages differ");
    // The same text without that line is a Micro/WIN export: both are templates.
    let export = dis.text.replace(microwin::GUTTA_BOXES, "");
    let export = compile(SourceFile::new("export.awl", export), None);
    assert_eq!(export.checked.ast.units.len(), 1);
}
