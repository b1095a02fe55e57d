//! One instruction page: each record's opcode, where the instruction may stand, its
//! operands against their specs, labels and jumps, CALL arguments against the
//! callee's parameters, and FOR/NEXT pairing. Fills the `VerifiedUnit` the VM runs;
//! every rule is `gutta_catalog::rules`' or `operand.rs`'s.

use std::collections::BTreeMap;

use gutta_catalog::rules::{self, DataRules};
use gutta_catalog::{BlockKind, InstrId, Instruction, InstructionSet, LoopRole, Role, Target};

use super::error::{Location, VerifyError};
use super::operand::{Checked, OperandChecker, Site};
use super::{UnitRecord, VerifiedUnit};
use crate::{
    decode_instructions, ArgumentPage, LocalSection, PackedOperand, PageId, Record, UnitRef,
};

/// Labels of one page: defined (`LBL`, with the offset of the first) and jumped to.
#[derive(Default)]
struct Labels {
    jumps: Vec<(Location, u16)>,
    first: BTreeMap<u16, usize>,
}

/// Check one instruction page and fill `unit` with its records; returns the CALLs
/// (callee page and where).
pub(super) fn verify_code(
    id: PageId,
    bytes: &[u8],
    checker: &OperandChecker<'_>,
    arguments: &BTreeMap<u8, ArgumentPage>,
    unit: &mut VerifiedUnit,
) -> Result<Vec<(u8, Location)>, VerifyError> {
    let target = checker.target;
    let records =
        decode_instructions(bytes).map_err(|error| VerifyError::Decode { page: id, error })?;
    let mut labels = Labels::default();
    let mut calls = Vec::new();
    let mut loops = LoopPairing::new(target);
    for (offset, record) in records {
        let at = Location { page: id, offset };
        let (opcode, operands) = match record {
            Record::Network(number) => {
                unit.records.push(UnitRecord::Network { offset, number });
                continue;
            }
            Record::Instruction { opcode, operands } => (opcode, operands),
        };
        let (instr_id, ins) = instruction(target, opcode, at)?;
        placement(ins, unit, at)?;
        let code = InstructionCode {
            page: id,
            offset,
            ins,
            operands: &operands,
        };
        code.count_declared()?;
        let callee = code.declared_operands(checker, &mut labels, unit)?;
        if ins.call_arguments {
            code.call_arguments(checker, arguments, callee)?;
            if let Some((_, page)) = callee {
                calls.push((page, at));
            }
        }
        loops.record(instr_id, at, unit)?;
        unit.records.push(UnitRecord::Instruction {
            offset,
            id: instr_id,
            operands,
        });
    }
    loops.finish()?;
    for (at, label) in labels.jumps {
        if !labels.first.contains_key(&label) {
            return Err(VerifyError::JumpWithoutLabel { at, label });
        }
    }
    Ok(calls)
}

/// The instruction an opcode stands for in the target's set.
fn instruction(
    target: &Target,
    opcode: u16,
    at: Location,
) -> Result<(InstrId, &Instruction), VerifyError> {
    target
        .instructions
        .by_opcode(opcode)
        .and_then(|id| {
            let ins = target.instructions.instructions.get(usize::from(id.0))?;
            Some((id, ins))
        })
        .ok_or(VerifyError::UnknownOpcode { at, opcode })
}

/// The instruction may stand in this unit (`Units` of ManagerFun.xml).
fn placement(ins: &Instruction, unit: &VerifiedUnit, at: Location) -> Result<(), VerifyError> {
    if rules::placement_allowed(ins.units, unit.kind, u32::from(unit.number)) {
        return Ok(());
    }
    let here = UnitRef {
        kind: unit.kind,
        number: u16::from(unit.number),
    };
    Err(VerifyError::NotInUnit {
        at,
        mnemonic: ins.mnemonic.clone(),
        unit: here.to_string(),
        allowed: ins.units.describe(),
    })
}

/// One instruction record being checked.
struct InstructionCode<'a> {
    page: PageId,
    /// Byte offset of the record in the page.
    offset: usize,
    ins: &'a Instruction,
    operands: &'a [PackedOperand],
}

impl InstructionCode<'_> {
    fn at(&self) -> Location {
        Location {
            page: self.page,
            offset: self.offset,
        }
    }

    /// Where operand `i` is: after the opcode (2 bytes) and the count (1).
    fn operand_at(&self, i: usize) -> Location {
        Location {
            page: self.page,
            offset: self.offset + 3 + 4 * i,
        }
    }

    /// The record has its declared operands (and, for CALL, perhaps arguments).
    fn count_declared(&self) -> Result<(), VerifyError> {
        let (found, declared) = (self.operands.len(), self.ins.operands.len());
        if found < declared || (!self.ins.call_arguments && found != declared) {
            return Err(self.count_error(declared));
        }
        Ok(())
    }

    fn count_error(&self, expected: usize) -> VerifyError {
        VerifyError::OperandCount {
            at: self.at(),
            mnemonic: self.ins.mnemonic.clone(),
            expected,
            found: self.operands.len(),
        }
    }

    /// The declared operands against their specs; labels defined and jumped to.
    /// Returns the subroutine a CALL names, with its page.
    fn declared_operands(
        &self,
        checker: &OperandChecker<'_>,
        labels: &mut Labels,
        unit: &mut VerifiedUnit,
    ) -> Result<Option<(UnitRef, u8)>, VerifyError> {
        let ins = self.ins;
        let mut callee = None;
        for (i, (op, spec)) in self.operands.iter().zip(&ins.operands).enumerate() {
            let site = Site::Operand {
                mnemonic: &ins.mnemonic,
                name: &spec.name,
                index: i,
            };
            match checker.check_spec(self.operand_at(i), site, *op, spec)? {
                Checked::Label(label) if ins.defines_label => {
                    if let Some(&first) = labels.first.get(&label) {
                        return Err(VerifyError::DuplicateLabel {
                            at: self.at(),
                            label,
                            first,
                        });
                    }
                    labels.first.insert(label, self.offset);
                    unit.labels.insert(label, unit.records.len());
                }
                Checked::Label(label) => labels.jumps.push((self.at(), label)),
                Checked::Unit(called, page)
                    if spec.block == Some(BlockKind::Subroutine) && callee.is_none() =>
                {
                    callee = Some((called, page));
                }
                _ => {}
            }
        }
        Ok(callee)
    }

    /// CALL's arguments against the callee's VAR_INPUT, VAR_IN_OUT and VAR_OUTPUT,
    /// each by `gutta_catalog::rules::parameter_spec`, as the checker does.
    fn call_arguments(
        &self,
        checker: &OperandChecker<'_>,
        arguments: &BTreeMap<u8, ArgumentPage>,
        callee: Option<(UnitRef, u8)>,
    ) -> Result<(), VerifyError> {
        let params: Vec<(usize, &crate::LocalEntry)> = callee
            .and_then(|(_, page)| arguments.get(&page))
            .map(|args| {
                args.locals
                    .iter()
                    .enumerate()
                    .filter(|(_, l)| l.section != LocalSection::Temp)
                    .collect()
            })
            .unwrap_or_default();
        let declared = self.ins.operands.len();
        if self.operands.len() != declared + params.len() {
            return Err(self.count_error(declared + params.len()));
        }
        let Some((callee, _)) = callee else {
            return Ok(());
        };
        let args = self.operands.iter().enumerate().skip(declared);
        for ((i, op), (local, entry)) in args.zip(params) {
            let role = match entry.section {
                LocalSection::Input => Role::In,
                LocalSection::InOut => Role::InOut,
                _ => Role::Out,
            };
            let spec = rules::parameter_spec(String::new(), role, entry.data_type);
            let site = Site::Argument {
                callee,
                index: i,
                local,
            };
            checker.check_data(self.operand_at(i), site, *op, DataRules::from_spec(&spec))?;
        }
        Ok(())
    }
}

/// FOR/NEXT pairing within one instruction page: every NEXT closes the innermost open
/// FOR, and no FOR is left open at the end. The pairs go to `VerifiedUnit::loops`, so the
/// VM never pairs them itself.
struct LoopPairing<'t> {
    set: &'t InstructionSet,
    for_id: Option<InstrId>,
    next_id: Option<InstrId>,
    /// Open FORs, innermost last: where, and their record index.
    open: Vec<(Location, usize)>,
}

impl<'t> LoopPairing<'t> {
    fn new(target: &'t Target) -> LoopPairing<'t> {
        LoopPairing {
            set: &target.instructions,
            for_id: target.instructions.by_loop_role(LoopRole::Start),
            next_id: target.instructions.by_loop_role(LoopRole::End),
            open: Vec::new(),
        }
    }

    /// Account for the instruction about to become record `unit.records.len()`.
    fn record(
        &mut self,
        id: InstrId,
        at: Location,
        unit: &mut VerifiedUnit,
    ) -> Result<(), VerifyError> {
        let index = unit.records.len();
        if Some(id) == self.for_id {
            self.open.push((at, index));
            if !rules::for_depth_allowed(self.set, self.open.len()) {
                return Err(VerifyError::LoopDepth {
                    at,
                    depth: self.open.len(),
                    max: self.set.for_depth,
                });
            }
        } else if Some(id) == self.next_id {
            let Some((_, for_index)) = self.open.pop() else {
                return Err(VerifyError::UnmatchedLoop {
                    at,
                    mnemonic: self.set.get(id).mnemonic.clone(),
                    role: LoopRole::End,
                });
            };
            unit.loops.insert(for_index, index);
        }
        Ok(())
    }

    fn finish(self) -> Result<(), VerifyError> {
        match self.open.first() {
            Some(&(at, _)) => Err(VerifyError::UnmatchedLoop {
                at,
                mnemonic: self
                    .for_id
                    .map_or_else(String::new, |id| self.set.get(id).mnemonic.clone()),
                role: LoopRole::Start,
            }),
            None => Ok(()),
        }
    }
}
