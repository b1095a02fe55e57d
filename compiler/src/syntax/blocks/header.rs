//! The header line of a program or data block: `KEYWORD name : OB1`, `KEYWORD SBR2`,
//! `KEYWORD name`. Finds the name and the block number (OBn, INTn, SBRn, DATn); whether
//! the number fits the block kind is the checker's.

use chumsky::prelude::*;

use super::BlockParser;
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
use crate::syntax::ast::{BlockHeader, BlockNumber, BlockPrefix};
use crate::syntax::lines;

impl BlockParser<'_> {
    /// The header of the block whose keyword is at `kw_span`; a header that does not
    /// parse is E0102 and gives a header without name or number.
    pub(super) fn block_header(&mut self, kw_span: Span, line_span: Span) -> BlockHeader {
        let eoi = self.eoi(line_span);
        let result = run_grammar!(self.chum[1..], eoi, lines::block_header());
        let (name, numbered) = match result {
            Ok(Some((name, numbered))) => (Some(name), numbered),
            Ok(None) => (None, None),
            Err(e) => {
                self.syntax_error(e, "block header");
                (None, None)
            }
        };
        let number = match (name, numbered) {
            (_, Some(n)) => match block_number(self.slice(n)) {
                Some(b) => Some((b, n)),
                None => {
                    let text = self.slice(n).to_string();
                    self.report(
                        Diagnostic::new(
                            Code::BadBlockHeader,
                            n,
                            format!("`{text}` is not a numbered block name"),
                        )
                        .help("numbered names are OB1, INTn, SBRn or DATn"),
                    );
                    None
                }
            },
            (Some(n), None) => block_number(self.slice(n)).map(|b| (b, n)),
            (None, None) => None,
        };
        BlockHeader {
            span: line_span,
            name: name.unwrap_or(Span {
                start: kw_span.end,
                end: kw_span.end,
            }),
            number,
        }
    }
}

/// `OB1`, `INT3`, `SBR0`, `DAT2` (prefix in any case); None for any other text.
fn block_number(text: &str) -> Option<BlockNumber> {
    let split = text.find(|c: char| c.is_ascii_digit())?;
    let (prefix, digits) = text.split_at(split);
    let prefix = match prefix.to_ascii_uppercase().as_str() {
        "OB" => BlockPrefix::Ob,
        "INT" => BlockPrefix::Int,
        "SBR" => BlockPrefix::Sbr,
        "DAT" => BlockPrefix::Dat,
        _ => return None,
    };
    Some(BlockNumber {
        prefix,
        number: digits.parse().ok()?,
    })
}
