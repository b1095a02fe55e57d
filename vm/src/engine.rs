//! The interpreter: pre-decoded units run on an explicit stack of frames, so a scan can
//! stop at any instruction (a breakpoint, a single step) and continue later exactly where
//! it stopped. A scan has phases: MAIN, then the interrupt routines of the events that
//! occurred, then the end of scan (forces, EXCH, clock). docs/vm.md, "Scan cycle" and
//! "Debugging".

use std::collections::VecDeque;
use std::sync::Arc;

use gutta_format::UnitRecord;

use crate::decode::{Arith, Combine, Op, Unit};
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

/// The caller's state a CALL saves.
#[derive(Debug, Clone)]
pub(crate) struct CallSave {
    pub saved_l: Vec<u8>,
    pub saved_stack: u32,
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
    #[inline(always)]
    fn bit(&self, at: u32, mask: u8) -> u32 {
        u32::from(self.memory.bytes[at as usize] & mask != 0)
    }

    #[inline(always)]
    fn load(&self, at: u32, width: u8) -> u32 {
        let at = at as usize;
        let b = &self.memory.bytes;
        match width {
            1 => u32::from(b[at]),
            2 => u32::from(u16::from_le_bytes([b[at], b[at + 1]])),
            _ => u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]]),
        }
    }

    #[inline(always)]
    fn store(&mut self, at: u32, width: u8, v: u32) {
        let at = at as usize;
        let b = &mut self.memory.bytes;
        match width {
            1 => b[at] = v as u8,
            2 => b[at..at + 2].copy_from_slice(&(v as u16).to_le_bytes()),
            _ => b[at..at + 4].copy_from_slice(&v.to_le_bytes()),
        }
    }

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
            crate::ops::finish_call(self, frame.page, save)?;
        }
        Ok(())
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
                let op = match op {
                    Op::Network => {
                        st = 0;
                        pc += 1;
                        continue;
                    }
                    Op::Break if SINGLE => {
                        self.debug.original.unwrap_or(Op::Generic { boxed: false })
                    }
                    Op::Break => {
                        self.stack = st;
                        self.set_pc(pc);
                        return Ok(Flow::Break);
                    }
                    op => op,
                };
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
                    Op::Ld(b) => st = ((st << 1) | self.bit(b.at, b.mask)) & mask,
                    Op::Ldn(b) => st = ((st << 1) | (self.bit(b.at, b.mask) ^ 1)) & mask,
                    Op::A(b) => st &= !1 | self.bit(b.at, b.mask),
                    Op::An(b) => st &= !1 | (self.bit(b.at, b.mask) ^ 1),
                    Op::O(b) => st |= self.bit(b.at, b.mask),
                    Op::On(b) => st |= self.bit(b.at, b.mask) ^ 1,
                    Op::Not => st ^= 1,
                    Op::Assign(b) => {
                        let byte = &mut self.memory.bytes[b.at as usize];
                        if st & 1 == 1 {
                            *byte |= b.mask;
                        } else {
                            *byte &= !b.mask;
                        }
                    }
                    Op::Ald => st = (st >> 1) & (st | !1),
                    Op::Old => st = (st >> 1) | (st & 1),
                    Op::Lps => st = ((st << 1) | (st & 1)) & mask,
                    Op::Lrd => st = (st & !1) | ((st >> 1) & 1),
                    Op::Lpp => st >>= 1,
                    Op::Move { src, dst, width } => {
                        if st & 1 == 1 {
                            let v = self.load(src, width);
                            self.store(dst, width, v);
                        }
                    }
                    Op::Math {
                        op,
                        src,
                        dst,
                        width,
                    } => {
                        if st & 1 == 1 {
                            let bits = u32::from(width) * 8;
                            let a = sign_extend(self.load(dst, width), bits);
                            let b = sign_extend(self.load(src, width), bits);
                            let exact = match op {
                                Arith::Add => a + b,
                                Arith::Sub => a - b,
                            };
                            let r = sign_extend(exact as u32, bits);
                            self.store(dst, width, exact as u32);
                            let flags = u8::from(r == 0)
                                | (u8::from(r != exact) << 1)
                                | (u8::from(r < 0) << 2);
                            let f = &mut self.memory.bytes[flags_at];
                            *f = (*f & !0x0F) | flags;
                        }
                    }
                    Op::Compare {
                        combine,
                        rel,
                        a,
                        b,
                        width,
                    } => {
                        let (x, y) = (self.load(a, width), self.load(b, width));
                        let r = if width == 1 {
                            rel.holds(x, y)
                        } else {
                            let bits = u32::from(width) * 8;
                            rel.holds(sign_extend(x, bits), sign_extend(y, bits))
                        };
                        let r = u32::from(r);
                        st = match combine {
                            Combine::Load => ((st << 1) | r) & mask,
                            Combine::And => st & (!1 | r),
                            Combine::Or => st | r,
                        };
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
                                next = unit.source.labels.get(&label).map_or(ops.len(), |&j| j + 1)
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
                    Op::Network | Op::Break => {}
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
    fn generic(&mut self, unit: &Arc<Unit>, pc: usize, boxed: bool) -> Result<Control, Fault> {
        let Some(UnitRecord::Instruction {
            offset,
            id,
            operands,
        }) = unit.source.records.get(pc)
        else {
            return Ok(Control::Next);
        };
        if boxed && self.stack & 1 == 0 {
            // FOR without power flow skips its whole loop.
            if let Some(&next) = self.for_pairs.get(&(unit.page, pc)) {
                return Ok(Control::Goto(next + 1));
            }
            return Ok(Control::Next);
        }
        let target = Arc::clone(&self.target);
        let ins = target.instructions.get(*id);
        let handler = self
            .handlers
            .get(id.0 as usize)
            .copied()
            .flatten()
            .ok_or_else(|| Fault::NoSemantics {
                mnemonic: ins.mnemonic.clone(),
            })?;
        let mut exec = Exec {
            vm: self,
            operands,
            page: unit.page,
            index: pc,
            offset: *offset,
            mnemonic: &ins.mnemonic,
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

    /// Whether the next instruction is the patched breakpoint.
    pub(crate) fn at_breakpoint(&self) -> bool {
        self.frames.last().is_some_and(|f| {
            self.units[f.page as usize]
                .as_ref()
                .and_then(|u| u.ops.get(f.pc))
                == Some(&Op::Break)
        })
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
