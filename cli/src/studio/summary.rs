//! The project as the page lists it (serde JSON): its files with their blocks (kind,
//! name, id, title, VAR sections, number of networks), the symbols, and the project's
//! `.gtest` files. Built from the ladder models the session holds; no I/O.

use gutta_ladder::json::{BlockJson, Model, SymbolJson, VarJson};
use serde::Serialize;

/// What `Session::project` returns.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ProjectSummary {
    /// `[program] name`, else the folder's name.
    pub name: String,
    /// The PLC type the program is checked for.
    pub plc: String,
    pub files: Vec<FileSummary>,
    /// The symbols of every file's program (SYMBOLS blocks and the project's tables),
    /// by name, each once.
    pub symbols: Vec<SymbolJson>,
    /// The project's symbol tables, each marked dirty while a symbol change made in
    /// the studio is not saved.
    pub tables: Vec<TableSummary>,
    /// The `.gtest` files in the folder, as the session names files (`tests/main.gtest`).
    pub tests: Vec<String>,
}

/// An open file.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FileSummary {
    pub name: String,
    pub dirty: bool,
    pub blocks: Vec<BlockSummary>,
}

/// A symbol table file.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TableSummary {
    pub name: String,
    pub dirty: bool,
}

/// A block without its networks.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BlockSummary {
    /// `ORGANIZATION_BLOCK`, `SUBROUTINE_BLOCK`, `INTERRUPT_BLOCK`.
    pub kind: String,
    pub name: String,
    pub id: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub title: Option<String>,
    pub networks: usize,
    #[serde(rename = "VAR_INPUT", skip_serializing_if = "Vec::is_empty")]
    pub var_input: Vec<VarJson>,
    #[serde(rename = "VAR_IN_OUT", skip_serializing_if = "Vec::is_empty")]
    pub var_in_out: Vec<VarJson>,
    #[serde(rename = "VAR_OUTPUT", skip_serializing_if = "Vec::is_empty")]
    pub var_output: Vec<VarJson>,
    #[serde(rename = "VAR", skip_serializing_if = "Vec::is_empty")]
    pub var: Vec<VarJson>,
}

impl BlockSummary {
    fn of(block: &BlockJson) -> BlockSummary {
        BlockSummary {
            kind: block.kind.clone(),
            name: block.name.clone(),
            id: block.id.clone(),
            title: block.title.clone(),
            networks: block.networks.len(),
            var_input: block.var_input.clone(),
            var_in_out: block.var_in_out.clone(),
            var_output: block.var_output.clone(),
            var: block.var.clone(),
        }
    }
}

impl FileSummary {
    pub(super) fn of(name: &str, dirty: bool, model: &Model) -> FileSummary {
        FileSummary {
            name: name.to_string(),
            dirty,
            blocks: model.blocks.iter().map(BlockSummary::of).collect(),
        }
    }
}

/// The symbols of `models`, by name (case-insensitively, as the compiler matches them),
/// each once, the first file's row winning.
pub(super) fn symbols<'m>(models: impl Iterator<Item = &'m Model>) -> Vec<SymbolJson> {
    let mut out: Vec<SymbolJson> = Vec::new();
    for model in models {
        for symbol in &model.symbols {
            if !out
                .iter()
                .any(|s| s.name.eq_ignore_ascii_case(&symbol.name))
            {
                out.push(symbol.clone());
            }
        }
    }
    out.sort_by_key(|s| s.name.to_ascii_uppercase());
    out
}

impl ProjectSummary {
    /// The summary as JSON text.
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).unwrap_or_default()
    }
}
