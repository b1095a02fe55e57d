//! Debugging as UM4001 describes it: a breakpoint by (function, network, step),
//! single-step stop, STEP_IN / STEP_OVER / STEP_OUT, and the debugger's state as the
//! host reads it (`DebugState`). It drives the engine (`engine.rs`) and knows no byte
//! layout: the simulator frames DEBUG_INFOR from `DebugState`. docs/vm.md, "Debugging".

use std::sync::Arc;

use crate::engine::{Engine, Flow, Phase, Position, ScanEnd};
use crate::fault::Fault;
use crate::op::Op;

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

/// What DEBUG_INFOR_READ reports, typed (the simulator lays it out in bytes).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DebugState {
    /// The breakpoint, if one is set.
    pub breakpoint: Option<Position>,
    /// Where execution is paused (the next instruction to run), if it is.
    pub paused_at: Option<Position>,
    /// Bytes of callers' L saved on the call stack (the VM's data stack).
    pub saved_local_bytes: usize,
    /// The logic stack, bit 0 the top.
    pub logic_stack: u32,
    /// Open calls (0 in MAIN or an interrupt routine).
    pub call_depth: usize,
    /// The fault's error code (0: none).
    pub error_code: u8,
}

/// Debugger state: the breakpoint and single-step mode (the pause itself is the
/// engine's, as a scan stops there).
#[derive(Debug, Clone, Default)]
pub(crate) struct Debugger {
    /// The breakpoint and the record index it is patched over.
    breakpoint: Option<(Position, usize)>,
    /// DEBUG_WRITE 0: stop before every instruction; the host steps.
    single_step: bool,
    /// DEBUG_RESET happened and nothing has run since (DEBUG_READ's RESET bit).
    pub reset_pending: bool,
}

impl Debugger {
    /// DEBUG_READ: bit0 RUN (running until a breakpoint, not in single-step stop),
    /// bit1 RESET (a DEBUG_RESET happened and nothing has run since).
    pub fn debug_byte(&self) -> u8 {
        u8::from(!self.single_step) | (u8::from(self.reset_pending) << 1)
    }

    /// The breakpoint, if one is set.
    pub fn breakpoint(&self) -> Option<Position> {
        self.breakpoint.map(|(p, _)| p)
    }

    /// The debugger's state for DEBUG_INFOR_READ.
    pub fn state(&self, engine: &Engine) -> DebugState {
        DebugState {
            breakpoint: self.breakpoint(),
            paused_at: engine.position(),
            saved_local_bytes: engine.machine.l_stack.len(),
            logic_stack: engine.machine.stack,
            call_depth: engine.machine.frames.len().saturating_sub(1),
            error_code: engine.fault.as_ref().map_or(0, Fault::code),
        }
    }

    /// DEBUG_INFOR_WRITE: set (or with `None` clear) the breakpoint. The PLC has one.
    pub fn set_breakpoint(
        &mut self,
        engine: &mut Engine,
        at: Option<Position>,
    ) -> Result<(), DebugError> {
        let found = match at {
            None => None,
            Some(p) => {
                let pc = engine
                    .program
                    .unit(p.function)
                    .and_then(|u| u.find(p.network, p.step))
                    .ok_or(DebugError::NoInstruction(p))?;
                Some((p, pc))
            }
        };
        if let Some((p, _)) = self.breakpoint.take() {
            rebuild(engine, p.function, None);
        }
        if let Some((p, pc)) = found {
            rebuild(engine, p.function, Some(pc));
            self.breakpoint = Some((p, pc));
        }
        // A breakpoint may sit inside a compiled region (or a subroutine one calls):
        // while one is set, everything runs interpreted.
        engine.native_hold = self.breakpoint.is_some();
        Ok(())
    }

    /// DEBUG_WRITE with 0: single-step stop. Execution pauses before the next
    /// instruction (starting a scan when between scans); scans do nothing until the host
    /// steps or runs.
    pub fn stop(&mut self, engine: &mut Engine) -> Result<(), DebugError> {
        check_runnable(engine)?;
        self.single_step = true;
        if !engine.paused {
            pause_at_next(engine)?;
        }
        Ok(())
    }

    /// DEBUG_WRITE with non-zero: run until a breakpoint. A paused scan continues at the
    /// next scan.
    pub fn run(&mut self, engine: &mut Engine) {
        self.single_step = false;
        engine.paused = false;
    }

    /// DEBUG_SCAN: one step while paused. Returns where execution is paused afterwards.
    pub fn step(&mut self, engine: &mut Engine, step: Step) -> Result<ScanEnd, DebugError> {
        check_runnable(engine)?;
        if !engine.paused {
            return Err(DebugError::NotPaused);
        }
        self.reset_pending = false;
        match step_inner(engine, step) {
            Ok(end) => Ok(end),
            Err(f) => {
                engine.record_fault(f.clone());
                Err(DebugError::Fault(f))
            }
        }
    }
}

/// Rebuild unit `page`'s fast operations with the breakpoint at `pc` (or none).
fn rebuild(engine: &mut Engine, page: u8, pc: Option<usize>) {
    let fast = engine.program.config.fast;
    if let Some(unit) = engine.program.units[page as usize].as_mut() {
        let unit = Arc::make_mut(unit);
        let plain = unit.plain_ops();
        unit.set_ops(plain, fast, pc);
    }
}

fn check_runnable(engine: &Engine) -> Result<(), DebugError> {
    if let Some(f) = &engine.fault {
        return Err(DebugError::Fault(f.clone()));
    }
    if engine.stopped {
        return Err(DebugError::Stopped);
    }
    Ok(())
}

fn step_inner(engine: &mut Engine, step: Step) -> Result<ScanEnd, Fault> {
    if engine.phase == Phase::Idle || engine.machine.frames.is_empty() {
        // Paused between scans: the step starts the next scan.
        return pause_at_next(engine);
    }
    let depth = engine.machine.frames.len();
    let until = match step {
        Step::In => depth,
        Step::Over => depth,
        Step::Out => depth - 1,
    };
    let mut crossed = single(engine)?;
    if step != Step::In {
        while !crossed && engine.machine.frames.len() > until {
            if engine.next_op(true) == Some(Op::Break) {
                break;
            }
            crossed = single(engine)?;
        }
    }
    pause_at_next(engine)
}

/// Run one instruction; true when the frames of the phase ran out (the scan moved to
/// its next phase, possibly ending).
fn single(engine: &mut Engine) -> Result<bool, Fault> {
    let flow = engine.exec::<true>()?;
    if flow == Flow::Stepped && !engine.machine.frames.is_empty() {
        return Ok(false);
    }
    let flow = if flow == Flow::Stepped {
        Flow::Empty
    } else {
        flow
    };
    engine.next_phase(flow, false)?;
    Ok(true)
}

/// Settle before the next instruction to run: skip network records, leave units at
/// their ends, move through the scan's phases, and start the next scan when the current
/// one ended. At most one scan starts here: a scan without any instruction pauses
/// between scans.
fn pause_at_next(engine: &mut Engine) -> Result<ScanEnd, Fault> {
    let mut begun = false;
    engine.paused = true;
    loop {
        if engine.phase == Phase::Idle {
            if begun {
                return Ok(ScanEnd::PausedIdle);
            }
            engine.begin_scan();
            begun = true;
        }
        let Some(f) = engine.machine.frames.last() else {
            engine.next_phase(Flow::Empty, false)?;
            continue;
        };
        let (page, pc) = (f.page, f.pc);
        let op = engine.program.unit(page).and_then(|u| u.plain_op(pc));
        match op {
            Some(op) if op.is_network() => {
                engine.machine.stack = 0;
                engine.machine.set_pc(pc + 1);
            }
            Some(_) => {
                return Ok(engine
                    .position()
                    .map_or(ScanEnd::PausedIdle, ScanEnd::Paused));
            }
            None => engine.leave()?,
        }
    }
}
