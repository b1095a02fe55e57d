//! The machine an instruction runs on: memory, the logic stack, the frames of the units
//! being run, the callers' saved L, open FOR loops and the hidden state of instruction
//! instances. It is what `ops/` semantics change; it knows nothing of scans, the
//! debugger or the host.

use std::collections::HashMap;

use gutta_catalog::Target;
use gutta_format::Operand;

use crate::memory::Memory;

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

/// The caller's state a CALL saves: its L is on `Machine::l_stack` from `l_mark`.
#[derive(Debug, Clone)]
pub(crate) struct CallSave {
    pub l_mark: usize,
    pub saved_stack: u32,
    /// A planned CALL: the plan's index in the caller's unit.
    pub plan: Option<u32>,
}

/// An open FOR loop.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct LoopFrame {
    pub page: u8,
    /// Record index of the first instruction after FOR.
    pub body: usize,
    /// The INDX operand (read again at every NEXT).
    pub indx: Operand,
    /// FINAL, read once at FOR.
    pub last: i64,
    /// The logic stack at FOR; every pass starts with it.
    pub stack: u32,
}

/// State the program cannot address that has no place after the areas in the flat
/// memory (`Memory::cell_state_at`, `Unit::edge_state`): the hidden words of a timer or
/// counter reached through a pointer into an area other than T and C. Cleared at reset.
#[derive(Debug, Default)]
pub(crate) struct HiddenState {
    /// Per (slot, byte offset).
    pub cells: HashMap<(u8, u32), [u32; 2]>,
}

/// The size of L on every target today; `save_local` and `restore_local` copy it with
/// moves of a known size (other sizes take the general copy).
const L_BYTES: usize = 32;

/// Memory, logic stack and frames.
#[derive(Debug)]
pub(crate) struct Machine {
    pub memory: Memory,
    /// Logic stack: bit 0 is the top.
    pub stack: u32,
    /// The stack's depth (LogicStackDepth levels) as a mask.
    pub stack_mask: u32,
    /// The units being run, innermost last.
    pub frames: Vec<Frame>,
    /// The callers' L areas, saved by CALL, innermost last.
    pub l_stack: Vec<u8>,
    /// Open FOR loops, innermost last.
    pub loops: Vec<LoopFrame>,
    /// A reused buffer of CALL (argument and result values).
    pub scratch: Vec<u32>,
    pub hidden: HiddenState,
}

impl Machine {
    pub fn new(target: &Target) -> Machine {
        let depth = target.instructions.logic_stack_depth.min(32) as u32;
        let stack_mask = if depth >= 32 {
            u32::MAX
        } else {
            (1u32 << depth) - 1
        };
        Machine {
            memory: Memory::new(&target.memory),
            stack: 0,
            stack_mask,
            frames: Vec::new(),
            l_stack: Vec::new(),
            loops: Vec::new(),
            scratch: Vec::new(),
            hidden: HiddenState::default(),
        }
    }

    /// Enter a unit (MAIN, an interrupt routine, or a called subroutine) with an empty
    /// logic stack.
    pub fn push_frame(&mut self, page: u8, call: Option<CallSave>) {
        self.frames.push(Frame {
            page,
            pc: 0,
            call,
            loops_at_entry: self.loops.len(),
        });
        self.stack = 0;
    }

    /// The top frame continues at record `pc`.
    pub fn set_pc(&mut self, pc: usize) {
        if let Some(f) = self.frames.last_mut() {
            f.pc = pc;
        }
    }

    /// Drop the units being run (frames, loops, saved L).
    pub fn unwind_all(&mut self) {
        self.frames.clear();
        self.loops.clear();
        self.l_stack.clear();
    }

    /// Save the caller's L (at `local`: start and length in the flat memory) on the L
    /// stack and clear it; returns where it starts on the L stack.
    #[inline(always)]
    pub fn save_local(&mut self, local: Option<(usize, usize)>) -> usize {
        let mark = self.l_stack.len();
        match local {
            Some((start, L_BYTES)) => {
                // L's size on every target today: a copy of known size, inline moves
                // instead of a call of `memmove`.
                let area = &mut self.memory.bytes[start..start + L_BYTES];
                let mut copy = [0u8; L_BYTES];
                copy.copy_from_slice(area);
                self.l_stack.extend_from_slice(&copy);
                area.fill(0);
            }
            Some((start, len)) => {
                let area = &mut self.memory.bytes[start..start + len];
                self.l_stack.extend_from_slice(area);
                area.fill(0);
            }
            None => {}
        }
        mark
    }

    /// Restore the caller's L saved from `mark` and drop it from the L stack.
    #[inline(always)]
    pub fn restore_local(&mut self, local: Option<(usize, usize)>, mark: usize) {
        match (local, self.l_stack.get(mark..mark + L_BYTES)) {
            (Some((start, L_BYTES)), Some(saved)) => {
                let mut copy = [0u8; L_BYTES];
                copy.copy_from_slice(saved);
                self.memory.bytes[start..start + L_BYTES].copy_from_slice(&copy);
            }
            (Some((start, len)), _) => {
                let saved = self.l_stack.get(mark..).unwrap_or(&[]);
                let n = saved.len().min(len);
                self.memory.bytes[start..start + n].copy_from_slice(&saved[..n]);
            }
            (None, _) => {}
        }
        self.l_stack.truncate(mark);
    }
}
