//! The `SYMBOLS ... END_SYMBOLS` block: global names for addresses, one
//! `Name : ADDRESS // comment` (or `Name : ADDRESS : TYPE // comment`) per line.
//! Parsing only; names and types are resolved by the checker.

use chumsky::prelude::*;

use super::{BlockParser, State};
use crate::source::Span;
use crate::syntax::ast::SymbolDecl;
use crate::syntax::lines;

impl BlockParser<'_> {
    /// `SYMBOLS`: opens the block.
    pub(super) fn symbols_header(&mut self, line_span: Span) {
        self.open_block(line_span);
        self.expect_nothing_after(line_span, "SYMBOLS");
        self.state = State::Symbols { header: line_span };
    }

    /// `Name : ADDRESS`, with the comment as the symbol's description.
    pub(super) fn symbol_line(&mut self, line_span: Span, comment: Option<Span>) {
        let eoi = self.eoi(line_span);
        match run_grammar!(self.chum[..], eoi, lines::symbol_decl()) {
            Ok((name, address, data_type)) => {
                let comment = comment.map(|c| self.comment_text(c));
                self.program.symbols.push(SymbolDecl {
                    name,
                    address,
                    data_type,
                    comment,
                    comment_escaped: false,
                });
            }
            Err(e) => self.syntax_error(
                e,
                "symbol declaration (`Name : ADDRESS` or `Name : ADDRESS : TYPE`)",
            ),
        }
    }
}
