//! The semantics of `Step`s as a plain interpreter, mirroring `vm/src/fast.rs` `fast_op`,
//! `vm/src/calls.rs` (enter_planned + return_planned), `vm/src/ops/timers.rs` (timers
//! and counters, their hidden state here in memory), `ops/bits.rs` (EU/ED, S/R) and
//! `ops/control.rs` (JMP/LBL) line by line; an Escape with power flow returns to the
//! caller, which runs the box itself. The tests and the
//! fuzz target compare the compiled code against it; it is also the documentation of
//! what the code must do. Slow on purpose (no fusing, no tricks) and only for step lists
//! that `compile` accepts: it indexes the memory (panics outside it) and would not end
//! on a cycle of Calls.

use crate::{
    Arg, Arith, Combine, Convert, CounterKind, Exit, Function, Layout, Logic, Preset, RealOp, Rel,
    Shift, Step, TimerKind,
};

/// Run function `f` on `memory` with the logic stack `stack`, as `Module::run` does;
/// returns the instructions executed.
pub fn run(
    layout: &Layout,
    functions: &[Function],
    f: usize,
    memory: &mut [u8],
    stack: &mut u32,
) -> u64 {
    enter(layout, functions, f, memory, stack).executed
}

/// Run function `f` as `Module::enter` does: the instructions executed and the Escape
/// it returned at, if any.
pub fn enter(
    layout: &Layout,
    functions: &[Function],
    f: usize,
    memory: &mut [u8],
    stack: &mut u32,
) -> Exit {
    let steps = &functions[f].steps;
    let mut count = 0;
    let mut i = 0;
    while i < steps.len() {
        if let Step::Escape { id } = steps[i] {
            if *stack & 1 == 1 {
                // Taken: back to the VM, which runs the box itself; not counted here.
                return Exit {
                    executed: count,
                    escape: Some(id),
                };
            }
        }
        if let Step::Jump { label } = steps[i] {
            if *stack & 1 == 1 {
                // Taken: on after its Label (which does not run); the jump counts 1.
                count += 1;
                i = steps[i + 1..]
                    .iter()
                    .position(|s| *s == Step::Label { number: label })
                    .map_or(steps.len(), |k| i + 1 + k + 1);
                continue;
            }
        }
        count += step(layout, functions, &steps[i], memory, stack);
        i += 1;
    }
    Exit {
        executed: count,
        escape: None,
    }
}

/// Word `k` (u32 LE) of the hidden state at `state`.
fn word(mem: &[u8], state: u32, k: u32) -> u32 {
    load(mem, state + 4 * k, 4)
}

fn set_word(mem: &mut [u8], state: u32, k: u32, v: u32) {
    store(mem, state + 4 * k, 4, v);
}

/// A timer's or counter's current value (signed INT).
fn current(mem: &[u8], at: u32) -> i64 {
    i64::from(load(mem, at, 2) as u16 as i16)
}

fn set_current(mem: &mut [u8], at: u32, v: i64) {
    store(mem, at, 2, v as i16 as u16 as u32);
}

fn preset(mem: &[u8], p: Preset) -> i64 {
    match p {
        Preset::Const(v) => i64::from(v),
        Preset::Word(at) => current(mem, at),
    }
}

// Timer flags (word 1) and counter flags (word 0), as in `vm/src/ops/timers.rs`.
const RUNNING: u32 = 1;
const ARMED: u32 = 2;
const PREV_UP: u32 = 1;
const PREV_DOWN: u32 = 2;
const TIMER_MAX: i64 = i16::MAX as i64;

/// One execution of a running timer's clock: the whole units since its previous one
/// (0 when this one starts the clock), the remainder kept.
fn advance(mem: &mut [u8], state: u32, res: u32, scan_ms: u32) -> i64 {
    let flags = word(mem, state, 1);
    if flags & RUNNING == 0 {
        set_word(mem, state, 1, flags | RUNNING);
        set_word(mem, state, 0, 0);
        return 0;
    }
    let total = u64::from(word(mem, state, 0)) + u64::from(scan_ms);
    set_word(mem, state, 0, (total % u64::from(res)) as u32);
    (total / u64::from(res)) as i64
}

/// Stop the clock, dropping the fraction of a unit.
fn stop(mem: &mut [u8], state: u32) {
    let flags = word(mem, state, 1);
    set_word(mem, state, 0, 0);
    set_word(mem, state, 1, flags & !RUNNING);
}

/// TON/TOF/TONR: the new top of the stack (done).
fn timer(mem: &mut [u8], s: u32, step: &Step) -> bool {
    let Step::Timer {
        kind,
        at,
        state,
        preset: p,
        res,
        scan_ms,
    } = *step
    else {
        unreachable!("a timer step");
    };
    let pt = preset(mem, p);
    let top = s & 1 == 1;
    match kind {
        TimerKind::On => {
            if top {
                let units = advance(mem, state, res, scan_ms);
                let mut t = current(mem, at);
                if units > 0 && t < TIMER_MAX {
                    t = (t + units).min(TIMER_MAX);
                    set_current(mem, at, t);
                }
                pt <= 0 || t >= pt
            } else {
                stop(mem, state);
                set_current(mem, at, 0);
                false
            }
        }
        TimerKind::Off => {
            if top {
                stop(mem, state);
                let flags = word(mem, state, 1);
                set_word(mem, state, 1, flags | ARMED);
                set_current(mem, at, 0);
                true
            } else if word(mem, state, 1) & ARMED != 0 {
                let units = advance(mem, state, res, scan_ms);
                let mut t = current(mem, at);
                if units > 0 && t < pt {
                    t = (t + units).min(pt);
                    set_current(mem, at, t);
                }
                if t < pt {
                    true
                } else {
                    stop(mem, state);
                    let flags = word(mem, state, 1);
                    set_word(mem, state, 1, flags & !ARMED);
                    false
                }
            } else {
                false
            }
        }
        TimerKind::Retentive => {
            let mut t = current(mem, at);
            if top {
                let units = advance(mem, state, res, scan_ms);
                if units > 0 && t < TIMER_MAX {
                    t = (t + units).min(TIMER_MAX);
                    set_current(mem, at, t);
                }
            } else {
                stop(mem, state);
            }
            t >= pt
        }
    }
}

/// A counter input's edge: records `now` in flag `bit`; true when it rose.
fn counter_edge(mem: &mut [u8], state: u32, bit: u32, now: bool) -> bool {
    let flags = word(mem, state, 0);
    let before = flags & bit != 0;
    set_word(mem, state, 0, if now { flags | bit } else { flags & !bit });
    now && !before
}

/// CTU/CTD/CTUD: the new stack.
fn counter(mem: &mut [u8], s: u32, mask: u32, step: &Step) -> u32 {
    let Step::Counter {
        kind,
        at,
        state,
        preset: p,
        max,
    } = *step
    else {
        unreachable!("a counter step");
    };
    let pv = preset(mem, p);
    let max = i64::from(max);
    let level = |k: u32| (s >> k) & 1 == 1;
    let (rest, done) = match kind {
        CounterKind::Up => {
            let (r, cu) = (level(0), level(1));
            let up = counter_edge(mem, state, PREV_UP, cu);
            let c = current(mem, at);
            let c = if r {
                set_current(mem, at, 0);
                0
            } else if up && c < max {
                set_current(mem, at, c + 1);
                c + 1
            } else {
                c
            };
            (s >> 2, c >= pv)
        }
        CounterKind::Down => {
            let (ld, cd) = (level(0), level(1));
            let down = counter_edge(mem, state, PREV_DOWN, cd);
            let c = current(mem, at);
            let c = if ld {
                set_current(mem, at, pv);
                pv
            } else if down && c > 0 {
                set_current(mem, at, c - 1);
                c - 1
            } else {
                c
            };
            (s >> 2, c == 0)
        }
        CounterKind::UpDown => {
            let (r, cd, cu) = (level(0), level(1), level(2));
            let up = counter_edge(mem, state, PREV_UP, cu);
            let down = counter_edge(mem, state, PREV_DOWN, cd);
            let c = current(mem, at);
            let c = if r {
                set_current(mem, at, 0);
                0
            } else if up && !down && c < max {
                set_current(mem, at, c + 1);
                c + 1
            } else if down && !up && c > i64::from(i16::MIN) {
                set_current(mem, at, c - 1);
                c - 1
            } else {
                c
            };
            (s >> 3, c >= pv)
        }
    };
    ((rest << 1) | u32::from(done)) & mask
}

fn bit(mem: &[u8], at: u32, bit: u8) -> u32 {
    u32::from(mem[at as usize] >> bit) & 1
}

/// A little-endian value of `width` bytes (1, 2, 4).
pub fn load(mem: &[u8], at: u32, width: u8) -> u32 {
    let at = at as usize;
    match width {
        1 => u32::from(mem[at]),
        2 => u32::from(u16::from_le_bytes([mem[at], mem[at + 1]])),
        _ => u32::from_le_bytes([mem[at], mem[at + 1], mem[at + 2], mem[at + 3]]),
    }
}

/// Where a Call argument lies: its variable (`param` false) or its parameter, as a
/// memory index and, for a BOOL, the bit.
fn arg_at(a: &Arg, param: bool) -> (u32, Option<u8>) {
    let at = if param { a.param } else { a.var };
    (at, a.bits.map(|(v, p)| if param { p } else { v }))
}

/// A Call argument's value (its variable's or its parameter's): `width` bytes, or the
/// bit (0 or 1) of a BOOL.
fn arg_load(mem: &[u8], a: &Arg, param: bool) -> u32 {
    match arg_at(a, param) {
        (at, Some(bit)) => u32::from(mem[at as usize] >> bit) & 1,
        (at, None) => load(mem, at, a.width),
    }
}

/// Store a Call argument's value: `width` bytes, or for a BOOL the low bit of `v` into
/// its bit, the other bits of the byte kept.
fn arg_store(mem: &mut [u8], a: &Arg, param: bool, v: u32) {
    match arg_at(a, param) {
        (at, Some(bit)) => {
            let byte = &mut mem[at as usize];
            *byte = (*byte & !(1 << bit)) | (((v & 1) as u8) << bit);
        }
        (at, None) => store(mem, at, a.width, v),
    }
}

/// Store the low `width` bytes of `v`, little-endian.
pub fn store(mem: &mut [u8], at: u32, width: u8, v: u32) {
    let at = at as usize;
    match width {
        1 => mem[at] = v as u8,
        2 => mem[at..at + 2].copy_from_slice(&(v as u16).to_le_bytes()),
        _ => mem[at..at + 4].copy_from_slice(&v.to_le_bytes()),
    }
}

fn sign_extend(v: u32, width: u8) -> i64 {
    match width {
        1 => i64::from(v as u8 as i8),
        2 => i64::from(v as u16 as i16),
        _ => i64::from(v as i32),
    }
}

fn holds<T: PartialOrd>(rel: Rel, a: T, b: T) -> bool {
    match rel {
        Rel::Eq => a == b,
        Rel::Ne => a != b,
        Rel::Lt => a < b,
        Rel::Le => a <= b,
        Rel::Gt => a > b,
        Rel::Ge => a >= b,
    }
}

/// Execute one step; returns the instructions it counts. A Jump or an Escape here is one
/// not taken (`enter` makes the jumps and the early returns).
pub fn step(
    layout: &Layout,
    functions: &[Function],
    step: &Step,
    mem: &mut [u8],
    st: &mut u32,
) -> u64 {
    let (s, mask) = (*st, layout.stack_mask);
    *st = match *step {
        Step::Timer { .. } => (s & !1) | u32::from(timer(mem, s, step)),
        Step::Counter { .. } => counter(mem, s, mask, step),
        Step::Edge { rising, state } => {
            let now = s & 1 == 1;
            let byte = &mut mem[state as usize];
            let before = *byte != 0;
            *byte = u8::from(now);
            let out = if rising {
                now && !before
            } else {
                !now && before
            };
            (s & !1) | u32::from(out)
        }
        Step::SetBits { at, bit, n, value } => {
            if s & 1 == 1 {
                for k in 0..u32::from(n) {
                    let b = u32::from(bit) + k;
                    let byte = &mut mem[(at + b / 8) as usize];
                    let m = 1u8 << (b % 8);
                    *byte = if value { *byte | m } else { *byte & !m };
                }
            }
            s
        }
        // Not taken (`run` makes a taken one), or a Label fallen through to.
        Step::Jump { .. } | Step::Label { .. } => s,
        Step::Network => {
            *st = 0;
            return 0;
        }
        Step::Ld { at, bit: b } => ((s << 1) | bit(mem, at, b)) & mask,
        Step::Ldn { at, bit: b } => ((s << 1) | (bit(mem, at, b) ^ 1)) & mask,
        Step::A { at, bit: b } => s & (!1 | bit(mem, at, b)),
        Step::An { at, bit: b } => s & (!1 | (bit(mem, at, b) ^ 1)),
        Step::O { at, bit: b } => s | bit(mem, at, b),
        Step::On { at, bit: b } => s | (bit(mem, at, b) ^ 1),
        Step::Not => s ^ 1,
        Step::Assign { at, bit: b } => {
            let byte = &mut mem[at as usize];
            *byte = (*byte & !(1 << b)) | (((s & 1) as u8) << b);
            s
        }
        Step::Ald => (s >> 1) & (s | !1),
        Step::Old => (s >> 1) | (s & 1),
        Step::Lps => ((s << 1) | (s & 1)) & mask,
        Step::Lrd => (s & !1) | ((s >> 1) & 1),
        Step::Lpp => s >> 1,
        Step::Move { src, dst, width } => {
            if s & 1 == 1 {
                let v = load(mem, src, width);
                store(mem, dst, width, v);
            }
            s
        }
        Step::Math {
            op,
            src,
            dst,
            width,
        } => {
            if s & 1 == 1 {
                let a = sign_extend(load(mem, dst, width), width);
                let b = sign_extend(load(mem, src, width), width);
                let exact = match op {
                    Arith::Add => a + b,
                    Arith::Sub => a - b,
                    Arith::Mul => a * b,
                };
                let r = sign_extend(exact as u32, width);
                store(mem, dst, width, exact as u32);
                // SM1.0 zero, SM1.1 overflow, SM1.2 negative; the other flags kept.
                let flags = u8::from(r == 0) | (u8::from(r != exact) << 1) | (u8::from(r < 0) << 2);
                let f = &mut mem[layout.flags_at as usize];
                *f = (*f & !0x07) | flags;
            }
            s
        }
        Step::Compare {
            combine,
            rel,
            a,
            b,
            width,
        } => {
            let (x, y) = (load(mem, a, width), load(mem, b, width));
            let r = if width == 1 {
                holds(rel, x, y)
            } else {
                holds(rel, sign_extend(x, width), sign_extend(y, width))
            };
            let r = u32::from(r);
            match combine {
                Combine::Load => ((s << 1) | r) & mask,
                Combine::And => s & (!1 | r),
                Combine::Or => s | r,
            }
        }
        Step::Call { callee, ref args } => {
            if s & 1 == 0 {
                return 1;
            }
            // enter_planned: inputs read in the caller's context, L saved and cleared,
            // inputs stored into the parameters, the callee run with an empty stack.
            let inputs: Vec<u32> = args
                .iter()
                .map(|a| if a.input { arg_load(mem, a, false) } else { 0 })
                .collect();
            let local = layout
                .local
                .map(|(start, len)| start as usize..(start + len) as usize);
            let saved = local.clone().map(|l| {
                let saved = mem[l.clone()].to_vec();
                mem[l].fill(0);
                saved
            });
            for (a, &v) in args.iter().zip(&inputs) {
                if a.input {
                    arg_store(mem, a, true, v);
                }
            }
            let mut callee_stack = 0;
            let executed = run(layout, functions, callee as usize, mem, &mut callee_stack);
            // return_planned: outputs read from the parameters, L and the stack
            // restored, outputs stored into the variables in argument order.
            let outputs: Vec<u32> = args
                .iter()
                .map(|a| if a.output { arg_load(mem, a, true) } else { 0 })
                .collect();
            if let (Some(l), Some(saved)) = (local, saved) {
                mem[l].copy_from_slice(&saved);
            }
            for (a, &v) in args.iter().zip(&outputs) {
                if a.output {
                    arg_store(mem, a, false, v);
                }
            }
            return 1 + executed;
        }
        // ---- Generic families ----
        Step::Logic { .. }
        | Step::Invert { .. }
        | Step::IncDec { .. }
        | Step::Divide { .. }
        | Step::MulWide { .. }
        | Step::DivWide { .. }
        | Step::Shift { .. }
        | Step::Convert { .. }
        | Step::RealMath { .. }
        | Step::Sqrt { .. }
        | Step::Const { .. }
        | Step::Swap { .. } => {
            if s & 1 == 1 {
                boxed(layout, step, mem);
            }
            s
        }
        Step::CompareReal { combine, rel, a, b } => {
            let x = f32::from_bits(load(mem, a, 4));
            let y = f32::from_bits(load(mem, b, 4));
            let r = u32::from(holds(rel, x, y));
            match combine {
                Combine::Load => ((s << 1) | r) & mask,
                Combine::And => s & (!1 | r),
                Combine::Or => s | r,
            }
        }
        Step::Lds { n } => {
            let level = if n < 32 { (s >> n) & 1 } else { 0 };
            ((s << 1) | level) & mask
        }
        Step::Nop | Step::Escape { .. } => s,
        Step::Store { at, value } => {
            mem[at as usize] = value;
            s
        }
    };
    1
}

// ---- Generic families: `vm/src/ops/{math,shift,convert,moves}.rs` ----------

/// SM1 bit `bit` := `v` (the handlers' `Exec::flag`).
fn flag(layout: &Layout, mem: &mut [u8], bit: u8, v: bool) {
    let f = &mut mem[layout.flags_at as usize];
    *f = (*f & !(1 << bit)) | (u8::from(v) << bit);
}

/// SM1.0 zero, SM1.1 overflow, SM1.2 negative (`Exec::flags`).
fn flags(layout: &Layout, mem: &mut [u8], zero: bool, overflow: bool, negative: bool) {
    flag(layout, mem, 0, zero);
    flag(layout, mem, 1, overflow);
    flag(layout, mem, 2, negative);
}

/// `Exec::divide_by_zero`.
fn divide_by_zero(layout: &Layout, mem: &mut [u8]) {
    flags(layout, mem, false, false, false);
    flag(layout, mem, 3, true);
}

/// math.rs `store_int`: the exact result wrapped into `width` bytes, stored, flags.
fn store_int(layout: &Layout, mem: &mut [u8], at: u32, width: u8, exact: i64) {
    let bits = u32::from(width) * 8;
    let (lo, hi) = (-(1i64 << (bits - 1)), (1i64 << (bits - 1)) - 1);
    let wrapped = ((exact as i128).rem_euclid(1i128 << bits)) as i64;
    let signed = if wrapped > hi {
        wrapped - (1i64 << bits)
    } else {
        wrapped
    };
    store(mem, at, width, wrapped as u32);
    flags(
        layout,
        mem,
        signed == 0,
        !(lo..=hi).contains(&exact),
        signed < 0,
    );
}

fn width_mask(width: u8) -> u32 {
    if width >= 4 {
        u32::MAX
    } else {
        (1u32 << (u32::from(width) * 8)) - 1
    }
}

/// A REAL already rounded to an integer into the DINT at `dst`, or flag 1.
fn real_to_dint(layout: &Layout, mem: &mut [u8], dst: u32, r: f32) {
    let ok = r.is_finite() && (-2_147_483_648.0..2_147_483_648.0).contains(&r);
    if ok {
        store(mem, dst, 4, (r as i32) as u32);
    }
    flag(layout, mem, 1, !ok);
}

/// The boxed generic steps, power flow known (their handlers, line by line).
fn boxed(layout: &Layout, step: &Step, mem: &mut [u8]) {
    match *step {
        Step::Logic {
            op,
            src,
            dst,
            width,
        } => {
            let (a, b) = (load(mem, dst, width), load(mem, src, width));
            let r = match op {
                Logic::And => a & b,
                Logic::Or => a | b,
                Logic::Xor => a ^ b,
            } & width_mask(width);
            store(mem, dst, width, r);
            flags(layout, mem, r == 0, false, false);
        }
        Step::Invert { at, width } => {
            let r = !load(mem, at, width) & width_mask(width);
            store(mem, at, width, r);
            flags(layout, mem, r == 0, false, false);
        }
        Step::IncDec { at, width, up } => {
            let delta = if up { 1 } else { -1 };
            if width == 1 {
                let v = i64::from(load(mem, at, 1)) + delta;
                let r = v.rem_euclid(256);
                store(mem, at, 1, r as u32);
                flags(layout, mem, r == 0, !(0..=255).contains(&v), false);
            } else {
                let v = sign_extend(load(mem, at, width), width) + delta;
                store_int(layout, mem, at, width, v);
            }
        }
        Step::Divide { src, dst, width } => {
            let a = sign_extend(load(mem, dst, width), width);
            let b = sign_extend(load(mem, src, width), width);
            if b == 0 {
                divide_by_zero(layout, mem);
                return;
            }
            flag(layout, mem, 3, false);
            let q = a / b;
            if q > (1i64 << (u32::from(width) * 8 - 1)) - 1 {
                flags(layout, mem, false, true, false);
                return;
            }
            store_int(layout, mem, dst, width, q);
        }
        Step::MulWide { src, dst } => {
            let a = sign_extend(load(mem, src, 2), 2);
            let b = i64::from(load(mem, dst, 4) as u16 as i16);
            store_int(layout, mem, dst, 4, a * b);
        }
        Step::DivWide { src, dst } => {
            let d = sign_extend(load(mem, src, 2), 2);
            let n = i64::from(load(mem, dst, 4) as u16 as i16);
            if d == 0 {
                divide_by_zero(layout, mem);
                return;
            }
            flag(layout, mem, 3, false);
            if n == -32768 && d == -1 {
                flags(layout, mem, false, true, false);
                return;
            }
            let (q, r) = (n.wrapping_div(d), n.wrapping_rem(d));
            let v = (u32::from(r as u16) << 16) | u32::from(q as u16);
            store(mem, dst, 4, v);
            flags(layout, mem, q == 0, !(-32768..=32767).contains(&q), q < 0);
        }
        Step::Shift {
            op,
            at,
            width,
            count,
        } => {
            let w = u32::from(width) * 8;
            let m = width_mask(width);
            let v = load(mem, at, width) & m;
            let n = load(mem, count, 1) & 0xFF;
            let (r, out) = match op {
                Shift::Right => (
                    if n >= w { 0 } else { v >> n },
                    (1..=w).contains(&n) && (v >> (n - 1)) & 1 == 1,
                ),
                Shift::Left => (
                    if n >= w { 0 } else { (v << n) & m },
                    (1..=w).contains(&n) && (v >> (w - n)) & 1 == 1,
                ),
                Shift::RotateRight | Shift::RotateLeft => {
                    let n = n % w;
                    if n == 0 {
                        (v, false)
                    } else if op == Shift::RotateRight {
                        let r = ((v >> n) | (v << (w - n))) & m;
                        (r, (r >> (w - 1)) & 1 == 1)
                    } else {
                        let r = ((v << n) | (v >> (w - n))) & m;
                        (r, r & 1 == 1)
                    }
                }
            };
            store(mem, at, width, r);
            flag(layout, mem, 0, r == 0);
            flag(layout, mem, 1, out);
        }
        Step::Convert { op, src, dst } => convert(layout, mem, op, src, dst),
        Step::RealMath { op, src, dst } => {
            if op == RealOp::Div {
                if f32::from_bits(load(mem, src, 4)) == 0.0 {
                    divide_by_zero(layout, mem);
                    return;
                }
                flag(layout, mem, 3, false);
            }
            let a = f32::from_bits(load(mem, dst, 4));
            let b = f32::from_bits(load(mem, src, 4));
            let r = match op {
                RealOp::Add => a + b,
                RealOp::Sub => a - b,
                RealOp::Mul => a * b,
                RealOp::Div => a / b,
            };
            store(mem, dst, 4, r.to_bits());
            flags(layout, mem, r == 0.0, !r.is_finite(), r < 0.0);
        }
        Step::Sqrt { src, dst } => {
            let r = f32::from_bits(load(mem, src, 4)).sqrt();
            store(mem, dst, 4, r.to_bits());
            flags(layout, mem, r == 0.0, !r.is_finite(), false);
        }
        Step::Const { value, dst, width } => store(mem, dst, width, value),
        Step::Swap { at } => {
            let v = load(mem, at, 2) as u16;
            store(mem, at, 2, u32::from(v.swap_bytes()));
        }
        _ => unreachable!("not a boxed generic step"),
    }
}

/// convert.rs, one conversion.
fn convert(layout: &Layout, mem: &mut [u8], op: Convert, src: u32, dst: u32) {
    let (from, to) = op.widths();
    let v = load(mem, src, from);
    match op {
        Convert::Bti => store(mem, dst, to, v & 0xFF),
        Convert::Itb => {
            let v = v as u16 as i16;
            let ok = (0..=255).contains(&v);
            if ok {
                store(mem, dst, to, v as u32);
            }
            flag(layout, mem, 1, !ok);
        }
        Convert::Itd => store(mem, dst, to, v as u16 as i16 as i32 as u32),
        Convert::Dti => {
            let v = v as i32;
            let ok = i16::try_from(v).is_ok();
            if ok {
                store(mem, dst, to, u32::from(v as u16));
            }
            flag(layout, mem, 1, !ok);
        }
        Convert::Dtr => store(mem, dst, to, (v as i32 as f32).to_bits()),
        Convert::Round => real_to_dint(layout, mem, dst, f32::from_bits(v).round()),
        Convert::Trunc => real_to_dint(layout, mem, dst, f32::from_bits(v).trunc()),
        Convert::Bcdi => {
            let v = v & 0xFFFF;
            let digits = [(v >> 12) & 0xF, (v >> 8) & 0xF, (v >> 4) & 0xF, v & 0xF];
            let ok = digits.iter().all(|d| *d <= 9);
            if ok {
                store(mem, dst, to, digits.iter().fold(0, |acc, d| acc * 10 + d));
            }
            flag(layout, mem, 6, !ok);
        }
        Convert::Ibcd => {
            let v = v as u16 as i16;
            let ok = (0..=9999).contains(&v);
            if ok {
                let v = v as u32;
                let bcd =
                    ((v / 1000) << 12) | ((v / 100 % 10) << 8) | ((v / 10 % 10) << 4) | (v % 10);
                store(mem, dst, to, bcd);
            }
            flag(layout, mem, 6, !ok);
        }
        Convert::Seg => store(mem, dst, to, SEGMENTS[(v & 0xF) as usize]),
        Convert::Deco => store(mem, dst, to, 1 << (v & 0xF)),
        Convert::Enco => {
            let v = v & 0xFFFF;
            if v != 0 {
                store(mem, dst, to, v.trailing_zeros());
            }
            flag(layout, mem, 1, v == 0);
        }
    }
}

/// Seven-segment patterns of 0..F (convert.rs).
const SEGMENTS: [u32; 16] = [
    0x3F, 0x06, 0x5B, 0x4F, 0x66, 0x6D, 0x7D, 0x07, 0x7F, 0x6F, 0x77, 0x7C, 0x39, 0x5E, 0x79, 0x71,
];
