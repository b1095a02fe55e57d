//! The compiled tier (docs/vm.md, "Speed"; docs/vm-jit.md): runs of a unit's
//! pre-decoded operations that need no run-time lookups (bit logic, moves, integer math,
//! compares, timers, counters, edges, S/R, JMP to a later LBL of the run, the generic
//! records `tier_generic.rs` compiles, planned CALLs of subroutines that are themselves
//! entirely such operations) become native functions through the `gutta-jit` crate
//! (Cranelift). The interpreter
//! stays the reference: a region runs natively only when the result cannot differ (the
//! watchdog cannot trip inside it, no CALL inside can go deeper than CallDepth, no
//! breakpoint is set); otherwise the interpreter runs the same records.
//!
//! A region starts at record 0 of a unit or right after a record the tier cannot take
//! (those are the only records the interpreter reaches other than by falling through,
//! apart from a resumed pause, which runs interpreted up to the next region, and where
//! an interpreted JMP lands, where a region starts too). A JMP inside a region lands
//! inside it (its LBL is later in the same region, or the JMP is left to the
//! interpreter).
//!
//! A box the tier cannot compile but whose unpowered run is "nothing, count 1" (EXCH,
//! ATCH, DTCH, CEVNT, ...: the records decode.rs runs as `Quick::Box`) does not end
//! its region: it becomes a `Step::Escape`, and with power flow the region returns
//! there, the interpreter runs the box and continues at the next record, where a
//! resume region starts (`resume`).

use std::collections::{BTreeMap, BTreeSet};
use std::sync::{Arc, Mutex, PoisonError, Weak};

use gutta_jit::{Arg, Function, Layout, Module, Step};

use gutta_format::Operand;

use crate::decode::Unit;
use crate::memory::Memory;
use crate::op::{Arith, CounterKind, Op, Preset, Quick, TimerKind};
use crate::program::Program;

/// What entering a region costs and what each instruction it runs natively saves, in
/// picoseconds, measured by `benches/regions.rs` (docs/vm-jit.md, "Regions"; 2-core
/// Xeon, 2026-11-28: entry 3.7 ns, gain 0.68 ns per bit-logic instruction, the family
/// the interpreter runs fastest, so the least any region saves).
const ENTRY_PS: u64 = 3_700;
const GAIN_PS: u64 = 680;

/// Whether a region of at most `max_count` instructions, with CALLs nested `depth` deep,
/// saves more than its entry costs: from 6 instructions on, or with a CALL (interpreted,
/// a CALL pushes and pops a frame and copies L and its arguments: more than an entry).
/// Shorter ones stay interpreted.
fn worth(max_count: u64, depth: u32) -> bool {
    depth > 0 || max_count.saturating_mul(GAIN_PS) >= ENTRY_PS
}

/// Longer runs are cut into regions of this many records: Cranelift compiles a few
/// medium functions faster than one huge one (10,000 mixed steps: 220 ms whole, 140 ms
/// in pieces of 500 to 2,000), and a region's bound on the watchdog stays small.
const MAX_REGION: usize = 1024;

/// A compiled region of a unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Region {
    /// First record.
    pub pc: u32,
    /// Records it covers (the interpreter continues at `pc + records`; after an escape
    /// taken, at the escape's record `pc + id`).
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
    /// Per unit page, per record: 1 + the index in `regions` of the region starting
    /// there, 0 where none does. One load per record the interpreter reaches (a binary
    /// search there cost more than a short region saved).
    starts: Vec<Vec<u32>>,
    /// Per unit page: no record outside its regions stops the fast path whatever the
    /// scan (`Unit::straight`, with the regions).
    straight: Vec<bool>,
    /// Per unit page: 1 + the index in `regions` of the region that is the whole unit
    /// (from its first record to its end), 0 when none is.
    whole: Vec<u32>,
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
    /// Per record of unit `page`: non-zero where a region starts.
    #[inline]
    pub fn starts(&self, page: u8) -> &[u32] {
        self.starts.get(page as usize).map_or(&[], Vec::as_slice)
    }

    /// Whether unit `page`, started without a frame, likely runs to its end
    /// (`Engine::run_direct`).
    #[inline]
    pub fn straight(&self, page: u8) -> bool {
        self.straight.get(page as usize).copied().unwrap_or(false)
    }

    /// The region that is the whole of unit `page`, if one is (`Engine::run_direct`
    /// enters it at once).
    #[inline]
    pub fn whole(&self, page: u8) -> Option<&Region> {
        let k = *self.whole.get(page as usize)?;
        self.regions
            .get(page as usize)?
            .get(k.checked_sub(1)? as usize)
    }

    /// The region of unit `page` starting at record `pc`.
    #[inline]
    pub fn region(&self, page: u8, pc: usize) -> Option<&Region> {
        let k = *self.starts.get(page as usize)?.get(pc)?;
        if k == 0 {
            return None;
        }
        self.regions.get(page as usize)?.get(k as usize - 1)
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
            combine: crate::tier_generic::jit_combine(combine),
            rel: crate::tier_generic::jit_rel(rel),
            a,
            b,
            width,
        },
        Op::Edge { rising, state } => Step::Edge { rising, state },
        Op::SetBits { at, bit, n, value } => Step::SetBits { at, bit, n, value },
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
        // With their side tables (`Builder::step`).
        | Op::Call { .. }
        | Op::Timer { .. }
        | Op::Counter { .. }
        | Op::Generic { .. }
        | Op::Break => return None,
    })
}

fn preset(p: Preset) -> gutta_jit::Preset {
    match p {
        Preset::Const(v) => gutta_jit::Preset::Const(v),
        Preset::Word(at) => gutta_jit::Preset::Word(at),
    }
}

/// A JMP or LBL record.
enum Control {
    /// JMP to a label later in the unit (the interpreter continues after its LBL).
    Jump(u16),
    /// The LBL a JMP of the unit lands after (`Unit::labels`).
    Label(u16),
    /// A JMP backwards or to no label, or a LBL no JMP lands after: interpreted.
    Other,
}

/// Where the interpreter continues when JMP record `pc` jumps: after its LBL.
fn landing(unit: &Unit, pc: usize) -> Option<usize> {
    let (id, _, operands) = unit.instruction(pc)?;
    if unit.mnemonic(id) != "JMP" {
        return None;
    }
    match crate::memory::operand(*operands.first()?) {
        Ok(Operand::Label(n)) => unit.labels.get(&n).map(|&j| j + 1),
        _ => None,
    }
}

/// Whether record `pc` is a JMP or LBL, and what the tier makes of it (`Builder::regions`
/// also ends a region at a JMP whose LBL lies beyond it).
fn jump_or_label(unit: &Unit, pc: usize) -> Option<Control> {
    let (id, _, operands) = unit.instruction(pc)?;
    let mnemonic = unit.mnemonic(id);
    if mnemonic != "JMP" && mnemonic != "LBL" {
        return None;
    }
    let Some(Ok(Operand::Label(n))) = operands.first().map(|&o| crate::memory::operand(o)) else {
        return Some(Control::Other);
    };
    let target = unit.labels.get(&n).copied();
    Some(match mnemonic {
        "JMP" if target.is_some_and(|j| j > pc) => Control::Jump(n),
        "LBL" if target == Some(pc) => Control::Label(n),
        _ => Control::Other,
    })
}

/// Whether record `pc` may become an Escape: a generic box the fast path runs as
/// `Quick::Box` (with power flow its handler runs, without it does nothing and counts
/// 1; never a FOR, whose records decode.rs keeps `Quick::Handler`) that goes on to the
/// next record: not a JMP (one the tier does not compile jumps backwards or nowhere: it
/// stays interpreted, so a region starts where it lands), nor the boxes that leave the
/// unit (CRET, CRETI, END, STOP), which stay where they were, ending their region.
fn escapable(unit: &Unit, pc: usize) -> bool {
    let Some(Op::Generic {
        boxed: true,
        quick: Quick::Box,
    }) = unit.plain_op(pc)
    else {
        return false;
    };
    unit.instruction(pc).is_some_and(|(id, _, _)| {
        !matches!(unit.mnemonic(id), "JMP" | "CRET" | "CRETI" | "END" | "STOP")
    })
}

impl Builder<'_> {
    /// The step of record `pc` of `unit`, with the most instructions it can run and its
    /// CALL depth; None when the tier cannot take it. With `escapes`, an escapable box
    /// (`escapable`) the tier cannot compile is an Escape (its id set by `region`);
    /// without, None (a whole unit that CALLs enter holds none: gutta-jit refuses it).
    fn step(&mut self, unit: &Unit, pc: usize, escapes: bool) -> Option<(Step, u64, u32)> {
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
                    bits: a.bits,
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
        if let Op::Timer { index } = op {
            let t = unit.tables.timers.get(index as usize)?;
            let step = Step::Timer {
                kind: match t.kind {
                    TimerKind::On => gutta_jit::TimerKind::On,
                    TimerKind::Off => gutta_jit::TimerKind::Off,
                    TimerKind::Retentive => gutta_jit::TimerKind::Retentive,
                },
                at: t.at,
                state: t.state,
                preset: preset(t.preset),
                res: t.res,
                scan_ms: t.scan_ms,
            };
            return Some((step, 1, 0));
        }
        if let Op::Counter { index } = op {
            let c = unit.tables.counters.get(index as usize)?;
            let step = Step::Counter {
                kind: match c.kind {
                    CounterKind::Up => gutta_jit::CounterKind::Up,
                    CounterKind::Down => gutta_jit::CounterKind::Down,
                    CounterKind::UpDown => gutta_jit::CounterKind::UpDown,
                },
                at: c.at,
                state: c.state,
                preset: preset(c.preset),
                max: c.max,
            };
            return Some((step, 1, 0));
        }
        if let Op::Generic { .. } = op {
            match jump_or_label(unit, pc) {
                Some(Control::Jump(label)) => return Some((Step::Jump { label }, 1, 0)),
                Some(Control::Label(number)) => return Some((Step::Label { number }, 1, 0)),
                Some(Control::Other) => return None,
                None => {}
            }
            // Instructions the interpreter runs through `ops/` that the tier compiles
            // from their operands (`tier_generic.rs`); else, inside a region, a box
            // that does nothing unpowered is an escape.
            return match crate::tier_generic::generic_step(unit, pc, self.memory) {
                Some(step) => Some((step, 1, 0)),
                None if escapes && escapable(unit, pc) => Some((Step::Escape { id: 0 }, 1, 0)),
                None => None,
            };
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
            let (step, count, d) = self.step(&unit, pc, false)?;
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
    /// not long (however short, from one instruction: a unit started without a frame,
    /// `Engine::run_direct`, then runs as one call), else its runs of compilable
    /// records that are `worth` it, cut every `MAX_REGION` records.
    fn regions(&mut self, page: u8) -> Vec<Region> {
        let Some(unit) = self.program.unit(page).cloned() else {
            return Vec::new();
        };
        let n = unit.ops.len();
        if n <= MAX_REGION {
            if let Some(whole) = self.whole_unit(page) {
                // Whatever its length (not `worth`): the region replaces the unit's
                // whole run on the fast path, whose start and end it would pay too.
                // Not without an instruction: an empty unit's run costs less.
                if whole.max_count == 0 {
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
        let mut steps: Vec<Option<(Step, u64, u32)>> =
            (0..n).map(|pc| self.step(&unit, pc, true)).collect();
        // A JMP whose LBL is not later in its region stays interpreted (it ends the
        // region), and where an interpreted JMP lands (after its LBL) a region starts,
        // so the interpreter enters it there; either can move a region's end before
        // another JMP's LBL: again until nothing moves.
        let mut starts = BTreeSet::new();
        loop {
            let mut moved = false;
            for (pc, step) in steps.iter().enumerate() {
                if step.is_none() {
                    if let Some(landing) = landing(&unit, pc) {
                        moved |= landing < n && starts.insert(landing);
                    }
                }
            }
            for (start, end) in spans(&steps, &starts, &spanned(&unit, &steps)) {
                for (pc, step) in steps.iter_mut().enumerate().take(end).skip(start) {
                    if let Some((Step::Jump { label }, _, _)) = step {
                        let inside = unit.labels.get(label).is_some_and(|&j| j > pc && j < end);
                        if !inside {
                            *step = None;
                            moved = true;
                        }
                    }
                }
            }
            if !moved {
                break;
            }
        }
        let mut regions = Vec::new();
        for (start, end) in spans(&steps, &starts, &spanned(&unit, &steps)) {
            let mut pieces = vec![(start, end)];
            pieces.extend(resume(&unit, &steps, start, end));
            for (first, last) in pieces {
                if let Some(region) = self.region(&steps, first, last) {
                    regions.push(region);
                }
            }
        }
        // The starts table (`compile`) wants them in record order.
        regions.sort_by_key(|r| r.pc);
        regions
    }

    /// Records `start..end` of `steps` as a region's function, if `worth` it; each
    /// Escape's id is its record's offset from `start`.
    fn region(
        &mut self,
        steps: &[Option<(Step, u64, u32)>],
        start: usize,
        end: usize,
    ) -> Option<Region> {
        let run = &steps[start..end];
        let (max_count, depth) = run.iter().flatten().fold((0u64, 0u32), |(c, d), s| {
            (c.saturating_add(s.1), d.max(s.2))
        });
        if !worth(max_count, depth) {
            return None;
        }
        let steps = run
            .iter()
            .enumerate()
            .filter_map(|(k, s)| {
                let (step, _, _) = s.as_ref()?;
                Some(match step {
                    // Regions are at most MAX_REGION records: the offset fits.
                    Step::Escape { .. } => Step::Escape {
                        id: u16::try_from(k).ok()?,
                    },
                    step => step.clone(),
                })
            })
            .collect();
        let region = Region {
            pc: start as u32,
            records: (end - start) as u32,
            function: self.functions.len() as u32,
            max_count,
            depth,
        };
        self.functions.push(Function { steps });
        Some(region)
    }
}

/// The resume regions of region `start..end`: after each Escape at record e (but the
/// last record, and one followed by another Escape), records e + 1 up to and including
/// the next Escape that no Jump of the piece spans (every Jump's Label lies inside the
/// piece), else to `end`. After a
/// box ran with power flow the interpreter continues at e + 1 and enters the piece
/// there; where it ends, the next piece (or the region after) starts. So the code is
/// at most about twice the region's, against the square of a copy of the whole rest
/// after each escape (docs/vm-jit.md, "Escapes").
fn resume(
    unit: &Unit,
    steps: &[Option<(Step, u64, u32)>],
    start: usize,
    end: usize,
) -> Vec<(usize, usize)> {
    let is_escape = |pc: usize| matches!(steps[pc], Some((Step::Escape { .. }, _, _)));
    let mut pieces = Vec::new();
    for e in (start..end).filter(|&pc| is_escape(pc)) {
        let first = e + 1;
        // Another escape right after: the interpreter runs that one too (a box the
        // fast path skips when unpowered) and enters the piece after it.
        if first >= end || is_escape(first) {
            continue;
        }
        // The furthest Label a Jump of the piece so far lands at.
        let mut reach = first;
        let mut last = end;
        for (pc, step) in steps.iter().enumerate().take(end).skip(first) {
            match *step {
                Some((Step::Jump { label }, _, _)) => {
                    if let Some(&j) = unit.labels.get(&label) {
                        reach = reach.max(j);
                    }
                }
                Some((Step::Escape { .. }, _, _)) if reach < pc => {
                    last = pc + 1;
                    break;
                }
                _ => {}
            }
        }
        pieces.push((first, last));
    }
    pieces
}

/// Per record pc: whether a compiled JMP before it lands at or after it (its LBL at pc or
/// later), so a region cut at pc would leave that JMP without its LBL.
fn spanned(unit: &Unit, steps: &[Option<(Step, u64, u32)>]) -> Vec<bool> {
    let mut open = vec![0i32; steps.len() + 1];
    for (pc, step) in steps.iter().enumerate() {
        if let Some((Step::Jump { label }, _, _)) = step {
            if let Some(&j) = unit.labels.get(label).filter(|&&j| j > pc) {
                open[pc + 1] += 1;
                open[(j + 1).min(steps.len())] -= 1;
            }
        }
    }
    let mut depth = 0;
    open.iter()
        .take(steps.len())
        .map(|d| {
            depth += d;
            depth > 0
        })
        .collect()
}

/// The runs of records that compile (`Some`), as (first, end) record ranges, cut where
/// a region must start (`starts`) and before `MAX_REGION` records: at the last record of
/// the run's second half that no compiled jump spans (`spanned`), so the jumps of a long
/// unit stay inside their regions, else at `MAX_REGION`.
fn spans<T>(
    steps: &[Option<T>],
    starts: &BTreeSet<usize>,
    spanned: &[bool],
) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut pc = 0;
    while pc < steps.len() {
        if steps[pc].is_none() {
            pc += 1;
            continue;
        }
        let start = pc;
        while pc < steps.len()
            && steps[pc].is_some()
            && pc - start < MAX_REGION
            && (pc == start || !starts.contains(&pc))
        {
            pc += 1;
        }
        if pc - start == MAX_REGION && pc < steps.len() && steps[pc].is_some() {
            // Cut by length: where no jump is open, if the second half has such a place.
            if let Some(cut) = (start + MAX_REGION / 2..pc)
                .rev()
                .find(|&c| !spanned.get(c).copied().unwrap_or(true))
            {
                pc = cut;
            }
        }
        spans.push((start, pc));
    }
    spans
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
    let starts = regions
        .iter()
        .map(|rs| {
            let Some(last) = rs.last() else {
                return Vec::new();
            };
            let mut table = vec![0u32; last.pc as usize + 1];
            for (k, r) in rs.iter().enumerate() {
                table[r.pc as usize] = k as u32 + 1;
            }
            table
        })
        .collect();
    let straight = regions
        .iter()
        .zip(&program.units)
        .map(|(rs, unit)| {
            let Some(unit) = unit else {
                return false;
            };
            let n = unit.ops.len();
            let mut covered = vec![false; n];
            for r in rs {
                let (from, to) = (r.pc as usize, (r.pc + r.records) as usize);
                covered[from.min(n)..to.min(n)].fill(true);
            }
            !unit
                .ops
                .iter()
                .zip(&covered)
                .any(|(op, &native)| !native && crate::fast::stops(op))
        })
        .collect();
    let whole = regions
        .iter()
        .zip(&program.units)
        .map(|(rs, unit)| match (rs.as_slice(), unit) {
            ([r], Some(unit)) if r.pc == 0 && r.records as usize == unit.ops.len() => 1,
            _ => 0,
        })
        .collect();
    Ok(Some(Native {
        module,
        regions,
        shared,
        starts,
        straight,
        whole,
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
