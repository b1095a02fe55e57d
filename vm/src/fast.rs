//! The fast path: pre-decoded operations (`op.rs`) executed directly on the flat
//! memory bytes and the logic stack, with no lookups and no allocation. Everything else
//! returns to the engine, which runs it through `ops/`. It must stay free of anything
//! that is not an instruction's effect on memory and the stack.

use crate::op::{
    Arith, Bit, ChainStep, Combine, CounterKind, CounterOp, DivideOp, Op, Preset, Quick, Rel,
    TimerKind, TimerOp, STEP_STORE, STEP_TABLE,
};

/// The side tables a unit's fast operations index: fused chains' steps, timers,
/// counters and divisions. A unit owns one (`decode::Unit::tables`), so entering a unit
/// hands the fast path one reference instead of a slice per table.
#[derive(Debug, Clone, Default)]
pub(crate) struct UnitTables {
    pub chain: Vec<ChainStep>,
    /// The operands of `Op::Timer` and `Op::Counter` records, by their `index`.
    pub timers: Vec<TimerOp>,
    pub counters: Vec<CounterOp>,
    /// The operands of `Quick::Divide` records, by their `index`.
    pub divides: Vec<DivideOp>,
}

/// What the fast path reads besides memory and the operations: the running unit's
/// side tables and where compiled regions start.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Tables<'a> {
    pub unit: &'a UnitTables,
    /// Per record of the unit, non-zero where a compiled region starts (the tier's
    /// table; empty without one): the fast path stops there after a generic record it
    /// ran itself, so the engine enters the region instead of interpreting it.
    pub regions: &'a [u32],
}

/// Whether `run_fast` stops at `op` whatever the logic stack: a CALL, a breakpoint, a
/// record only its handler runs. (It also stops at a box with power flow, and where
/// the watchdog's bound is: those depend on the scan.)
pub(crate) fn stops(op: &Op) -> bool {
    matches!(
        op,
        Op::Call { .. }
            | Op::Break
            | Op::Generic {
                quick: Quick::Handler,
                ..
            }
    )
}

/// Run fast operations from `pc` until one is not (or the ops end). Returns where it
/// stopped and how many instructions ran (network records do not count).
#[inline(always)]
pub(crate) fn run_fast(
    mem: &mut [u8],
    ops: &[Op],
    tables: Tables<'_>,
    mut pc: usize,
    st: &mut u32,
    mask: u32,
    flags_at: usize,
) -> (usize, u64) {
    let (start, mut networks, mut skipped) = (pc, 0u64, 0u64);
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
                for step in &tables.unit.chain[first..first + steps] {
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
            Op::Generic { quick, .. } => {
                match quick {
                    Quick::Nothing => pc += 1,
                    Quick::Box if s & 1 == 0 => pc += 1,
                    Quick::Jump { to } => {
                        if s & 1 == 1 {
                            // Forward: the records jumped over do not run.
                            skipped += u64::from(to) - pc as u64 - 1;
                            pc = to as usize;
                        } else {
                            pc += 1;
                        }
                    }
                    Quick::Step { at, width, up } => {
                        if s & 1 == 1 {
                            step(mem, at, width, up, flags_at);
                        }
                        pc += 1;
                    }
                    Quick::Divide { index } => {
                        if s & 1 == 1 {
                            divide(mem, &tables.unit.divides[index as usize], flags_at);
                        }
                        pc += 1;
                    }
                    Quick::Store { at, value } => {
                        mem[at as usize] = value;
                        pc += 1;
                    }
                    Quick::Box | Quick::Handler => break,
                }
                if tables.regions.get(pc).is_some_and(|&k| k != 0) {
                    break;
                }
                continue;
            }
            op => {
                if !fast_op(mem, op, tables, &mut s, mask, flags_at) {
                    break;
                }
            }
        }
        pc += 1;
    }
    *st = s;
    (pc, (pc - start) as u64 - networks - skipped)
}

/// INCx (`up`) / DECx of `width` bytes at `at` (`ops/math.rs` `step`): a byte wraps
/// unsigned (SM1.1 when it wrapped, SM1.2 clear), a word or double word signed.
#[inline(never)]
fn step(mem: &mut [u8], at: u32, width: u8, up: bool, flags_at: usize) {
    let delta: i64 = if up { 1 } else { -1 };
    let bits = u32::from(width) * 8;
    let v = load(mem, at, width);
    let (r, overflow, negative) = if width == 1 {
        let exact = i64::from(v) + delta;
        let r = exact.rem_euclid(256);
        (r, !(0..=255).contains(&exact), false)
    } else {
        let exact = sign_extend(v, bits) + delta;
        let r = sign_extend(exact as u32, bits);
        (r, r != exact, r < 0)
    };
    store(mem, at, width, r as u32);
    let flags = u8::from(r == 0) | (u8::from(overflow) << 1) | (u8::from(negative) << 2);
    let f = &mut mem[flags_at];
    *f = (*f & !0x07) | flags;
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
pub(crate) fn fast_op(
    mem: &mut [u8],
    op: Op,
    tables: Tables<'_>,
    st: &mut u32,
    mask: u32,
    flags_at: usize,
) -> bool {
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
        Op::Timer { index } => timer(mem, s, &tables.unit.timers[index as usize]),
        Op::Counter { index } => counter(mem, s, mask, &tables.unit.counters[index as usize]),
        Op::Edge { rising, state } => {
            let now = s & 1;
            let cell = &mut mem[state as usize];
            let before = u32::from(*cell != 0);
            *cell = now as u8;
            let out = if rising {
                now & (before ^ 1)
            } else {
                (now ^ 1) & before
            };
            (s & !1) | out
        }
        Op::SetBits { at, bit, n, value } => {
            if s & 1 == 1 {
                set_bits(mem, at, bit, n, value);
            }
            s
        }
        Op::Network
        | Op::NetworkLoad { .. }
        | Op::Chain { .. }
        | Op::Call { .. }
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

/// S/R: `n` bits from bit `bit` of the byte at `at` on take `value` (inside the area:
/// `decode` checked).
#[inline(never)]
fn set_bits(mem: &mut [u8], at: u32, bit: u8, n: u16, value: bool) {
    let (mut at, mut bit, mut n) = (at as usize, u32::from(bit), u32::from(n));
    while n > 0 {
        // The bits of this byte from `bit` on, at most `n`.
        let take = (8 - bit).min(n);
        let mask = (((1u32 << take) - 1) << bit) as u8;
        let byte = &mut mem[at];
        *byte = if value { *byte | mask } else { *byte & !mask };
        n -= take;
        bit = 0;
        at += 1;
    }
}

/// Bits of a timer's hidden state (word 1) and a counter's (word 0), as `ops/timers.rs`.
const RUNNING: u32 = 1;
const ARMED: u32 = 2;
const PREV_UP: u32 = 1;
const PREV_DOWN: u32 = 2;

#[inline(always)]
fn word(mem: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([mem[at], mem[at + 1], mem[at + 2], mem[at + 3]])
}

#[inline(always)]
fn set_word(mem: &mut [u8], at: usize, v: u32) {
    mem[at..at + 4].copy_from_slice(&v.to_le_bytes());
}

#[inline(always)]
fn int(mem: &[u8], at: u32) -> i64 {
    i64::from(load(mem, at, 2) as u16 as i16)
}

#[inline(always)]
fn set_int(mem: &mut [u8], at: u32, v: i64) {
    store(mem, at, 2, v as i16 as u16 as u32);
}

#[inline(always)]
fn preset(mem: &[u8], p: Preset) -> i64 {
    match p {
        Preset::Const(v) => i64::from(v),
        Preset::Word(at) => int(mem, at),
    }
}

/// One execution of a timer's clock: the whole units elapsed since its previous
/// advancing execution (0 when this one starts it); the remainder is kept.
#[inline(always)]
fn advance(mem: &mut [u8], t: &TimerOp) -> i64 {
    let state = t.state as usize;
    let flags = word(mem, state + 4);
    if flags & RUNNING == 0 {
        set_word(mem, state + 4, flags | RUNNING);
        set_word(mem, state, 0);
        return 0;
    }
    let total = u64::from(word(mem, state)) + u64::from(t.scan_ms);
    let res = u64::from(t.res);
    set_word(mem, state, (total % res) as u32);
    (total / res) as i64
}

/// Stop a timer's clock (the uncounted fraction dropped).
#[inline(always)]
fn stop(mem: &mut [u8], state: usize) {
    let flags = word(mem, state + 4);
    set_word(mem, state, 0);
    set_word(mem, state + 4, flags & !RUNNING);
}

/// TON/TOF/TONR (`ops/timers.rs`): the done state replaces the top.
#[inline(never)]
fn timer(mem: &mut [u8], s: u32, t: &TimerOp) -> u32 {
    const MAX: i64 = i16::MAX as i64;
    let pt = preset(mem, t.preset);
    let state = t.state as usize;
    let top = s & 1 == 1;
    let out = match t.kind {
        TimerKind::On => {
            if top {
                let units = advance(mem, t);
                let mut v = int(mem, t.at);
                if units > 0 && v < MAX {
                    v = (v + units).min(MAX);
                    set_int(mem, t.at, v);
                }
                pt <= 0 || v >= pt
            } else {
                stop(mem, state);
                set_int(mem, t.at, 0);
                false
            }
        }
        TimerKind::Off => {
            if top {
                stop(mem, state);
                let flags = word(mem, state + 4);
                set_word(mem, state + 4, flags | ARMED);
                set_int(mem, t.at, 0);
                true
            } else if word(mem, state + 4) & ARMED != 0 {
                let units = advance(mem, t);
                let mut v = int(mem, t.at);
                if units > 0 && v < pt {
                    v = (v + units).min(pt);
                    set_int(mem, t.at, v);
                }
                if v < pt {
                    true
                } else {
                    stop(mem, state);
                    let flags = word(mem, state + 4);
                    set_word(mem, state + 4, flags & !ARMED);
                    false
                }
            } else {
                false
            }
        }
        TimerKind::Retentive => {
            let mut v = int(mem, t.at);
            if top {
                let units = advance(mem, t);
                if units > 0 && v < MAX {
                    v = (v + units).min(MAX);
                    set_int(mem, t.at, v);
                }
            } else {
                stop(mem, state);
            }
            v >= pt
        }
    };
    (s & !1) | u32::from(out)
}

/// Record a counter's up (down) input; true on its rising edge.
#[inline(always)]
fn counter_edge(mem: &mut [u8], state: usize, bit: u32, now: bool) -> bool {
    let flags = word(mem, state);
    set_word(mem, state, if now { flags | bit } else { flags & !bit });
    now && flags & bit == 0
}

/// CTU/CTD/CTUD (`ops/timers.rs`): their inputs popped, the done state pushed.
#[inline(never)]
fn counter(mem: &mut [u8], s: u32, mask: u32, c: &CounterOp) -> u32 {
    let pv = preset(mem, c.preset);
    let state = c.state as usize;
    let max = i64::from(c.max);
    let (rest, out) = match c.kind {
        CounterKind::Up => {
            let (r, cu) = (s & 1 == 1, s & 2 == 2);
            let up = counter_edge(mem, state, PREV_UP, cu);
            let mut v = int(mem, c.at);
            if r {
                v = 0;
                set_int(mem, c.at, v);
            } else if up && v < max {
                v += 1;
                set_int(mem, c.at, v);
            }
            (s >> 2, v >= pv)
        }
        CounterKind::Down => {
            let (ld, cd) = (s & 1 == 1, s & 2 == 2);
            let down = counter_edge(mem, state, PREV_DOWN, cd);
            let mut v = int(mem, c.at);
            if ld {
                v = pv;
                set_int(mem, c.at, v);
            } else if down && v > 0 {
                v -= 1;
                set_int(mem, c.at, v);
            }
            (s >> 2, v == 0)
        }
        CounterKind::UpDown => {
            let (r, cd, cu) = (s & 1 == 1, s & 2 == 2, s & 4 == 4);
            let up = counter_edge(mem, state, PREV_UP, cu);
            let down = counter_edge(mem, state, PREV_DOWN, cd);
            let mut v = int(mem, c.at);
            if r {
                v = 0;
                set_int(mem, c.at, v);
            } else if up && !down && v < max {
                v += 1;
                set_int(mem, c.at, v);
            } else if down && !up && v > i64::from(i16::MIN) {
                v -= 1;
                set_int(mem, c.at, v);
            }
            (s >> 3, v >= pv)
        }
    };
    ((rest << 1) | u32::from(out)) & mask
}

/// /I, /D (`ops/math.rs` `divide`): by zero SM1.3 set and SM1.0-2 clear, OUT kept;
/// MIN / -1 SM1.1 set (SM1.0, SM1.2, SM1.3 clear), OUT kept; else OUT := the truncated
/// quotient, SM1.0 zero, SM1.2 negative, SM1.1 and SM1.3 clear.
#[inline(never)]
fn divide(mem: &mut [u8], d: &DivideOp, flags_at: usize) {
    let bits = u32::from(d.width) * 8;
    let a = sign_extend(load(mem, d.dst, d.width), bits);
    let b = sign_extend(load(mem, d.src, d.width), bits);
    let flags = if b == 0 {
        0b1000
    } else {
        let q = a / b;
        if q > (1i64 << (bits - 1)) - 1 {
            0b0010
        } else {
            store(mem, d.dst, d.width, q as u32);
            u8::from(q == 0) | (u8::from(q < 0) << 2)
        }
    };
    let f = &mut mem[flags_at];
    *f = (*f & !0x0F) | flags;
}
