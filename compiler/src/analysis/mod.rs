//! The analysis API for editors: text in; diagnostics, definitions, references and
//! hover text out, all with byte spans. Plain data only; no LSP types, no I/O.

pub mod actions;
pub mod completion;
mod place;
pub mod rename;
pub mod signature;

use gutta_catalog::Address;

use crate::check::{DefKind, Definition};
use crate::diagnostics::Diagnostic;
use crate::source::{SourceFile, Span};
use crate::{check_source, CheckedFile, ExplicitTarget};

/// One analysed document.
#[derive(Debug, Clone)]
pub struct Analysis {
    pub checked: CheckedFile,
}

impl Analysis {
    pub fn new(name: &str, text: &str, target: Option<&ExplicitTarget>) -> Analysis {
        Analysis {
            checked: check_source(SourceFile::new(name, text), target),
        }
    }

    pub fn diagnostics(&self) -> &[Diagnostic] {
        self.checked.diagnostics()
    }

    /// Symbols, blocks, locals, data blocks and labels, in definition order.
    pub fn definitions(&self) -> &[Definition] {
        &self.checked.output.definitions
    }

    /// The definition named at `offset` (a use or the definition itself).
    pub fn definition_at(&self, offset: usize) -> Option<&Definition> {
        let out = &self.checked.output;
        out.references
            .iter()
            .find(|r| r.span.contains(offset))
            .map(|r| &out.definitions[r.definition])
            .or_else(|| {
                out.definitions
                    .iter()
                    .find(|d| d.span.contains(offset) && !d.span.is_empty())
            })
    }

    /// Every use of the definition at `offset`, plus the definition's own span first.
    pub fn references_at(&self, offset: usize) -> Vec<Span> {
        let out = &self.checked.output;
        let def = out
            .references
            .iter()
            .find(|r| r.span.contains(offset))
            .map(|r| r.definition)
            .or_else(|| {
                out.definitions
                    .iter()
                    .position(|d| d.span.contains(offset) && !d.span.is_empty())
            });
        let Some(def) = def else { return Vec::new() };
        let mut spans = vec![out.definitions[def].span];
        spans.extend(
            out.references
                .iter()
                .filter(|r| r.definition == def)
                .map(|r| r.span),
        );
        spans
    }

    /// Markdown hover text for what is at `offset`: an instruction, a definition or an
    /// address (with its area and Modbus address).
    pub fn hover(&self, offset: usize) -> Option<(Span, String)> {
        let out = &self.checked.output;
        let target = &self.checked.target;
        if let Some((span, id)) = out.mnemonics.iter().find(|(s, _)| s.contains(offset)) {
            let ins = target.instructions.get(*id);
            let ops: Vec<&str> = ins.operands.iter().map(|o| o.name.as_str()).collect();
            let text = format!(
                "**{} {}**\n\n{}\n\n{}",
                ins.mnemonic,
                ops.join(", "),
                ins.summary,
                ins.description
            );
            return Some((*span, text));
        }
        if let Some(r) = out.references.iter().find(|r| r.span.contains(offset)) {
            let d = &out.definitions[r.definition];
            return Some((r.span, self.definition_hover(d)));
        }
        if let Some((span, a)) = out.addresses.iter().find(|(s, _)| s.contains(offset)) {
            return Some((*span, self.address_hover(a)));
        }
        out.definitions
            .iter()
            .find(|d| d.span.contains(offset) && !d.span.is_empty())
            .map(|d| (d.span, self.definition_hover(d)))
    }

    fn definition_hover(&self, d: &Definition) -> String {
        let kind = match d.kind {
            DefKind::Symbol => "symbol",
            DefKind::Local => "local variable",
            DefKind::Unit => "program block",
            DefKind::DataBlock => "data block",
            DefKind::Label => "label",
        };
        format!("{kind} `{}`\n\n{}", d.name, d.detail)
    }

    fn address_hover(&self, a: &Address) -> String {
        let memory = &self.checked.target.memory;
        let name = memory.format_address(a);
        let area = memory
            .area_by_slot(a.slot)
            .map(|x| x.description.as_str())
            .unwrap_or("");
        let mut text = format!("`{name}`: {} in {area} (byte {})", a.width, a.offset);
        if let Some(m) = memory.modbus_location(a) {
            text.push_str(&format!("\n\nModbus: {m}"));
        }
        text
    }
}
