//! Instruction lines inside a program block's networks: the mnemonic (`LD`, `=`, `+I`,
//! `LDW>=`) and its operand list. Only the shape of a line: whether the mnemonic exists
//! and the operands fit it is the checker's.

use chumsky::prelude::*;

use super::BlockParser;
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
use crate::syntax::ast::{Instruction, Network, Operand, OperandKind};
use crate::syntax::lexer::{Spanned, Tok};
use crate::syntax::lines::{self, RawOperand};

impl BlockParser<'_> {
    /// One instruction, added to the current network (an implicit one, reported once per
    /// block, when the code has no NETWORK line yet). Operands that do not parse give an
    /// error operand and an instruction marked as a syntax error.
    pub(super) fn instruction_line(&mut self, toks: &[Spanned], line_span: Span) {
        if self.microwin {
            let toks = self.microwin_line(toks);
            if !toks.is_empty() {
                self.gutta_instruction(&toks, line_span);
            }
        } else {
            self.gutta_instruction(toks, line_span);
        }
    }

    /// The Micro/WIN dialect's line rules, giving the tokens of the GUTTA instruction the
    /// line stands for (none: nothing to compile). `NOP 0` is GUTTA's `NOP`; `MEND`, the
    /// S7-200 main program's unconditional end, compiles to nothing as the last
    /// instruction of the `ORGANIZATION_BLOCK` (GUTTA's main program ends there anyway)
    /// and is E0115 anywhere else; an operand `NAME:SBRn` / `NAME:INTn` is its NAME.
    fn microwin_line(&mut self, toks: &[Spanned]) -> Vec<Spanned> {
        let text = self.text;
        let word = |i: usize| {
            toks.get(i)
                .filter(|t| t.0 == Tok::Word)
                .and_then(|t| text.get(t.1.range()))
        };
        if let Some((mend, reported)) = self.mend {
            if !reported {
                self.mend = Some((mend, true));
                self.report(
                    Diagnostic::new(
                        Code::MisplacedMend,
                        mend,
                        "`MEND` ends the main program, but code follows it",
                    )
                    .label("S7-200 would stop the scan here"),
                );
            }
        }
        if toks.len() == 1 && word(0).is_some_and(|w| w.eq_ignore_ascii_case("MEND")) {
            let in_main = self.program.units.last().is_some_and(|u| {
                self.slice(u.header.span)
                    .split_whitespace()
                    .next()
                    .is_some_and(|k| k.eq_ignore_ascii_case("ORGANIZATION_BLOCK"))
            });
            if in_main {
                self.mend = Some((toks[0].1, false));
            } else {
                self.report(
                    Diagnostic::new(
                        Code::MisplacedMend,
                        toks[0].1,
                        "`MEND` outside the main program",
                    )
                    .help("MEND ends the ORGANIZATION_BLOCK; a subroutine returns with RET, an interrupt routine with RETI"),
                );
            }
            return Vec::new();
        }
        if toks.len() == 2
            && word(0).is_some_and(|w| w.eq_ignore_ascii_case("NOP"))
            && text.get(toks[1].1.range()) == Some("0")
        {
            self.chum.truncate(1);
            return toks[..1].to_vec();
        }
        let mut keep = vec![true; toks.len()];
        for i in 1..toks.len() {
            if toks[i].0 == Tok::Colon
                && toks[i - 1].0 == Tok::Word
                && keep[i - 1]
                && word(i + 1).is_some_and(is_numbered_block)
            {
                keep[i] = false;
                keep[i + 1] = false;
            }
        }
        let kept: Vec<Spanned> = toks
            .iter()
            .zip(&keep)
            .filter(|(_, k)| **k)
            .map(|(t, _)| *t)
            .collect();
        if kept.len() != toks.len() {
            let mut index = 0;
            self.chum.retain(|_| {
                let k = keep.get(index).copied().unwrap_or(true);
                index += 1;
                k
            });
        }
        kept
    }

    /// A GUTTA instruction line.
    fn gutta_instruction(&mut self, toks: &[Spanned], line_span: Span) {
        let length = mnemonic_length(toks);
        if length == 0 {
            let found = toks[0].0.describe();
            self.syntax_error(
                (format!("expected an instruction, found {found}"), toks[0].1),
                "program code",
            );
            return;
        }
        let mnemonic = toks[0].1.to(toks[length - 1].1);
        let raw = self.raw_operands(toks, length, line_span);
        let raw_failed = raw.is_none();
        let operands: Vec<Operand> = match raw {
            Some(ops) => ops.into_iter().map(|o| self.convert_number(o)).collect(),
            None => vec![Operand {
                span: Span {
                    start: mnemonic.end,
                    end: line_span.end,
                },
                kind: OperandKind::Error,
            }],
        };
        let Some(net) = self.network_for_code(line_span) else {
            return;
        };
        let start = net.operands.len() as u32;
        net.operands.extend(operands);
        let end = net.operands.len() as u32;
        net.instructions.push(Instruction {
            mnemonic,
            operands: (start, end),
            span: line_span,
            syntax_error: raw_failed,
        });
    }

    /// The operands after the mnemonic's `length` tokens; None (reported) when they do
    /// not parse.
    fn raw_operands(
        &mut self,
        toks: &[Spanned],
        length: usize,
        line_span: Span,
    ) -> Option<Vec<RawOperand>> {
        // Token index in the filtered chumsky buffer equals the index in `toks` (same
        // filtering).
        if let Some(ops) = lines::simple_operand_list(&self.chum[length..]) {
            return Some(ops);
        }
        let eoi = self.eoi(line_span);
        match run_grammar!(self.chum[length..], eoi, lines::operand_list()) {
            Ok(ops) => Some(ops),
            Err(e) => {
                // `LDW >= T4, 2`: a compare mnemonic written with a space.
                let spaced_compare = length == 1
                    && toks[0].0 == Tok::Word
                    && toks
                        .get(1)
                        .is_some_and(|t| is_compare(t.0) && t.1.start > toks[0].1.end);
                if spaced_compare {
                    self.report_spaced_compare(toks);
                } else {
                    self.syntax_error(e, "operands");
                }
                None
            }
        }
    }

    /// `LDW >= T4, 2`: one E0102 that shows the mnemonic without the space.
    fn report_spaced_compare(&mut self, toks: &[Spanned]) {
        let word = self.slice(toks[0].1).to_ascii_uppercase();
        let op = self.slice(toks[1].1);
        let at = toks[0].1.to(toks[1].1);
        if !self.line_reported {
            self.line_reported = true;
            self.report(
                Diagnostic::new(
                    Code::Syntax,
                    at,
                    format!("compare instructions are one word: `{word}{op}`"),
                )
                .label("space inside the mnemonic")
                .help(format!("write `{word}{op}` without the space")),
            );
        }
    }

    /// The network code goes into: the current unit's last one, or a new implicit one
    /// (E0108, once per block) when the unit has none. None outside a unit.
    fn network_for_code(&mut self, line_span: Span) -> Option<&mut Network> {
        let unit = self.program.units.last_mut()?;
        if unit.networks.is_empty() {
            unit.networks.push(Network {
                number: None,
                header: None,
                span: line_span,
                title: None,
                instructions: Vec::new(),
                operands: Vec::new(),
            });
            if !self.reported_no_network {
                self.reported_no_network = true;
                self.diags.push(
                    Diagnostic::new(
                        Code::NoNetwork,
                        line_span,
                        "instruction before the first NETWORK",
                    )
                    .label("not inside a network")
                    .help("add a line `NETWORK 1` before the code"),
                );
            }
        }
        self.program
            .units
            .last_mut()
            .and_then(|u| u.networks.last_mut())
    }
}

/// How many tokens the mnemonic takes: adjacent tokens `[op] [word] [compare]`, e.g.
/// `=`, `+I`, `LDW>=`, `=I`. 0 when the line does not start with one.
fn mnemonic_length(toks: &[Spanned]) -> usize {
    let mut i = 0;
    if is_op(toks[0].0) {
        i = 1;
    }
    if i < toks.len() && toks[i].0 == Tok::Word && (i == 0 || toks[i].1.start == toks[i - 1].1.end)
    {
        i += 1;
        if i < toks.len() && is_compare(toks[i].0) && toks[i].1.start == toks[i - 1].1.end {
            i += 1;
        }
    }
    i
}

/// A token that may start a mnemonic (`=`, `+I`, `<>`).
/// `SBR0`, `INT12` (any case): the numbered part of a Micro/WIN `NAME:SBR0` operand.
fn is_numbered_block(word: &str) -> bool {
    let upper = word.to_ascii_uppercase();
    let digits = upper
        .strip_prefix("SBR")
        .or_else(|| upper.strip_prefix("INT"));
    digits.is_some_and(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()))
}

fn is_op(t: Tok) -> bool {
    matches!(
        t,
        Tok::Plus
            | Tok::Minus
            | Tok::Star
            | Tok::Slash
            | Tok::Eq
            | Tok::Ne
            | Tok::Lt
            | Tok::Le
            | Tok::Gt
            | Tok::Ge
    )
}

/// A comparison token (`=`, `<>`, `<`, `<=`, `>`, `>=`).
fn is_compare(t: Tok) -> bool {
    matches!(t, Tok::Eq | Tok::Ne | Tok::Lt | Tok::Le | Tok::Gt | Tok::Ge)
}
