//! Symbol declarations (SYMBOLS blocks and symbol tables, one namespace): names that
//! may not be symbols, duplicates (shown with the first declaration, in whichever file),
//! addresses, and declared types that must fit the address's width. Operands that use a
//! symbol are resolved in names.rs; a symbol's declared type is not checked against them.

use gutta_catalog::DataType;

use super::{Checker, DefKind};
use crate::diagnostics::{Code, Diagnostic, Suggestion};
use crate::syntax::ast::SymbolDecl;

impl Checker<'_> {
    pub(super) fn symbols(&mut self) {
        let ast = self.ast;
        for decl in &ast.symbols {
            let name = self.slice(decl.name);
            let key = name.to_ascii_uppercase();
            let address_like = self.looks_like_address(name);
            if address_like || crate::syntax::is_reserved(name) {
                self.report(
                    Diagnostic::new(Code::BadSymbolName, decl.name, format!("symbol name `{name}` is not allowed"))
                        .label(if address_like { "has the shape of an address" } else { "reserved word" })
                        .help("choose a name that starts with a letter and is not an address such as M0 or VB100"),
                );
                continue;
            }
            let address = match self.s_operand(decl.address) {
                Some(s) => {
                    self.sequence.s_symbols.insert(key.clone());
                    s
                }
                None => self.direct_address(decl.address, None),
            };
            let Some(address) = address else {
                continue;
            };
            if let Some((first_address, first)) = self.symbols.get(&key) {
                let first_span = self.out.definitions[*first].span;
                if *first_address == address && self.same_declared_type(name, decl) {
                    // Two tables (or blocks) that agree: one symbol, said twice.
                    self.report(
                        Diagnostic::new(
                            Code::SymbolRepeated,
                            decl.name,
                            format!("symbol `{name}` is declared again, with the same address"),
                        )
                        .label("the same address and type as before")
                        .with_secondary(first_span, "first declared here")
                        .help("the two declarations agree; the second can go"),
                    );
                    continue;
                }
                self.report(
                    Diagnostic::new(
                        Code::DuplicateSymbol,
                        decl.name,
                        format!("symbol `{name}` is declared twice"),
                    )
                    .with_secondary(first_span, "first declared here"),
                );
                continue;
            }
            let ty = self.declared_type(decl, address.width);
            let mut text = self.target.memory.format_address(&address);
            if let Some(ty) = ty {
                text = format!("{text} : {}", ty.keyword());
            }
            let detail = match decl.comment_text(self.text) {
                Some(c) if !c.is_empty() => format!("{name} : {text}  // {c}"),
                _ => format!("{name} : {text}"),
            };
            let def = self.define(name.to_string(), DefKind::Symbol, decl.name, detail, None);
            self.symbols.insert(key, (address, def));
        }
    }

    /// Whether `decl` declares the same type (or none) as the first declaration of
    /// `name` (names compared as symbols are: without case).
    fn same_declared_type(&self, name: &str, decl: &SymbolDecl) -> bool {
        let ty = |d: &SymbolDecl| d.data_type.map(|t| self.slice(t).to_ascii_uppercase());
        self.ast
            .symbols
            .iter()
            .find(|d| self.slice(d.name).eq_ignore_ascii_case(name))
            .is_some_and(|first| ty(first) == ty(decl))
    }

    /// The declaration's type, when it names a known one; reported when it is unknown
    /// (E0213) or does not fit the address (E0214).
    fn declared_type(
        &mut self,
        decl: &SymbolDecl,
        width: gutta_catalog::Width,
    ) -> Option<DataType> {
        let span = decl.data_type?;
        let text = self.slice(span);
        let Ok(ty) = text.parse::<DataType>() else {
            let known: Vec<&str> = DataType::ALL.iter().map(|t| t.keyword()).collect();
            let hint = crate::suggest::closest(text, known.iter().copied());
            self.report(
                Diagnostic::new(
                    Code::UnknownDataType,
                    span,
                    format!("unknown data type `{text}`"),
                )
                .maybe_suggest(hint.map(|h| Suggestion::new(span, h))),
            );
            return None;
        };
        if ty.width() != width {
            let address = self.slice(decl.address);
            let fitting: Vec<&str> = DataType::ALL
                .iter()
                .filter(|t| t.width() == width)
                .map(|t| t.keyword())
                .collect();
            self.report(
                Diagnostic::new(
                    Code::SymbolTypeWidth,
                    span,
                    format!("{} does not fit `{address}`", ty.keyword()),
                )
                .label(format!("{} bits", ty.width().bits()))
                .with_secondary(decl.address, format!("{} bits", width.bits()))
                .help(format!("`{address}` holds {}", fitting.join(", "))),
            );
            return None;
        }
        Some(ty)
    }
}
