//! The ladder model as JSON (docs/ladder.md, "The model as JSON";
//! docs/ladder-model.schema.json): the serde types of the fixed format
//! (`{"format": "gutta-ladder", "version": 1, "plc", "symbols", "blocks"}`),
//! `from_program.rs` (a checked program's ladder into it), `read.rs` (JSON text back
//! into it, every shape error with its JSON path), `validate.rs` (the catalog's checks:
//! mnemonics, operand counts, outputs last) with `power.rs` (the rules that make a
//! rung's STL mean what it draws), `to_program.rs` (a validated model back into program
//! text with the JSON path behind each line, its rungs turned into `model::Rung` by
//! `to_rung.rs` and written by `crate::write`), `check.rs` (the compiler's diagnostics
//! on that program at the parts of the model that caused them) and `codes.rs` (the L
//! codes). No I/O.

mod check;
mod codes;
mod from_program;
mod power;
mod read;
mod to_program;
mod to_rung;
mod validate;

use serde::Serialize;

pub use check::{check, names_a_part, ModelCheck, ModelDiagnostic, ModelNote};
pub use codes::{ModelError, ModelErrorCode};
pub use from_program::model_of;
pub use read::read_model;
pub use to_program::{program_of, written_program, WrittenProgram};
pub use validate::validate;

// One network or element at a time, for the edit operations (`crate::edit`): the same
// reading, checks and writing as a whole model's.
pub(crate) use read::{element as read_element, network as read_network};
pub(crate) use to_program::{network_fields_one_line, network_instructions};
pub(crate) use validate::network as validate_network;

/// The `format` of a ladder model.
pub const FORMAT: &str = "gutta-ladder";
/// The `version` this crate writes and the latest it reads.
pub const VERSION: u64 = 1;

/// A whole program's ladder model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Model {
    /// Always [`FORMAT`].
    pub format: String,
    /// [`VERSION`] when written.
    pub version: u64,
    /// The PLC type whose instruction set the mnemonics are from.
    pub plc: String,
    pub symbols: Vec<SymbolJson>,
    pub blocks: Vec<BlockJson>,
}

/// A symbol: written back as a row of the SYMBOLS block.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SymbolJson {
    pub name: String,
    pub address: String,
    #[serde(rename = "type", skip_serializing_if = "Option::is_none")]
    pub data_type: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub comment: Option<String>,
}

/// A program block.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BlockJson {
    /// The source keyword: `ORGANIZATION_BLOCK`, `SUBROUTINE_BLOCK`, `INTERRUPT_BLOCK`.
    pub kind: String,
    /// `MAIN` of `MAIN:OB1`.
    pub name: String,
    /// `OB1` of `MAIN:OB1`.
    pub id: String,
    /// `TITLE=`, when the block has one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub title: Option<String>,
    /// The variable sections as in the source, each left out when empty.
    #[serde(rename = "VAR_INPUT", skip_serializing_if = "Vec::is_empty")]
    pub var_input: Vec<VarJson>,
    #[serde(rename = "VAR_IN_OUT", skip_serializing_if = "Vec::is_empty")]
    pub var_in_out: Vec<VarJson>,
    #[serde(rename = "VAR_OUTPUT", skip_serializing_if = "Vec::is_empty")]
    pub var_output: Vec<VarJson>,
    #[serde(rename = "VAR", skip_serializing_if = "Vec::is_empty")]
    pub var: Vec<VarJson>,
    pub networks: Vec<NetworkJson>,
}

/// `name : TYPE; // comment` in a VAR section.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct VarJson {
    pub name: String,
    #[serde(rename = "type")]
    pub data_type: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub comment: Option<String>,
}

/// One network: a rung, or its STL with the reason it is not one rung.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NetworkJson {
    /// The network number (optional on input).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub number: Option<u32>,
    /// The text after `NETWORK n //` ("" for none).
    pub title: String,
    /// The comment lines before the first instruction, one per line ("" for none).
    pub comment: String,
    #[serde(flatten)]
    pub body: NetworkBody,
}

/// A network's content.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum NetworkBody {
    Rung { rung: Element },
    Stl { stl: Vec<String>, reason: String },
}

/// A piece of rung.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Element {
    /// Left to right.
    Series { series: Vec<Element> },
    /// Top to bottom: paths that rejoin, or (after the shared contacts) outputs.
    Parallel { parallel: Vec<Element> },
    /// A contact: its mnemonic in the load form (`LD`, `LDN`, `LDW>=`) or `EU`, `ED`,
    /// `NOT`; its operands in STL order.
    Contact {
        contact: String,
        operands: Vec<String>,
    },
    /// A coil: `=`, `S`, `R`, `=I`...; the bit, and the count of `S`/`R`.
    Coil { coil: String, operands: Vec<String> },
    /// A box: its operands in STL order, and its power inputs after the first (a
    /// counter's reset, CTUD's count down) in the order STL loads them.
    Box {
        #[serde(rename = "box")]
        mnemonic: String,
        operands: Vec<String>,
        inputs: Vec<Element>,
    },
}

/// A network `comment`'s lines: split at every line break a file may hold (`\r\n`,
/// `\n`, a lone `\r`), as the program's text reads them.
pub fn comment_lines(comment: &str) -> impl Iterator<Item = &str> {
    let mut rest = (!comment.is_empty()).then_some(comment);
    std::iter::from_fn(move || {
        let text = rest?;
        match text.find(['\r', '\n']) {
            Some(i) => {
                let skip = if text[i..].starts_with("\r\n") { 2 } else { 1 };
                let next = &text[i + skip..];
                rest = (!next.is_empty()).then_some(next);
                Some(&text[..i])
            }
            None => {
                rest = None;
                Some(text)
            }
        }
    })
}

impl Model {
    /// The model as JSON text: pretty, two-space indented, with a final newline.
    pub fn to_json(&self) -> String {
        let mut text = serde_json::to_string_pretty(self).unwrap_or_default();
        text.push('\n');
        text
    }
}
