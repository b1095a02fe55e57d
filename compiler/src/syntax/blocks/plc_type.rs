//! The `PLC_TYPE NAME` line: which target the program is for. It stands once per file,
//! before the file's blocks; the files of one program must agree on it. Whether the name
//! is a known target is decided by the front end.

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
        if let Some(first) = self.file_plc_type {
            self.report(
                Diagnostic::new(Code::BadPlcType, line_span, "PLC_TYPE given twice")
                    .with_secondary(first, "first given here"),
            );
            return;
        }
        self.file_plc_type = Some(line_span);
        if self.blocks_so_far() > self.blocks_before_file {
            self.report(
                Diagnostic::new(
                    Code::BadPlcType,
                    line_span,
                    "PLC_TYPE after the first block",
                )
                .label("move it to the top of the file"),
            );
        }
        match &self.program.plc_type {
            // Another file of the program named one already.
            Some((first, first_span)) => {
                if !first.eq_ignore_ascii_case(&name) {
                    let d = Diagnostic::new(
                        Code::PlcTypeConflict,
                        name_span,
                        format!("this file names PLC type {name}, another file {first}"),
                    )
                    .label("differs")
                    .with_secondary(*first_span, format!("{first} named here"))
                    .help("the files of one program name one PLC type (or none)");
                    self.report(d);
                }
            }
            None => self.program.plc_type = Some((name, name_span)),
        }
    }
}
