//! The compiled tier (docs/vm.md, "Speed"; docs/vm-jit.md): runs of a unit's
//! pre-decoded operations that need no run-time lookups (bit logic, moves, integer math,
//! compares, planned CALLs of subroutines that are themselves entirely such operations)
//! become native functions through the `gutta-jit` crate (Cranelift). The interpreter
//! stays the reference: a region runs natively only when the result cannot differ (the
//! watchdog cannot trip inside it, no CALL inside can go deeper than CallDepth, no
//! breakpoint is set); otherwise the interpreter runs the same records.
//!
//! A region starts at record 0 of a unit or right after a record the tier cannot take
//! (those are the only records the interpreter reaches other than by falling through,
//! apart from a resumed pause, which runs interpreted up to the next region).

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex, PoisonError, Weak};

use gutta_jit::{Arg, Function, Layout, Module, Step};

use crate::decode::Unit;
use crate::memory::Memory;
use crate::op::{Arith, Combine, Op, Rel};
use crate::program::Program;

/// Regions shorter than this (in instructions) stay interpreted: entering native code
/// costs about as much as interpreting a couple of operations.
const MIN_REGION: u64 = 3;

/// Longer runs are cut into regions of this many records: Cranelift compiles a few
/// medium functions faster than one huge one (10,000 mixed steps: 220 ms whole, 140 ms
/// in pieces of 500 to 2,000), and a region's bound on the watchdog stays small.
const MAX_REGION: usize = 1024;

/// A compiled region of a unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Region {
    /// First record.
    pub pc: u32,
    /// Records it covers (the interpreter continues at `pc + records`).
    pub records: u32,
    /// Its function in the module.
    pub function: u32,
    /// Most instructions it can execute (every CALL in it taken).
    pub max_count: u64,
    /// Deepest nesting of CALLs in it (0: none).
    pub depth: u32,
}

/// The compiled program: the module (shared by every VM of the same program in the
/// process) and, per unit page, its regions by first record.
pub(crate) struct Native {
    pub module: Arc<Module>,
    /// The module was compiled for another VM first.
    pub shared: bool,
    pub regions: Vec<Vec<Region>>,
}

impl std::fmt::Debug for Native {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Native")
            .field("code_bytes", &self.module.code_bytes())
            .field("regions", &self.regions.iter().map(Vec::len).sum::<usize>())
            .finish()
    }
}

impl Native {
    /// The region of unit `page` starting at record `pc`.
    #[inline]
    pub fn region(&self, page: u8, pc: usize) -> Option<&Region> {
        let regions = self.regions.get(page as usize)?;
        let k = regions.binary_search_by_key(&pc, |r| r.pc as usize).ok()?;
        regions.get(k)
    }
}

/// What the tier knows of a whole unit that CALLs may enter natively.
#[derive(Debug, Clone, Copy)]
struct Callee {
    function: u32,
    max_count: u64,
    depth: u32,
}

/// Builds the functions: whole units first (as callees, in call order), then regions.
struct Builder<'a> {
    program: &'a Program,
    memory: &'a Memory,
    functions: Vec<Function>,
    /// Per page: `Some` once the unit is known to compile whole, `None` when it cannot;
    /// absent while being looked at (a cycle of CALLs is not compiled).
    whole: BTreeMap<u8, Option<Callee>>,
}

/// The step of a bit operation: its byte index and bit number.
fn bit(b: crate::op::Bit, step: impl FnOnce(u32, u8) -> Step) -> Step {
    step(b.at, b.mask.trailing_zeros() as u8)
}

/// The step of a plain operation that needs no callee (None: the tier cannot take it).
fn simple_step(op: Op) -> Option<Step> {
    Some(match op {
        Op::Network => Step::Network,
        Op::Ld(b) => bit(b, |at, bit| Step::Ld { at, bit }),
        Op::Ldn(b) => bit(b, |at, bit| Step::Ldn { at, bit }),
        Op::A(b) => bit(b, |at, bit| Step::A { at, bit }),
        Op::An(b) => bit(b, |at, bit| Step::An { at, bit }),
        Op::O(b) => bit(b, |at, bit| Step::O { at, bit }),
        Op::On(b) => bit(b, |at, bit| Step::On { at, bit }),
        Op::Assign(b) => bit(b, |at, bit| Step::Assign { at, bit }),
        Op::Not => Step::Not,
        Op::Ald => Step::Ald,
        Op::Old => Step::Old,
        Op::Lps => Step::Lps,
        Op::Lrd => Step::Lrd,
        Op::Lpp => Step::Lpp,
        Op::Move { src, dst, width } => Step::Move { src, dst, width },
        Op::Math {
            op,
            src,
            dst,
            width,
        } => Step::Math {
            op: match op {
                Arith::Add => gutta_jit::Arith::Add,
                Arith::Sub => gutta_jit::Arith::Sub,
                Arith::Mul => gutta_jit::Arith::Mul,
            },
            src,
            dst,
            width,
        },
        Op::Compare {
            combine,
            rel,
            a,
            b,
            width,
        } => Step::Compare {
            combine: match combine {
                Combine::Load => gutta_jit::Combine::Load,
                Combine::And => gutta_jit::Combine::And,
                Combine::Or => gutta_jit::Combine::Or,
            },
            rel: match rel {
                Rel::Eq => gutta_jit::Rel::Eq,
                Rel::Ne => gutta_jit::Rel::Ne,
                Rel::Lt => gutta_jit::Rel::Lt,
                Rel::Le => gutta_jit::Rel::Le,
                Rel::Gt => gutta_jit::Rel::Gt,
                Rel::Ge => gutta_jit::Rel::Ge,
            },
            a,
            b,
            width,
        },
        // Plain operations are never fused or per-width forms (`Unit::plain_op`).
        Op::Chain { .. }
        | Op::NetworkLoad { .. }
        | Op::MoveB { .. }
        | Op::MoveW { .. }
        | Op::MoveD { .. }
        | Op::MathW { .. }
        | Op::MathD { .. }
        | Op::CompareB { .. }
        | Op::CompareW { .. }
        | Op::CompareD { .. }
        | Op::Call { .. }
        | Op::Timer { .. }
        | Op::Counter { .. }
        | Op::Edge { .. }
        | Op::SetBits { .. }
        | Op::Generic { .. }
        | Op::Break => return None,
    })
}

impl Builder<'_> {
    /// The step of record `pc` of `unit`, with the most instructions it can run and its
    /// CALL depth; None when the tier cannot take it.
    fn step(&mut self, unit: &Unit, pc: usize) -> Option<(Step, u64, u32)> {
        let op = unit.plain_op(pc)?;
        if let Op::Call { plan } = op {
            let plan = unit.calls.get(plan as usize)?;
            let callee = self.whole_unit(plan.callee)?;
            let args = plan
                .args
                .iter()
                .map(|a| Arg {
                    var: a.var,
                    param: a.param,
                    width: a.width,
                    input: a.input,
                    output: a.output,
                })
                .collect();
            return Some((
                Step::Call {
                    callee: callee.function,
                    args,
                },
                1 + callee.max_count,
                1 + callee.depth,
            ));
        }
        if let Op::Generic { .. } = op {
            // Instructions the interpreter runs through `ops/` that the tier compiles
            // from their operands (`tier_generic.rs`).
            let step = crate::tier_generic::generic_step(unit, pc, self.memory)?;
            return Some((step, 1, 0));
        }
        let step = simple_step(op)?;
        let count = u64::from(op != Op::Network);
        Some((step, count, 0))
    }

    /// Unit `page` as one function, if every record of it compiles (and it is not part
    /// of a cycle of CALLs).
    fn whole_unit(&mut self, page: u8) -> Option<Callee> {
        if let Some(known) = self.whole.get(&page) {
            return *known;
        }
        let unit = self.program.unit(page)?.clone();
        // Absent while looking: a CALL back into it (recursion) finds None below.
        self.whole.insert(page, None);
        let mut steps = Vec::with_capacity(unit.ops.len());
        let (mut max_count, mut depth) = (0u64, 0u32);
        for pc in 0..unit.ops.len() {
            let (step, count, d) = self.step(&unit, pc)?;
            steps.push(step);
            max_count = max_count.saturating_add(count);
            depth = depth.max(d);
        }
        let callee = Callee {
            function: self.functions.len() as u32,
            max_count,
            depth,
        };
        self.functions.push(Function { steps });
        self.whole.insert(page, Some(callee));
        Some(callee)
    }

    /// The regions of unit `page`: the whole unit as one when it compiles whole and is
    /// not long, else its runs of compilable records, cut every `MAX_REGION` records.
    fn regions(&mut self, page: u8) -> Vec<Region> {
        let Some(unit) = self.program.unit(page).cloned() else {
            return Vec::new();
        };
        let n = unit.ops.len();
        if n <= MAX_REGION {
            if let Some(whole) = self.whole_unit(page) {
                if whole.max_count < MIN_REGION {
                    return Vec::new();
                }
                return vec![Region {
                    pc: 0,
                    records: n as u32,
                    function: whole.function,
                    max_count: whole.max_count,
                    depth: whole.depth,
                }];
            }
        }
        let mut regions = Vec::new();
        let mut pc = 0;
        while pc < n {
            let start = pc;
            let mut steps = Vec::new();
            let (mut max_count, mut depth) = (0u64, 0u32);
            while pc < n && pc - start < MAX_REGION {
                let Some((step, count, d)) = self.step(&unit, pc) else {
                    break;
                };
                steps.push(step);
                max_count = max_count.saturating_add(count);
                depth = depth.max(d);
                pc += 1;
            }
            let cut = pc - start == MAX_REGION;
            if max_count >= MIN_REGION {
                regions.push(Region {
                    pc: start as u32,
                    records: (pc - start) as u32,
                    function: self.functions.len() as u32,
                    max_count,
                    depth,
                });
                self.functions.push(Function { steps });
            }
            if !cut {
                // The record the tier cannot take (or the end).
                pc += 1;
            }
        }
        regions
    }
}

/// Compile `program`'s units on `memory`'s layout. None when nothing is worth compiling
/// or the code generator refuses (the interpreter then runs everything; the reason is
/// returned for the host to show).
pub(crate) fn compile(
    program: &Program,
    memory: &Memory,
    stack_mask: u32,
) -> Result<Option<Native>, String> {
    let mut b = Builder {
        program,
        memory,
        functions: Vec::new(),
        whole: BTreeMap::new(),
    };
    let mut regions = vec![Vec::new(); 256];
    for page in 0..=255u8 {
        regions[page as usize] = b.regions(page);
    }
    if b.functions.is_empty() {
        return Ok(None);
    }
    let layout = Layout {
        memory_len: u32::try_from(memory.bytes.len()).map_err(|e| e.to_string())?,
        flags_at: program.flags_at as u32,
        stack_mask,
        local: memory
            .span(program.slots.local)
            .map(|(start, len)| (start as u32, len as u32)),
    };
    let (module, shared) = shared_module(layout, b.functions).map_err(|e| e.to_string())?;
    Ok(Some(Native {
        module,
        regions,
        shared,
    }))
}

/// Code compiled in this process, by what it was compiled from: VMs of the same program
/// on the same memory layout (many simulated PLCs, a test suite's fresh VMs) share one
/// module instead of compiling it again. An entry lives while a VM uses its module.
struct SharedCode {
    layout: Layout,
    functions: Vec<Function>,
    module: Weak<Module>,
}

static SHARED: Mutex<Vec<SharedCode>> = Mutex::new(Vec::new());

/// The module for `functions` on `layout`: one a VM of this process already uses, or
/// newly compiled (outside the lock; two VMs compiling the same program at once may
/// both compile it, which costs time, never correctness).
fn shared_module(
    layout: Layout,
    functions: Vec<Function>,
) -> Result<(Arc<Module>, bool), gutta_jit::JitError> {
    {
        let mut shared = SHARED.lock().unwrap_or_else(PoisonError::into_inner);
        shared.retain(|s| s.module.strong_count() > 0);
        let found = shared
            .iter()
            .find(|s| s.layout == layout && s.functions == functions)
            .and_then(|s| s.module.upgrade());
        if let Some(module) = found {
            return Ok((module, true));
        }
    }
    let module = Arc::new(gutta_jit::compile(&layout, &functions)?);
    SHARED
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .push(SharedCode {
            layout,
            functions,
            module: Arc::downgrade(&module),
        });
    Ok((module, false))
}
