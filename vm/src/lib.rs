//! The reference VM: runs a verified GUTTA image as the PLC would. It depends only on
//! the image format (and, through it, the target description), never on the compiler,
//! and does no I/O: the host attaches serial ports (`SerialPort`) and frames the
//! protocols. Semantics are in `ops/`, one file per instruction family, keyed by
//! mnemonic; the VM refuses an image that uses an instruction it has no semantics for.
//!
//! Modules in layers, lowest first; a module uses only modules of lower layers, so the
//! module graph has no cycles (`tests/layers.rs` checks it on the real module graph):
//!
//! 0. `fault` (run-time faults), `memory` (the flat byte memory), `op` (decoded
//!    operations), `vcd` (waveform text, used by the tools)
//! 1. `fuse` (bit-logic chains), `fast` (running operations on memory), and the VM's
//!    parts: `machine` (memory, logic stack, frames, L stack, loops, hidden state),
//!    `clock` (virtual time, scan counters), `terminals` (input terminals and forces),
//!    `interrupts`, `exch` (the EXCH queue and serial ports)
//! 2. `decode` (a unit's records into operations, CALL plans)
//! 3. `program` (target, image data, config, decoded units)
//! 4. `calls` (planned CALLs), `ops` (semantics: each sees an `Exec` with the parts it
//!    may change, never the `Vm`), `tier` (the compiled tier: regions of a program's
//!    units as native code through gutta-jit; feature `jit`)
//! 5. `engine` (the parts together; the scan on its explicit frame stack)
//! 6. `debug` (breakpoint, single steps), `load` (image -> engine)
//! 7. this file: `Vm`, the public API, delegating to the above

mod calls;
mod clock;
mod debug;
mod decode;
mod engine;
pub mod exch;
mod fast;
mod fault;
mod fuse;
mod interrupts;
mod load;
mod machine;
mod memory;
mod op;
pub mod ops;
mod program;
mod terminals;
#[cfg(feature = "jit")]
mod tier;
#[cfg(feature = "jit")]
mod tier_generic;
pub mod vcd;

use std::sync::Arc;

use gutta_catalog::{Address, Target};
use gutta_format::VerifiedImage;
use op::{Op, Quick};

pub use debug::{DebugError, DebugState, Status, Step};
pub use engine::{Position, ScanEnd, TierState};
pub use exch::{Queued, SerialPort};
pub use fault::Fault;
pub use load::LoadError;
pub use memory::{AccessError, Memory};
pub use program::{VmConfig, DEFAULT_NATIVE_AFTER};
pub use terminals::ForceError;

/// A loaded PLC.
///
/// An image runs only once verified for its target: compile, verify, load, scan.
///
/// ```rust
/// use std::sync::Arc;
///
/// use gutta_catalog::stdlib;
/// use gutta_compiler::{compile, source::SourceFile};
/// use gutta_vm::{Vm, VmConfig};
///
/// let text = "\
/// ORGANIZATION_BLOCK MAIN:OB1
/// BEGIN
/// NETWORK 1
/// LD     SM0.0
/// MOVW   3585, MW24
/// +I     1, MW26
/// END_ORGANIZATION_BLOCK
/// ";
/// let target = stdlib::shared(stdlib::DEFAULT)?;
/// let image = compile(SourceFile::new("main.lad", text), None)
///     .image
///     .expect("the program compiles");
/// let verified = gutta_format::verify(&image, &target)?;
/// let mut vm = Vm::new(verified, Arc::clone(&target), VmConfig::default())?;
/// for _ in 0..3 {
///     vm.scan()?;
/// }
/// let read = |var: &str| {
///     let address = target.memory.parse_address(var).expect("an address");
///     vm.read(address).expect("inside its area")
/// };
/// assert_eq!(read("MW24"), 3585);
/// assert_eq!(read("MW26"), 3); // one increment per scan
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct Vm {
    engine: engine::Engine,
    debugger: debug::Debugger,
    /// PLC_ATTACH: a tool is logged in (the host says so).
    attached: bool,
}

impl Vm {
    /// Load a verified image.
    pub fn new(
        image: VerifiedImage,
        target: Arc<Target>,
        config: VmConfig,
    ) -> Result<Vm, LoadError> {
        Ok(Vm {
            engine: load::load(image, target, config)?,
            debugger: debug::Debugger::default(),
            attached: false,
        })
    }

    /// Power-on reset: memory cleared, K from the const page, data pages applied,
    /// edge memory and clock cleared, the next scan is the first.
    pub fn reset(&mut self) {
        self.engine.reset();
        self.debugger.reset_pending = false;
    }

    /// The fault that stopped the VM, if any.
    pub fn fault(&self) -> Option<&Fault> {
        self.engine.fault.as_ref()
    }

    /// The instruction the fault stopped in, when it stopped in one (a watchdog, a bad
    /// access, a call too deep); `None` without a fault.
    pub fn fault_position(&self) -> Option<Position> {
        self.engine.fault_at
    }

    /// Whether the PLC is in RUN (false after STOP).
    pub fn is_running(&self) -> bool {
        !self.engine.stopped
    }

    /// RUN (true) or STOP (false), as STATUS_WRITE does.
    /// Going to STOP abandons a scan paused in the middle.
    pub fn set_running(&mut self, run: bool) {
        self.engine.stopped = !run;
        if !run {
            self.engine.abandon_scan();
        }
    }

    /// Instructions the last scan executed (MAIN, calls and interrupt routines).
    pub fn executed_last_scan(&self) -> u64 {
        self.engine.clock.executed
    }

    /// Instructions run as compiled code (docs/vm-jit.md) since load, of all scans:
    /// against the instructions executed, the share the compiled tier covers.
    pub fn executed_natively(&self) -> u64 {
        self.engine.native_executed
    }

    pub fn scans(&self) -> u64 {
        self.engine.clock.scans
    }

    pub fn clock_ms(&self) -> u64 {
        self.engine.clock.ms
    }

    pub fn memory(&self) -> &Memory {
        &self.engine.machine.memory
    }

    pub fn target(&self) -> &Target {
        &self.engine.program.target
    }

    /// Read a variable (e.g. parsed with `MemoryMap::parse_address`).
    pub fn read(&self, address: Address) -> Result<u32, AccessError> {
        self.engine.machine.memory.read(address)
    }

    /// Write a variable. Writing an input (I, AI) sets its terminal: the value holds
    /// across scans until changed, as a wired input does. A forced bit keeps its force
    /// value (the force wins at the next scan); `write_through_forces` changes the
    /// force value too.
    pub fn write(&mut self, address: Address, value: u32) -> Result<(), AccessError> {
        let engine = &mut self.engine;
        engine
            .terminals
            .write(&mut engine.machine.memory, address, value)
    }

    /// Write a variable as `write` does; its forced bits take the value as their force
    /// value too, so the write holds (UM4001's STATUS_VAR_WRITE).
    pub fn write_through_forces(
        &mut self,
        address: Address,
        value: u32,
    ) -> Result<(), AccessError> {
        self.write(address, value)?;
        let engine = &mut self.engine;
        engine
            .terminals
            .hold_written(&engine.machine.memory, address);
        Ok(())
    }

    /// Force a variable of a forcing area (I, Q): it reads (inputs) and is written
    /// (outputs) with `value` at every scan until unforced. Forces survive `reset()`.
    pub fn force(&mut self, address: Address, value: u32) -> Result<(), ForceError> {
        let engine = &mut self.engine;
        engine.terminals.force(
            &mut engine.machine.memory,
            &engine.program.target,
            address,
            value,
        )
    }

    /// Remove the force of one variable (its bits; the rest of the byte stays forced).
    pub fn unforce(&mut self, address: Address) {
        self.engine.terminals.unforce(address);
    }

    /// Remove every force.
    pub fn unforce_all(&mut self) {
        self.engine.terminals.unforce_all();
    }

    /// The force mask and value image of a slot (all zero when nothing is forced;
    /// empty for a slot without an area).
    pub fn force_image(&self, slot: u8) -> (Vec<u8>, Vec<u8>) {
        self.engine
            .terminals
            .force_image(&self.engine.machine.memory, slot)
    }

    /// STATUS_RESET: request a reset; RESET shows in the status byte until it happens,
    /// at the start of the next scan (or `reset()`).
    pub fn request_reset(&mut self) {
        self.engine.reset_requested = true;
    }

    /// STATUS_SCAN: a PLC in STOP runs `n` scans and stays in STOP. A running PLC is not
    /// affected (it scans anyway).
    pub fn scan_while_stopped(&mut self, n: u8) -> Result<(), Fault> {
        if !self.engine.stopped {
            return Ok(());
        }
        self.engine.stopped = false;
        let mut result = Ok(());
        for _ in 0..n {
            result = self.scan();
            if result.is_err() || self.engine.stopped {
                break;
            }
        }
        self.set_running(false);
        result
    }

    /// One scan: inputs, system bits, MAIN, interrupt routines, forces, EXCH, clock. A
    /// fault stops the VM (ERROR) until reset. While paused (breakpoint, single-step
    /// stop) or in STOP, nothing runs.
    pub fn scan(&mut self) -> Result<(), Fault> {
        self.run_scan().map(|_| ())
    }

    /// Like `scan`, saying how it ended: a paused scan continues where it stopped.
    pub fn run_scan(&mut self) -> Result<ScanEnd, Fault> {
        let engine = &self.engine;
        // One test of the flags of the rare states (a fault, STOP, a pause, a reset
        // requested) before anything else in most scans.
        if engine.fault.is_some() | engine.stopped | engine.paused | engine.reset_requested {
            if let Some(end) = self.engine.blocked() {
                return end;
            }
            if self.engine.reset_requested {
                self.reset();
            }
        }
        self.debugger.reset_pending = false;
        let engine = &mut self.engine;
        let end = engine
            .continue_scan()
            .inspect_err(|f| engine.record_fault(f.clone()))?;
        if end == ScanEnd::Completed {
            engine.tier_up();
        }
        Ok(end)
    }

    /// The records of the loaded program whose semantic the interpreter runs from
    /// `ops/` (not pre-decoded into a fast operation, nor run by the fast path itself
    /// as LBL, NOP, a forward JMP, INC/DEC, /I, /D, ENI and DISI are), counted per
    /// mnemonic.
    /// With `VmConfig::fast` off every instruction is one. For tests and benchmarks:
    /// what the interpreter still looks up at run time.
    pub fn generic_records(&self) -> Vec<(String, usize)> {
        let mut counts = std::collections::BTreeMap::<String, usize>::new();
        for unit in self.engine.program.units.iter().flatten() {
            for pc in 0..unit.ops.len() {
                let quick = matches!(
                    unit.plain_op(pc),
                    Some(Op::Generic {
                        quick: Quick::Nothing
                            | Quick::Jump { .. }
                            | Quick::Step { .. }
                            | Quick::Divide { .. }
                            | Quick::Store { .. },
                        ..
                    })
                );
                if let Some((id, _, _)) = unit.instruction(pc).filter(|_| !quick) {
                    *counts.entry(unit.mnemonic(id).to_string()).or_default() += 1;
                }
            }
        }
        counts.into_iter().collect()
    }

    /// The compiled tier's state: interpreted (not yet or off), compiled (regions and
    /// machine code bytes), nothing to compile, or refused with the reason.
    pub fn tier(&self) -> &TierState {
        &self.engine.tier
    }

    /// Compile the program to the compiled tier now, if it is not compiled yet, instead
    /// of waiting for `VmConfig::native_after` scans (a host that times its scans
    /// compiles between them: `gutta-vm --tier auto --stats`). Nothing happens without
    /// `VmConfig::fast`, while a breakpoint is set, or without the `jit` feature.
    pub fn compile_tier(&mut self) -> &TierState {
        self.engine.compile_now();
        &self.engine.tier
    }

    /// Connect a device to serial port `port` (replacing any previous one).
    pub fn attach_port(&mut self, port: u8, p: Box<dyn SerialPort>) {
        self.engine.exch.ports.insert(port, p);
    }

    /// Disconnect serial port `port`; its exchanges then time out.
    pub fn detach_port(&mut self, port: u8) -> Option<Box<dyn SerialPort>> {
        self.engine.exch.ports.remove(&port)
    }

    /// Whether serial port `port` leads somewhere (a port was attached to it).
    pub fn has_port(&self, port: u8) -> bool {
        self.engine.exch.ports.contains_key(&port)
    }

    /// Exchanges waiting in the EXCH queue.
    pub fn exch_queue(&self) -> &[Queued] {
        &self.engine.exch.queue.0
    }

    // ---- status and debugging (UM4001) ---------------------------------------------

    /// The status byte's bits.
    pub fn status(&self) -> Status {
        Status {
            run: !self.engine.stopped,
            reset: self.engine.reset_requested,
            attach: self.attached,
            error: self.engine.fault.is_some(),
        }
    }

    /// PLC_ATTACH / PLC_DETACH: the host's login state, shown in the status byte.
    pub fn set_attached(&mut self, attached: bool) {
        self.attached = attached;
    }

    /// DEBUG_READ: bit0 RUN (running until a breakpoint, not in single-step stop),
    /// bit1 RESET (a DEBUG_RESET happened and nothing has run since).
    pub fn debug_byte(&self) -> u8 {
        self.debugger.debug_byte()
    }

    /// Whether execution is paused before an instruction.
    pub fn is_paused(&self) -> bool {
        self.engine.paused
    }

    /// Where execution is paused (the next instruction to run).
    pub fn position(&self) -> Option<Position> {
        self.engine.position()
    }

    /// The breakpoint, if one is set.
    pub fn breakpoint(&self) -> Option<Position> {
        self.debugger.breakpoint()
    }

    /// DEBUG_INFOR_WRITE: set (or with `None` clear) the breakpoint. The PLC has one.
    pub fn set_breakpoint(&mut self, at: Option<Position>) -> Result<(), DebugError> {
        self.debugger.set_breakpoint(&mut self.engine, at)
    }

    /// DEBUG_WRITE with 0: single-step stop. Execution pauses before the next
    /// instruction (starting a scan when between scans); scans do nothing until the host
    /// steps or runs.
    pub fn debug_stop(&mut self) -> Result<(), DebugError> {
        self.debugger.stop(&mut self.engine)
    }

    /// DEBUG_WRITE with non-zero: run until a breakpoint. A paused scan continues at the
    /// next `scan()`.
    pub fn debug_run(&mut self) {
        self.debugger.run(&mut self.engine);
    }

    /// DEBUG_RESET: reset, then single-step stop before the first instruction.
    pub fn debug_reset(&mut self) -> Result<(), DebugError> {
        self.reset();
        self.debug_stop()?;
        self.debugger.reset_pending = true;
        Ok(())
    }

    /// DEBUG_SCAN: one step while paused. Returns where execution is paused afterwards.
    pub fn debug_step(&mut self, step: Step) -> Result<ScanEnd, DebugError> {
        self.debugger.step(&mut self.engine, step)
    }

    /// DEBUG_INFOR_READ's contents: breakpoint, paused position, stacks, call depth,
    /// error code.
    pub fn debug_state(&self) -> DebugState {
        self.debugger.state(&self.engine)
    }
}
