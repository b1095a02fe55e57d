//! The semantics of `Step`s as a plain interpreter, mirroring `vm/src/fast.rs` `fast_op`
//! and `vm/src/calls.rs` (enter_planned + return_planned) line by line. The tests and the
//! fuzz target compare the compiled code against it; it is also the documentation of
//! what the code must do. Slow on purpose (no fusing, no tricks) and only for step lists
//! that `compile` accepts: it indexes the memory (panics outside it) and would not end
//! on a cycle of Calls.

use crate::{Arith, Combine, Function, Layout, Rel, Step};

/// Run function `f` on `memory` with the logic stack `stack`, as `Module::run` does;
/// returns the instructions executed.
pub fn run(
    layout: &Layout,
    functions: &[Function],
    f: usize,
    memory: &mut [u8],
    stack: &mut u32,
) -> u64 {
    let mut count = 0;
    for s in &functions[f].steps {
        count += step(layout, functions, s, memory, stack);
    }
    count
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

/// Execute one step; returns the instructions it counts.
pub fn step(
    layout: &Layout,
    functions: &[Function],
    step: &Step,
    mem: &mut [u8],
    st: &mut u32,
) -> u64 {
    let (s, mask) = (*st, layout.stack_mask);
    *st = match *step {
        Step::Timer { .. }
        | Step::Counter { .. }
        | Step::Edge { .. }
        | Step::SetBits { .. }
        | Step::Jump { .. }
        | Step::Label { .. } => unimplemented!("issue 31: not stated yet"),
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
                .map(|a| {
                    if a.input {
                        load(mem, a.var, a.width)
                    } else {
                        0
                    }
                })
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
                    store(mem, a.param, a.width, v);
                }
            }
            let mut callee_stack = 0;
            let executed = run(layout, functions, callee as usize, mem, &mut callee_stack);
            // return_planned: outputs read from the parameters, L and the stack
            // restored, outputs stored into the variables in argument order.
            let outputs: Vec<u32> = args
                .iter()
                .map(|a| {
                    if a.output {
                        load(mem, a.param, a.width)
                    } else {
                        0
                    }
                })
                .collect();
            if let (Some(l), Some(saved)) = (local, saved) {
                mem[l].copy_from_slice(&saved);
            }
            for (a, &v) in args.iter().zip(&outputs) {
                if a.output {
                    store(mem, a.var, a.width, v);
                }
            }
            return 1 + executed;
        }
    };
    1
}
