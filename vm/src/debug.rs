//! Status and debugging as UM4001 describes them: the status byte, a breakpoint by
//! (function, network, step), single-step stop, STEP_IN / STEP_OVER / STEP_OUT, and the
//! 16-byte DEBUG_INFOR block. docs/vm.md, "Debugging".

use std::sync::Arc;

use crate::decode::Op;
use crate::engine::{Flow, Phase, ScanEnd};
use crate::{Fault, Vm};

/// An instruction: function (unit page: 0 MAIN, n INTn, IntSize + n SBRn), network
/// number and 0-based step within the network.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Position {
    pub function: u8,
    pub network: u16,
    pub step: u16,
}

impl std::fmt::Display for Position {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}:{}", self.function, self.network, self.step)
    }
}

/// DEBUG_SCAN's steps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Step {
    /// One instruction; a CALL stops at the subroutine's first instruction.
    In,
    /// One instruction; a CALL runs the whole subroutine.
    Over,
    /// Run until the current unit returns.
    Out,
}

/// The status byte (STATUS_READ).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Status {
    /// In RUN (not STOP).
    pub run: bool,
    /// A reset was requested (STATUS_RESET) and has not happened yet.
    pub reset: bool,
    /// A programming tool is logged in (PLC_ATTACH); the host sets it.
    pub attach: bool,
    /// A fault stopped the program.
    pub error: bool,
}

impl Status {
    /// bit0 RUN, bit1 RESET, bit2 ATTACH, bit3 ERROR.
    pub fn byte(self) -> u8 {
        u8::from(self.run)
            | (u8::from(self.reset) << 1)
            | (u8::from(self.attach) << 2)
            | (u8::from(self.error) << 3)
    }
}

/// Why a debugging request cannot be carried out.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum DebugError {
    /// No instruction at that position.
    NoInstruction(Position),
    /// Stepping needs the program paused (single-step stop or a breakpoint).
    NotPaused,
    /// The program is in STOP.
    Stopped,
    /// The program faulted.
    Fault(Fault),
}

impl std::fmt::Display for DebugError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DebugError::NoInstruction(p) => write!(
                f,
                "no instruction at function {} network {} step {}",
                p.function, p.network, p.step
            ),
            DebugError::NotPaused => f.write_str("the program is not paused"),
            DebugError::Stopped => f.write_str("the PLC is in STOP"),
            DebugError::Fault(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for DebugError {}

impl From<Fault> for DebugError {
    fn from(f: Fault) -> Self {
        DebugError::Fault(f)
    }
}

/// Debugger state.
#[derive(Debug, Clone, Default)]
pub(crate) struct Debug {
    /// The breakpoint and the record index it is patched over.
    pub breakpoint: Option<(Position, usize)>,
    /// Execution is suspended before the next instruction.
    pub paused: bool,
    /// DEBUG_WRITE 0: stop before every instruction; the host steps.
    pub single_step: bool,
    /// PLC_ATTACH: a tool is logged in.
    pub attached: bool,
    /// DEBUG_RESET happened and nothing has run since (DEBUG_READ's RESET bit).
    pub reset_pending: bool,
}

impl Vm {
    /// The status byte's bits.
    pub fn status(&self) -> Status {
        Status {
            run: !self.stopped,
            reset: self.reset_requested,
            attach: self.debug.attached,
            error: self.fault.is_some(),
        }
    }

    /// PLC_ATTACH / PLC_DETACH: the host's login state, shown in the status byte.
    pub fn set_attached(&mut self, attached: bool) {
        self.debug.attached = attached;
    }

    /// DEBUG_READ: bit0 RUN (running until a breakpoint, not in single-step stop),
    /// bit1 RESET (a DEBUG_RESET happened and nothing has run since).
    pub fn debug_byte(&self) -> u8 {
        u8::from(!self.debug.single_step) | (u8::from(self.debug.reset_pending) << 1)
    }

    /// Whether execution is paused before an instruction.
    pub fn is_paused(&self) -> bool {
        self.debug.paused
    }

    /// Where execution is paused (the next instruction to run).
    pub fn position(&self) -> Option<Position> {
        if !self.debug.paused {
            return None;
        }
        let f = self.frames.last()?;
        let unit = self.units[f.page as usize].as_ref()?;
        let &(network, step) = unit.positions.get(f.pc)?;
        Some(Position {
            function: f.page,
            network,
            step,
        })
    }

    /// The breakpoint, if one is set.
    pub fn breakpoint(&self) -> Option<Position> {
        self.debug.breakpoint.map(|(p, _)| p)
    }

    /// DEBUG_INFOR_WRITE: set (or with `None` clear) the breakpoint. The PLC has one.
    pub fn set_breakpoint(&mut self, at: Option<Position>) -> Result<(), DebugError> {
        let found = match at {
            None => None,
            Some(p) => {
                let pc = self.units[p.function as usize]
                    .as_ref()
                    .and_then(|u| {
                        u.positions.iter().zip(&u.plain).position(|(&(n, s), op)| {
                            n == p.network && s == p.step && !op.is_network()
                        })
                    })
                    .ok_or(DebugError::NoInstruction(p))?;
                Some((p, pc))
            }
        };
        if let Some((p, _)) = self.debug.breakpoint.take() {
            self.rebuild(p.function, None);
        }
        if let Some((p, pc)) = found {
            self.rebuild(p.function, Some(pc));
            self.debug.breakpoint = Some((p, pc));
        }
        Ok(())
    }

    /// Rebuild unit `page`'s fast operations with the breakpoint at `pc` (or none).
    fn rebuild(&mut self, page: u8, pc: Option<usize>) {
        let fast = self.config.fast;
        if let Some(unit) = self.units[page as usize].as_mut() {
            let unit = Arc::make_mut(unit);
            let mut chain = std::mem::take(&mut unit.chain);
            unit.ops = if fast {
                crate::decode::build(&unit.plain, pc, &mut chain)
            } else {
                let mut ops = unit.plain.clone();
                if let Some(op) = pc.and_then(|pc| ops.get_mut(pc)) {
                    *op = Op::Break;
                }
                ops
            };
            unit.chain = chain;
        }
    }

    /// DEBUG_WRITE with 0: single-step stop. Execution pauses before the next
    /// instruction (starting a scan when between scans); scans do nothing until the host
    /// steps or runs.
    pub fn debug_stop(&mut self) -> Result<(), DebugError> {
        self.check_runnable()?;
        self.debug.single_step = true;
        if !self.debug.paused {
            self.pause_at_next()?;
        }
        Ok(())
    }

    /// DEBUG_WRITE with non-zero: run until a breakpoint. A paused scan continues at the
    /// next `scan()`.
    pub fn debug_run(&mut self) {
        self.debug.single_step = false;
        self.debug.paused = false;
    }

    /// DEBUG_RESET: reset, then single-step stop before the first instruction.
    pub fn debug_reset(&mut self) -> Result<(), DebugError> {
        self.reset();
        self.debug_stop()?;
        self.debug.reset_pending = true;
        Ok(())
    }

    /// DEBUG_SCAN: one step while paused. Returns where execution is paused afterwards.
    pub fn debug_step(&mut self, step: Step) -> Result<ScanEnd, DebugError> {
        self.check_runnable()?;
        if !self.debug.paused {
            return Err(DebugError::NotPaused);
        }
        self.debug.reset_pending = false;
        let result = self.step_inner(step);
        match result {
            Ok(end) => Ok(end),
            Err(f) => {
                self.record_fault(f.clone());
                Err(DebugError::Fault(f))
            }
        }
    }

    fn check_runnable(&self) -> Result<(), DebugError> {
        if let Some(f) = &self.fault {
            return Err(DebugError::Fault(f.clone()));
        }
        if self.stopped {
            return Err(DebugError::Stopped);
        }
        Ok(())
    }

    fn step_inner(&mut self, step: Step) -> Result<ScanEnd, Fault> {
        if self.phase == Phase::Idle || self.frames.is_empty() {
            // Paused between scans: the step starts the next scan.
            return self.pause_at_next();
        }
        let depth = self.frames.len();
        let until = match step {
            Step::In => depth,
            Step::Over => depth,
            Step::Out => depth - 1,
        };
        let mut crossed = self.single()?;
        if step != Step::In {
            while !crossed && self.frames.len() > until {
                if self.next_op(true) == Some(Op::Break) {
                    break;
                }
                crossed = self.single()?;
            }
        }
        self.pause_at_next()
    }

    /// Run one instruction; true when the frames of the phase ran out (the scan moved
    /// to its next phase, possibly ending).
    fn single(&mut self) -> Result<bool, Fault> {
        let flow = self.exec::<true>()?;
        if flow == Flow::Stepped && !self.frames.is_empty() {
            return Ok(false);
        }
        let flow = if flow == Flow::Stepped {
            Flow::Empty
        } else {
            flow
        };
        self.next_phase(flow)?;
        Ok(true)
    }

    /// Settle before the next instruction to run: skip network records, leave units at
    /// their ends, move through the scan's phases, and start the next scan when the
    /// current one ended. At most one scan starts here: a scan without any instruction
    /// pauses between scans.
    fn pause_at_next(&mut self) -> Result<ScanEnd, Fault> {
        let mut begun = false;
        self.debug.paused = true;
        loop {
            if self.phase == Phase::Idle {
                if begun {
                    return Ok(ScanEnd::PausedIdle);
                }
                self.begin_scan();
                begun = true;
            }
            let Some(f) = self.frames.last() else {
                self.next_phase(Flow::Empty)?;
                continue;
            };
            let (page, pc) = (f.page, f.pc);
            let op = self.units[page as usize]
                .as_ref()
                .and_then(|u| u.plain.get(pc).copied());
            match op {
                Some(op) if op.is_network() => {
                    self.stack = 0;
                    if let Some(f) = self.frames.last_mut() {
                        f.pc = pc + 1;
                    }
                }
                Some(_) => {
                    return Ok(self.position().map_or(ScanEnd::PausedIdle, ScanEnd::Paused));
                }
                None => self.leave()?,
            }
        }
    }

    /// The 16-byte DEBUG_INFOR block (words high byte first): 0 breakpoint function
    /// (0xFF none), 1-2 its network, 3-4 its step, 5 function of the paused position
    /// (0xFF when running), 6-7 its network, 8-9 its step, 10-11 bytes of caller L saved
    /// on the call stack, 12-13 the logic stack (bit 0 top), 14 call depth, 15 error
    /// code.
    pub fn debug_info(&self) -> [u8; 16] {
        let mut b = [0u8; 16];
        let none = Position {
            function: 0xFF,
            network: 0xFFFF,
            step: 0xFFFF,
        };
        let bp = self.breakpoint().unwrap_or(none);
        let at = self.position().unwrap_or(none);
        b[0] = bp.function;
        b[1..3].copy_from_slice(&bp.network.to_be_bytes());
        b[3..5].copy_from_slice(&bp.step.to_be_bytes());
        b[5] = at.function;
        b[6..8].copy_from_slice(&at.network.to_be_bytes());
        b[8..10].copy_from_slice(&at.step.to_be_bytes());
        let saved = self.l_stack.len();
        b[10..12].copy_from_slice(&(saved.min(0xFFFF) as u16).to_be_bytes());
        b[12..14].copy_from_slice(&((self.stack & 0xFFFF) as u16).to_be_bytes());
        b[14] = self.frames.len().saturating_sub(1).min(255) as u8;
        b[15] = self.fault.as_ref().map_or(0, Fault::code);
        b
    }
}
