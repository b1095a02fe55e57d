//! What the studio's operand editor offers (docs/studio.md, "Editing"): for an
//! element's operand, the symbols and addresses that fit its pin; for a box, the
//! mnemonics the ladder draws as boxes with their pin names. The editor analysis
//! (`gutta_analysis::completion`) decides what fits: the buffer is checked with one
//! more line, the instruction being written, in its first block, and completed at the
//! end of that line. Also the file's ladder, which the page draws, its history's state
//! and the symbol tables' names. No I/O.

use gutta_analysis::completion::{completions, CompletionKind};
use gutta_catalog::LadderClass;
use gutta_compiler::check_program;
use gutta_compiler::source::SourceFile;
use gutta_compiler::ProgramSources;
use gutta_ladder::model::Ladder;
use serde::Serialize;

use super::{Session, StudioError};

/// The most items one answer carries.
const MAX_ITEMS: usize = 60;

/// What is being completed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Wanted {
    /// An operand of the element.
    Operand,
    /// The element's mnemonic.
    Mnemonic,
}

/// One completion question of the page.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CompletionRequest<'a> {
    pub wanted: Wanted,
    /// `contact`, `coil` or `box`.
    pub element: &'a str,
    /// The element's mnemonic when known (`LDN`, `S`, `TON`); else the plain one.
    pub mnemonic: Option<&'a str>,
    /// The operand's place in STL order (a timer's number is 0, its `PT` 1).
    pub pin: usize,
    /// What is typed so far.
    pub prefix: &'a str,
}

/// One item the editor offers.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Completion {
    pub label: String,
    /// `symbol`, `address`, `constant`, `mnemonic`, ...
    pub kind: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub detail: Option<String>,
    /// A mnemonic's operand names in STL order (what the box asks for next).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub operands: Vec<String>,
    /// A box's power inputs after the first (a `CTU`'s `R`; a `CTUD`'s `CD`, `R`): each
    /// a path of its own the box asks a contact for.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub inputs: Vec<String>,
}

impl Session {
    /// The ladder of `file` as it is now.
    pub fn ladder(&self, file: &str) -> Result<&Ladder, StudioError> {
        let name = self.root.plain_name(file)?;
        self.files
            .iter()
            .find(|f| f.name == name)
            .map(|f| &f.ladder)
            .ok_or_else(|| StudioError::NotOpen {
                file: file.to_string(),
            })
    }

    /// Whether `file` has an edit to undo and one to redo.
    pub fn history(&self, file: &str) -> Result<(bool, bool), StudioError> {
        let name = self.root.plain_name(file)?;
        self.files
            .iter()
            .find(|f| f.name == name)
            .map(|f| (!f.undo_texts.is_empty(), !f.redo_texts.is_empty()))
            .ok_or_else(|| StudioError::NotOpen {
                file: file.to_string(),
            })
    }

    /// The symbol tables' names (as the session reads them: inside the folder relative
    /// to it, else their whole path).
    pub fn tables(&self) -> Vec<&str> {
        self.tables.iter().map(|t| t.name.as_str()).collect()
    }

    /// What fits where `request` says in `file`, best first, those starting with the
    /// prefix (case-insensitively) only.
    pub fn complete(
        &self,
        file: &str,
        request: &CompletionRequest<'_>,
    ) -> Result<Vec<Completion>, StudioError> {
        let name = self.root.plain_name(file)?;
        let f = self
            .files
            .iter()
            .find(|f| f.name == name)
            .ok_or_else(|| StudioError::NotOpen {
                file: file.to_string(),
            })?;
        let set = &f.checked.target.instructions;
        let classes: &[LadderClass] = match request.element {
            "contact" => &[
                LadderClass::Contact,
                LadderClass::ClosedContact,
                LadderClass::Compare,
                LadderClass::Not,
                LadderClass::RisingEdge,
                LadderClass::FallingEdge,
            ],
            "coil" => &[
                LadderClass::Coil,
                LadderClass::SetCoil,
                LadderClass::ResetCoil,
            ],
            _ => &[LadderClass::Box],
        };
        let prefix = request.prefix.trim();
        let line = match request.wanted {
            Wanted::Mnemonic => prefix.to_string(),
            Wanted::Operand => {
                let mnemonic = request.mnemonic.unwrap_or(match request.element {
                    "contact" => "LD",
                    "coil" => "=",
                    _ => "MOVW",
                });
                let mut line = format!("{mnemonic} ");
                for _ in 0..request.pin {
                    line.push_str("X, ");
                }
                line.push_str(prefix);
                line
            }
        };
        // The line goes into the first block, before its END line (or at the end).
        let text = &f.text;
        let at = f
            .checked
            .ast
            .units
            .first()
            .and_then(|u| u.end)
            .map_or(text.len(), |end| (end.start as usize).min(text.len()));
        let mut probe = String::with_capacity(text.len() + line.len() + 32);
        probe.push_str(&text[..at]);
        if !probe.is_empty() && !probe.ends_with('\n') {
            probe.push('\n');
        }
        probe.push_str("NETWORK 9999\n");
        probe.push_str(&line);
        let offset = probe.len();
        probe.push('\n');
        probe.push_str(&text[at..]);
        let checked = check_program(
            ProgramSources {
                sources: vec![SourceFile::new(&f.name, &probe)],
                symbol_tables: self.tables.clone(),
                options: self.options.clone(),
            },
            self.target.as_ref(),
        );
        let upper = prefix.to_uppercase();
        let mut out = Vec::new();
        for item in completions(&checked, offset).items {
            if !item.label.to_uppercase().starts_with(&upper) {
                continue;
            }
            let kind = match item.kind {
                CompletionKind::Mnemonic => "mnemonic",
                CompletionKind::Symbol => "symbol",
                CompletionKind::Local => "local",
                CompletionKind::Address => "address",
                CompletionKind::Constant => "constant",
                CompletionKind::Block => "block",
                CompletionKind::Label => "label",
                _ => continue,
            };
            let mut operands = Vec::new();
            let mut inputs = Vec::new();
            if request.wanted == Wanted::Mnemonic {
                let Some(id) = set.lookup(&item.label) else {
                    continue;
                };
                let ins = set.get(id);
                if !classes.contains(&ins.ladder) {
                    continue;
                }
                operands = ins.operands.iter().map(|o| o.name.clone()).collect();
                inputs = ins.power_inputs.iter().skip(1).cloned().collect();
            } else if kind == "mnemonic" {
                continue;
            }
            out.push(Completion {
                label: item.label,
                kind,
                detail: item.detail,
                operands,
                inputs,
            });
            if out.len() == MAX_ITEMS {
                break;
            }
        }
        Ok(out)
    }
}
