//! The interpreter: pre-decoded units run on an explicit stack of frames, so a scan can
//! stop at any instruction (a breakpoint, a single step) and continue later exactly where
//! it stopped. A scan has phases: MAIN, then the interrupt routines of the events that
//! occurred, then the end of scan (forces, EXCH, clock). docs/vm.md, "Scan cycle" and
//! "Debugging". The engine owns the VM's parts; it knows no debugger policy (that is
//! `debug.rs`, above it) and no protocol.

use std::collections::VecDeque;

use gutta_catalog::{Address, Width};

use crate::calls;
use crate::clock::Clock;
use crate::decode::Unit;
use crate::exch::Exch;
use crate::fast::{fast_op, run_fast, Tables};
use crate::fault::Fault;
use crate::interrupts::Interrupts;
use crate::machine::Machine;
use crate::op::Op;
use crate::ops::{self, Control, Exec, Handler, Instruction};
use crate::program::Program;
use crate::terminals::Terminals;

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

/// Where a scan is. A plain value: setting it at every scan's start and end drops
/// nothing (the events still to serve are `Engine::events`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) enum Phase {
    /// Between scans.
    #[default]
    Idle,
    /// MAIN (and what it calls) runs.
    Main,
    /// Interrupt routines run: the events still to serve are `Engine::events`.
    Events,
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
    Paused(Position),
    /// Paused between scans (a program with no instruction to stop at).
    PausedIdle,
    /// The PLC is in STOP: nothing ran.
    Stopped,
}

/// The VM's parts, and the scan that runs on them.
#[derive(Debug)]
pub(crate) struct Engine {
    pub program: Program,
    /// The semantic of each instruction id.
    pub handlers: Vec<Option<Handler>>,
    pub machine: Machine,
    pub terminals: Terminals,
    pub interrupts: Interrupts,
    pub exch: Exch,
    pub clock: Clock,
    /// Where the current scan is.
    pub phase: Phase,
    /// In `Phase::Events`, the events whose routines are still to run, in order (empty
    /// otherwise; the buffer is kept between scans, so no scan allocates).
    pub events: VecDeque<u32>,
    /// Execution is suspended before the next instruction (breakpoint, single step).
    pub paused: bool,
    /// STOP was executed: scans do nothing until set running.
    pub stopped: bool,
    /// STATUS_RESET was requested; the next scan resets first.
    pub reset_requested: bool,
    pub fault: Option<Fault>,
    /// The instruction that faulted, when the fault happened in one.
    pub fault_at: Option<Position>,
    /// The compiled tier (`tier.rs`), once compiled.
    #[cfg(feature = "jit")]
    pub native: Option<Box<crate::tier::Native>>,
    /// What became of compiling: not yet, compiled, nothing to compile, or refused.
    pub tier: TierState,
    /// A breakpoint is set: everything runs interpreted (a breakpoint may sit inside a
    /// compiled region).
    pub native_hold: bool,
    /// Instructions run by compiled regions since load (`Vm::executed_natively`).
    pub native_executed: u64,
}

/// The compiled tier's state (`Vm::tier`).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub enum TierState {
    /// Not compiled (yet): `VmConfig::native_after` scans have not completed, or the
    /// tier is off (`VmConfig::fast` false, `native_after` None, no `jit` feature).
    #[default]
    Interpreted,
    /// Compiled: regions of native code and their machine code size; `shared` when
    /// the code was compiled for another VM of the same program in this process and is
    /// shared with it.
    Compiled {
        regions: usize,
        code_bytes: usize,
        shared: bool,
    },
    /// Nothing in the program is worth compiling.
    NothingToCompile,
    /// The code generator refused (the interpreter runs everything): why.
    Refused(String),
}

impl Engine {
    /// Power-on reset: memory cleared, K from the const page, data pages applied,
    /// hidden state and clock cleared, the next scan is the first.
    pub fn reset(&mut self) {
        let memory = &mut self.machine.memory;
        memory.clear();
        crate::program::initial_values(memory, &self.program.image, self.program.slots.constant);
        self.machine.hidden = Default::default();
        self.abandon_scan();
        self.interrupts = Interrupts::default();
        self.exch.queue.0.clear();
        self.stopped = false;
        self.reset_requested = false;
        self.clock = Clock::default();
        self.fault = None;
        self.fault_at = None;
    }

    /// Drop a scan in progress (frames, loops, saved L, pause).
    pub fn abandon_scan(&mut self) {
        self.machine.unwind_all();
        self.phase = Phase::Idle;
        self.events.clear();
        self.paused = false;
    }

    /// A fault: SMB2 holds its code, the scan is abandoned (and counted), ERROR is set.
    pub fn record_fault(&mut self, f: Fault) {
        let smb2 = Address {
            slot: self.program.slots.sm,
            offset: 2,
            width: Width::Byte,
            bit: 0,
        };
        let _ = self.machine.memory.write(smb2, u32::from(f.code()));
        if self.phase != Phase::Idle {
            self.clock.end_scan(self.program.config.scan_ms);
        }
        self.fault_at = self.current_instruction();
        self.abandon_scan();
        self.fault = Some(f);
    }

    /// Why a scan cannot run now (a fault, STOP, a pause), as `run_scan` reports it.
    pub fn blocked(&self) -> Option<Result<ScanEnd, Fault>> {
        if let Some(f) = &self.fault {
            return Some(Err(f.clone()));
        }
        if self.stopped {
            return Some(Ok(ScanEnd::Stopped));
        }
        if self.paused {
            return Some(Ok(self
                .position()
                .map_or(ScanEnd::PausedIdle, ScanEnd::Paused)));
        }
        None
    }

    /// Where execution is paused (the next instruction to run).
    pub fn position(&self) -> Option<Position> {
        if !self.paused {
            return None;
        }
        self.current_instruction()
    }

    /// The instruction the top frame is at (running or about to run).
    fn current_instruction(&self) -> Option<Position> {
        let f = self.machine.frames.last()?;
        let unit = self.program.unit(f.page)?;
        let (network, step) = unit.position(f.pc)?;
        Some(Position {
            function: f.page,
            network,
            step,
        })
    }

    /// Leave the top unit: a called subroutine copies its outputs back to the caller,
    /// which continues after its CALL.
    pub fn leave(&mut self) -> Result<(), Fault> {
        let Some(frame) = self.machine.frames.pop() else {
            return Ok(());
        };
        self.machine.loops.truncate(frame.loops_at_entry);
        if let Some(save) = frame.call {
            match save.plan {
                Some(plan) => calls::return_planned(&mut self.machine, &self.program, plan, save),
                None => ops::finish_call(&mut self.machine, &self.program, frame.page, save)?,
            }
        }
        Ok(())
    }

    fn unwind(&mut self) -> Result<(), Fault> {
        while !self.machine.frames.is_empty() {
            self.leave()?;
        }
        Ok(())
    }

    /// Run the top frames. `SINGLE`: return after one instruction (a breakpoint's own
    /// instruction runs); otherwise run until the frames are done or a breakpoint is next.
    /// The running unit is borrowed from the program while the machine and the clock are
    /// changed (no reference count per frame change); what needs the whole engine (a
    /// generic instruction, leaving a unit) ends the borrow and continues at `'frames`.
    pub fn exec<const SINGLE: bool>(&mut self) -> Result<Flow, Fault> {
        let limits = self.limits();
        let watchdog = limits.watchdog;
        'frames: loop {
            let Some(frame) = self.machine.frames.last() else {
                return Ok(Flow::Empty);
            };
            let mut pc = frame.pc;
            let page = frame.page;
            let Some(shared) = self.program.unit(frame.page) else {
                self.leave()?;
                continue;
            };
            let unit: &Unit = shared;
            let ops: &[Op] = &unit.ops;
            let tables = Tables {
                unit: &unit.tables,
                #[cfg(feature = "jit")]
                regions: match &self.native {
                    Some(native) if !SINGLE && !self.native_hold => native.starts(page),
                    _ => &[],
                },
                #[cfg(not(feature = "jit"))]
                regions: &[],
            };
            let mut st = self.machine.stack;
            loop {
                if !SINGLE {
                    #[cfg(feature = "jit")]
                    let depth = self.machine.frames.len();
                    pc = Straight {
                        #[cfg(feature = "jit")]
                        native: self.native.as_deref().filter(|_| !self.native_hold),
                        bytes: &mut self.machine.memory.bytes,
                        clock: &mut self.clock,
                        #[cfg(feature = "jit")]
                        native_executed: &mut self.native_executed,
                        #[cfg(feature = "jit")]
                        depth,
                    }
                    .run(limits, page, ops, tables, pc, &mut st);
                }
                let Some(&fast) = ops.get(pc) else {
                    // The unit's end: return from it.
                    self.machine.stack = st;
                    let machine = &mut self.machine;
                    if let [root] = machine.frames.as_slice() {
                        if root.call.is_none() {
                            // The phase's unit (MAIN, an interrupt routine) ends:
                            // nothing to copy back, no frame left (`leave`, shortly).
                            let loops = root.loops_at_entry;
                            machine.frames.clear();
                            machine.loops.truncate(loops);
                            return Ok(if SINGLE { Flow::Stepped } else { Flow::Empty });
                        }
                    }
                    self.machine.set_pc(pc);
                    if !calls::leave_planned(&mut self.machine, &self.program) {
                        self.leave()?;
                    }
                    if SINGLE {
                        return Ok(Flow::Stepped);
                    }
                    continue 'frames;
                };
                if matches!(fast, Op::Break) && !SINGLE {
                    self.machine.stack = st;
                    self.machine.set_pc(pc);
                    return Ok(Flow::Break);
                }
                // One record, unfused (a breakpoint's own instruction when stepping). A
                // CALL or a generic record is never fused nor widened: no lookup.
                let op = match fast {
                    Op::Call { .. } | Op::Generic { .. } => fast,
                    _ => unit.unfused(pc, fast),
                };
                if matches!(op, Op::Network) {
                    st = 0;
                    pc += 1;
                    continue;
                }
                self.clock.executed += 1;
                if self.clock.executed > watchdog {
                    self.machine.stack = st;
                    self.machine.set_pc(pc);
                    return Err(Fault::Watchdog { limit: watchdog });
                }
                match op {
                    Op::Call { plan } => {
                        if st & 1 == 1 {
                            self.machine.stack = st;
                            self.machine.set_pc(pc);
                            calls::enter_planned(&mut self.machine, &self.program, unit, plan)?;
                            if SINGLE {
                                return Ok(Flow::Stepped);
                            }
                            continue 'frames;
                        }
                    }
                    Op::Generic { boxed, .. } => {
                        self.machine.stack = st;
                        self.machine.set_pc(pc);
                        // The unit stays borrowed from the program while the semantic
                        // changes the other parts: no reference count, and the frame
                        // goes on in this loop unless the semantic left it.
                        let parts = Parts {
                            program: &self.program,
                            handlers: &self.handlers,
                            machine: &mut self.machine,
                            terminals: &self.terminals,
                            interrupts: &mut self.interrupts,
                            exch: &mut self.exch.queue,
                            clock: &mut self.clock,
                        };
                        let control = generic(parts, unit, pc, boxed)?;
                        let next = match control {
                            Control::Next => pc + 1,
                            Control::Goto(j) => j,
                            Control::Jump(label) => {
                                unit.labels.get(&label).map_or(unit.ops.len(), |&j| j + 1)
                            }
                            Control::Return => {
                                self.leave()?;
                                if SINGLE {
                                    return Ok(Flow::Stepped);
                                }
                                continue 'frames;
                            }
                            Control::Stop | Control::EndScan => {
                                if control == Control::Stop {
                                    self.stopped = true;
                                }
                                self.unwind()?;
                                return Ok(Flow::EndScan);
                            }
                            Control::Enter => {
                                if SINGLE {
                                    return Ok(Flow::Stepped);
                                }
                                continue 'frames;
                            }
                        };
                        // The semantic may have changed the stack; the frame continues.
                        st = self.machine.stack;
                        pc = next;
                        if SINGLE {
                            self.machine.set_pc(pc);
                            return Ok(Flow::Stepped);
                        }
                        continue;
                    }
                    _ => {
                        fast_op(
                            &mut self.machine.memory.bytes,
                            op,
                            tables,
                            &mut st,
                            limits.mask,
                            limits.flags_at,
                        );
                    }
                }
                pc += 1;
                if SINGLE {
                    self.machine.stack = st;
                    self.machine.set_pc(pc);
                    return Ok(Flow::Stepped);
                }
            }
        }
    }

    /// After a completed scan: compile the program when `VmConfig::native_after` scans
    /// have completed (once; never while a breakpoint is set).
    #[inline]
    pub fn tier_up(&mut self) {
        if self.tier != TierState::Interpreted {
            return;
        }
        let config = self.program.config;
        let due = config.native_after.is_some_and(|n| self.clock.scans >= n);
        if !config.fast || !due || self.tier != TierState::Interpreted || self.native_hold {
            return;
        }
        self.compile_tier();
    }

    /// Compile the program now, whatever `VmConfig::native_after` says, if it is not
    /// compiled yet (never without `fast` or while a breakpoint is set, as `tier_up`).
    pub fn compile_now(&mut self) {
        if self.tier == TierState::Interpreted && self.program.config.fast && !self.native_hold {
            self.compile_tier();
        }
    }

    #[cfg(feature = "jit")]
    fn compile_tier(&mut self) {
        let compiled =
            crate::tier::compile(&self.program, &self.machine.memory, self.machine.stack_mask);
        self.tier = match compiled {
            Ok(Some(native)) => {
                let state = TierState::Compiled {
                    regions: native.regions.iter().map(Vec::len).sum(),
                    code_bytes: native.module.code_bytes(),
                    shared: native.shared,
                };
                self.native = Some(Box::new(native));
                state
            }
            Ok(None) => TierState::NothingToCompile,
            Err(why) => TierState::Refused(why),
        };
    }

    #[cfg(not(feature = "jit"))]
    fn compile_tier(&mut self) {}

    /// Start a scan: inputs, forces, system bits, then MAIN's frame.
    #[inline(always)]
    pub fn begin_scan(&mut self) {
        self.open_scan();
        self.machine.push_frame(0, None);
    }

    /// Start a scan up to MAIN: inputs, forces, system bits.
    #[inline(always)]
    fn open_scan(&mut self) {
        let memory = &mut self.machine.memory;
        self.terminals.refresh_inputs(memory);
        self.terminals.apply_forces(memory);
        self.clock
            .set_system_bits(&mut memory.bytes, self.program.smb0_at);
        self.clock.executed = 0;
        self.machine.frames.clear();
        self.phase = Phase::Main;
    }

    /// The frames of a phase are done (`flow`: they ran out or ended with END/STOP):
    /// start the next routine, or end the scan. True when the scan has ended. After
    /// MAIN, the interrupts check is inline and, when no event occurred (most scans),
    /// so is the end of the scan.
    #[inline(always)]
    pub fn next_phase(&mut self, flow: Flow, direct: bool) -> Result<bool, Fault> {
        match std::mem::take(&mut self.phase) {
            Phase::Main => {
                if !self.interrupts.after_main(
                    &self.program.target,
                    &self.machine.memory,
                    self.program.config.scan_ms,
                    &mut self.events,
                ) {
                    self.end_scan();
                    return Ok(true);
                }
            }
            Phase::Events if flow != Flow::EndScan => {}
            // END or STOP in a routine: the rest of the queue is dropped.
            Phase::Events | Phase::Idle => self.events.clear(),
        }
        Ok(self.next_routine(direct))
    }

    /// Start the routine of the next event still attached (true: none, the scan has
    /// ended).
    #[inline]
    fn next_routine(&mut self, direct: bool) -> bool {
        while let Some(event) = self.events.pop_front() {
            let Some(page) = self.interrupts.routine(event) else {
                continue;
            };
            self.phase = Phase::Events;
            if !direct || !self.straight(page) {
                self.machine.push_frame(page, None);
            } else if self.run_direct(page) {
                continue;
            }
            return false;
        }
        self.phase = Phase::Idle;
        self.end_scan();
        true
    }

    /// A unit started without a frame (MAIN, by `continue_scan`, and an interrupt
    /// routine, by `next_routine`, when no breakpoint is set and it is `straight`): its
    /// compiled regions and fast operations run from its first record as `exec` would
    /// run them; only where they stop before the unit's end (a box with power flow, or
    /// the watchdog's bound) is its frame pushed, at that record with that logic stack,
    /// for `exec`. True when the unit ran to its end. A short routine then costs what
    /// its instructions do, not a frame, a return from `exec` and a new call of it.
    #[inline]
    fn run_direct(&mut self, page: u8) -> bool {
        // Interpreted (no compiled tier, or nothing compiled): a test, not a call.
        #[cfg(feature = "jit")]
        if self.native.is_some() {
            if let Some(done) = self.run_whole(page) {
                return done;
            }
        }
        self.run_unit(page)
    }

    /// A unit that is one compiled region (`Native::whole`), entered at once without
    /// the fast path's setup: Some(true) when it ran to its end, Some(false) when it
    /// returned at an escape (its frame pushed there), None when it is no such unit or
    /// the region cannot be entered (the watchdog's bound). Out of line, so the
    /// interpreter's `run_unit` stays as it is.
    #[cfg(feature = "jit")]
    #[inline(never)]
    fn run_whole(&mut self, page: u8) -> Option<bool> {
        let native = self.native.as_deref()?;
        let r = native.whole(page)?;
        let mut st = 0;
        let limits = self.limits();
        let escape = Straight {
            native: Some(native),
            bytes: &mut self.machine.memory.bytes,
            clock: &mut self.clock,
            native_executed: &mut self.native_executed,
            depth: 1,
        }
        .enter(native, limits, r, &mut st)?;
        let Some(id) = escape else {
            return Some(true);
        };
        self.machine.push_frame(page, None);
        self.machine.stack = st;
        self.machine.set_pc(usize::from(id));
        Some(false)
    }

    /// `run_direct`'s general way: regions and fast operations from record 0 through
    /// `Straight::run`.
    #[inline(never)]
    fn run_unit(&mut self, page: u8) -> bool {
        let Some(shared) = self.program.unit(page) else {
            self.machine.push_frame(page, None);
            return false;
        };
        let unit: &Unit = shared;
        let tables = Tables {
            unit: &unit.tables,
            #[cfg(feature = "jit")]
            regions: self.native.as_ref().map_or(&[], |n| n.starts(page)),
            #[cfg(not(feature = "jit"))]
            regions: &[],
        };
        let mut st = 0;
        let limits = self.limits();
        let pc = Straight {
            #[cfg(feature = "jit")]
            native: self.native.as_deref(),
            bytes: &mut self.machine.memory.bytes,
            clock: &mut self.clock,
            #[cfg(feature = "jit")]
            native_executed: &mut self.native_executed,
            #[cfg(feature = "jit")]
            depth: 1,
        }
        .run(limits, page, &unit.ops, tables, 0, &mut st);
        if pc >= unit.ops.len() {
            return true;
        }
        self.machine.push_frame(page, None);
        self.machine.stack = st;
        self.machine.set_pc(pc);
        false
    }

    /// Whether unit `page` would run straight to its end (`Unit::straight`, and with
    /// the compiled tier `Native::straight`): else it would stop at a CALL or a
    /// handler's record whatever the scan, and gets its frame at once. Inline, so that
    /// such a unit costs a test, not a call of `run_direct`.
    #[inline(always)]
    fn straight(&self, page: u8) -> bool {
        #[cfg(feature = "jit")]
        if let Some(native) = &self.native {
            return native.straight(page);
        }
        self.program.unit(page).is_some_and(|u| u.straight)
    }

    /// What a straight run keeps to, read once per `exec` or routine start.
    #[inline(always)]
    fn limits(&self) -> Limits {
        Limits {
            mask: self.machine.stack_mask,
            flags_at: self.program.flags_at,
            watchdog: self.program.config.watchdog,
            #[cfg(feature = "jit")]
            call_depth: usize::from(self.program.target.instructions.call_depth),
        }
    }

    /// The end of a scan (the phase is `Idle`): forces, EXCH, the clock.
    #[inline]
    fn end_scan(&mut self) {
        self.terminals.apply_forces(&mut self.machine.memory);
        self.exch.service(
            &mut self.machine.memory,
            &self.program.image,
            self.clock.scans,
        );
        self.clock.end_scan(self.program.config.scan_ms);
    }

    /// Continue the current scan (starting one when idle) until it ends or pauses at
    /// a breakpoint.
    #[inline]
    pub fn continue_scan(&mut self) -> Result<ScanEnd, Fault> {
        if matches!(self.phase, Phase::Idle) {
            self.open_scan();
            if self.native_hold || !self.straight(0) {
                self.machine.push_frame(0, None);
            } else if self.run_direct(0) && self.next_phase(Flow::Empty, true)? {
                // MAIN ran without a frame, as a routine does (`run_direct`), and so
                // did the scan's routines: most scans of most programs.
                return Ok(ScanEnd::Completed);
            }
        }
        // Only a set breakpoint patches a `Break` into a unit (`native_hold` says one is
        // set): without one, the scan does not look.
        if self.native_hold && self.leave_breakpoint()? {
            return Ok(ScanEnd::Completed);
        }
        loop {
            match self.exec::<false>()? {
                Flow::Break => {
                    self.paused = true;
                    return Ok(self.position().map_or(ScanEnd::PausedIdle, ScanEnd::Paused));
                }
                flow => {
                    if self.next_phase(flow, !self.native_hold)? {
                        return Ok(ScanEnd::Completed);
                    }
                }
            }
        }
    }

    /// A scan paused at the breakpoint continues by running its instruction once (and
    /// nothing when the top frame is elsewhere). True when that ended the scan.
    #[cold]
    #[inline(never)]
    fn leave_breakpoint(&mut self) -> Result<bool, Fault> {
        if !self.at_breakpoint() {
            return Ok(false);
        }
        let flow = self.exec::<true>()?;
        Ok(flow != Flow::Stepped && self.next_phase(flow, false)?)
    }

    /// Whether the record the top frame is at is the patched breakpoint (a scan paused
    /// there continues by running it once).
    pub fn at_breakpoint(&self) -> bool {
        self.next_op(false) == Some(Op::Break)
    }

    /// The top frame's fast operation; with `skip_networks`, at the first instruction
    /// from there (network records are skipped by the plain operations).
    pub fn next_op(&self, skip_networks: bool) -> Option<Op> {
        let f = self.machine.frames.last()?;
        let unit = self.program.unit(f.page)?;
        let mut pc = f.pc;
        while skip_networks && unit.plain_op(pc).is_some_and(|o| o.is_network()) {
            pc += 1;
        }
        unit.ops.get(pc).copied()
    }
}

/// The parts of the engine a generic semantic may reach, borrowed apart from the
/// program (which the running unit is borrowed from).
struct Parts<'a> {
    program: &'a Program,
    handlers: &'a [Option<Handler>],
    machine: &'a mut Machine,
    terminals: &'a Terminals,
    interrupts: &'a mut Interrupts,
    exch: &'a mut crate::exch::ExchQueue,
    clock: &'a mut Clock,
}

/// Run an instruction's semantic from `ops/`.
fn generic(parts: Parts<'_>, unit: &Unit, pc: usize, boxed: bool) -> Result<Control, Fault> {
    let Some((id, offset, operands)) = unit.instruction(pc) else {
        return Ok(Control::Next);
    };
    if boxed && parts.machine.stack & 1 == 0 {
        // FOR without power flow skips its whole loop.
        if let Some(&next) = unit.loops.get(&pc) {
            return Ok(Control::Goto(next + 1));
        }
        return Ok(Control::Next);
    }
    let mnemonic = unit.mnemonic(id);
    let handler = parts
        .handlers
        .get(id.0 as usize)
        .copied()
        .flatten()
        .ok_or_else(|| Fault::NoSemantics {
            mnemonic: mnemonic.to_string(),
        })?;
    let mut exec = Exec {
        machine: parts.machine,
        program: parts.program,
        terminals: parts.terminals,
        interrupts: parts.interrupts,
        exch: parts.exch,
        clock: parts.clock,
        at: Instruction {
            unit,
            operands,
            index: pc,
            offset,
            mnemonic,
        },
    };
    handler(&mut exec)
}

/// What a straight run keeps to (`Engine::limits`).
#[derive(Clone, Copy)]
struct Limits {
    mask: u32,
    flags_at: usize,
    watchdog: u64,
    #[cfg(feature = "jit")]
    call_depth: usize,
}

/// The parts of the engine a straight run changes, borrowed beside the unit it runs
/// (the program's): `exec` and a routine started without a frame (`run_direct`) run
/// a unit's regions and fast operations through it.
struct Straight<'a> {
    /// The compiled tier (None: interpreted only: none, or a breakpoint is set).
    #[cfg(feature = "jit")]
    native: Option<&'a crate::tier::Native>,
    bytes: &'a mut Vec<u8>,
    clock: &'a mut Clock,
    #[cfg(feature = "jit")]
    native_executed: &'a mut u64,
    /// The frames below the unit's own, and its own (a region's CALLs go deeper).
    #[cfg(feature = "jit")]
    depth: usize,
}

impl Straight<'_> {
    /// Enter region `r` where it cannot differ from the interpreter (the watchdog
    /// cannot trip inside, no CALL inside can pass CallDepth): None when it cannot,
    /// else the id of the escape it returned at (power flow into a box it leaves to the
    /// interpreter), if any.
    #[cfg(feature = "jit")]
    #[inline(always)]
    fn enter(
        &mut self,
        native: &crate::tier::Native,
        limits: Limits,
        r: &crate::tier::Region,
        st: &mut u32,
    ) -> Option<Option<u16>> {
        let remaining = limits.watchdog.saturating_sub(self.clock.executed);
        if r.max_count > remaining || self.depth + r.depth as usize > limits.call_depth + 1 {
            return None;
        }
        let exit = native.module.enter(r.function as usize, self.bytes, st);
        self.clock.executed += exit.executed;
        *self.native_executed += exit.executed;
        Some(exit.escape)
    }

    /// Run unit `page` (`ops`, `tables`) from `pc` as far as compiled regions and fast
    /// operations go: to the unit's end, or a record that needs the engine (a generic
    /// record, a CALL, a breakpoint), or the watchdog's bound. Returns where it
    /// stopped; `st` is the logic stack there.
    #[inline(always)]
    #[cfg_attr(not(feature = "jit"), allow(unused_variables))]
    fn run(
        &mut self,
        limits: Limits,
        page: u8,
        ops: &[Op],
        tables: Tables<'_>,
        mut pc: usize,
        st: &mut u32,
    ) -> usize {
        loop {
            #[cfg(feature = "jit")]
            if let Some(native) = self.native {
                // Regions follow one another where a long run was cut.
                while let Some(r) = native.region(page, pc) {
                    let Some(escape) = self.enter(native, limits, r, st) else {
                        break;
                    };
                    if let Some(id) = escape {
                        // A box with power flow (tier.rs, escapes): the interpreter
                        // runs it, then the resume region at the next record.
                        pc = r.pc as usize + usize::from(id);
                        break;
                    }
                    pc += r.records as usize;
                }
            }
            // Straight-line fast operations, bounded so the watchdog stays exact.
            let remaining = limits.watchdog.saturating_sub(self.clock.executed);
            let end = ops
                .len()
                .min(pc.saturating_add(usize::try_from(remaining).unwrap_or(usize::MAX)));
            let (at, ran) = run_fast(
                self.bytes,
                &ops[..end],
                tables,
                pc,
                st,
                limits.mask,
                limits.flags_at,
            );
            let moved = at != pc;
            pc = at;
            self.clock.executed += ran;
            // Where the fast path stopped at a region's start, the region runs (it
            // moved, so this cannot repeat at one record when the region is not
            // entered).
            if !(moved && tables.regions.get(pc).is_some_and(|&k| k != 0)) {
                return pc;
            }
        }
    }
}
