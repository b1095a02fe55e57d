//! Instruction semantics, one file per family, found by mnemonic: the instruction
//! set is data (ManagerFun.xml), and `semantics` maps each mnemonic to what it does
//! (docs/vm.md). `Exec` is what a semantic sees: its instruction and operands, the
//! machine (memory, logic stack, frames), the program, and the few other parts some
//! families need (terminals for BIR, interrupts, the EXCH queue, the clock). A semantic
//! never sees the whole VM, the debugger or the host.

mod bits;
mod comm;
mod compare;
mod control;
mod convert;
mod interrupts;
mod math;
mod moves;
mod shift;
mod special;
mod table;
mod timers;

pub(crate) use control::finish_call;

use gutta_catalog::{Address, Width};
use gutta_format::{Operand, PackedOperand};

use crate::clock::Clock;
use crate::decode::Unit;
use crate::exch::ExchQueue;
use crate::fault::Fault;
use crate::interrupts::Interrupts;
use crate::machine::Machine;
use crate::memory;
use crate::program::Program;
use crate::terminals::Terminals;

/// What happens after an instruction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Control {
    Next,
    /// Continue after `LBL n` of the same unit.
    Jump(u16),
    /// Leave the unit (RET, CRET).
    Return,
    /// End the scan (END).
    EndScan,
    /// End the scan and stay in STOP (STOP).
    Stop,
    /// Continue at record `n` of the same unit (FOR/NEXT).
    Goto(usize),
    /// A CALL entered its subroutine (pushed a frame).
    Enter,
}

/// A semantic.
pub type Handler = fn(&mut Exec<'_>) -> Result<Control, Fault>;

/// The semantics of an instruction, if the VM has them: timers and counters by their
/// kind (ManagerFun.xml `Kind`), every other instruction by its mnemonic.
pub fn semantics(instruction: &gutta_catalog::Instruction) -> Option<Handler> {
    if let Some(kind) = instruction.kind {
        return Some(timers::semantics(kind));
    }
    let mnemonic = instruction.mnemonic.as_str();
    bits::lookup(mnemonic)
        .or_else(|| compare::lookup(mnemonic))
        .or_else(|| moves::lookup(mnemonic))
        .or_else(|| math::lookup(mnemonic))
        .or_else(|| control::lookup(mnemonic))
        .or_else(|| shift::lookup(mnemonic))
        .or_else(|| convert::lookup(mnemonic))
        .or_else(|| table::lookup(mnemonic))
        .or_else(|| interrupts::lookup(mnemonic))
        .or_else(|| comm::lookup(mnemonic))
        .or_else(|| special::lookup(mnemonic))
}

/// The access width of an operand: a variable's or a pointer's; a DWORD for a number
/// (label, unit, literal).
fn width_of(op: Operand) -> Width {
    match op {
        Operand::Value(a) => a.width,
        Operand::AddressOf { width, .. } | Operand::Pointer { width, .. } => width,
        Operand::Label(_) | Operand::Unit(_) | Operand::Literal(_) => Width::Dword,
    }
}

/// The instruction being executed.
#[derive(Debug)]
pub(crate) struct Instruction<'a> {
    pub unit: &'a Unit,
    pub operands: &'a [PackedOperand],
    /// Record index in the unit.
    pub index: usize,
    /// Byte offset in the instruction page (for fault messages).
    pub offset: usize,
    pub mnemonic: &'a str,
}

/// One instruction being executed, and the parts of the VM its semantic may reach.
#[derive(Debug)]
pub struct Exec<'a> {
    pub(crate) machine: &'a mut Machine,
    pub(crate) program: &'a Program,
    pub(crate) terminals: &'a Terminals,
    pub(crate) interrupts: &'a mut Interrupts,
    pub(crate) exch: &'a mut ExchQueue,
    pub(crate) clock: &'a mut Clock,
    pub(crate) at: Instruction<'a>,
}

impl Exec<'_> {
    fn fault(&self, detail: String) -> Fault {
        Fault::BadAccess {
            page: self.page(),
            offset: self.at.offset,
            detail: format!("{}: {detail}", self.at.mnemonic),
        }
    }

    /// The page of the unit being run.
    fn page(&self) -> u8 {
        self.at.unit.page
    }

    /// Operand `i`, decoded.
    pub fn operand(&self, i: usize) -> Result<Operand, Fault> {
        let word = self
            .at
            .operands
            .get(i)
            .copied()
            .ok_or_else(|| self.fault(format!("operand {i} missing")))?;
        memory::operand(word).map_err(|e| self.fault(e.0))
    }

    /// The access width of operand `i`: a variable's or a pointer's; a DWORD for an
    /// operand that is a number (label, unit, literal).
    pub fn width(&self, i: usize) -> Result<Width, Fault> {
        Ok(width_of(self.operand(i)?))
    }

    /// The operand's value, zero-extended.
    pub fn get(&self, i: usize) -> Result<u32, Fault> {
        let op = self.operand(i)?;
        self.machine.memory.value(op).map_err(|e| self.fault(e.0))
    }

    /// The operand's value, sign-extended from the access width (the operand decoded
    /// once: timers and counters read their preset this way at every execution).
    pub fn get_signed(&self, i: usize) -> Result<i64, Fault> {
        let op = self.operand(i)?;
        let v = self.machine.memory.value(op).map_err(|e| self.fault(e.0))?;
        Ok(match width_of(op) {
            Width::Bit => v as i64,
            Width::Byte => v as u8 as i8 as i64,
            Width::Word => v as u16 as i16 as i64,
            Width::Dword => v as i32 as i64,
        })
    }

    pub fn get_real(&self, i: usize) -> Result<f32, Fault> {
        Ok(f32::from_bits(self.get(i)?))
    }

    pub fn set(&mut self, i: usize, value: u32) -> Result<(), Fault> {
        let op = self.operand(i)?;
        let r = self.machine.memory.store(op, value);
        r.map_err(|e| self.fault(e.0))
    }

    pub fn locate(&self, i: usize) -> Result<Address, Fault> {
        let op = self.operand(i)?;
        self.machine.memory.locate(op).map_err(|e| self.fault(e.0))
    }

    pub fn read_at(&self, loc: Address) -> Result<u32, Fault> {
        self.machine.memory.read(loc).map_err(|e| self.fault(e.0))
    }

    pub fn write_at(&mut self, loc: Address, value: u32) -> Result<(), Fault> {
        let r = self.machine.memory.write(loc, value);
        r.map_err(|e| self.fault(e.0))
    }

    // ---- logic stack (bit 0 is the top) ------------------------------------------

    pub fn top(&self) -> bool {
        self.machine.stack & 1 == 1
    }

    pub fn set_top(&mut self, v: bool) {
        self.machine.stack = (self.machine.stack & !1) | u32::from(v);
    }

    pub fn push(&mut self, v: bool) {
        self.machine.stack = ((self.machine.stack << 1) | u32::from(v)) & self.machine.stack_mask;
    }

    pub fn pop(&mut self) -> bool {
        let v = self.top();
        self.machine.stack >>= 1;
        v
    }

    /// Level `n` of the stack (0 = top).
    pub fn level(&self, n: u32) -> bool {
        n < 32 && (self.machine.stack >> n) & 1 == 1
    }

    // ---- flags in SM1 --------------------------------------------------------------

    fn sm_bit(&mut self, bit: u8, v: bool) {
        let loc = Address {
            slot: self.program.slots.sm,
            offset: 1,
            width: Width::Bit,
            bit,
        };
        let _ = self.machine.memory.write(loc, u32::from(v));
    }

    /// SM1.0 zero, SM1.1 overflow, SM1.2 negative.
    pub fn flags(&mut self, zero: bool, overflow: bool, negative: bool) {
        self.sm_bit(0, zero);
        self.sm_bit(1, overflow);
        self.sm_bit(2, negative);
    }

    /// Division by zero (ManagerFun.xml /I /D /R DIV): SM1.3 set, SM1.0, SM1.1 and
    /// SM1.2 cleared.
    pub fn divide_by_zero(&mut self) {
        self.flags(false, false, false);
        self.sm_bit(3, true);
    }

    /// Word `k` (0 or 1) of the hidden state of the T or C cell at `loc` (zeroed at
    /// reset), kept after the areas in the flat memory (`Memory::cell_state_at`); a cell
    /// of another area (reachable only through a pointer) keeps it in a map.
    pub fn cell_word(&mut self, loc: Address, k: usize) -> u32 {
        match self.machine.memory.cell_state_at(loc.slot, loc.offset) {
            Some(at) => self.machine.memory.state_word(at, k),
            None => self
                .machine
                .hidden
                .cells
                .get(&(loc.slot, loc.offset))
                .map_or(0, |w| w[k]),
        }
    }

    pub fn set_cell_word(&mut self, loc: Address, k: usize, v: u32) {
        match self.machine.memory.cell_state_at(loc.slot, loc.offset) {
            Some(at) => self.machine.memory.set_state_word(at, k, v),
            None => {
                self.machine
                    .hidden
                    .cells
                    .entry((loc.slot, loc.offset))
                    .or_default()[k] = v;
            }
        }
    }

    /// The flat index of this EU/ED instance's edge byte (its input at its previous
    /// execution, 0 or 1; zeroed at reset).
    pub fn edge_state(&self) -> Option<usize> {
        self.at.unit.edge_state(self.at.index)
    }

    /// Virtual milliseconds one scan lasts.
    pub fn scan_ms(&self) -> u32 {
        self.program.config.scan_ms
    }

    /// The running target (timer resolutions, counter limits, ...).
    pub fn target(&self) -> &gutta_catalog::Target {
        &self.program.target
    }

    /// SM1 bit `bit` (0 zero, 1 overflow, 2 negative, 3 divide by zero, 4 table full,
    /// 5 table empty, 6 BCD error).
    pub fn flag(&mut self, bit: u8, v: bool) {
        self.sm_bit(bit, v);
    }

    pub fn clear_divide(&mut self) {
        self.sm_bit(3, false);
    }
}
