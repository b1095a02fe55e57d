//! Pre-decoding: at load, every record of every unit becomes an `Op`. The frequent
//! instructions with plain operands (bit logic on a variable, moves, integer add and
//! subtract, compares) become operations that name their bytes by index into the flat
//! memory; everything else is `Generic` and runs its semantic from `ops/` with the
//! record's packed operands; runs of bit logic are then fused (`fuse.rs`). Op `k` of a
//! unit is record `k`, so labels, FOR/NEXT pairs and debugger positions use one
//! numbering. A unit is stored for size (a loaded program costs at most about twice its
//! image): see `Unit`. docs/vm.md, "Speed", says why.

use std::collections::BTreeMap;
use std::sync::Arc;

use gutta_catalog::{Address, Flow, InstrId, Instruction, Target, TimerCounterKind, Width};
use gutta_format::{LocalEntry, LocalSection, Operand, PackedOperand, UnitRecord, VerifiedUnit};

use crate::fast::UnitTables;
use crate::fuse::build;
use crate::memory::Memory;
use crate::op::{
    Arith, Bit, Combine, CounterKind, CounterOp, DivideOp, Op, Preset, Quick, Rel, TimerKind,
    TimerOp,
};

/// One argument of a planned CALL: the caller's variable and the callee's parameter in
/// L, as flat memory indices.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) struct ArgPlan {
    pub var: u32,
    pub param: u32,
    pub width: u8,
    /// VAR_INPUT or VAR_IN_OUT: copied in.
    pub input: bool,
    /// VAR_OUTPUT or VAR_IN_OUT: copied back.
    pub output: bool,
    /// A BOOL parameter: the bit of `var` and the bit of `param` (`width` is then 1, and
    /// `var`, `param` the bytes holding them).
    pub bits: Option<(u8, u8)>,
}

/// A CALL whose arguments are all plain variables of their parameters' widths (BOOL,
/// BYTE, WORD, DWORD; a literal argument arrives as a constant's plain address). CALLs
/// with the same callee and arguments share one plan.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) struct CallPlan {
    pub callee: u8,
    pub args: Vec<ArgPlan>,
}

/// The plan of a CALL into `plan`, if its arguments allow one (false otherwise).
/// `params`: the parameters of each unit, by page.
fn plan_call(
    memory: &Memory,
    target: &Target,
    operands: &[PackedOperand],
    params: &BTreeMap<u8, Vec<LocalEntry>>,
    plan: &mut CallPlan,
) -> bool {
    let Some(Ok(Operand::Unit(unit))) = operands.first().map(|o| o.decode()) else {
        return false;
    };
    let Some(params) = unit.page(&target.plc).and_then(|callee| {
        plan.callee = callee;
        params.get(&callee)
    }) else {
        return false;
    };
    if operands.len() != params.len() + 1 {
        return false;
    }
    plan.args.clear();
    for (p, &op) in params.iter().zip(&operands[1..]) {
        let Ok(Operand::Value(declared)) = p.operand.decode() else {
            return false;
        };
        let width = declared.width;
        let (var, param, bits) = if width == Width::Bit {
            let (Some(param), Some(var)) = (plain_bit(memory, p.operand), plain_bit(memory, op))
            else {
                return false;
            };
            let bit = |b: Bit| b.mask.trailing_zeros() as u8;
            (var.at, param.at, Some((bit(var), bit(param))))
        } else {
            let (Some(param), Some(var)) =
                (plain(memory, p.operand, width), plain(memory, op, width))
            else {
                return false;
            };
            (var, param, None)
        };
        plan.args.push(ArgPlan {
            var,
            param,
            width: width.bytes() as u8,
            input: p.section != LocalSection::Output,
            output: p.section != LocalSection::Input,
            bits,
        });
    }
    true
}

/// The index of `plan` in `calls`, added there the first time (CALLs with the same
/// callee and arguments share it).
fn intern(plan: &CallPlan, calls: &mut Vec<CallPlan>, index: &mut BTreeMap<CallPlan, u32>) -> u32 {
    if let Some(&k) = index.get(plan) {
        return k;
    }
    let k = u32::try_from(calls.len()).unwrap_or(u32::MAX);
    calls.push(plan.clone());
    index.insert(plan.clone(), k);
    k
}

/// A `Generic` record, compactly: its operands are `Unit::operands[first..first + len]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Record {
    pub id: InstrId,
    pub len: u16,
    /// Byte offset in the instruction page (for fault messages).
    pub offset: u32,
    pub first: u32,
}

/// Which records run `Generic`, and each one's place among them: a bit per record and,
/// per 64 records, how many generic records come before (a rank in O(1)).
#[derive(Debug, Clone, Default)]
struct GenericRecords {
    bits: Vec<u64>,
    before: Vec<u32>,
}

impl GenericRecords {
    fn push(&mut self, pc: usize, generic: bool) {
        if pc.is_multiple_of(64) {
            let count = self.bits.last().map_or(0, |w| w.count_ones());
            let base = self.before.last().copied().unwrap_or(0);
            self.before.push(base + count);
            self.bits.push(0);
        }
        if generic {
            if let Some(w) = self.bits.last_mut() {
                *w |= 1 << (pc % 64);
            }
        }
    }

    /// Record `pc`'s index among the generic records, if it is one.
    #[inline]
    fn rank(&self, pc: usize) -> Option<usize> {
        let word = *self.bits.get(pc / 64)?;
        let bit = 1u64 << (pc % 64);
        if word & bit == 0 {
            return None;
        }
        Some(self.before[pc / 64] as usize + (word & (bit - 1)).count_ones() as usize)
    }
}

/// A network record: its record index and number. A unit's positions derive from
/// these (docs/vm.md, "Code layout").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct NetworkStart {
    at: u32,
    number: u16,
}

/// A unit ready to run. Everything the interpreter needs, so the VM keeps no other copy
/// of the code. Stored for size (docs/vm.md, "Code layout"): one operation per record,
/// the plain operations the fused ones displaced, the network starts (positions derive
/// from them) and the record and operands of the `Generic` records only (the others
/// never read them).
#[derive(Debug, Clone)]
pub(crate) struct Unit {
    pub page: u8,
    /// What the fast path runs (fused, breakpoint patched in); see `build`.
    pub ops: Vec<Op>,
    /// (record index, plain operation) where `ops` holds another: the heads of fused
    /// chains and the breakpoint, sorted. `plain_op` reads through it.
    displaced: Vec<(u32, Op)>,
    /// What the fast path indexes: the steps of the fused chains in `ops`, the operands
    /// of timers, counters and divisions.
    pub tables: UnitTables,
    /// No record of `ops` stops the fast path whatever the scan (`fast::stops`): the
    /// unit, started without a frame, likely runs to its end (`Engine::run_direct`).
    pub straight: bool,
    /// The network records, in order.
    networks: Vec<NetworkStart>,
    generic: GenericRecords,
    /// Per generic record, in record order.
    records: Vec<Record>,
    operands: Vec<PackedOperand>,
    /// Label number -> record index of its LBL.
    pub labels: BTreeMap<u16, usize>,
    /// FOR record index -> record index of its NEXT (paired by the verifier).
    pub loops: BTreeMap<usize, usize>,
    /// The parameters a CALL passes (VAR_INPUT, VAR_IN_OUT, VAR_OUTPUT), in order.
    pub params: Vec<LocalEntry>,
    /// Plans of the unit's planned CALLs.
    pub calls: Vec<CallPlan>,
    /// (record index, flat index of its edge byte) of each EU/ED record, sorted: the
    /// hidden state after the areas (`Memory::add_hidden`), allocated at load.
    pub edges: Vec<(u32, u32)>,
    /// The instruction set, for mnemonics.
    pub target: Arc<Target>,
}

impl Unit {
    /// Record `pc` if it runs `Generic`: its id, page offset and operands. (Fast and
    /// planned records keep neither: their operation says all they do.)
    pub fn instruction(&self, pc: usize) -> Option<(InstrId, usize, &[PackedOperand])> {
        let r = *self.records.get(self.generic.rank(pc)?)?;
        let ops = self
            .operands
            .get(r.first as usize..r.first as usize + r.len as usize)?;
        Some((r.id, r.offset as usize, ops))
    }

    /// The flat index of record `pc`'s edge byte, if it is an EU/ED.
    pub fn edge_state(&self, pc: usize) -> Option<usize> {
        let pc = u32::try_from(pc).ok()?;
        let k = self.edges.binary_search_by_key(&pc, |&(p, _)| p).ok()?;
        Some(self.edges[k].1 as usize)
    }

    pub fn mnemonic(&self, id: InstrId) -> &str {
        &self.target.instructions.get(id).mnemonic
    }

    /// Record `pc`'s own operation, unfused and without the breakpoint: what single
    /// steps and the slow path run.
    #[inline]
    pub fn plain_op(&self, pc: usize) -> Option<Op> {
        Some(self.unfused(pc, *self.ops.get(pc)?))
    }

    /// Record `pc`'s own operation, given `op = ops[pc]`: `op` itself unless it is a
    /// chain or the breakpoint patched over it. Not inlined: inlined into the
    /// interpreter's loop it cost the bit-logic benchmark about 5% (code layout).
    #[inline(never)]
    pub fn unfused(&self, pc: usize, op: Op) -> Op {
        match op {
            Op::Chain { .. } | Op::NetworkLoad { .. } | Op::Break => {
                self.displaced_op(pc).unwrap_or(op)
            }
            op => op.widened(),
        }
    }

    /// The plain operation displaced from record `pc` (rare: single steps, breakpoints).
    #[cold]
    #[inline(never)]
    fn displaced_op(&self, pc: usize) -> Option<Op> {
        let at = u32::try_from(pc).ok()?;
        let k = self.displaced.binary_search_by_key(&at, |&(p, _)| p).ok()?;
        Some(self.displaced[k].1)
    }

    /// Every record's plain operation (to fuse again with another breakpoint).
    pub fn plain_ops(&self) -> Vec<Op> {
        let mut ops = self.ops.clone();
        for &(pc, op) in &self.displaced {
            ops[pc as usize] = op;
        }
        ops
    }

    /// The operations to run: `plain` fused (when `fast`) with the breakpoint at `pc`
    /// patched in; the plain operations they displace are kept.
    pub fn set_ops(&mut self, plain: Vec<Op>, fast: bool, breakpoint: Option<usize>) {
        let mut ops = if fast {
            build(&plain, breakpoint, &mut self.tables.chain)
        } else {
            self.tables.chain.clear();
            let mut ops = plain.clone();
            if let Some(op) = breakpoint.and_then(|pc| ops.get_mut(pc)) {
                *op = Op::Break;
            }
            ops
        };
        // Per-width forms are not kept: `Op::widened` gives their plain form back.
        self.displaced = (0..plain.len())
            .filter(|&k| ops[k].widened() != plain[k])
            .map(|k| (k as u32, plain[k]))
            .collect();
        ops.shrink_to_fit();
        self.tables.chain.shrink_to_fit();
        self.straight = !ops.iter().any(crate::fast::stops);
        self.ops = ops;
    }

    /// Record `pc`'s (network number, step within the network); a network record's
    /// step is 0xFFFF. Records before the first network are in network 0.
    pub fn position(&self, pc: usize) -> Option<(u16, u16)> {
        if pc >= self.ops.len() {
            return None;
        }
        let k = self.networks.partition_point(|n| n.at as usize <= pc);
        let step = |from: usize| u16::try_from(pc - from).unwrap_or(u16::MAX);
        Some(match k.checked_sub(1).map(|k| self.networks[k]) {
            None => (0, step(0)),
            Some(n) if n.at as usize == pc => (n.number, u16::MAX),
            Some(n) => (n.number, step(n.at as usize + 1)),
        })
    }

    /// The first instruction record at (`network`, `step`), if there is one.
    pub fn find(&self, network: u16, step: u16) -> Option<usize> {
        let ends = self
            .networks
            .iter()
            .map(|n| n.at as usize)
            .chain([self.ops.len()]);
        let starts = std::iter::once((0, 0))
            .chain(self.networks.iter().map(|n| (n.at as usize + 1, n.number)));
        starts
            .zip(ends)
            .filter(|&((_, number), _)| number == network)
            .map(|((first, _), end)| (first + usize::from(step), end))
            .find(|&(pc, end)| pc < end)
            .map(|(pc, _)| pc)
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

/// A compare mnemonic's parts: LD/A/O, the type letter (B, W, D, R) and the relation.
pub(crate) fn decode_compare(m: &str) -> Option<(Combine, char, Rel)> {
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

/// A timer's or counter's preset (operand 1): a literal that fits an INT, or a plain
/// INT variable (what `Exec::get_signed` reads the same way at every execution).
fn preset(memory: &Memory, op: Option<&PackedOperand>) -> Option<Preset> {
    let op = *op?;
    match op.decode() {
        Ok(Operand::Literal(n)) => i16::try_from(n).ok().map(Preset::Const),
        _ => plain(memory, op, Width::Word).map(Preset::Word),
    }
}

/// The T or C cell operand (operand 0) of a timer or counter: a plain word inside its
/// area, with its hidden state; (the address, its flat index, its state's flat index).
fn cell(memory: &Memory, op: Option<&PackedOperand>) -> Option<(Address, u32, u32)> {
    let a = variable(*op?, Width::Word)?;
    let at = u32::try_from(memory.index_of(a)?).ok()?;
    let state = u32::try_from(memory.cell_state_at(a.slot, a.offset)?).ok()?;
    Some((a, at, state))
}

/// What `decode` collects besides the operations: the side tables of timers and
/// counters, and the configuration their operations need.
struct Stateful<'a> {
    target: &'a Target,
    scan_ms: u32,
    /// The K slot and K as a reset leaves it.
    constants: (u8, &'a [u8]),
    timers: Vec<TimerOp>,
    counters: Vec<CounterOp>,
}

impl Stateful<'_> {
    /// The fast form of a timer, counter, EU/ED or S/R/SI/RI record, if it has one
    /// (`edge`: the record's edge byte, for EU/ED). Anything the handler could fault
    /// on (a timer without a resolution, bits past the area, a pointer) stays `Generic`,
    /// so the fault stays the handler's.
    fn op(
        &mut self,
        memory: &Memory,
        ins: &Instruction,
        ops: &[PackedOperand],
        edge: Option<u32>,
    ) -> Option<Op> {
        if let Some(kind) = ins.kind {
            return match kind {
                TimerCounterKind::OnDelay
                | TimerCounterKind::OffDelay
                | TimerCounterKind::RetentiveOnDelay => self.timer(memory, kind, ops),
                _ => self.counter(memory, kind, ops),
            };
        }
        match ins.mnemonic.as_str() {
            "EU" | "ED" => Some(Op::Edge {
                rising: ins.mnemonic == "EU",
                state: edge?,
            }),
            "S" | "SI" | "R" | "RI" => {
                set_bits(memory, self.constants, ins.mnemonic.starts_with('S'), ops)
            }
            _ => None,
        }
    }

    fn timer(
        &mut self,
        memory: &Memory,
        kind: TimerCounterKind,
        ops: &[PackedOperand],
    ) -> Option<Op> {
        let (a, at, state) = cell(memory, ops.first())?;
        let res = self.target.memory.timer_resolution(a.offset / 2)?.max(1);
        let preset = preset(memory, ops.get(1))?;
        let kind = match kind {
            TimerCounterKind::OnDelay => TimerKind::On,
            TimerCounterKind::OffDelay => TimerKind::Off,
            _ => TimerKind::Retentive,
        };
        let index = u32::try_from(self.timers.len()).ok()?;
        self.timers.push(TimerOp {
            kind,
            at,
            state,
            preset,
            res,
            scan_ms: self.scan_ms,
        });
        Some(Op::Timer { index })
    }

    fn counter(
        &mut self,
        memory: &Memory,
        kind: TimerCounterKind,
        ops: &[PackedOperand],
    ) -> Option<Op> {
        let (_, at, state) = cell(memory, ops.first())?;
        let preset = preset(memory, ops.get(1))?;
        let kind = match kind {
            TimerCounterKind::CountUp => CounterKind::Up,
            TimerCounterKind::CountDown => CounterKind::Down,
            _ => CounterKind::UpDown,
        };
        // The handler's limit: counter_max, at most i16::MAX.
        let max = i16::try_from(self.target.memory.counter_max.min(i32::from(i16::MAX))).ok()?;
        let index = u32::try_from(self.counters.len()).ok()?;
        self.counters.push(CounterOp {
            kind,
            at,
            state,
            preset,
            max,
        });
        Some(Op::Counter { index })
    }
}

/// S/R BIT, N with N a constant (a byte of K, `constants`: the K slot and its bytes
/// after reset; or a literal) and all N bits inside BIT's area (N = 0 included).
fn set_bits(
    memory: &Memory,
    (k_slot, k): (u8, &[u8]),
    value: bool,
    ops: &[PackedOperand],
) -> Option<Op> {
    let a = variable(*ops.first()?, Width::Bit)?;
    let n = match ops.get(1)?.decode() {
        Ok(Operand::Literal(n)) => n,
        Ok(Operand::Value(c)) if c.slot == k_slot && c.width == Width::Byte => {
            u16::from(*k.get(c.offset as usize)?)
        }
        _ => return None,
    };
    let at = u32::try_from(memory.index_of(a)?).ok()?;
    // The byte holding the last bit lies inside the area too.
    let last = u32::from(a.bit) + u32::from(n.max(1)) - 1;
    memory.index_of(Address {
        offset: a.offset.checked_add(last / 8)?,
        ..a
    })?;
    Some(Op::SetBits {
        at,
        bit: a.bit,
        n,
        value,
    })
}

/// How the fast path runs generic record `pc` (`Op::Generic`'s `quick`).
fn quick(
    memory: &Memory,
    unit: &VerifiedUnit,
    pc: usize,
    ins: &Instruction,
    ops: &[PackedOperand],
    divides: &mut Vec<DivideOp>,
) -> Quick {
    let boxed = ins.flow == Flow::Box;
    let fallback = if boxed && !unit.loops.contains_key(&pc) {
        Quick::Box
    } else {
        Quick::Handler
    };
    let m = ins.mnemonic.as_str();
    match m {
        "LBL" | "NOP" if ins.flow == Flow::Always && ops.len() <= 1 => Quick::Nothing,
        "ENI" | "DISI" if ins.flow == Flow::Always && ops.is_empty() => {
            match u32::try_from(memory.enable_at()) {
                Ok(at) => Quick::Store {
                    at,
                    value: u8::from(m == "ENI"),
                },
                Err(_) => fallback,
            }
        }
        "JMP" if boxed => {
            let Some(Ok(Operand::Label(n))) = ops.first().map(|o| o.decode()) else {
                return fallback;
            };
            let to = unit.labels.get(&n).map_or(unit.records.len(), |&j| j + 1);
            match u32::try_from(to) {
                Ok(to) if to as usize > pc => Quick::Jump { to },
                _ => fallback,
            }
        }
        "INCB" | "INCW" | "INCD" | "DECB" | "DECW" | "DECD" if boxed && ops.len() == 1 => {
            let width = match m.as_bytes()[3] {
                b'B' => 1,
                b'W' => 2,
                _ => 4,
            };
            match plain(memory, ops[0], width_of(width)) {
                Some(at) => Quick::Step {
                    at,
                    width,
                    up: m.starts_with("INC"),
                },
                None => fallback,
            }
        }
        "/I" | "/D" if boxed && ops.len() == 2 => {
            let width = if m == "/I" { 2 } else { 4 };
            let (src, dst) = (
                plain(memory, ops[0], width_of(width)),
                plain(memory, ops[1], width_of(width)),
            );
            match (src, dst, u32::try_from(divides.len())) {
                (Some(src), Some(dst), Ok(index)) => {
                    divides.push(DivideOp { src, dst, width });
                    Quick::Divide { index }
                }
                _ => fallback,
            }
        }
        _ => fallback,
    }
}

/// Decode a unit. `fast_ops` false keeps every instruction `Generic` (the tests compare
/// both forms).
/// `params`: the parameters of each unit, by page (for CALL plans). The hidden state
/// of its EU/ED records is allocated from `memory` (`Memory::add_hidden`).
pub(crate) fn decode(
    unit: &VerifiedUnit,
    target: &Arc<Target>,
    memory: &mut Memory,
    fast_ops: bool,
    scan_ms: u32,
    constants: (u8, &[u8]),
    params: &BTreeMap<u8, Vec<LocalEntry>>,
) -> Unit {
    let mut stateful = Stateful {
        target,
        scan_ms,
        constants,
        timers: Vec::new(),
        counters: Vec::new(),
    };
    let mut calls = Vec::new();
    let mut plan_of: BTreeMap<CallPlan, u32> = BTreeMap::new();
    let mut scratch = CallPlan {
        callee: 0,
        args: Vec::new(),
    };
    let mut plain = Vec::with_capacity(unit.records.len());
    let (mut networks, mut generic, mut records) =
        (Vec::new(), GenericRecords::default(), Vec::new());
    let mut operands = Vec::new();
    let mut edges = Vec::new();
    let mut divides = Vec::new();
    for (pc, r) in unit.records.iter().enumerate() {
        match r {
            UnitRecord::Network { number, .. } => {
                networks.push(NetworkStart {
                    at: u32::try_from(pc).unwrap_or(u32::MAX),
                    number: *number,
                });
                plain.push(Op::Network);
                generic.push(pc, false);
            }
            UnitRecord::Instruction {
                id,
                operands: packed,
                offset,
            } => {
                let ins = target.instructions.get(*id);
                let mut edge = None;
                if matches!(ins.mnemonic.as_str(), "EU" | "ED") {
                    let at = u32::try_from(memory.add_hidden(1)).unwrap_or(u32::MAX);
                    edges.push((u32::try_from(pc).unwrap_or(u32::MAX), at));
                    edge = Some(at);
                }
                let planned = (fast_ops
                    && ins.mnemonic == "CALL"
                    && plan_call(memory, target, packed, params, &mut scratch))
                .then(|| Op::Call {
                    plan: intern(&scratch, &mut calls, &mut plan_of),
                });
                let op = planned
                    .or_else(|| {
                        fast_ops
                            .then(|| fast(memory, &ins.mnemonic, packed))
                            .flatten()
                    })
                    .or_else(|| {
                        fast_ops
                            .then(|| stateful.op(memory, ins, packed, edge))
                            .flatten()
                    })
                    .unwrap_or_else(|| Op::Generic {
                        boxed: ins.flow == Flow::Box,
                        quick: if fast_ops {
                            quick(memory, unit, pc, ins, packed, &mut divides)
                        } else {
                            Quick::Handler
                        },
                    });
                let is_generic = matches!(op, Op::Generic { .. });
                plain.push(op);
                generic.push(pc, is_generic);
                if is_generic {
                    records.push(Record {
                        id: *id,
                        len: u16::try_from(packed.len()).unwrap_or(u16::MAX),
                        offset: u32::try_from(*offset).unwrap_or(u32::MAX),
                        first: u32::try_from(operands.len()).unwrap_or(u32::MAX),
                    });
                    operands.extend_from_slice(packed);
                }
            }
        }
    }
    networks.shrink_to_fit();
    records.shrink_to_fit();
    operands.shrink_to_fit();
    calls.shrink_to_fit();
    let mut unit = Unit {
        page: unit.page,
        ops: Vec::new(),
        displaced: Vec::new(),
        tables: UnitTables {
            chain: Vec::new(),
            timers: stateful.timers,
            counters: stateful.counters,
            divides,
        },
        straight: false,
        networks,
        generic,
        records,
        operands,
        labels: unit.labels.clone(),
        loops: unit.loops.clone(),
        params: unit.parameters().copied().collect(),
        calls,
        edges,
        target: Arc::clone(target),
    };
    unit.set_ops(plain, fast_ops, None);
    unit
}
