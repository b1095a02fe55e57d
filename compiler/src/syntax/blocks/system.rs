//! The `SYSTEM_BLOCK ... END_SYSTEM_BLOCK` block: PLC settings, one `KEY = VALUE` entry
//! per line (a word, a whole number or a string). Parsing only; keys and ranges are the
//! checker's.

use chumsky::prelude::*;

use super::{BlockParser, State};
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
use crate::syntax::ast::{Operand, OperandKind, SystemBlock, SystemEntry, SystemValue};
use crate::syntax::lines::{self, RawValue};

impl BlockParser<'_> {
    /// `SYSTEM_BLOCK`: opens the block.
    pub(super) fn system_header(&mut self, line_span: Span) {
        self.open_block(line_span);
        self.expect_nothing_after(line_span, "SYSTEM_BLOCK");
        self.program.system_blocks.push(SystemBlock {
            span: line_span,
            entries: Vec::new(),
            end: None,
        });
        self.state = State::System;
    }

    /// `KEY = VALUE`.
    pub(super) fn system_line(&mut self, line_span: Span) {
        let eoi = self.eoi(line_span);
        match run_grammar!(self.chum[..], eoi, lines::system_entry()) {
            Ok((key, value)) => {
                let value = self.system_value(value);
                if let Some(b) = self.program.system_blocks.last_mut() {
                    b.entries.push(SystemEntry {
                        span: line_span,
                        key,
                        value,
                    });
                }
            }
            Err(e) => self.syntax_error(e, "system block entry (`KEY = VALUE`)"),
        }
    }

    /// A word, a string without its quotes and escapes, or a whole number (a real number
    /// is E0602).
    fn system_value(&mut self, value: RawValue) -> SystemValue {
        match value {
            RawValue::Word(w) => SystemValue::Word(w),
            RawValue::Str(s) => {
                let inner = self.slice(s);
                let inner = &inner[1..inner.len().saturating_sub(1).max(1)];
                SystemValue::Str(unescape(inner), s)
            }
            RawValue::Number(n) => match self.convert_number(n) {
                Operand {
                    kind: OperandKind::Integer(v),
                    span,
                } => SystemValue::Integer(v, span),
                Operand {
                    kind: OperandKind::Real(_),
                    span,
                } => {
                    self.report(Diagnostic::new(
                        Code::SystemValue,
                        span,
                        "system block values are whole numbers",
                    ));
                    SystemValue::Error
                }
                _ => SystemValue::Error,
            },
        }
    }
}

/// Unescape `\"` and `\\` in a string literal's contents.
fn unescape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut chars = s.chars();
    while let Some(c) = chars.next() {
        if c == '\\' {
            if let Some(n) = chars.next() {
                out.push(n);
            }
        } else {
            out.push(c);
        }
    }
    out
}
