//! The Neovim runtime files (editors/neovim/ftdetect, ftplugin, syntax): the syntax
//! file's mnemonic list is the stdlib instruction set's (always; `UPDATE_DOCS=1`
//! rewrites it), and headless Neovim, with that folder on 'runtimepath' and gutta-lsp.lua
//! loaded, gives a `.lad` file the filetype `gutta`, `commentstring` `// %s` and the
//! formatter's indent, colours each construct with its syntax group, comments a line
//! with `gcc` where Neovim has it (0.10 and newer), and formats a badly laid out file
//! through the real `gutta-lsp`, both with the version's formatting call and with `gq`.
//! Without Neovim the test fails saying how to install it, unless GUTTA_SKIP_EXTERNAL=1.

mod external;

use std::collections::BTreeSet;
use std::process::Command;

use serde_json::Value;

const SYNTAX: &str = "editors/neovim/syntax/gutta.vim";
const BEGIN: &str = "\" BEGIN GENERATED MNEMONICS\n";
const END: &str = "\" END GENERATED MNEMONICS\n";
/// Mnemonics per `syn match` line.
const PER_LINE: usize = 12;

/// The generated part of the syntax file: one `syn match guttaMnemonic` per
/// `PER_LINE` mnemonics of every stdlib target (aliases too), longest first.
fn mnemonic_matches() -> String {
    let mut mnemonics = BTreeSet::new();
    for plc in gutta_catalog::stdlib::names() {
        let target = gutta_catalog::stdlib::shared(plc).expect("stdlib target");
        for (name, _) in target.instructions.names() {
            mnemonics.insert(name.to_uppercase());
        }
    }
    let mut sorted: Vec<String> = mnemonics.into_iter().collect();
    sorted.sort_by(|a, b| b.len().cmp(&a.len()).then(a.cmp(b)));
    let escape = |m: &String| {
        m.chars()
            .flat_map(|c| {
                let special = "\\/*.[]~^$".contains(c);
                special.then_some('\\').into_iter().chain([c])
            })
            .collect::<String>()
    };
    let mut text = String::from(
        "\" Generated from the stdlib instruction set by lsp/tests/neovim_filetype.rs:\n\
         \" UPDATE_DOCS=1 cargo test -p gutta-lsp --test neovim_filetype\n",
    );
    for chunk in sorted.chunks(PER_LINE) {
        let names: Vec<String> = chunk.iter().map(escape).collect();
        text.push_str(&format!(
            "syn match guttaMnemonic /^\\s*\\zs\\%({}\\)\\ze\\%(\\s\\|\\/\\/\\|;\\|,\\|$\\)\\%([^:\\/]*:\\)\\@!/\n",
            names.join("\\|")
        ));
    }
    text
}

#[test]
fn syntax_file_lists_the_instruction_set() {
    let path = external::repo_root().join(SYNTAX);
    let file = std::fs::read_to_string(&path).expect("reads the syntax file");
    let start = file.find(BEGIN).expect("the BEGIN marker") + BEGIN.len();
    let end = file.find(END).expect("the END marker");
    let generated = mnemonic_matches();
    if file[start..end] == generated {
        return;
    }
    if std::env::var_os("UPDATE_DOCS").is_some_and(|v| v == "1") {
        let updated = format!("{}{generated}{}", &file[..start], &file[end..]);
        std::fs::write(&path, updated).expect("writes the syntax file");
        return;
    }
    panic!(
        "{SYNTAX}: the mnemonic list is not the stdlib's; regenerate it with \
         `UPDATE_DOCS=1 cargo test -p gutta-lsp --test neovim_filetype`"
    );
}

/// The file the syntax groups are read in, and where: (line, column, text there, group).
const PROGRAM: &str = "\
PLC_TYPE CPU-EC20
SYMBOLS
  Stop  : I0.1   // TODO wire it
  Level : MW20 : INT
END_SYMBOLS

ORGANIZATION_BLOCK MAIN:OB1
TITLE=Compare and move
VAR
  a, count : INT;
END_VAR
BEGIN
Network 1 // level high
LDW>=  Level, +350
AN     Stop
MOVW   16#0E01, *MD4
+I     #count, VW2
TON    T37, 100
=      Q0.0
STOP
END_ORGANIZATION_BLOCK
";

const PROBES: [(usize, usize, &str, &str); 22] = [
    (14, 1, "LDW>=", "guttaMnemonic"),
    (1, 1, "PLC_TYPE", "guttaDirective"),
    (1, 10, "CPU-EC20", "guttaPlcType"),
    (2, 1, "SYMBOLS", "guttaBlock"),
    (3, 3, "Stop", "guttaSymbolDecl"),
    (3, 11, "I0.1", "guttaAddress"),
    (3, 21, "TODO", "guttaTodo"),
    (4, 18, "INT", "guttaType"),
    (7, 1, "ORGANIZATION_BLOCK", "guttaBlock"),
    (7, 20, "MAIN:OB1", "guttaBlockName"),
    (8, 1, "TITLE=", "guttaTitle"),
    (13, 1, "Network", "guttaNetwork"),
    (13, 11, "// level high", "guttaComment"),
    (14, 8, "Level", "guttaSymbol"),
    (14, 15, "+350", "guttaNumber"),
    (16, 8, "16#0E01", "guttaNumber"),
    (16, 17, "*", "guttaOperator"),
    (17, 1, "+I", "guttaMnemonic"),
    (17, 8, "#count", "guttaLocal"),
    (18, 8, "T37", "guttaAddress"),
    (20, 1, "STOP", "guttaMnemonic"),
    (10, 3, "a", "guttaSymbolDecl"),
];

/// A valid program laid out badly, and the layout gutta-lsp's formatter gives it
/// (docs/language.md, "Layout").
const BAD: &str = "\
SYMBOLS
Start:I0.0 // push button
    Lamp :   Q0.0
END_SYMBOLS
ORGANIZATION_BLOCK MAIN:OB1
BEGIN
  Network 1
    LD Start   // pressed
  =   Lamp
END_ORGANIZATION_BLOCK
";

const FORMATTED: &str = "\
SYMBOLS
  Start : I0.0  // push button
  Lamp  : Q0.0
END_SYMBOLS

ORGANIZATION_BLOCK MAIN:OB1
BEGIN
Network 1
LD     Start  // pressed
=      Lamp
END_ORGANIZATION_BLOCK
";

/// Neovim's major and minor version.
fn nvim_version() -> (u32, u32) {
    let out = external::run(Command::new("nvim").arg("--version"), "nvim --version");
    let first = out.lines().next().unwrap_or_default();
    let numbers: Vec<u32> = first
        .trim_start_matches("NVIM v")
        .split(['.', '-'])
        .take(2)
        .filter_map(|n| n.parse().ok())
        .collect();
    assert_eq!(numbers.len(), 2, "no version in `{first}`");
    (numbers[0], numbers[1])
}

#[test]
fn neovim_sets_up_colours_and_formats_a_lad_file() {
    if !external::have("nvim") {
        return;
    }
    let version = nvim_version();
    assert!(
        version >= (0, 7),
        "the runtime files need Neovim 0.7 or newer"
    );
    for (line, column, text, _) in PROBES {
        let at = &PROGRAM.lines().nth(line - 1).expect("line")[column - 1..];
        assert!(at.starts_with(text), "probe {line}:{column} is `{at}`");
    }
    let work = external::scratch("neovim-filetype");
    let file = work.join("colours.lad");
    std::fs::write(&file, PROGRAM).expect("writes");
    std::fs::write(work.join("format.lad"), BAD).expect("writes");
    std::fs::write(work.join("gq.lad"), BAD).expect("writes");
    let out = work.join("answer.json");
    let probes: Vec<[usize; 2]> = PROBES.iter().map(|p| [p.0, p.1]).collect();
    let answer = external::nvim_answer(
        external::nvim("filetype.lua", &file, &work, &out)
            .env("GUTTA_NVIM_PROBES", serde_json::json!(probes).to_string())
            .env("GUTTA_NVIM_FORMAT", work.join("format.lad"))
            .env("GUTTA_NVIM_GQ", work.join("gq.lad")),
        &out,
    );

    assert_eq!(answer["timeout"], Value::Null, "no server: {answer}");
    assert_eq!(answer["filetype"], "gutta", "{answer}");
    assert_eq!(answer["syntax"], "gutta", "{answer}");
    assert_eq!(answer["commentstring"], "// %s", "{answer}");
    assert_eq!(answer["comments"], "://", "{answer}");
    assert_eq!(answer["expandtab"], true, "{answer}");
    assert_eq!(answer["shiftwidth"], 2, "{answer}");
    assert_eq!(answer["softtabstop"], 2, "{answer}");
    let options = answer["formatoptions"].as_str().expect("formatoptions");
    assert!(!options.contains('t'), "code is not wrapped: {options}");
    for flag in ['c', 'r', 'o', 'q', 'j'] {
        assert!(options.contains(flag), "`{flag}` in {options}");
    }
    let groups = answer["groups"].as_array().expect("groups");
    for (probe, group) in PROBES.iter().zip(groups) {
        assert_eq!(
            group, probe.3,
            "`{}` at {}:{}: {answer}",
            probe.2, probe.0, probe.1
        );
    }
    let has_gc = version >= (0, 10);
    assert_eq!(answer["hasGc"], has_gc, "{answer}");
    if has_gc {
        assert_eq!(answer["gcc"], "// LDW>=  Level, +350", "{answer}");
        assert_eq!(answer["gccTwice"], "LDW>=  Level, +350", "{answer}");
    } else {
        assert_eq!(answer["gcc"], Value::Null, "{answer}");
    }

    let call = if version >= (0, 8) {
        "vim.lsp.buf.format"
    } else {
        "vim.lsp.buf.formatting_sync"
    };
    assert_eq!(answer["formatCall"], call, "{answer}");
    assert_eq!(answer["formatted"], FORMATTED, "{answer}");
    assert_eq!(answer["gq"], FORMATTED, "{answer}");
    assert_eq!(
        answer["formatexprOnAttach"], "v:lua.vim.lsp.formatexpr()",
        "{answer}"
    );
    let _ = std::fs::remove_dir_all(&work);
}
