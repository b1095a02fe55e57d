//! Bytes to a layout, functions, memory and a logic stack, then compiled code against
//! `gutta_jit::reference`: the fuzz target `jit_steps` (fuzz/fuzz_targets/jit_steps.rs
//! includes this file), the proptest of random step lists (tests/random.rs) and the
//! replay of the fuzzer's finds (tests/data/fuzz/) all run `check_bytes`. Test code only.

#![allow(dead_code, reason = "each includer uses a part")]

use gutta_jit::{
    compile, reference, Arg, Arith, Combine, Convert, CounterKind, Function, Layout, Logic, Preset,
    RealOp, Rel, Shift, Step, TimerKind,
};

/// Reads bytes; zeros once they run out (every input decodes to something).
pub struct Reader<'a> {
    data: &'a [u8],
}

impl Reader<'_> {
    pub fn byte(&mut self) -> u8 {
        match self.data.split_first() {
            Some((&b, rest)) => {
                self.data = rest;
                b
            }
            None => 0,
        }
    }

    fn below(&mut self, n: u32) -> u32 {
        let v = u32::from(self.byte()) | (u32::from(self.byte()) << 8);
        v % n.max(1)
    }

    fn u32(&mut self) -> u32 {
        u32::from_le_bytes([self.byte(), self.byte(), self.byte(), self.byte()])
    }
}

/// A decoded program and what to run it on.
#[derive(Debug, Clone)]
pub struct Case {
    pub layout: Layout,
    pub functions: Vec<Function>,
    pub memory: Vec<u8>,
    pub stack: u32,
    /// Some index, width, bit or callee may be out of range (`compile` may refuse).
    pub loose: bool,
}

const STACK_MASKS: [u32; 4] = [0x1FF, 0xFF, 0x3, u32::MAX];

/// Decode a case. Strict cases (first byte below 0xC0) are valid by construction:
/// indices inside the memory, widths the steps have, Calls only to later functions.
pub fn decode(data: &[u8]) -> Case {
    let mut r = Reader { data };
    let loose = r.byte() >= 0xC0;
    let memory_len = 8 + r.below(57);
    let flags_at = r.below(memory_len);
    let local = if r.byte() & 1 == 1 {
        let start = r.below(memory_len);
        Some((start, r.below(memory_len - start + 1)))
    } else {
        None
    };
    let stack_mask = STACK_MASKS[r.below(4) as usize];
    let layout = Layout {
        memory_len,
        flags_at,
        stack_mask,
        local,
    };
    let count = 1 + r.below(4);
    let mut functions: Vec<Function> = (0..count)
        .map(|f| {
            let large = r.byte() & 3 == 0;
            let mut steps: Vec<Step> = (0..r.below(25))
                .map(|_| step(&mut r, &layout, f, count, loose))
                .collect();
            if large {
                grow(&mut steps);
            }
            if !loose {
                forward_jumps(&mut steps);
            }
            Function { steps }
        })
        .collect();
    if !loose {
        no_escapes_in_callees(&mut functions);
    }
    let memory = (0..memory_len).map(|_| r.byte()).collect();
    let stack = r.u32() & stack_mask;
    Case {
        layout,
        functions,
        memory,
        stack,
        loose,
    }
}

/// Repeat `steps` (or Nots, when empty) until there are more than 64 of them: long
/// functions, many Calls and power runs in one function.
fn grow(steps: &mut Vec<Step>) {
    if steps.is_empty() {
        steps.push(Step::Not);
    }
    let mut i = 0;
    while steps.len() <= 64 {
        steps.push(steps[i].clone());
        i += 1;
    }
}

/// Strict functions: every Label a number of its own, every Jump to one of the Labels
/// after it (chosen by its decoded number), or a Not when none follows.
fn forward_jumps(steps: &mut [Step]) {
    let mut next = 0u16;
    for s in steps.iter_mut() {
        if let Step::Label { number } = s {
            *number = next;
            next += 1;
        }
    }
    for i in 0..steps.len() {
        if let Step::Jump { label } = steps[i] {
            let later: Vec<u16> = steps[i + 1..]
                .iter()
                .filter_map(|s| match s {
                    Step::Label { number } => Some(*number),
                    _ => None,
                })
                .collect();
            steps[i] = match later.len() {
                0 => Step::Not,
                n => Step::Jump {
                    label: later[usize::from(label) % n],
                },
            };
        }
    }
}

fn preset(r: &mut Reader, layout: &Layout, loose: bool) -> Preset {
    if r.byte() & 1 == 0 {
        Preset::Const(i16::from_le_bytes([r.byte(), r.byte()]))
    } else {
        Preset::Word(index(r, layout, 2, loose))
    }
}

/// A memory index for `width` bytes (loose: anything up to 255, maybe outside).
fn index(r: &mut Reader, layout: &Layout, width: u8, loose: bool) -> u32 {
    if loose && r.byte() & 7 == 0 {
        return u32::from(r.byte());
    }
    r.below(layout.memory_len - u32::from(width) + 1)
}

fn width(r: &mut Reader, allowed: &[u8], loose: bool) -> u8 {
    if loose && r.byte() & 7 == 0 {
        return r.byte() % 6;
    }
    allowed[r.below(allowed.len() as u32) as usize]
}

fn bit(r: &mut Reader, loose: bool) -> u8 {
    if loose && r.byte() & 7 == 0 {
        return r.byte() % 10;
    }
    r.byte() % 8
}

fn step(r: &mut Reader, layout: &Layout, f: u32, functions: u32, loose: bool) -> Step {
    if r.byte() & 3 == 0 {
        return generic_step(r, layout, loose);
    }
    let kind = r.below(24);
    match kind {
        0 => Step::Network,
        1..=7 => {
            let at = index(r, layout, 1, loose);
            let bit = bit(r, loose);
            match kind {
                1 => Step::Ld { at, bit },
                2 => Step::Ldn { at, bit },
                3 => Step::A { at, bit },
                4 => Step::An { at, bit },
                5 => Step::O { at, bit },
                6 => Step::On { at, bit },
                _ => Step::Assign { at, bit },
            }
        }
        8 => Step::Not,
        9 => Step::Ald,
        10 => Step::Old,
        11 => Step::Lps,
        12 => Step::Lrd,
        13 => Step::Lpp,
        14 => {
            let width = width(r, &[1, 2, 4], loose);
            let w = width.min(4);
            Step::Move {
                src: index(r, layout, w, loose),
                dst: index(r, layout, w, loose),
                width,
            }
        }
        15 => {
            let op = [Arith::Add, Arith::Sub, Arith::Mul][r.below(3) as usize];
            let width = width(r, &[2, 4], loose);
            let w = width.min(4);
            Step::Math {
                op,
                src: index(r, layout, w, loose),
                dst: index(r, layout, w, loose),
                width,
            }
        }
        16 => {
            let combine = [Combine::Load, Combine::And, Combine::Or][r.below(3) as usize];
            let rel = [Rel::Eq, Rel::Ne, Rel::Lt, Rel::Le, Rel::Gt, Rel::Ge][r.below(6) as usize];
            let width = width(r, &[1, 2, 4], loose);
            let w = width.min(4);
            Step::Compare {
                combine,
                rel,
                a: index(r, layout, w, loose),
                b: index(r, layout, w, loose),
                width,
            }
        }
        18 => {
            let kind = [TimerKind::On, TimerKind::Off, TimerKind::Retentive][r.below(3) as usize];
            let at = index(r, layout, 2, loose);
            let state = index(r, layout, 8, loose);
            let preset = preset(r, layout, loose);
            let res = match r.below(5) {
                0 => 1,
                1 => 10,
                2 => 100,
                3 if loose => u32::from(r.byte()),
                _ => 1 + u32::from(r.byte()),
            };
            let scan_ms = [7, 10, 100, 1, u32::from(r.byte())][r.below(5) as usize];
            Step::Timer {
                kind,
                at,
                state,
                preset,
                res,
                scan_ms,
            }
        }
        19 => {
            let kind =
                [CounterKind::Up, CounterKind::Down, CounterKind::UpDown][r.below(3) as usize];
            let at = index(r, layout, 2, loose);
            let state = index(r, layout, 4, loose);
            let preset = preset(r, layout, loose);
            let max = match r.below(3) {
                0 => i16::MAX,
                _ => i16::from_le_bytes([r.byte(), r.byte()]),
            };
            Step::Counter {
                kind,
                at,
                state,
                preset,
                max,
            }
        }
        20 => Step::Edge {
            rising: r.byte() & 1 == 1,
            state: index(r, layout, 1, loose),
        },
        21 => {
            let at = index(r, layout, 1, loose);
            let bit = bit(r, loose);
            let n = if loose {
                u16::from(r.byte())
            } else {
                // Bits left from `bit` of `at` to the memory's end.
                let room = (layout.memory_len - at) * 8 - u32::from(bit);
                r.below(room.min(48) + 1) as u16
            };
            Step::SetBits {
                at,
                bit,
                n,
                value: r.byte() & 1 == 1,
            }
        }
        22 => Step::Jump {
            label: u16::from(r.byte() % 4),
        },
        23 => Step::Label {
            number: u16::from(r.byte() % 4),
        },
        _ => {
            let later = functions - f - 1;
            if later == 0 && !loose {
                return Step::Not;
            }
            let callee = if loose && r.byte() & 3 == 0 {
                r.below(functions + 1)
            } else if later == 0 {
                return Step::Lpp;
            } else {
                f + 1 + r.below(later)
            };
            let args = (0..r.below(4))
                .map(|_| {
                    let width = width(r, &[1, 2, 4], loose);
                    let w = width.min(4);
                    let io = r.byte();
                    let var = index(r, layout, w, loose);
                    let param = index(r, layout, w, loose);
                    // Bit 2 of `io`: a BOOL argument (its bits drawn after the rest).
                    let bits = (io & 4 == 4).then(|| {
                        let b = r.byte();
                        if loose {
                            (b & 15, b >> 4)
                        } else {
                            (b & 7, (b >> 4) & 7)
                        }
                    });
                    Arg {
                        var,
                        param,
                        width: if bits.is_some() && !loose { 1 } else { width },
                        input: io & 1 == 1,
                        output: io & 2 == 2,
                        bits,
                    }
                })
                .collect();
            Step::Call { callee, args }
        }
    }
}

// ---- Generic families ----------------------------------------------------

/// One of the generic families' steps.
fn generic_step(r: &mut Reader, layout: &Layout, loose: bool) -> Step {
    let kind = r.below(17);
    let any = |r: &mut Reader, w: u8| index(r, layout, w, loose);
    match kind {
        0 => {
            let op = [Logic::And, Logic::Or, Logic::Xor][r.below(3) as usize];
            let width = width(r, &[1, 2, 4], loose);
            let w = width.min(4);
            Step::Logic {
                op,
                src: any(r, w),
                dst: any(r, w),
                width,
            }
        }
        1 => {
            let width = width(r, &[1, 2, 4], loose);
            Step::Invert {
                at: any(r, width.min(4)),
                width,
            }
        }
        2 => {
            let width = width(r, &[1, 2, 4], loose);
            Step::IncDec {
                at: any(r, width.min(4)),
                width,
                up: r.byte() & 1 == 1,
            }
        }
        3 => {
            let width = width(r, &[2, 4], loose);
            let w = width.min(4);
            Step::Divide {
                src: any(r, w),
                dst: any(r, w),
                width,
            }
        }
        4 => Step::MulWide {
            src: any(r, 2),
            dst: any(r, 4),
        },
        5 => Step::DivWide {
            src: any(r, 2),
            dst: any(r, 4),
        },
        6 => {
            let op = [
                Shift::Right,
                Shift::Left,
                Shift::RotateRight,
                Shift::RotateLeft,
            ][r.below(4) as usize];
            let width = width(r, &[1, 2, 4], loose);
            Step::Shift {
                op,
                at: any(r, width.min(4)),
                width,
                count: any(r, 1),
            }
        }
        7 => {
            let op = Convert::ALL[r.below(Convert::ALL.len() as u32) as usize];
            let (from, to) = op.widths();
            Step::Convert {
                op,
                src: any(r, from),
                dst: any(r, to),
            }
        }
        8 => {
            let op = [RealOp::Add, RealOp::Sub, RealOp::Mul, RealOp::Div][r.below(4) as usize];
            Step::RealMath {
                op,
                src: any(r, 4),
                dst: any(r, 4),
            }
        }
        9 => Step::Sqrt {
            src: any(r, 4),
            dst: any(r, 4),
        },
        10 => {
            let combine = [Combine::Load, Combine::And, Combine::Or][r.below(3) as usize];
            let rel = [Rel::Eq, Rel::Ne, Rel::Lt, Rel::Le, Rel::Gt, Rel::Ge][r.below(6) as usize];
            Step::CompareReal {
                combine,
                rel,
                a: any(r, 4),
                b: any(r, 4),
            }
        }
        11 => {
            let width = width(r, &[1, 2, 4], loose);
            Step::Const {
                value: r.u32(),
                dst: any(r, width.min(4)),
                width,
            }
        }
        12 => Step::Swap { at: any(r, 2) },
        13 => Step::Lds {
            n: u16::from(r.byte() % 40),
        },
        14 => Step::Nop,
        15 => Step::Store {
            at: any(r, 1),
            value: r.byte(),
        },
        _ => Step::Escape {
            id: u16::from_le_bytes([r.byte(), r.byte()]),
        },
    }
}

/// Strict cases: an Escape in a function some Call enters becomes a Not (`compile`
/// refuses it there).
fn no_escapes_in_callees(functions: &mut [Function]) {
    let callees: Vec<usize> = functions
        .iter()
        .flat_map(|f| &f.steps)
        .filter_map(|s| match s {
            Step::Call { callee, .. } => Some(*callee as usize),
            _ => None,
        })
        .collect();
    for c in callees {
        if let Some(f) = functions.get_mut(c) {
            for s in &mut f.steps {
                if let Step::Escape { .. } = s {
                    *s = Step::Not;
                }
            }
        }
    }
}

/// Compile the case and run every function in turn on the same memory, both compiled
/// and by the reference; memory, stack and count must agree after each. A strict case
/// must compile.
pub fn check_case(case: &Case) {
    let module = match compile(&case.layout, &case.functions) {
        Ok(module) => module,
        Err(e) => {
            assert!(case.loose, "a valid case was refused: {e}\n{case:#?}");
            assert!(!e.to_string().is_empty());
            return;
        }
    };
    let (mut jit_memory, mut ref_memory) = (case.memory.clone(), case.memory.clone());
    for f in 0..case.functions.len() {
        let (mut jit_stack, mut ref_stack) = (case.stack, case.stack);
        let jit_exit = module.enter(f, &mut jit_memory, &mut jit_stack);
        let ref_exit = reference::enter(
            &case.layout,
            &case.functions,
            f,
            &mut ref_memory,
            &mut ref_stack,
        );
        assert_eq!(
            jit_memory, ref_memory,
            "memory after function {f}\n{case:#?}"
        );
        assert_eq!(jit_stack, ref_stack, "stack after function {f}\n{case:#?}");
        assert_eq!(
            jit_exit, ref_exit,
            "count and exit of function {f}\n{case:#?}"
        );
    }
}

/// The fuzz target's body.
pub fn check_bytes(data: &[u8]) {
    check_case(&decode(data));
}
