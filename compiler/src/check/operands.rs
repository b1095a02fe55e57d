//! Operands against their instruction's operand spec, by the spec's kind: labels,
//! literals (`PORT`, `EVNT` narrowed to the target; a number an earlier stage renumbered
//! is checked as renumbered, `Conventions`), program units, and data operands
//! (variables in `memory.rs`, constants in `constants.rs`). The rules come from the
//! target's description through `gutta_catalog::rules`, the same the verifier applies.

use gutta_catalog::rules::{self, LiteralRefusal};
use gutta_catalog::{BlockKind, DataType, OperandKind as SpecKind, OperandSpec};

use super::{CheckedOperand, Checker};
use crate::diagnostics::{Code, Diagnostic, Suggestion};
use crate::source::Span;
use crate::syntax::ast::{Operand, OperandKind, Prefix};

/// `INT, DINT` for messages.
pub(super) fn types_text(types: &[DataType]) -> String {
    types
        .iter()
        .map(|t| t.keyword())
        .collect::<Vec<_>>()
        .join(", ")
}

impl Checker<'_> {
    /// Resolve one operand against its spec. `mnemonic` names the instruction in messages.
    pub(super) fn operand(
        &mut self,
        unit: usize,
        op: &Operand,
        spec: &OperandSpec,
        mnemonic: &str,
    ) -> Option<CheckedOperand> {
        match (spec.kind, op.kind) {
            (_, OperandKind::Error) => None,
            (SpecKind::Label, kind) => self.label_operand(op.span, kind, spec, mnemonic),
            (SpecKind::Literal, kind) => self.literal_operand(op.span, kind, spec, mnemonic),
            (
                SpecKind::Block,
                OperandKind::Name {
                    prefix: Prefix::None,
                    local: false,
                    name,
                },
            ) => self.block_operand(name, spec, mnemonic),
            (SpecKind::Block, _) => {
                let what = match rules::unit_operand_kind(spec) {
                    BlockKind::Interrupt => "an interrupt routine",
                    BlockKind::Subroutine => "a subroutine",
                };
                self.report(Diagnostic::new(
                    Code::WrongOperandKind,
                    op.span,
                    format!("{mnemonic} needs {what} name here"),
                ));
                None
            }
            (SpecKind::Data, OperandKind::Integer(v)) => {
                self.integer_constant(op.span, v, spec, mnemonic)
            }
            (SpecKind::Data, OperandKind::Real(v)) => {
                self.real_constant(op.span, v, spec, mnemonic)
            }
            (
                SpecKind::Data,
                OperandKind::Name {
                    prefix,
                    local,
                    name,
                },
            ) => self.variable_operand(unit, op.span, prefix, local, name, spec, mnemonic),
        }
    }

    /// `JMP 3`: a label number in the spec's range (0..255).
    fn label_operand(
        &mut self,
        span: Span,
        kind: OperandKind,
        spec: &OperandSpec,
        mnemonic: &str,
    ) -> Option<CheckedOperand> {
        let range = rules::label_range(spec);
        if let OperandKind::Integer(n) = kind {
            if range.contains(&n) {
                return u16::try_from(n).ok().map(CheckedOperand::Label);
            }
        }
        self.report(
            Diagnostic::new(
                Code::WrongOperandKind,
                span,
                format!(
                    "{mnemonic} needs a label number {}..{}",
                    range.start(),
                    range.end()
                ),
            )
            .help(format!(
                "for example `{mnemonic} 3` with `LBL 3` in the same block"
            )),
        );
        None
    }

    /// `LDS 1`, `EXCH MB0, 0`: a literal number in its range; `PORT` one of the
    /// target's serial ports, `EVNT` one of its events (in a Micro/WIN export, an
    /// S7-200 event number first translated to the target's: `events.rs`).
    fn literal_operand(
        &mut self,
        span: Span,
        kind: OperandKind,
        spec: &OperandSpec,
        mnemonic: &str,
    ) -> Option<CheckedOperand> {
        let OperandKind::Integer(n) = kind else {
            self.report(
                Diagnostic::new(
                    Code::ConstantNotAllowed,
                    span,
                    format!("{} of {mnemonic} must be a literal number", spec.name),
                )
                .label("a number is required here"),
            );
            return None;
        };
        // An event number an earlier stage translated (docs/microwin.md, "Interrupt events").
        let n = match self.conventions.renumbered_literals.get(&span) {
            Some(renumbered) => (*renumbered)?,
            None => n,
        };
        match rules::check_literal(spec, &self.target.memory, n) {
            Ok(()) => Some(CheckedOperand::Literal(n)),
            Err(LiteralRefusal::NoSuchEvent) => {
                let list: Vec<String> = self
                    .target
                    .memory
                    .events
                    .iter()
                    .map(|e| format!("{} {}", e.number, e.name))
                    .collect();
                self.report(
                    Diagnostic::new(
                        Code::ConstantOutOfRange,
                        span,
                        format!("{} raises no interrupt event {n}", self.target.name()),
                    )
                    .help(format!("events: {}", list.join(", "))),
                );
                None
            }
            Err(LiteralRefusal::OutOfRange { min, max }) => {
                self.report(
                    Diagnostic::new(
                        Code::ConstantOutOfRange,
                        span,
                        format!("{} of {mnemonic} must be {min}..{max}", spec.name),
                    )
                    .label(format!("{n} is out of range")),
                );
                None
            }
        }
    }

    /// The key (upper case) under which a block operand is looked up: a numbered
    /// interrupt `INTn` is INT(n + the interrupt operand offset, `Conventions`), any
    /// other text is as written.
    fn block_key(&self, text: &str) -> String {
        let key = text.to_ascii_uppercase();
        let offset = self.conventions.interrupt_operand_offset;
        if offset == 0 {
            return key;
        }
        match key.strip_prefix("INT").map(str::parse::<u32>) {
            Some(Ok(n)) => format!("INT{}", n + offset),
            _ => key,
        }
    }

    /// `CALL ADD3`, `ATCH TICK, 10`: a unit of the kind the spec names.
    fn block_operand(
        &mut self,
        name: Span,
        spec: &OperandSpec,
        mnemonic: &str,
    ) -> Option<CheckedOperand> {
        let text = self.slice(name);
        let key = self.block_key(text);
        if !self.unit_names.contains_key(&key)
            && (self.looks_like_address(text) || self.symbols.contains_key(&key))
        {
            self.report(
                Diagnostic::new(
                    Code::WrongOperandKind,
                    name,
                    format!("{mnemonic} needs a block name; `{text}` is a variable"),
                )
                .help(format!(
                    "for example `{mnemonic} ADD3` or `{mnemonic} SBR0`"
                )),
            );
            return None;
        }
        let Some(&u) = self.unit_names.get(&key) else {
            let d = Diagnostic::new(
                Code::UndefinedBlock,
                name,
                format!("no block named `{text}`"),
            );
            // A block of another file of an export (Conventions), else the closest name.
            let d = match self.conventions.block_elsewhere_help.get(&name) {
                Some(help) => d.help(help.clone()),
                None => {
                    let cands: Vec<String> = self.units.iter().map(|u| u.name.clone()).collect();
                    let hint = crate::suggest::closest(text, cands.iter().map(String::as_str))
                        .map(|s| Suggestion::new(name, s));
                    d.maybe_suggest(hint)
                }
            };
            self.report(d);
            return None;
        };
        let want = rules::unit_operand_kind(spec);
        let (kind, number, def) = (
            self.units[u].kind,
            self.units[u].number,
            self.units[u].definition,
        );
        self.reference(name, def);
        if !rules::unit_operand_accepts(spec, kind, number) {
            let msg = match want {
                BlockKind::Subroutine => {
                    format!("{mnemonic} calls subroutines; `{text}` is an interrupt routine")
                }
                BlockKind::Interrupt => {
                    format!("{mnemonic} takes an interrupt routine (not MAIN); `{text}` is not one")
                }
            };
            self.report(Diagnostic::new(Code::WrongOperandKind, name, msg));
            return None;
        }
        Some(CheckedOperand::Unit { kind, number })
    }
}
