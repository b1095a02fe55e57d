//! `AENO` lines, where an earlier stage asks for them (`Conventions::aeno`: in a
//! Micro/WIN export). `AENO` is no instruction of GUTTA's: it ANDs the top of the logic
//! stack with the previous box's ENO, and what that ENO is on GUTTA comes with the
//! conventions as plain data per instruction ([`AenoMeaning`], built by the dialect's
//! stage from `gutta_catalog::s7200_eno`). The checker turns the line into `AN` of each
//! flag the box sets on its error (or into nothing), with the line's span, so the
//! logic stack analysis and the source map stay true; where the ENO cannot be known it
//! reports E0225 with the reason the meaning carries.

use gutta_catalog::{Address, InstrId, Join, LadderClass, Width};

use super::{CheckedInstruction, CheckedOperand, Checker, Use};
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
use crate::syntax::ast::{Instruction, Operand};

/// What `AENO` after an instruction compiles to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum AenoMeaning {
    /// `AN` of each flag (the box sets one of them when it fails, and clears them when
    /// it runs without error); `what` names the error for the listing's hover.
    Flags { flags: Vec<Address>, what: String },
    /// Nothing: the box cannot fail, so its ENO is its power flow.
    Nothing,
    /// GUTTA cannot know the ENO; the reason, as the end of E0225's sentence
    /// ("`AENO` follows `SHRB`, REASON").
    Unknown(String),
}

/// The line before an `AENO` in its network.
#[derive(Debug, Clone, Copy)]
pub(super) enum PreviousLine {
    /// An instruction of the target.
    Known(InstrId),
    /// A line that named no instruction of the target (reported already).
    Unknown(Span),
}

impl Checker<'_> {
    /// Whether the line is an `AENO` the conventions give a meaning.
    pub(super) fn is_aeno_line(&self, ins: &Instruction) -> bool {
        self.conventions.aeno.is_some()
            && self.slice(ins.mnemonic).eq_ignore_ascii_case("AENO")
            && self.target.instructions.lookup("AENO").is_none()
    }

    /// The instructions an `AENO` line compiles to (`depth`: the logic stack levels
    /// before it, when known), or E0225 and none.
    pub(super) fn aeno_line(
        &mut self,
        ins: &Instruction,
        ops: &[Operand],
        previous: Option<PreviousLine>,
        depth: Option<i32>,
    ) -> Vec<CheckedInstruction> {
        let at = ins.span;
        let help = "read the flag the box sets yourself (`AN SM1.1` after `+I`), or end the chain of boxes before this line";
        if let Some(first) = ops.first() {
            let d = Diagnostic::new(Code::S7200Aeno, first.span, "`AENO` takes no operand")
                .label("AENO ANDs the previous box's ENO");
            self.report(d);
            return Vec::new();
        }
        let reason = match previous {
            None => Some("`AENO` at the start of a network has no box before it".to_string()),
            Some(_) if depth == Some(0) => {
                Some("`AENO` needs power flow, but nothing is loaded in this network".to_string())
            }
            Some(PreviousLine::Unknown(span)) => Some(format!(
                "`AENO` follows `{}`, which {} does not have, so its ENO is unknown",
                self.slice(span),
                self.target.name()
            )),
            Some(PreviousLine::Known(id)) => {
                let mnemonic = self.target.instructions.get(id).mnemonic.clone();
                match self.conventions.aeno.as_ref().and_then(|m| m.get(&id)) {
                    Some(AenoMeaning::Nothing) => return Vec::new(),
                    Some(AenoMeaning::Flags { flags, .. }) => {
                        return self.and_not_flags(flags.clone(), at);
                    }
                    Some(AenoMeaning::Unknown(why)) => {
                        Some(format!("`AENO` follows `{mnemonic}`, {why}"))
                    }
                    None => Some(format!(
                        "`AENO` follows `{mnemonic}`, whose S7-200 ENO GUTTA does not know"
                    )),
                }
            }
        };
        if let Some(message) = reason {
            self.report(
                Diagnostic::new(Code::S7200Aeno, at, message)
                    .label("the previous box's ENO is unknown here")
                    .help(help),
            );
        }
        Vec::new()
    }

    /// `AN flag` for each flag, at the `AENO` line.
    fn and_not_flags(&mut self, flags: Vec<Address>, at: Span) -> Vec<CheckedInstruction> {
        let Some(an) = self
            .target
            .instructions
            .plain(LadderClass::ClosedContact, Some(Join::And))
        else {
            self.report(Diagnostic::new(
                Code::S7200Aeno,
                at,
                format!(
                    "{} has no `AN`, which `AENO` compiles to",
                    self.target.name()
                ),
            ));
            return Vec::new();
        };
        flags
            .into_iter()
            .map(|address| CheckedInstruction {
                id: an,
                operands: vec![CheckedOperand::Memory {
                    address,
                    use_: Use::Value,
                    width: Width::Bit,
                }],
                span: at,
            })
            .collect()
    }
}
