//! What `compile` demands before any code is generated: every memory access a step can
//! make lies inside `Layout::memory_len` (so the generated code, which does no checks of
//! its own, never leaves the slice `Module::run` was given: a timer's word, preset word
//! and 8 bytes of state, a counter's word, preset word and 4 bytes of state, an edge's
//! byte, every byte an S/R touches), widths and bit numbers are ones the steps have,
//! timers have a resolution, every Jump has its Label later in its function (once),
//! Calls name existing functions without a cycle, and no function a Call enters holds
//! an Escape. It generates nothing.

use crate::{Function, JitError, Layout, Preset, Step};

/// Check the layout and every step of every function.
pub(crate) fn check(layout: &Layout, functions: &[Function]) -> Result<(), JitError> {
    let len = u64::from(layout.memory_len);
    if u64::from(layout.flags_at) >= len {
        return Err(JitError::Layout {
            what: "the math flags byte (flags_at)",
        });
    }
    if let Some((start, l)) = layout.local {
        if u64::from(start) + u64::from(l) > len {
            return Err(JitError::Layout { what: "the L area" });
        }
    }
    for (function, f) in functions.iter().enumerate() {
        for (step, s) in f.steps.iter().enumerate() {
            check_step(layout, functions.len(), s).map_err(|e| e.at(function, step))?;
        }
        labels(function, f)?;
    }
    no_cycles(functions)?;
    no_escape_in_callees(functions)
}

/// No Escape in a function that some Call enters: its early return would leave the
/// caller's code mid-step (the VM resumes only at a record of the region it entered).
fn no_escape_in_callees(functions: &[Function]) -> Result<(), JitError> {
    for (caller, f) in functions.iter().enumerate() {
        for s in &f.steps {
            let Step::Call { callee, .. } = *s else {
                continue;
            };
            let c = callee as usize;
            if let Some(step) = functions[c]
                .steps
                .iter()
                .position(|s| matches!(s, Step::Escape { .. }))
            {
                return Err(JitError::EscapeInCallee {
                    function: c,
                    step,
                    caller,
                });
            }
        }
    }
    Ok(())
}

/// Every Label number once per function, every Jump to a Label later in it (forward
/// jumps only: the function still runs each step at most once).
fn labels(function: usize, f: &Function) -> Result<(), JitError> {
    let mut seen = std::collections::BTreeSet::new();
    for (step, s) in f.steps.iter().enumerate() {
        if let Step::Label { number } = *s {
            if !seen.insert(number) {
                return Err(JitError::DuplicateLabel {
                    function,
                    step,
                    label: number,
                });
            }
        }
    }
    for (step, s) in f.steps.iter().enumerate() {
        if let Step::Jump { label } = *s {
            let later = f.steps[step + 1..].contains(&Step::Label { number: label });
            if !later {
                return Err(JitError::NoLabel {
                    function,
                    step,
                    label,
                });
            }
        }
    }
    Ok(())
}

/// The bytes of `n` bits from bit `bit` of the byte at `at` on: (first byte, count;
/// none when `n` is 0).
pub(crate) fn bit_span(at: u32, bit: u8, n: u16) -> (u64, u64) {
    if n == 0 {
        return (u64::from(at), 0);
    }
    let bits = u64::from(bit) + u64::from(n);
    (u64::from(at), bits.div_ceil(8))
}

fn preset(layout: &Layout, p: Preset) -> Result<(), Fault> {
    match p {
        Preset::Const(_) => Ok(()),
        Preset::Word(at) => inside(layout, at, 2),
    }
}

/// A step's fault before it knows where it is.
enum Fault {
    OutOfRange { at: u32, width: u8 },
    BitNumber(u8),
    Width(u8),
    NoSuchCallee(u32),
    Resolution,
}

impl Fault {
    fn at(self, function: usize, step: usize) -> JitError {
        match self {
            Fault::OutOfRange { at, width } => JitError::OutOfRange {
                function,
                step,
                at,
                width,
            },
            Fault::BitNumber(bit) => JitError::BitNumber {
                function,
                step,
                bit,
            },
            Fault::Width(width) => JitError::Width {
                function,
                step,
                width,
            },
            Fault::Resolution => JitError::Resolution { function, step },
            Fault::NoSuchCallee(callee) => JitError::NoSuchCallee {
                function,
                step,
                callee,
            },
        }
    }
}

fn inside(layout: &Layout, at: u32, width: u8) -> Result<(), Fault> {
    if u64::from(at) + u64::from(width) > u64::from(layout.memory_len) {
        return Err(Fault::OutOfRange { at, width });
    }
    Ok(())
}

fn bit(layout: &Layout, at: u32, bit: u8) -> Result<(), Fault> {
    if bit > 7 {
        return Err(Fault::BitNumber(bit));
    }
    inside(layout, at, 1)
}

fn width(width: u8, allowed: &[u8]) -> Result<(), Fault> {
    if !allowed.contains(&width) {
        return Err(Fault::Width(width));
    }
    Ok(())
}

fn check_step(layout: &Layout, functions: usize, step: &Step) -> Result<(), Fault> {
    match *step {
        Step::Timer {
            at,
            state,
            preset: p,
            res,
            ..
        } => {
            inside(layout, at, 2)?;
            inside(layout, state, 8)?;
            preset(layout, p)?;
            if res == 0 {
                return Err(Fault::Resolution);
            }
            Ok(())
        }
        Step::Counter {
            at,
            state,
            preset: p,
            ..
        } => {
            inside(layout, at, 2)?;
            inside(layout, state, 4)?;
            preset(layout, p)
        }
        Step::Edge { state, .. } => inside(layout, state, 1),
        Step::SetBits { at, bit: b, n, .. } => {
            if b > 7 {
                return Err(Fault::BitNumber(b));
            }
            let (first, bytes) = bit_span(at, b, n);
            if first + bytes > u64::from(layout.memory_len) {
                // The last byte it would touch.
                let last = first + bytes - 1;
                return Err(Fault::OutOfRange {
                    at: u32::try_from(last).unwrap_or(u32::MAX),
                    width: 1,
                });
            }
            Ok(())
        }
        // Checked per function (`labels`).
        Step::Jump { .. } | Step::Label { .. } => Ok(()),
        Step::Network | Step::Not | Step::Ald | Step::Old | Step::Lps | Step::Lrd | Step::Lpp => {
            Ok(())
        }
        Step::Ld { at, bit: b }
        | Step::Ldn { at, bit: b }
        | Step::A { at, bit: b }
        | Step::An { at, bit: b }
        | Step::O { at, bit: b }
        | Step::On { at, bit: b }
        | Step::Assign { at, bit: b } => bit(layout, at, b),
        Step::Move { src, dst, width: w } => {
            width(w, &[1, 2, 4])?;
            inside(layout, src, w)?;
            inside(layout, dst, w)
        }
        Step::Math {
            src, dst, width: w, ..
        } => {
            width(w, &[2, 4])?;
            inside(layout, src, w)?;
            inside(layout, dst, w)
        }
        Step::Compare { a, b, width: w, .. } => {
            width(w, &[1, 2, 4])?;
            inside(layout, a, w)?;
            inside(layout, b, w)
        }
        Step::Call { callee, ref args } => {
            if callee as usize >= functions {
                return Err(Fault::NoSuchCallee(callee));
            }
            for a in args {
                if let Some((var_bit, param_bit)) = a.bits {
                    width(a.width, &[1])?;
                    bit(layout, a.var, var_bit)?;
                    bit(layout, a.param, param_bit)?;
                }
                width(a.width, &[1, 2, 4])?;
                inside(layout, a.var, a.width)?;
                inside(layout, a.param, a.width)?;
            }
            Ok(())
        }
        // ---- Generic families ----
        Step::Logic {
            src, dst, width: w, ..
        } => {
            width(w, &[1, 2, 4])?;
            inside(layout, src, w)?;
            inside(layout, dst, w)
        }
        Step::Invert { at, width: w } | Step::IncDec { at, width: w, .. } => {
            width(w, &[1, 2, 4])?;
            inside(layout, at, w)
        }
        Step::Divide { src, dst, width: w } => {
            width(w, &[2, 4])?;
            inside(layout, src, w)?;
            inside(layout, dst, w)
        }
        Step::MulWide { src, dst } | Step::DivWide { src, dst } => {
            inside(layout, src, 2)?;
            inside(layout, dst, 4)
        }
        Step::Shift {
            at,
            width: w,
            count,
            ..
        } => {
            width(w, &[1, 2, 4])?;
            inside(layout, at, w)?;
            inside(layout, count, 1)
        }
        Step::Convert { op, src, dst } => {
            let (from, to) = op.widths();
            inside(layout, src, from)?;
            inside(layout, dst, to)
        }
        Step::RealMath { src, dst, .. } | Step::Sqrt { src, dst } => {
            inside(layout, src, 4)?;
            inside(layout, dst, 4)
        }
        Step::CompareReal { a, b, .. } => {
            inside(layout, a, 4)?;
            inside(layout, b, 4)
        }
        Step::Const { dst, width: w, .. } => {
            width(w, &[1, 2, 4])?;
            inside(layout, dst, w)
        }
        Step::Swap { at } => inside(layout, at, 2),
        Step::Store { at, .. } => inside(layout, at, 1),
        Step::Lds { .. } | Step::Nop | Step::Escape { .. } => Ok(()),
    }
}

/// The call graph is acyclic (callees already checked to exist). Depth-first, without
/// recursion of its own (a long chain of calls must not overflow the compiler's stack).
fn no_cycles(functions: &[Function]) -> Result<(), JitError> {
    #[derive(Clone, Copy, PartialEq)]
    enum Mark {
        New,
        Open,
        Done,
    }
    let callees = |f: usize| -> Vec<usize> {
        functions[f]
            .steps
            .iter()
            .filter_map(|s| match s {
                Step::Call { callee, .. } => Some(*callee as usize),
                _ => None,
            })
            .collect()
    };
    let mut mark = vec![Mark::New; functions.len()];
    for root in 0..functions.len() {
        if mark[root] != Mark::New {
            continue;
        }
        mark[root] = Mark::Open;
        let mut path = vec![(root, callees(root), 0usize)];
        while let Some((f, next, i)) = path.last_mut() {
            let Some(&c) = next.get(*i) else {
                mark[*f] = Mark::Done;
                path.pop();
                continue;
            };
            *i += 1;
            match mark[c] {
                Mark::Open => return Err(JitError::Recursion { function: c }),
                Mark::Done => {}
                Mark::New => {
                    mark[c] = Mark::Open;
                    path.push((c, callees(c), 0));
                }
            }
        }
    }
    Ok(())
}
