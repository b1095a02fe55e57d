//! Pre-decoding: at load, every record of every unit becomes an `Op`. The frequent
//! instructions with plain operands (bit logic on a variable, moves, integer add and
//! subtract, compares) become operations that name their bytes by index into the flat
//! memory; everything else is `Generic` and runs its semantic from `ops/` with the
//! record's packed operands. Op `k` of a unit is record `k`, so labels, FOR/NEXT pairs
//! and debugger positions use one numbering. docs/vm.md, "Speed", says why.

use gutta_catalog::{Flow, Target, Width};
use gutta_format::{PackedOperand, UnitRecord, Use, VerifiedUnit};

use crate::memory::{Location, Memory};

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
}

/// One decoded record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Op {
    /// A network record: the logic stack starts empty.
    Network,
    /// A network record fused with the LD (LDN) that follows it: the stack becomes that
    /// one bit, and the LD record is passed over. Only the fast path fuses; everything
    /// else treats it as `Network`.
    NetLd(Bit),
    NetLdn(Bit),
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
    /// +I/-I (width 2) and +D/-D (width 4) on plain variables, with the SM1 flags.
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
    /// Any other instruction: its semantic runs with the record's operands. `boxed`:
    /// it runs only with power flow.
    Generic {
        boxed: bool,
    },
    /// A breakpoint patched over the op (the original is kept aside).
    Break,
}

impl Op {
    /// A network record, fused or not.
    pub fn is_network(self) -> bool {
        matches!(self, Op::Network | Op::NetLd(_) | Op::NetLdn(_))
    }
}

/// Fuse the network record at `k` with the LD/LDN after it, if there is one.
pub(crate) fn fuse(ops: &mut [Op], k: usize) {
    if !ops.get(k).is_some_and(|o| o.is_network()) {
        return;
    }
    ops[k] = match ops.get(k + 1) {
        Some(&Op::Ld(b)) => Op::NetLd(b),
        Some(&Op::Ldn(b)) => Op::NetLdn(b),
        _ => Op::Network,
    };
}

/// A unit ready to run.
#[derive(Debug, Clone)]
pub(crate) struct Unit {
    pub page: u8,
    pub ops: Vec<Op>,
    pub source: VerifiedUnit,
    /// Per record: (network number, step within the network); networks have step 0xFFFF.
    pub positions: Vec<(u16, u16)>,
}

/// A plain variable operand (USE 0) of the given width, as a flat memory index.
fn plain(memory: &Memory, op: PackedOperand, width: Width) -> Option<u32> {
    if op.use_() != Some(Use::Value) || op.width() != Some(width) {
        return None;
    }
    let loc = Location {
        slot: op.slot(),
        offset: op.offset() as u32,
        width,
        bit: op.bit(),
    };
    memory.index_of(loc).and_then(|i| u32::try_from(i).ok())
}

fn plain_bit(memory: &Memory, op: PackedOperand) -> Option<Bit> {
    let at = plain(memory, op, Width::Bit)?;
    Some(Bit {
        at,
        mask: 1 << (op.bit() & 7),
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
        "+I" | "-I" | "+D" | "-D" => {
            let width = if mnemonic.ends_with('I') { 2 } else { 4 };
            Op::Math {
                op: if mnemonic.starts_with('+') {
                    Arith::Add
                } else {
                    Arith::Sub
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
pub(crate) fn decode(
    unit: &VerifiedUnit,
    target: &Target,
    memory: &Memory,
    fast_ops: bool,
) -> Unit {
    let mut ops = Vec::with_capacity(unit.records.len());
    let mut positions = Vec::with_capacity(unit.records.len());
    let (mut network, mut step) = (0u16, 0u16);
    for r in &unit.records {
        match r {
            UnitRecord::Network { number, .. } => {
                (network, step) = (*number, 0);
                ops.push(Op::Network);
                positions.push((network, u16::MAX));
            }
            UnitRecord::Instruction { id, operands, .. } => {
                let ins = target.instructions.get(*id);
                let op = fast_ops
                    .then(|| fast(memory, &ins.mnemonic, operands))
                    .flatten()
                    .unwrap_or(Op::Generic {
                        boxed: ins.flow == Flow::Box,
                    });
                ops.push(op);
                positions.push((network, step));
                step = step.saturating_add(1);
            }
        }
    }
    for k in 0..ops.len() {
        fuse(&mut ops, k);
    }
    Unit {
        page: unit.page,
        ops,
        source: unit.clone(),
        positions,
    }
}
