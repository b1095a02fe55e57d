//! The `PLC_TYPE NAME` line: which target the program is for. It stands once, before
//! every block; whether the name is a known target is decided by the front end.

use super::{BlockParser, State};
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
use crate::syntax::lexer::Spanned;

impl BlockParser<'_> {
    /// Records the PLC type name, or reports (E0111) a line inside a block, without one
    /// name, given twice, or after the first block (recorded all the same).
    pub(super) fn plc_type_line(&mut self, kw_span: Span, line_span: Span, toks: &[Spanned]) {
        if self.state != State::Top {
            self.report(
                Diagnostic::new(Code::BadPlcType, line_span, "PLC_TYPE inside a block")
                    .label("must stand before all blocks"),
            );
            return;
        }
        let name_span = Span {
            start: toks.get(1).map(|t| t.1.start).unwrap_or(kw_span.end),
            end: line_span.end,
        };
        let name = self.slice(name_span).trim().to_string();
        if name.is_empty() || name.contains(char::is_whitespace) {
            self.report(
                Diagnostic::new(
                    Code::BadPlcType,
                    if name.is_empty() { kw_span } else { name_span },
                    "PLC_TYPE needs one PLC type name",
                )
                .help("for example `PLC_TYPE CPU-EC20`"),
            );
            return;
        }
        if let Some((_, first)) = &self.program.plc_type {
            let first = *first;
            self.report(
                Diagnostic::new(Code::BadPlcType, line_span, "PLC_TYPE given twice")
                    .with_secondary(first, "first given here"),
            );
            return;
        }
        let blocks = self.program.units.len()
            + self.program.data_blocks.len()
            + self.program.system_blocks.len()
            + self.program.symbols.len();
        if blocks > 0 {
            self.report(
                Diagnostic::new(
                    Code::BadPlcType,
                    line_span,
                    "PLC_TYPE after the first block",
                )
                .label("move it to the top of the file"),
            );
        }
        self.program.plc_type = Some((name, name_span));
    }
}
