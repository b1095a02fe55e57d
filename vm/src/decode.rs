//! Pre-decoding: at load, every record of every unit becomes an `Op`. The frequent
//! instructions with plain operands (bit logic on a variable, moves, integer add and
//! subtract, compares) become operations that name their bytes by index into the flat
//! memory; everything else is `Generic` and runs its semantic from `ops/` with the
//! record's packed operands. Op `k` of a unit is record `k`, so labels, FOR/NEXT pairs
//! and debugger positions use one numbering. docs/vm.md, "Speed", says why.

use std::collections::BTreeMap;
use std::sync::Arc;

use gutta_catalog::{Address, Flow, InstrId, Target, Width};
use gutta_format::{LocalEntry, LocalSection, Operand, PackedOperand, UnitRecord, VerifiedUnit};

use crate::memory::Memory;

/// A bit of memory: byte index into the flat memory and the bit's mask.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Bit {
    pub at: u32,
    pub mask: u8,
}

/// Which stack operation a compare feeds (LD pushes, A ands, O ors).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Combine {
    Load,
    And,
    Or,
}

/// A compare's relation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Rel {
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
}

impl Rel {
    #[inline(always)]
    pub fn holds<T: PartialOrd>(self, a: T, b: T) -> bool {
        match self {
            Rel::Eq => a == b,
            Rel::Ne => a != b,
            Rel::Lt => a < b,
            Rel::Le => a <= b,
            Rel::Gt => a > b,
            Rel::Ge => a >= b,
        }
    }
}

/// Integer math the fast path knows (OUT := OUT op IN1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Arith {
    Add,
    Sub,
    Mul,
}

/// One decoded record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Op {
    /// A network record: the logic stack starts empty.
    Network,
    /// Bit logic fused (see `build`): `Unit::chain[first..]` run in order; it covers
    /// `records` records, `networks` of them network records and each other one a step.
    Chain {
        first: u32,
        records: u32,
        networks: u16,
    },
    Ld(Bit),
    Ldn(Bit),
    A(Bit),
    An(Bit),
    O(Bit),
    On(Bit),
    Not,
    Assign(Bit),
    Ald,
    Old,
    Lps,
    Lrd,
    Lpp,
    /// MOVB/MOVW/MOVD/MOVR between plain variables (bytes `width`).
    Move {
        src: u32,
        dst: u32,
        width: u8,
    },
    /// +I -I *I (width 2) and +D -D *D (width 4) on plain variables, with the SM1 flags.
    Math {
        op: Arith,
        src: u32,
        dst: u32,
        width: u8,
    },
    /// Signed compares of INT (width 2) and DINT (width 4), unsigned of BYTE (width 1).
    Compare {
        combine: Combine,
        rel: Rel,
        a: u32,
        b: u32,
        width: u8,
    },
    /// CALL with plain arguments whose widths match the parameters: `Unit::calls[plan]`.
    Call {
        plan: u32,
    },
    /// Any other instruction: its semantic runs with the record's operands. `boxed`:
    /// it runs only with power flow.
    Generic {
        boxed: bool,
    },
    /// A breakpoint patched over the op (the original is in `Unit::plain`).
    Break,
}

impl Op {
    /// A network record.
    pub fn is_network(self) -> bool {
        self == Op::Network
    }
}

/// What a chain step does (`ChainStep::kind`).
pub(crate) const STEP_AND: u8 = 0;
pub(crate) const STEP_OR: u8 = 1;
pub(crate) const STEP_LOAD: u8 = 2;
pub(crate) const STEP_STORE: u8 = 3;

/// One step of a fused chain. Only the top of the logic stack changes in a chain, so
/// it is kept apart as `t` (0 or 1). With v the bit `bit` of the byte at `at` (inverted
/// for LDN/AN/ON): a network's LD/LDN (`STEP_LOAD`) starts the network, t := v with the
/// rest of the stack empty; A/AN (`STEP_AND`) make t := t AND v; O/ON (`STEP_OR`) make
/// t := t OR v; a `=` (`STEP_STORE`) writes t into that bit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct ChainStep {
    pub at: u32,
    /// The bit's number in its byte.
    pub bit: u8,
    pub invert: u8,
    pub kind: u8,
    /// Arithmetic form of the kind, for t in {0, 1}: t := ((t AND keep) + v + or) / 2
    /// is t AND v for A (keep 1, or 0), t OR v for O (keep 1, or 1) and v for a
    /// network's LD (keep 0, or 1).
    pub keep_or: u8,
}

/// `keep_or` of a kind: keep in bit 0, or in bit 1.
const fn keep_or(kind: u8) -> u8 {
    match kind {
        STEP_AND => 0b01,
        STEP_OR => 0b11,
        STEP_LOAD => 0b10,
        _ => 0,
    }
}

fn chain_step(op: Op) -> Option<ChainStep> {
    let (b, invert, kind) = match op {
        Op::A(b) => (b, 0, STEP_AND),
        Op::An(b) => (b, 1, STEP_AND),
        Op::O(b) => (b, 0, STEP_OR),
        Op::On(b) => (b, 1, STEP_OR),
        Op::Assign(b) => (b, 0, STEP_STORE),
        _ => return None,
    };
    Some(ChainStep {
        at: b.at,
        bit: b.mask.trailing_zeros() as u8,
        invert,
        kind,
        keep_or: keep_or(kind),
    })
}

/// A network record followed by LD/LDN at `k`: the chain step that starts it.
fn network_start(ops: &[Op], k: usize) -> Option<ChainStep> {
    if ops.get(k) != Some(&Op::Network) {
        return None;
    }
    let (b, invert) = match ops.get(k + 1) {
        Some(&Op::Ld(b)) => (b, 0),
        Some(&Op::Ldn(b)) => (b, 1),
        _ => return None,
    };
    Some(ChainStep {
        at: b.at,
        bit: b.mask.trailing_zeros() as u8,
        invert,
        kind: STEP_LOAD,
        keep_or: keep_or(STEP_LOAD),
    })
}

/// The operations the fast path runs: `plain` with the breakpoint (if any) patched in,
/// and fused: runs of bit logic become one chain (steps appended to `chain`). A chain
/// is A/AN/O/ON/`=` records, and whole networks that are a network record, LD/LDN and
/// such records; it covers at least two records. Fused operations sit at the first
/// record they cover; the records after keep their plain operations, so record
/// numbering is unchanged and a scan can stop at any of them.
pub(crate) fn build(
    plain: &[Op],
    breakpoint: Option<usize>,
    chain: &mut Vec<ChainStep>,
) -> Vec<Op> {
    let mut ops = plain.to_vec();
    chain.clear();
    if let Some(op) = breakpoint.and_then(|pc| ops.get_mut(pc)) {
        *op = Op::Break;
    }
    let mut k = 0;
    while k < ops.len() {
        let first = chain.len();
        let mut j = k;
        loop {
            if chain.len() - first >= u16::MAX as usize - 1 {
                break;
            }
            if let Some(load) = network_start(&ops, j) {
                chain.push(load);
                j += 2;
            } else if j != k {
                break;
            }
            while let Some(step) = ops.get(j).and_then(|&op| chain_step(op)) {
                if chain.len() - first >= u16::MAX as usize {
                    break;
                }
                chain.push(step);
                j += 1;
            }
            if network_start(&ops, j).is_none() {
                break;
            }
        }
        let records = j - k;
        if records >= 2 {
            let steps = chain.len() - first;
            ops[k] = Op::Chain {
                first: u32::try_from(first).unwrap_or(u32::MAX),
                records: u32::try_from(records).unwrap_or(u32::MAX),
                networks: (records - steps) as u16,
            };
            k = j;
        } else {
            chain.truncate(first);
            k += 1;
        }
    }
    ops
}

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
