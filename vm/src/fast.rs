//! The fast path: pre-decoded operations (`op.rs`) executed directly on the flat
//! memory bytes and the logic stack, with no lookups and no allocation. Everything else
//! returns to the engine, which runs it through `ops/`. It must stay free of anything
//! that is not an instruction's effect on memory and the stack.

use crate::op::{Arith, Bit, ChainStep, Combine, Op, Rel, STEP_STORE, STEP_TABLE};

/// Run fast operations from `pc` until one is not (or the ops end). Returns where it
/// stopped and how many instructions ran (network records do not count).
#[inline(always)]
pub(crate) fn run_fast(
    mem: &mut [u8],
    ops: &[Op],
    chain: &[ChainStep],
    mut pc: usize,
    st: &mut u32,
    mask: u32,
    flags_at: usize,
) -> (usize, u64) {
    let (start, mut networks) = (pc, 0u64);
    let mut s = *st;
    while let Some(&op) = ops.get(pc) {
        match op {
            Op::Network => {
                s = 0;
                networks += 1;
            }
            Op::NetworkLoad { bit: b, invert } => {
                if pc + 2 > ops.len() {
                    // Past the watchdog's bound: the slow path runs it record by record.
                    break;
                }
                s = bit(mem, b) ^ u32::from(invert);
                networks += 1;
                pc += 2;
                continue;
            }
            Op::Chain {
                first,
                records,
                networks: n,
            } => {
                let records = records as usize;
                if pc + records > ops.len() {
                    // Past the watchdog's bound: the slow path runs it record by record.
                    break;
                }
                let first = first as usize;
                let steps = records - usize::from(n);
                // After a network start the rest of the stack is empty; t is the top.
                let mut t = s & 1;
                let rest = if n > 0 { 0 } else { s & !1 };
                for step in &chain[first..first + steps] {
                    let at = step.at as usize;
                    let byte = mem[at];
                    if step.kind == STEP_STORE {
                        mem[at] = (byte & !(1 << step.bit)) | ((t as u8) << step.bit);
                    } else {
                        // The new t, looked up by (kind, v, t): no branch on data.
                        let v = u32::from(byte >> step.bit) & 1;
                        t = (STEP_TABLE >> (u32::from(step.kind) * 4 + v * 2 + t)) & 1;
                    }
                }
                s = rest | t;
                networks += u64::from(n);
                pc += records;
                continue;
            }
            op => {
                if !fast_op(mem, op, &mut s, mask, flags_at) {
                    break;
                }
            }
        }
        pc += 1;
    }
    *st = s;
    (pc, (pc - start) as u64 - networks)
}

#[inline(always)]
fn bit(mem: &[u8], b: Bit) -> u32 {
    u32::from(mem[b.at as usize] & b.mask != 0)
}

#[inline(always)]
pub(crate) fn load(mem: &[u8], at: u32, width: u8) -> u32 {
    let at = at as usize;
    match width {
        1 => u32::from(mem[at]),
        2 => u32::from(u16::from_le_bytes([mem[at], mem[at + 1]])),
        _ => u32::from_le_bytes([mem[at], mem[at + 1], mem[at + 2], mem[at + 3]]),
    }
}

#[inline(always)]
pub(crate) fn store(mem: &mut [u8], at: u32, width: u8, v: u32) {
    let at = at as usize;
    match width {
        1 => mem[at] = v as u8,
        2 => mem[at..at + 2].copy_from_slice(&(v as u16).to_le_bytes()),
        _ => mem[at..at + 4].copy_from_slice(&v.to_le_bytes()),
    }
}

/// Execute a fast operation on the flat memory and the logic stack `st`; false (and
/// nothing done) for an op that is not one (network records, generic, breakpoints).
#[inline(always)]
pub(crate) fn fast_op(mem: &mut [u8], op: Op, st: &mut u32, mask: u32, flags_at: usize) -> bool {
    let s = *st;
    *st = match op {
        Op::Ld(b) => ((s << 1) | bit(mem, b)) & mask,
        Op::Ldn(b) => ((s << 1) | (bit(mem, b) ^ 1)) & mask,
        Op::A(b) => s & (!1 | bit(mem, b)),
        Op::An(b) => s & (!1 | (bit(mem, b) ^ 1)),
        Op::O(b) => s | bit(mem, b),
        Op::On(b) => s | (bit(mem, b) ^ 1),
        Op::Not => s ^ 1,
        Op::Assign(b) => {
            // Branch-free: the top is data, a branch on it would mispredict.
            let byte = &mut mem[b.at as usize];
            let set = (s & 1) as u8 * b.mask;
            *byte = (*byte & !b.mask) | set;
            s
        }
        Op::Ald => (s >> 1) & (s | !1),
        Op::Old => (s >> 1) | (s & 1),
        Op::Lps => ((s << 1) | (s & 1)) & mask,
        Op::Lrd => (s & !1) | ((s >> 1) & 1),
        Op::Lpp => s >> 1,
        Op::Move { src, dst, width } => match width {
            1 => mov::<1>(mem, s, src, dst),
            2 => mov::<2>(mem, s, src, dst),
            _ => mov::<4>(mem, s, src, dst),
        },
        Op::MoveB { src, dst } => mov::<1>(mem, s, src, dst),
        Op::MoveW { src, dst } => mov::<2>(mem, s, src, dst),
        Op::MoveD { src, dst } => mov::<4>(mem, s, src, dst),
        Op::Math {
            op,
            src,
            dst,
            width,
        } => match width {
            2 => math::<2>(mem, s, op, src, dst, flags_at),
            _ => math::<4>(mem, s, op, src, dst, flags_at),
        },
        Op::MathW { op, src, dst } => math::<2>(mem, s, op, src, dst, flags_at),
        Op::MathD { op, src, dst } => math::<4>(mem, s, op, src, dst, flags_at),
        Op::Compare {
            combine,
            rel,
            a,
            b,
            width,
        } => match width {
            1 => compare::<1>(mem, s, mask, combine, rel, a, b),
            2 => compare::<2>(mem, s, mask, combine, rel, a, b),
            _ => compare::<4>(mem, s, mask, combine, rel, a, b),
        },
        Op::CompareB { combine, rel, a, b } => compare::<1>(mem, s, mask, combine, rel, a, b),
        Op::CompareW { combine, rel, a, b } => compare::<2>(mem, s, mask, combine, rel, a, b),
        Op::CompareD { combine, rel, a, b } => compare::<4>(mem, s, mask, combine, rel, a, b),
        Op::Network
        | Op::NetworkLoad { .. }
        | Op::Chain { .. }
        | Op::Call { .. }
        | Op::Timer { .. }
        | Op::Counter { .. }
        | Op::Edge { .. }
        | Op::SetBits { .. }
        | Op::Generic { .. }
        | Op::Break => return false,
    };
    true
}

/// MOVB/MOVW/MOVD/MOVR of `W` bytes with power flow; the stack unchanged.
#[inline(always)]
fn mov<const W: u8>(mem: &mut [u8], s: u32, src: u32, dst: u32) -> u32 {
    if s & 1 == 1 {
        let v = load(mem, src, W);
        store(mem, dst, W, v);
    }
    s
}

/// OUT := OUT op IN1 on `W` bytes, signed, with power flow; SM1.0 zero, SM1.1
/// overflow, SM1.2 negative set, the other flags kept.
#[inline(always)]
fn math<const W: u8>(
    mem: &mut [u8],
    s: u32,
    op: Arith,
    src: u32,
    dst: u32,
    flags_at: usize,
) -> u32 {
    if s & 1 == 1 {
        let bits = u32::from(W) * 8;
        let a = sign_extend(load(mem, dst, W), bits);
        let b = sign_extend(load(mem, src, W), bits);
        let exact = match op {
            Arith::Add => a + b,
            Arith::Sub => a - b,
            Arith::Mul => a * b,
        };
        let r = sign_extend(exact as u32, bits);
        store(mem, dst, W, exact as u32);
        let flags = u8::from(r == 0) | (u8::from(r != exact) << 1) | (u8::from(r < 0) << 2);
        let f = &mut mem[flags_at];
        *f = (*f & !0x07) | flags;
    }
    s
}

/// A compare of `W` bytes (a byte unsigned, words and double words signed) combined
/// into the stack.
#[inline(always)]
fn compare<const W: u8>(
    mem: &[u8],
    s: u32,
    mask: u32,
    combine: Combine,
    rel: Rel,
    a: u32,
    b: u32,
) -> u32 {
    let (x, y) = (load(mem, a, W), load(mem, b, W));
    let r = if W == 1 {
        rel.holds(x, y)
    } else {
        let bits = u32::from(W) * 8;
        rel.holds(sign_extend(x, bits), sign_extend(y, bits))
    };
    let r = u32::from(r);
    match combine {
        Combine::Load => ((s << 1) | r) & mask,
        Combine::And => s & (!1 | r),
        Combine::Or => s | r,
    }
}

#[inline(always)]
fn sign_extend(v: u32, bits: u32) -> i64 {
    match bits {
        8 => v as u8 as i8 as i64,
        16 => v as u16 as i16 as i64,
        _ => v as i32 as i64,
    }
}
