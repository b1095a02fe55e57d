//! The analysis API for editors: text in; diagnostics, definitions, references and
//! hover text out, all with byte spans. Plain data only; no LSP types, no I/O. Each
//! editor feature has its own module here over `&CheckedFile` and byte offsets. The
//! package sits on gutta-compiler (as rust-analyzer's `ide` sits on `hir`) and uses only
//! its public API; the language server adapts it to LSP, and a studio can call it as is.

pub mod actions;
pub mod completion;
pub mod folding;
pub mod format;
pub mod free_address;
pub mod inlay;
pub mod navigation;
pub mod network_edit;
pub mod outline;
mod place;
pub mod rename;
pub mod signature;
pub mod timers;
pub mod tokens;
pub mod workspace_symbols;

use gutta_compiler::check::Definition;
use gutta_compiler::diagnostics::Diagnostic;
use gutta_compiler::source::{SourceFile, Span};
use gutta_compiler::{check_source, CheckedFile, ExplicitTarget};

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
        navigation::definition_at(&self.checked, offset)
            .map(|(_, d)| &self.checked.output.definitions[d])
    }

    /// Every use of the definition at `offset`, plus the definition's own span first.
    pub fn references_at(&self, offset: usize) -> Vec<Span> {
        navigation::references_at(&self.checked, offset)
            .into_iter()
            .map(|(s, _)| s)
            .collect()
    }

    /// Markdown hover text for what is at `offset`: an instruction, a definition or an
    /// address (with its area and Modbus address).
    pub fn hover(&self, offset: usize) -> Option<(Span, String)> {
        navigation::hover(&self.checked, offset)
    }
}
