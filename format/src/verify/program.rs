//! Program units: argument pages (header, locals) and instruction pages (opcodes,
//! operands, CALL arguments, labels), then the call graph (no recursion, CallDepth).
//! Works on decoded pages; every index into them comes from `get` or a zip.

use std::collections::{BTreeMap, BTreeSet};

use gutta_catalog::{AreaKind, BlockKind, DataType, InstrId, OperandKind, Target, Width};

use super::error::{unit_name, Location, VerifyError};
use super::operand::{AreaRule, DataRules, OperandChecker, Site};
use super::{UnitRecord, VerifiedUnit};
use crate::{decode_instructions, ArgumentPage, Image, LocalSection, PageId, PageKind, Record};

/// The unit a program page number stands for on the target.
pub(super) fn unit_of_page(target: &Target, page: u8) -> Option<(BlockKind, u8)> {
    let int = target.plc.program_block_page_int_size;
    let sbr = target.plc.program_block_page_sbr_size;
    let page32 = u32::from(page);
    if page32 < int {
        Some((BlockKind::Interrupt, page))
    } else if page32 < int.saturating_add(sbr) {
        u8::try_from(page32 - int)
            .ok()
            .map(|n| (BlockKind::Subroutine, n))
    } else {
        None
    }
}

/// Decode and check every argument page, then every instruction page.
pub(super) fn verify_units(
    image: &Image,
    target: &Target,
) -> Result<BTreeMap<u8, VerifiedUnit>, VerifyError> {
    let mut arguments = BTreeMap::new();
    for (id, bytes) in image.pages.range(kind_range(PageKind::Argument)) {
        let page = verify_argument_page(*id, bytes, target)?;
        arguments.insert(id.number, page);
    }
    let unit_pages: BTreeSet<u8> = arguments.keys().copied().collect();
    let checker = OperandChecker {
        target,
        unit_pages: &unit_pages,
    };
    let mut units = BTreeMap::new();
    let mut calls: BTreeMap<u8, Vec<(u8, Location)>> = BTreeMap::new();
    for (id, bytes) in image.pages.range(kind_range(PageKind::Instruction)) {
        let (kind, number, locals) =
            match (unit_of_page(target, id.number), arguments.get(&id.number)) {
                (Some((kind, number)), Some(args)) => (kind, number, args.locals.clone()),
                _ => continue, // Excluded by the page checks before.
            };
        let mut unit = VerifiedUnit {
            page: id.number,
            kind,
            number,
            locals,
            records: Vec::new(),
            labels: BTreeMap::new(),
            loops: BTreeMap::new(),
        };
        let edges = verify_code(*id, bytes, &checker, &arguments, &mut unit)?;
        calls.insert(id.number, edges);
        units.insert(id.number, unit);
    }
    verify_call_graph(target, &calls)?;
    Ok(units)
}

/// All pages of one kind in an image's page map.
pub(super) fn kind_range(kind: PageKind) -> std::ops::RangeInclusive<PageId> {
    PageId::new(kind, 0)..=PageId::new(kind, u8::MAX)
}

fn verify_argument_page(
    id: PageId,
    bytes: &[u8],
    target: &Target,
) -> Result<ArgumentPage, VerifyError> {
    let Some((kind, number)) = unit_of_page(target, id.number) else {
        return Err(VerifyError::PageNotOnTarget {
            page: id,
            count: target.plc.program_block_page_int_size + target.plc.program_block_page_sbr_size,
            limit: "ProgramBlockPageIntSize + ProgramBlockPageSbrSize",
        });
    };
    let page =
        ArgumentPage::decode(bytes).map_err(|error| VerifyError::Decode { page: id, error })?;
    let reserved =
        std::iter::once(3).chain((0..page.locals.len()).flat_map(|i| [10 + 8 * i, 11 + 8 * i]));
    for offset in reserved {
        match bytes.get(offset) {
            Some(&value) if value != 0 => {
                return Err(VerifyError::ReservedNotZero {
                    at: Location { page: id, offset },
                    value,
                })
            }
            _ => {}
        }
    }
    let found = if page.subroutine {
        BlockKind::Subroutine
    } else {
        BlockKind::Interrupt
    };
    if found != kind || page.unit_number != number {
        return Err(VerifyError::UnitHeader {
            at: Location {
                page: id,
                offset: if found != kind { 0 } else { 1 },
            },
            expected: (kind, number),
            found: (found, page.unit_number),
        });
    }
    let (max, limit) = match kind {
        BlockKind::Interrupt => (
            target.plc.program_block_page_arg_int_size,
            "ProgramBlockPageArgIntSize",
        ),
        BlockKind::Subroutine => (
            target.plc.program_block_page_arg_sbr_size,
            "ProgramBlockPageArgSbrSize",
        ),
    };
    if page.locals.len() as u64 > u64::from(max) {
        return Err(VerifyError::SizeLimit {
            page: Some(id),
            what: "locals",
            size: page.locals.len() as u64,
            limit: limit.to_string(),
            max: u64::from(max),
        });
    }
    let no_units = BTreeSet::new();
    let checker = OperandChecker {
        target,
        unit_pages: &no_units,
    };
    let mut previous = LocalSection::Input;
    for (i, local) in page.locals.iter().enumerate() {
        let at = |offset| Location {
            page: id,
            offset: 4 + 8 * i + offset,
        };
        if kind == BlockKind::Interrupt && local.section != LocalSection::Temp {
            return Err(VerifyError::InterruptParameter {
                at: at(4),
                local: i,
            });
        }
        if (local.section as u8) < previous as u8 {
            return Err(VerifyError::LocalOrder {
                at: at(4),
                local: i,
            });
        }
        previous = local.section;
        let rules = DataRules {
            width: local.data_type.width(),
            writes: false,
            constant: false,
            pointer: false,
            address_of: false,
            areas: AreaRule::Kinds(&[AreaKind::Local]),
        };
        checker.check_data(at(0), Site::Local { index: i }, local.operand, rules)?;
    }
    Ok(page)
}

/// Check one instruction page and fill `unit` with its records; returns the CALLs
/// (callee page and where).
fn verify_code(
    id: PageId,
    bytes: &[u8],
    checker: &OperandChecker<'_>,
    arguments: &BTreeMap<u8, ArgumentPage>,
    unit: &mut VerifiedUnit,
) -> Result<Vec<(u8, Location)>, VerifyError> {
    let target = checker.target;
    let records =
        decode_instructions(bytes).map_err(|error| VerifyError::Decode { page: id, error })?;
    let mut jumps: Vec<(Location, u16)> = Vec::new();
    let mut first_label: BTreeMap<u16, usize> = BTreeMap::new();
    let mut calls = Vec::new();
    let mut loops = LoopPairing::new(target);
    let unit_text = unit_name(unit.kind, u16::from(unit.number));
    for (offset, record) in records {
        let at = Location { page: id, offset };
        let (opcode, operands) = match record {
            Record::Network(number) => {
                unit.records.push(UnitRecord::Network { offset, number });
                continue;
            }
            Record::Instruction { opcode, operands } => (opcode, operands),
        };
        let Some(instr_id) = target.instructions.by_opcode(opcode) else {
            return Err(VerifyError::UnknownOpcode { at, opcode });
        };
        let Some(ins) = target
            .instructions
            .instructions
            .get(usize::from(instr_id.0))
        else {
            return Err(VerifyError::UnknownOpcode { at, opcode });
        };
        let allowed = match unit.kind {
            BlockKind::Interrupt if unit.number == 0 => ins.units.main,
            BlockKind::Interrupt => ins.units.interrupt,
            BlockKind::Subroutine => ins.units.subroutine,
        };
        if !allowed {
            return Err(VerifyError::NotInUnit {
                at,
                mnemonic: ins.mnemonic.clone(),
                unit: unit_text.clone(),
                allowed: ins.units.describe(),
            });
        }
        let declared = ins.operands.len();
        let count_error = |expected| VerifyError::OperandCount {
            at,
            mnemonic: ins.mnemonic.clone(),
            expected,
            found: operands.len(),
        };
        if operands.len() < declared || (!ins.call_arguments && operands.len() != declared) {
            return Err(count_error(declared));
        }
        let operand_at = |i: usize| Location {
            page: id,
            offset: offset + 3 + 4 * i,
        };
        let mut callee = None;
        for (i, (op, spec)) in operands.iter().zip(&ins.operands).enumerate() {
            let site = Site::Operand {
                mnemonic: &ins.mnemonic,
                name: &spec.name,
                index: i,
            };
            let unit_page = checker.check_spec(operand_at(i), site, *op, spec)?;
            if spec.kind == OperandKind::Label {
                let label = op.offset();
                if ins.mnemonic == "LBL" {
                    if let Some(first) = first_label.get(&label) {
                        return Err(VerifyError::DuplicateLabel {
                            at,
                            label,
                            first: *first,
                        });
                    }
                    first_label.insert(label, offset);
                    unit.labels.insert(label, unit.records.len());
                } else {
                    jumps.push((at, label));
                }
            }
            if spec.block == Some(BlockKind::Subroutine) && callee.is_none() {
                callee = unit_page;
            }
        }
        if ins.call_arguments {
            let params: Vec<(usize, DataType, LocalSection)> = callee
                .and_then(|page| arguments.get(&page))
                .map(|args| {
                    args.locals
                        .iter()
                        .enumerate()
                        .filter(|(_, l)| l.section != LocalSection::Temp)
                        .map(|(i, l)| (i, l.data_type, l.section))
                        .collect()
                })
                .unwrap_or_default();
            let expected = declared + params.len();
            if operands.len() != expected {
                return Err(count_error(expected));
            }
            let callee_unit = callee
                .and_then(|page| unit_of_page(target, page))
                .unwrap_or((BlockKind::Subroutine, 0));
            let args = operands.iter().enumerate().skip(declared);
            for ((i, op), (local, ty, section)) in args.zip(params) {
                let input = section == LocalSection::Input;
                let rules = DataRules {
                    width: ty.width(),
                    writes: !input,
                    constant: input,
                    pointer: ty.width() != Width::Bit,
                    address_of: matches!(ty, DataType::Dword | DataType::Udint),
                    areas: AreaRule::Any,
                };
                let site = Site::Argument {
                    callee: callee_unit,
                    index: i,
                    local,
                };
                checker.check_data(operand_at(i), site, *op, rules)?;
            }
            if let Some(page) = callee {
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
    for (at, label) in jumps {
        if !first_label.contains_key(&label) {
            return Err(VerifyError::JumpWithoutLabel { at, label });
        }
    }
    Ok(calls)
}

/// FOR/NEXT pairing within one instruction page: every NEXT closes the innermost open
/// FOR, and no FOR is left open at the end. The pairs go to `VerifiedUnit::loops`, so the
/// VM never pairs them itself.
struct LoopPairing {
    for_id: Option<InstrId>,
    next_id: Option<InstrId>,
    /// Open FORs, innermost last: where, and their record index.
    open: Vec<(Location, usize)>,
}

impl LoopPairing {
    fn new(target: &Target) -> LoopPairing {
        LoopPairing {
            for_id: target.instructions.lookup("FOR"),
            next_id: target.instructions.lookup("NEXT"),
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
        } else if Some(id) == self.next_id {
            let Some((_, for_index)) = self.open.pop() else {
                return Err(VerifyError::UnmatchedLoop {
                    at,
                    mnemonic: "NEXT".to_string(),
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
                mnemonic: "FOR".to_string(),
            }),
            None => Ok(()),
        }
    }
}

/// No unit reaches itself through CALLs; from every interrupt routine, calls nest at
/// most `CallDepth` deep.
fn verify_call_graph(
    target: &Target,
    calls: &BTreeMap<u8, Vec<(u8, Location)>>,
) -> Result<(), VerifyError> {
    const NEW: u8 = 0;
    const ON_PATH: u8 = 1;
    const DONE: u8 = 2;
    let mut state = [NEW; 256];
    let mut depth = [0usize; 256];
    let edges = |u: u8| calls.get(&u).map(Vec::as_slice).unwrap_or(&[]);
    for &start in calls.keys() {
        if state[usize::from(start)] != NEW {
            continue;
        }
        state[usize::from(start)] = ON_PATH;
        let mut stack: Vec<(u8, usize)> = vec![(start, 0)];
        while let Some(top) = stack.last_mut() {
            let (node, next) = *top;
            if let Some(&(callee, at)) = edges(node).get(next) {
                top.1 += 1;
                match state[usize::from(callee)] {
                    ON_PATH => return Err(VerifyError::CallCycle { at, callee }),
                    NEW => {
                        state[usize::from(callee)] = ON_PATH;
                        stack.push((callee, 0));
                    }
                    _ => {}
                }
            } else {
                depth[usize::from(node)] = edges(node)
                    .iter()
                    .map(|(callee, _)| depth[usize::from(*callee)].saturating_add(1))
                    .max()
                    .unwrap_or(0);
                state[usize::from(node)] = DONE;
                stack.pop();
            }
        }
    }
    let max = usize::from(target.instructions.call_depth);
    for &page in calls.keys() {
        let d = depth[usize::from(page)];
        if matches!(unit_of_page(target, page), Some((BlockKind::Interrupt, _))) && d > max {
            return Err(VerifyError::CallDepth {
                page: PageId::new(PageKind::Instruction, page),
                depth: d,
                max,
            });
        }
    }
    Ok(())
}
