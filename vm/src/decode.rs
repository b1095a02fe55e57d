//! Pre-decoding: at load, every record of every unit becomes an `Op`. The frequent
//! instructions with plain operands (bit logic on a variable, moves, integer add and
//! subtract, compares) become operations that name their bytes by index into the flat
//! memory; everything else is `Generic` and runs its semantic from `ops/` with the
//! record's packed operands; runs of bit logic are then fused (`fuse.rs`). Op `k` of a
//! unit is record `k`, so labels, FOR/NEXT pairs and debugger positions use one
//! numbering. docs/vm.md, "Speed", says why.

use std::collections::BTreeMap;
use std::sync::Arc;

use gutta_catalog::{Address, Flow, InstrId, Target, Width};
use gutta_format::{LocalEntry, LocalSection, Operand, PackedOperand, UnitRecord, VerifiedUnit};

use crate::fuse::build;
use crate::memory::Memory;
use crate::op::{Arith, Bit, ChainStep, Combine, Op, Rel};

/// One argument of a planned CALL: the caller's variable and the callee's parameter in
/// L, as flat memory indices.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct ArgPlan {
    pub var: u32,
    pub param: u32,
    pub width: u8,
    /// VAR_INPUT or VAR_IN_OUT: copied in.
    pub input: bool,
    /// VAR_OUTPUT or VAR_IN_OUT: copied back.
    pub output: bool,
}

/// A CALL whose arguments are all plain variables of their parameters' widths.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct CallPlan {
    pub callee: u8,
    pub args: Vec<ArgPlan>,
}

/// The plan of a CALL, if its arguments allow one.
fn plan_call(
    memory: &Memory,
    target: &Target,
    operands: &[PackedOperand],
    params: &dyn Fn(u8) -> Option<Vec<LocalEntry>>,
) -> Option<CallPlan> {
    let Ok(Operand::Unit(unit)) = operands.first()?.decode() else {
        return None;
    };
    let callee = unit.page(&target.plc)?;
    let params = params(callee)?;
    if operands.len() != params.len() + 1 {
        return None;
    }
    let mut args = Vec::with_capacity(params.len());
    for (p, &op) in params.iter().zip(&operands[1..]) {
        let Ok(Operand::Value(declared)) = p.operand.decode() else {
            return None;
        };
        let width = declared.width;
        if width == Width::Bit {
            return None;
        }
        let param = plain(memory, p.operand, width)?;
        let var = plain(memory, op, width)?;
        args.push(ArgPlan {
            var,
            param,
            width: width.bytes() as u8,
            input: p.section != LocalSection::Output,
            output: p.section != LocalSection::Input,
        });
    }
    Some(CallPlan { callee, args })
}

/// An instruction record, compactly: its operands are `Unit::operands[first..first + len]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Record {
    pub id: InstrId,
    /// Byte offset in the instruction page (for fault messages).
    pub offset: u32,
    pub first: u32,
    pub len: u16,
}

/// A unit ready to run. Everything the interpreter needs, so the VM keeps no other copy
/// of the code.
#[derive(Debug, Clone)]
pub(crate) struct Unit {
    pub page: u8,
    /// What the fast path runs (fused, breakpoint patched in); see `build`.
    pub ops: Vec<Op>,
    /// One operation per record, unfused: what single steps and the slow path run.
    pub plain: Vec<Op>,
    /// Steps of the fused chains in `ops`.
    pub chain: Vec<ChainStep>,
    /// Per record: (network number, step within the network); networks have step 0xFFFF.
    pub positions: Vec<(u16, u16)>,
    /// Per record: the instruction (None for network records).
    pub records: Vec<Option<Record>>,
    pub operands: Vec<PackedOperand>,
    /// Label number -> record index of its LBL.
    pub labels: BTreeMap<u16, usize>,
    /// FOR record index -> record index of its NEXT (paired by the verifier).
    pub loops: BTreeMap<usize, usize>,
    /// The parameters a CALL passes (VAR_INPUT, VAR_IN_OUT, VAR_OUTPUT), in order.
    pub params: Vec<LocalEntry>,
    /// Plans of the unit's planned CALLs.
    pub calls: Vec<CallPlan>,
    /// The instruction set, for mnemonics.
    pub target: Arc<Target>,
}

impl Unit {
    /// Record `pc` if it is an instruction: its id, page offset and operands.
    pub fn instruction(&self, pc: usize) -> Option<(InstrId, usize, &[PackedOperand])> {
        let r = (*self.records.get(pc)?)?;
        let ops = self
            .operands
            .get(r.first as usize..r.first as usize + r.len as usize)?;
        Some((r.id, r.offset as usize, ops))
    }

    pub fn mnemonic(&self, id: InstrId) -> &str {
        &self.target.instructions.get(id).mnemonic
    }
}

/// A plain variable operand (USE 0) of the given width.
fn variable(op: PackedOperand, width: Width) -> Option<Address> {
    match op.decode() {
        Ok(Operand::Value(a)) if a.width == width => Some(a),
        _ => None,
    }
}

/// A plain variable operand of the given width, as a flat memory index.
fn plain(memory: &Memory, op: PackedOperand, width: Width) -> Option<u32> {
    let a = variable(op, width)?;
    memory.index_of(a).and_then(|i| u32::try_from(i).ok())
}

fn plain_bit(memory: &Memory, op: PackedOperand) -> Option<Bit> {
    let a = variable(op, Width::Bit)?;
    let at = memory.index_of(a).and_then(|i| u32::try_from(i).ok())?;
    Some(Bit {
        at,
        mask: 1 << a.bit,
    })
}

fn width_of(bytes: u8) -> Width {
    match bytes {
        1 => Width::Byte,
        2 => Width::Word,
        _ => Width::Dword,
    }
}

fn decode_compare(m: &str) -> Option<(Combine, char, Rel)> {
    let (combine, rest) = if let Some(r) = m.strip_prefix("LD") {
        (Combine::Load, r)
    } else if let Some(r) = m.strip_prefix('A') {
        (Combine::And, r)
    } else {
        (Combine::Or, m.strip_prefix('O')?)
    };
    let ty = rest.chars().next()?;
    let rel = match rest.get(1..)? {
        "=" => Rel::Eq,
        "<>" => Rel::Ne,
        "<" => Rel::Lt,
        "<=" => Rel::Le,
        ">" => Rel::Gt,
        ">=" => Rel::Ge,
        _ => return None,
    };
    Some((combine, ty, rel))
}

/// The fast form of an instruction, if it has one.
fn fast(memory: &Memory, mnemonic: &str, ops: &[PackedOperand]) -> Option<Op> {
    let bit = |k: usize| ops.get(k).and_then(|&o| plain_bit(memory, o));
    let var = |k: usize, w: u8| ops.get(k).and_then(|&o| plain(memory, o, width_of(w)));
    Some(match mnemonic {
        "LD" | "LDI" => Op::Ld(bit(0)?),
        "LDN" | "LDNI" => Op::Ldn(bit(0)?),
        "A" | "AI" => Op::A(bit(0)?),
        "AN" | "ANI" => Op::An(bit(0)?),
        "O" | "OI" => Op::O(bit(0)?),
        "ON" | "ONI" => Op::On(bit(0)?),
        "=" | "=I" => Op::Assign(bit(0)?),
        "NOT" => Op::Not,
        "ALD" => Op::Ald,
        "OLD" => Op::Old,
        "LPS" => Op::Lps,
        "LRD" => Op::Lrd,
        "LPP" => Op::Lpp,
        "MOVB" | "MOVW" | "MOVD" | "MOVR" => {
            let width = match mnemonic {
                "MOVB" => 1,
                "MOVW" => 2,
                _ => 4,
            };
            Op::Move {
                src: var(0, width)?,
                dst: var(1, width)?,
                width,
            }
        }
        "+I" | "-I" | "*I" | "+D" | "-D" | "*D" => {
            let width = if mnemonic.ends_with('I') { 2 } else { 4 };
            Op::Math {
                op: match mnemonic.as_bytes()[0] {
                    b'+' => Arith::Add,
                    b'-' => Arith::Sub,
                    _ => Arith::Mul,
                },
                src: var(0, width)?,
                dst: var(1, width)?,
                width,
            }
        }
        _ => {
            let (combine, ty, rel) = decode_compare(mnemonic)?;
            let width = match ty {
                'B' => 1,
                'W' => 2,
                'D' => 4,
                _ => return None,
            };
            Op::Compare {
                combine,
                rel,
                a: var(0, width)?,
                b: var(1, width)?,
                width,
            }
        }
    })
}

/// Decode a unit. `fast_ops` false keeps every instruction `Generic` (the tests compare
/// both forms).
/// `params(page)`: the parameters of unit `page` (for CALL plans).
pub(crate) fn decode(
    unit: &VerifiedUnit,
    target: &Arc<Target>,
    memory: &Memory,
    fast_ops: bool,
    params: &dyn Fn(u8) -> Option<Vec<LocalEntry>>,
) -> Unit {
    let mut calls = Vec::new();
    let n = unit.records.len();
    let (mut ops, mut positions, mut records) = (
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    );
    let mut operands = Vec::new();
    let (mut network, mut step) = (0u16, 0u16);
    for r in &unit.records {
        match r {
            UnitRecord::Network { number, .. } => {
                (network, step) = (*number, 0);
                ops.push(Op::Network);
                positions.push((network, u16::MAX));
                records.push(None);
            }
            UnitRecord::Instruction {
                id,
                operands: packed,
                offset,
            } => {
                let ins = target.instructions.get(*id);
                let planned = (fast_ops && ins.mnemonic == "CALL")
                    .then(|| plan_call(memory, target, packed, params))
                    .flatten()
                    .map(|plan| {
                        calls.push(plan);
                        Op::Call {
                            plan: (calls.len() - 1) as u32,
                        }
                    });
                let op = planned
                    .or_else(|| {
                        fast_ops
                            .then(|| fast(memory, &ins.mnemonic, packed))
                            .flatten()
                    })
                    .unwrap_or(Op::Generic {
                        boxed: ins.flow == Flow::Box,
                    });
                ops.push(op);
                positions.push((network, step));
                records.push(Some(Record {
                    id: *id,
                    offset: u32::try_from(*offset).unwrap_or(u32::MAX),
                    first: u32::try_from(operands.len()).unwrap_or(u32::MAX),
                    len: u16::try_from(packed.len()).unwrap_or(u16::MAX),
                }));
                operands.extend_from_slice(packed);
                step = step.saturating_add(1);
            }
        }
    }
    operands.shrink_to_fit();
    let mut chain = Vec::new();
    let fused = if fast_ops {
        build(&ops, None, &mut chain)
    } else {
        ops.clone()
    };
    Unit {
        page: unit.page,
        ops: fused,
        plain: ops,
        chain,
        positions,
        records,
        operands,
        labels: unit.labels.clone(),
        loops: unit.loops.clone(),
        params: unit.parameters().copied().collect(),
        calls,
        target: Arc::clone(target),
    }
}
