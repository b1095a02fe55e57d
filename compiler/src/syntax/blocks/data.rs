//! The `DATA_BLOCK ... END_DATA_BLOCK` block: initial values, one `ADDRESS TYPE VALUE`
//! row per line. Parsing only; rows are checked against the target by the checker.

use chumsky::prelude::*;

use super::{BlockParser, State};
use crate::source::Span;
use crate::syntax::ast::{DataBlock, DataRow};
use crate::syntax::lines;

impl BlockParser<'_> {
    /// `DATA_BLOCK name : DATn`: opens the block.
    pub(super) fn data_header(&mut self, kw_span: Span, line_span: Span) {
        self.open_block(line_span);
        let header = self.block_header(kw_span, line_span);
        self.program.data_blocks.push(DataBlock {
            header,
            rows: Vec::new(),
            end: None,
        });
        self.state = State::Data;
    }

    /// `ADDRESS TYPE VALUE`.
    pub(super) fn data_line(&mut self, line_span: Span) {
        let eoi = self.eoi(line_span);
        match run_grammar!(self.chum[..], eoi, lines::data_row()) {
            Ok((address, ty, value)) => {
                let value = self.convert_number(value);
                if let Some(d) = self.program.data_blocks.last_mut() {
                    d.rows.push(DataRow {
                        span: line_span,
                        address,
                        ty,
                        value,
                    });
                }
            }
            Err(e) => self.syntax_error(e, "data row (`ADDRESS TYPE VALUE`)"),
        }
    }
}
