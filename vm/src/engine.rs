//! The interpreter: pre-decoded units run on an explicit stack of frames, so a scan can
//! stop at any instruction (a breakpoint, a single step) and continue later exactly where
//! it stopped. A scan has phases: MAIN, then the interrupt routines of the events that
//! occurred, then the end of scan (forces, EXCH, clock). docs/vm.md, "Scan cycle" and
//! "Debugging".

use std::collections::VecDeque;

use crate::decode::{Arith, Bit, ChainStep, Combine, Op, Unit, STEP_STORE};
use crate::ops::{Control, Exec};
use crate::{exch, Fault, Vm};

/// A unit being run.
#[derive(Debug, Clone)]
pub(crate) struct Frame {
    pub page: u8,
    /// The next record to run (for a caller: its CALL record while the callee runs).
    pub pc: usize,
    /// Set for a subroutine called by CALL: what the return restores.
    pub call: Option<CallSave>,
    /// Open FOR loops when the unit was entered.
    pub loops_at_entry: usize,
}

/// The caller's state a CALL saves: its L is on `Vm::l_stack` from `l_mark`.
#[derive(Debug, Clone)]
pub(crate) struct CallSave {
    pub l_mark: usize,
    pub saved_stack: u32,
    /// A planned CALL: the plan's index in the caller's unit.
    pub plan: Option<u32>,
}

/// Where a scan is.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) enum Phase {
    /// Between scans.
    #[default]
    Idle,
    /// MAIN (and what it calls) runs.
    Main,
    /// Interrupt routines run: the events still to serve, in order.
    Events(VecDeque<u32>),
}

/// Why `exec` returned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Flow {
    /// No frame left: the phase's units ran to their ends.
    Empty,
    /// END or STOP: the phase ends now.
    EndScan,
    /// A breakpoint is the next instruction.
    Break,
    /// One instruction ran (single-instruction mode).
    Stepped,
}

/// How a call to `Vm::run_scan` ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScanEnd {
    /// The scan ran to its end.
    Completed,
    /// The scan is paused before an instruction (breakpoint or single-step stop).
    Paused(crate::debug::Position),
    /// Paused between scans (a program with no instruction to stop at).
    PausedIdle,
    /// The PLC is in STOP: nothing ran.
    Stopped,
}

impl Vm {
    fn set_pc(&mut self, pc: usize) {
        if let Some(f) = self.frames.last_mut() {
            f.pc = pc;
        }
    }

    /// Enter a unit (MAIN, an interrupt routine, or a called subroutine).
    pub(crate) fn push_frame(&mut self, page: u8, call: Option<CallSave>) {
        self.frames.push(Frame {
            page,
            pc: 0,
            call,
            loops_at_entry: self.loops.len(),
        });
        self.stack = 0;
    }

    /// Leave the top unit: a called subroutine copies its outputs back to the caller,
    /// which continues after its CALL.
    pub(crate) fn leave(&mut self) -> Result<(), Fault> {
        let Some(frame) = self.frames.pop() else {
            return Ok(());
        };
        self.loops.truncate(frame.loops_at_entry);
        if let Some(save) = frame.call {
            match save.plan {
                Some(plan) => self.finish_planned_call(plan, save),
                None => crate::ops::finish_call(self, frame.page, save)?,
            }
        }
        Ok(())
    }

    /// A planned CALL (docs/vm.md, CALL): arguments read in the caller's context, the
    /// caller's L saved and cleared, inputs copied into the parameters, a new frame.
    fn planned_call(&mut self, unit: &Unit, plan: u32) -> Result<(), Fault> {
        let limit = self.target.instructions.call_depth;
        if self.frames.len() > usize::from(limit) {
            return Err(Fault::CallDepth { limit });
        }
        let Some(p) = unit.calls.get(plan as usize) else {
            return Ok(());
        };
        let mem = &mut self.memory.bytes;
        self.scratch.clear();
        for a in &p.args {
            self.scratch.push(if a.input {
                load(mem, a.var, a.width)
            } else {
                0
            });
        }
        let l_mark = self.l_stack.len();
        if let Some((start, len)) = self.memory.span(self.slots.local) {
            let mem = &mut self.memory.bytes;
            self.l_stack.extend_from_slice(&mem[start..start + len]);
            mem[start..start + len].fill(0);
        }
        let mem = &mut self.memory.bytes;
        for (a, &v) in p.args.iter().zip(&self.scratch) {
            if a.input {
                store(mem, a.param, a.width, v);
            }
        }
        let saved_stack = self.stack;
        self.push_frame(
            p.callee,
            Some(CallSave {
                l_mark,
                saved_stack,
                plan: Some(plan),
            }),
        );
        Ok(())
    }

    /// The return of a planned CALL (its frame popped): outputs read from L, the
    /// caller's L and stack restored, outputs stored, the caller continues after it.
    fn finish_planned_call(&mut self, plan: u32, save: CallSave) {
        let Some((page, pc)) = self.frames.last().map(|f| (f.page, f.pc)) else {
            return;
        };
        let Some(p) = self.units[page as usize]
            .as_ref()
            .and_then(|u| u.calls.get(plan as usize))
        else {
            return;
        };
        let mem = &mut self.memory.bytes;
        self.scratch.clear();
        for a in &p.args {
            self.scratch.push(if a.output {
                load(mem, a.param, a.width)
            } else {
                0
            });
        }
        if let Some((start, len)) = self.memory.span(self.slots.local) {
            let saved = self.l_stack.get(save.l_mark..).unwrap_or(&[]);
            let n = saved.len().min(len);
            self.memory.bytes[start..start + n].copy_from_slice(&saved[..n]);
        }
        self.l_stack.truncate(save.l_mark);
        self.stack = save.saved_stack;
        let mem = &mut self.memory.bytes;
        for (a, &v) in p.args.iter().zip(&self.scratch) {
            if a.output {
                store(mem, a.var, a.width, v);
            }
        }
        if let Some(f) = self.frames.last_mut() {
            f.pc = pc + 1;
        }
    }

    fn unwind(&mut self) -> Result<(), Fault> {
        while !self.frames.is_empty() {
            self.leave()?;
        }
        Ok(())
    }

    /// Run the top frames. `SINGLE`: return after one instruction (a breakpoint's own
    /// instruction runs); otherwise run until the frames are done or a breakpoint is next.
    pub(crate) fn exec<const SINGLE: bool>(&mut self) -> Result<Flow, Fault> {
        let mask = self.stack_mask;
        let flags_at = self.flags_at;
        'frames: loop {
            let Some(frame) = self.frames.last() else {
                return Ok(Flow::Empty);
            };
            let mut pc = frame.pc;
            let Some(unit) = self.units[frame.page as usize].clone() else {
                self.leave()?;
                continue;
            };
            let ops: &[Op] = &unit.ops;
            let mut st = self.stack;
            loop {
                if !SINGLE {
                    // Straight-line fast operations, bounded so the watchdog stays exact.
                    let remaining = self.config.watchdog.saturating_sub(self.executed);
                    let end = ops
                        .len()
                        .min(pc.saturating_add(usize::try_from(remaining).unwrap_or(usize::MAX)));
                    let (at, ran) = run_fast(
                        &mut self.memory.bytes,
                        &ops[..end],
                        &unit.chain,
                        pc,
                        &mut st,
                        mask,
                        flags_at,
                    );
                    pc = at;
                    self.executed += ran;
                }
                let Some(&op) = ops.get(pc) else {
                    // The unit's end: return from it.
                    self.stack = st;
                    self.set_pc(pc);
                    self.leave()?;
                    if SINGLE {
                        return Ok(Flow::Stepped);
                    }
                    continue 'frames;
                };
                if op == Op::Break && !SINGLE {
                    self.stack = st;
                    self.set_pc(pc);
                    return Ok(Flow::Break);
                }
                // One record, unfused (a breakpoint's own instruction when stepping).
                let op = unit.plain[pc];
                if op == Op::Network {
                    st = 0;
                    pc += 1;
                    continue;
                }
                self.executed += 1;
                if self.executed > self.config.watchdog {
                    self.stack = st;
                    self.set_pc(pc);
                    return Err(Fault::Watchdog {
                        limit: self.config.watchdog,
                    });
                }
                let mut next = pc + 1;
                match op {
                    _ if fast_op(&mut self.memory.bytes, op, &mut st, mask, flags_at) => {}
                    Op::Call { plan } if st & 1 == 1 => {
                        self.stack = st;
                        self.set_pc(pc);
                        self.planned_call(&unit, plan)?;
                        if SINGLE {
                            return Ok(Flow::Stepped);
                        }
                        continue 'frames;
                    }
                    Op::Generic { boxed } => {
                        self.stack = st;
                        self.set_pc(pc);
                        let control = self.generic(&unit, pc, boxed)?;
                        st = self.stack;
                        match control {
                            Control::Next => {}
                            Control::Goto(j) => next = j,
                            Control::Jump(label) => {
                                next = unit.labels.get(&label).map_or(ops.len(), |&j| j + 1)
                            }
                            Control::Return => {
                                self.leave()?;
                                if SINGLE {
                                    return Ok(Flow::Stepped);
                                }
                                continue 'frames;
                            }
                            Control::EndScan => {
                                self.unwind()?;
                                return Ok(Flow::EndScan);
                            }
                            Control::Enter => {
                                if SINGLE {
                                    return Ok(Flow::Stepped);
                                }
                                continue 'frames;
                            }
                        }
                    }
                    _ => {}
                }
                pc = next;
                if SINGLE {
                    self.stack = st;
                    self.set_pc(pc);
                    return Ok(Flow::Stepped);
                }
            }
        }
    }

    /// Run an instruction's semantic from `ops/`.
    fn generic(&mut self, unit: &Unit, pc: usize, boxed: bool) -> Result<Control, Fault> {
        let Some((id, offset, operands)) = unit.instruction(pc) else {
            return Ok(Control::Next);
        };
        if boxed && self.stack & 1 == 0 {
            // FOR without power flow skips its whole loop.
            if let Some(&next) = self.for_pairs.get(&(unit.page, pc)) {
                return Ok(Control::Goto(next + 1));
            }
            return Ok(Control::Next);
        }
        let mnemonic = unit.mnemonic(id);
        let handler = self
            .handlers
            .get(id.0 as usize)
            .copied()
            .flatten()
            .ok_or_else(|| Fault::NoSemantics {
                mnemonic: mnemonic.to_string(),
            })?;
        let mut exec = Exec {
            vm: self,
            operands,
            page: unit.page,
            index: pc,
            offset,
            mnemonic,
        };
        handler(&mut exec)
    }

    /// Start a scan: inputs, forces, system bits, then MAIN.
    pub(crate) fn begin_scan(&mut self) {
        self.refresh_inputs();
        self.apply_forces();
        self.set_system_bits();
        self.executed = 0;
        self.frames.clear();
        self.push_frame(0, None);
        self.phase = Phase::Main;
    }

    /// The frames of a phase are done (`flow`: they ran out or ended with END/STOP):
    /// start the next routine, or end the scan. True when the scan has ended.
    pub(crate) fn next_phase(&mut self, flow: Flow) -> Result<bool, Fault> {
        let mut queue = match std::mem::take(&mut self.phase) {
            Phase::Main => self.occurred_events().into(),
            Phase::Events(q) if flow != Flow::EndScan => q,
            _ => VecDeque::new(),
        };
        while let Some(event) = queue.pop_front() {
            let Some(&routine) = self.interrupts.attached.get(&event) else {
                continue;
            };
            let Ok(page) = u8::try_from(routine) else {
                continue;
            };
            self.push_frame(page, None);
            self.phase = Phase::Events(queue);
            return Ok(false);
        }
        self.phase = Phase::Idle;
        self.apply_forces();
        exch::service(self)?;
        self.end_scan_clock();
        Ok(true)
    }

    pub(crate) fn end_scan_clock(&mut self) {
        self.scans += 1;
        self.clock_ms += self.config.scan_ms as u64;
    }

    /// Continue the current scan (starting one when idle) until it ends or pauses at
    /// a breakpoint.
    pub(crate) fn continue_scan(&mut self) -> Result<ScanEnd, Fault> {
        if self.phase == Phase::Idle {
            self.begin_scan();
        }
        if self.at_breakpoint() {
            // Leaving a breakpoint: its instruction runs once.
            let flow = self.exec::<true>()?;
            if flow != Flow::Stepped && self.next_phase(flow)? {
                return Ok(ScanEnd::Completed);
            }
        }
        loop {
            match self.exec::<false>()? {
                Flow::Break => {
                    self.debug.paused = true;
                    return Ok(match self.position() {
                        Some(p) => ScanEnd::Paused(p),
                        None => ScanEnd::PausedIdle,
                    });
                }
                flow => {
                    if self.next_phase(flow)? {
                        return Ok(ScanEnd::Completed);
                    }
                }
            }
        }
    }

    /// Whether the record the top frame is at is the patched breakpoint (a scan paused
    /// there continues by running it once).
    pub(crate) fn at_breakpoint(&self) -> bool {
        self.next_op(false) == Some(Op::Break)
    }

    /// The top frame's fast operation; with `skip_networks`, at the first instruction
    /// from there (network records are skipped by the plain operations).
    pub(crate) fn next_op(&self, skip_networks: bool) -> Option<Op> {
        let f = self.frames.last()?;
        let unit = self.units[f.page as usize].as_ref()?;
        let mut pc = f.pc;
        while skip_networks && unit.plain.get(pc).is_some_and(|o| o.is_network()) {
            pc += 1;
        }
        unit.ops.get(pc).copied()
    }
}

/// Run fast operations from `pc` until one is not (or the ops end). Returns where it
/// stopped and how many instructions ran (network records do not count).
#[inline(always)]
fn run_fast(
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
                    if step.kind == STEP_STORE {
                        let byte = &mut mem[at];
                        *byte = (*byte & !(1 << step.bit)) | ((t as u8) << step.bit);
                    } else {
                        let v = ((u32::from(mem[at]) >> step.bit) & 1) ^ u32::from(step.invert);
                        let ko = u32::from(step.keep_or);
                        t = ((t & ko) + v + (ko >> 1)) >> 1;
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
fn load(mem: &[u8], at: u32, width: u8) -> u32 {
    let at = at as usize;
    match width {
        1 => u32::from(mem[at]),
        2 => u32::from(u16::from_le_bytes([mem[at], mem[at + 1]])),
        _ => u32::from_le_bytes([mem[at], mem[at + 1], mem[at + 2], mem[at + 3]]),
    }
}

#[inline(always)]
fn store(mem: &mut [u8], at: u32, width: u8, v: u32) {
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
fn fast_op(mem: &mut [u8], op: Op, st: &mut u32, mask: u32, flags_at: usize) -> bool {
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
        Op::Move { src, dst, width } => {
            if s & 1 == 1 {
                let v = load(mem, src, width);
                store(mem, dst, width, v);
            }
            s
        }
        Op::Math {
            op,
            src,
            dst,
            width,
        } => {
            if s & 1 == 1 {
                let bits = u32::from(width) * 8;
                let a = sign_extend(load(mem, dst, width), bits);
                let b = sign_extend(load(mem, src, width), bits);
                let exact = match op {
                    Arith::Add => a + b,
                    Arith::Sub => a - b,
                    Arith::Mul => a * b,
                };
                let r = sign_extend(exact as u32, bits);
                store(mem, dst, width, exact as u32);
                // SM1.0 zero, SM1.1 overflow, SM1.2 negative; the other flags kept.
                let flags = u8::from(r == 0) | (u8::from(r != exact) << 1) | (u8::from(r < 0) << 2);
                let f = &mut mem[flags_at];
                *f = (*f & !0x07) | flags;
            }
            s
        }
        Op::Compare {
            combine,
            rel,
            a,
            b,
            width,
        } => {
            let (x, y) = (load(mem, a, width), load(mem, b, width));
            let r = if width == 1 {
                rel.holds(x, y)
            } else {
                let bits = u32::from(width) * 8;
                rel.holds(sign_extend(x, bits), sign_extend(y, bits))
            };
            let r = u32::from(r);
            match combine {
                Combine::Load => ((s << 1) | r) & mask,
                Combine::And => s & (!1 | r),
                Combine::Or => s | r,
            }
        }
        Op::Network | Op::Chain { .. } | Op::Call { .. } | Op::Generic { .. } | Op::Break => {
            return false
        }
    };
    true
}

#[inline(always)]
fn sign_extend(v: u32, bits: u32) -> i64 {
    match bits {
        8 => v as u8 as i8 as i64,
        16 => v as u16 as i16 as i64,
        _ => v as i32 as i64,
    }
}
