//! Neovim end to end: `nvim --headless --clean -u lsp/tests/neovim/smoke.lua FILE.lad`
//! with the real `gutta-lsp` on PATH loads editors/neovim/gutta-lsp.lua (the config
//! docs/editors.md shows), opens a program with a misspelt symbol, waits for its
//! diagnostic, asks for a hover and writes both to a file; the test reads them. Without
//! Neovim the test fails saying how to install it, unless GUTTA_SKIP_EXTERNAL=1. Also:
//! docs/editors.md shows that config verbatim.

mod external;

use std::process::Command;

use serde_json::Value;

/// A program with one mistake: `Strat` is not a symbol (E0202, did you mean `Start`).
const PROGRAM: &str = "\
SYMBOLS
  Start : I0.0   // push button
END_SYMBOLS

ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1 // the mistake
LD     Strat
=      Q0.0
END_ORGANIZATION_BLOCK
";

/// Where the hover is asked: `=` on line 8 (0-based), column 0.
const HOVER: (u32, u32) = (8, 0);

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
fn docs_show_the_config_the_smoke_test_runs() {
    let root = external::repo_root();
    let config = std::fs::read_to_string(root.join("editors/neovim/gutta-lsp.lua"))
        .expect("reads the config");
    let docs = std::fs::read_to_string(root.join("docs/editors.md")).expect("reads the docs");
    assert!(
        docs.contains(&format!("```lua\n{config}```")),
        "docs/editors.md must show editors/neovim/gutta-lsp.lua verbatim"
    );
}

#[test]
fn neovim_gets_the_diagnostic_and_a_hover() {
    if !external::have("nvim") {
        return;
    }
    assert!(
        nvim_version() >= (0, 7),
        "the config needs Neovim 0.7 or newer"
    );
    let work = external::scratch("neovim");
    let file = work.join("mistake.lad");
    std::fs::write(&file, PROGRAM).expect("writes");
    let out = work.join("answer.json");
    let answer = external::nvim_answer(
        external::nvim("smoke.lua", &file, &work, &out)
            .env("GUTTA_HOVER_LINE", HOVER.0.to_string())
            .env("GUTTA_HOVER_COLUMN", HOVER.1.to_string()),
        &out,
    );

    assert_eq!(answer["filetype"], "gutta", "{answer}");
    assert_eq!(answer["clients"], 1, "{answer}");
    assert_eq!(
        answer["timeout"],
        Value::Null,
        "no diagnostic came: {answer}"
    );
    let diagnostics = answer["diagnostics"].as_array().expect("diagnostics");
    assert_eq!(diagnostics.len(), 1, "{answer}");
    assert_eq!(diagnostics[0]["code"], "E0202", "{answer}");
    assert_eq!(diagnostics[0]["line"], 7, "{answer}");
    assert!(
        diagnostics[0]["message"]
            .as_str()
            .is_some_and(|m| m.contains("Strat")),
        "{answer}"
    );
    let hover = answer["hover"]
        .as_str()
        .unwrap_or_else(|| panic!("no hover: {answer}"));
    assert!(hover.contains('='), "{answer}");
    assert!(!hover.starts_with("error:"), "{answer}");
    let _ = std::fs::remove_dir_all(&work);
}
