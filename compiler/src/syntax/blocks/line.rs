//! What the block parser does with the tokens of one line whatever block it is in:
//! reporting lexical errors, reporting a grammar's failure (once per line), turning
//! number tokens into values, finding a comment's text. No block structure here.

use chumsky::prelude::*;

use super::BlockParser;
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
use crate::syntax::ast::{Operand, OperandKind};
use crate::syntax::lexer::{Spanned, Tok};
use crate::syntax::lines::RawOperand;
use crate::syntax::numbers::{self, Number};

impl BlockParser<'_> {
    /// One E0101 per run of adjacent invalid characters, one per unterminated string.
    pub(super) fn report_lexical_errors(&mut self, toks: &[Spanned]) {
        let mut i = 0;
        while i < toks.len() {
            match toks[i].0 {
                Tok::Error => {
                    let start = toks[i].1;
                    let mut end = start;
                    while i + 1 < toks.len()
                        && toks[i + 1].0 == Tok::Error
                        && toks[i + 1].1.start == end.end
                    {
                        i += 1;
                        end = toks[i].1;
                    }
                    self.report_invalid_characters(start.to(end));
                }
                Tok::UnterminatedStr => {
                    self.report(
                        Diagnostic::new(Code::UnterminatedString, toks[i].1, "unterminated string")
                            .label("no closing `\"` on this line"),
                    );
                    self.line_reported = true;
                }
                _ => {}
            }
            i += 1;
        }
    }

    fn report_invalid_characters(&mut self, s: Span) {
        let text = self.slice(s).to_string();
        self.report(
            Diagnostic::new(
                Code::InvalidCharacter,
                s,
                format!("invalid character `{text}`"),
            )
            .label("not part of the language")
            .help("comments start with `//`"),
        );
        self.line_reported = true;
    }

    /// The end of input a line grammar sees: the end of the line.
    pub(super) fn eoi(&self, line_span: Span) -> SimpleSpan {
        SimpleSpan::from(line_span.end as usize..line_span.end as usize)
    }

    /// Report a grammar failure, unless the line already has a lexical error.
    pub(super) fn syntax_error(&mut self, (message, at): (String, Span), context: &str) {
        if self.line_reported {
            return;
        }
        self.line_reported = true;
        self.report(Diagnostic::new(
            Code::Syntax,
            at,
            format!("{message} in {context}"),
        ));
    }

    /// A raw operand with its number converted; a malformed number is E0104 and an
    /// error operand.
    pub(super) fn convert_number(&mut self, raw: RawOperand) -> Operand {
        match raw {
            RawOperand::Name {
                prefix,
                local,
                name,
                span,
            } => Operand {
                span,
                kind: OperandKind::Name {
                    prefix,
                    local,
                    name,
                },
            },
            RawOperand::Number {
                negative,
                digits,
                span,
            } => match numbers::convert(self.slice(digits), negative) {
                Ok(Number::Integer(v)) => Operand {
                    span,
                    kind: OperandKind::Integer(v),
                },
                Ok(Number::Real(v)) => Operand {
                    span,
                    kind: OperandKind::Real(v),
                },
                Err(e) => {
                    self.report(Diagnostic::new(
                        Code::MalformedNumber,
                        digits,
                        format!("malformed number: {e}"),
                    ));
                    Operand {
                        span,
                        kind: OperandKind::Error,
                    }
                }
            },
        }
    }

    /// Span of a comment's text without `//` and surrounding blanks.
    pub(super) fn comment_text(&self, c: Span) -> Span {
        let text = self.slice(c);
        let body = text.trim_start_matches('/');
        let lead = text.len() - body.len() + (body.len() - body.trim_start().len());
        let trimmed = body.trim();
        Span::new(
            c.start as usize + lead,
            c.start as usize + lead + trimmed.len(),
        )
    }
}
