//! gutta-jit: compiles runs of the VM's operations (bit logic, moves, integer math,
//! compares, planned CALLs, timers, counters, edges, S/R, forward jumps) to native code
//! with Cranelift, with exactly the semantics of `vm/src/fast.rs`, `vm/src/calls.rs` and
//! `vm/src/ops/` (`reference` is the executable statement of them). It knows nothing of images, units or the VM: the VM translates
//! its pre-decoded operations into `Step`s. The soundness argument (docs/vm-jit.md):
//! `compile` checks every memory index against `Layout::memory_len` (`check.rs`) and
//! `Module::run` checks the slice's length, so the generated code only touches the slice.

use std::fmt;

#[allow(unsafe_code)]
mod call;
mod check;
mod lower;
pub mod reference;

/// Integer math (dst := dst op src).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Arith {
    Add,
    Sub,
    Mul,
}

/// Which stack operation a compare feeds (LD pushes, A ands, O ors).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Combine {
    Load,
    And,
    Or,
}

/// A compare's relation (a rel b).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rel {
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
}

/// One argument of a Call: caller's variable and callee's parameter, flat memory indices.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Arg {
    pub var: u32,
    pub param: u32,
    pub width: u8,
    pub input: bool,
    pub output: bool,
}

/// Which timer (ManagerFun.xml TON, TOF, TONR; `vm/src/ops/timers.rs`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimerKind {
    On,
    Off,
    Retentive,
}

/// Which counter (CTU, CTD, CTUD; `vm/src/ops/timers.rs`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CounterKind {
    Up,
    Down,
    UpDown,
}

/// A timer's or counter's preset: a constant, or the signed INT at a memory index
/// (read at each execution).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Preset {
    Const(i16),
    Word(u32),
}

/// One straight-line operation (the semantics: `reference::step`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Step {
    /// s := 0; not an instruction (counts 0).
    Network,
    Ld {
        at: u32,
        bit: u8,
    },
    Ldn {
        at: u32,
        bit: u8,
    },
    A {
        at: u32,
        bit: u8,
    },
    An {
        at: u32,
        bit: u8,
    },
    O {
        at: u32,
        bit: u8,
    },
    On {
        at: u32,
        bit: u8,
    },
    Assign {
        at: u32,
        bit: u8,
    },
    Not,
    Ald,
    Old,
    Lps,
    Lrd,
    Lpp,
    /// Width 1, 2, 4.
    Move {
        src: u32,
        dst: u32,
        width: u8,
    },
    /// Width 2, 4.
    Math {
        op: Arith,
        src: u32,
        dst: u32,
        width: u8,
    },
    /// Width 1 unsigned; 2, 4 signed.
    Compare {
        combine: Combine,
        rel: Rel,
        a: u32,
        b: u32,
        width: u8,
    },
    /// callee: index into the functions.
    Call {
        callee: u32,
        args: Vec<Arg>,
    },
    /// TON/TOF/TONR exactly as `vm/src/ops/timers.rs` (Flow Stack: runs whatever the
    /// power flow, leaves its done state on top of the logic stack). `at`: the T word
    /// (signed, little-endian); `state`: its 8 bytes of hidden state (u32 LE: the
    /// milliseconds not yet counted as a unit, then the flags RUNNING = 1, ARMED = 2);
    /// `res`: ms per unit (>= 1); `scan_ms`: the virtual ms one execution counts.
    Timer {
        kind: TimerKind,
        at: u32,
        state: u32,
        preset: Preset,
        res: u32,
        scan_ms: u32,
    },
    /// CTU/CTD/CTUD exactly as `vm/src/ops/timers.rs` (pops its inputs, pushes whether
    /// done). `at`: the C word; `state`: its hidden u32 LE flags (PREV_UP = 1,
    /// PREV_DOWN = 2); `max`: the upper limit of the count.
    Counter {
        kind: CounterKind,
        at: u32,
        state: u32,
        preset: Preset,
        max: i16,
    },
    /// EU (`rising`) / ED exactly as `vm/src/ops/bits.rs` `edge`: `state` is this
    /// instance's byte (its input at its previous execution, 0 or 1).
    Edge {
        rising: bool,
        state: u32,
    },
    /// S (`value` true) / R and their immediate forms: while the top is 1, `n` bits
    /// from bit `bit` of the byte at `at` on (crossing into the following bytes) take
    /// `value`; the stack is unchanged.
    SetBits {
        at: u32,
        bit: u8,
        n: u16,
        value: bool,
    },
    /// JMP: with power flow (top 1), continue after the `Label` step of the same number
    /// in the same function (the VM continues after the LBL record; the LBL does not
    /// run); without, nothing. Counts 1 either way. The label must follow the jump
    /// (forward jumps only: every function still ends, and its count is bounded by
    /// the number of its steps).
    Jump {
        label: u16,
    },
    /// LBL: a jump target; counts 1 when reached by falling through (it does nothing).
    Label {
        number: u16,
    },
}

/// A function: its steps, run from the first.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Function {
    pub steps: Vec<Step>,
}

/// The memory every function runs on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Layout {
    /// Bytes of the flat memory every function runs on.
    pub memory_len: u32,
    /// Index of SMB1 (math flags).
    pub flags_at: u32,
    /// Logic stack depth as a mask (9 levels: 0x1FF).
    pub stack_mask: u32,
    /// L area: (start, len) in the flat memory.
    pub local: Option<(u32, u32)>,
}

/// Why `compile` refused or failed. `function` and `step` are indices into the
/// functions given and into that function's steps.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum JitError {
    /// A step's memory access (`at`, `width` bytes; an argument's var or param) reaches
    /// past `Layout::memory_len`.
    OutOfRange {
        function: usize,
        step: usize,
        at: u32,
        width: u8,
    },
    /// A bit number above 7.
    BitNumber {
        function: usize,
        step: usize,
        bit: u8,
    },
    /// A width the step does not have (Move, Compare, arguments: 1, 2, 4; Math: 2, 4).
    Width {
        function: usize,
        step: usize,
        width: u8,
    },
    /// `Layout::flags_at` or the L area lies outside the memory.
    Layout { what: &'static str },
    /// A Call of a function that does not exist.
    NoSuchCallee {
        function: usize,
        step: usize,
        callee: u32,
    },
    /// A cycle of Calls through `function` (the VM never compiles recursion).
    Recursion { function: usize },
    /// A Timer whose resolution (`res`, ms per unit) is 0 (its clock would divide by it).
    Resolution { function: usize, step: usize },
    /// A Jump without a Label of its number later in the same function.
    NoLabel {
        function: usize,
        step: usize,
        label: u16,
    },
    /// A second Label of the same number in one function.
    DuplicateLabel {
        function: usize,
        step: usize,
        label: u16,
    },
    /// Cranelift failed: the host ISA is not supported, or code generation failed.
    Cranelift(String),
}

impl fmt::Display for JitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            JitError::OutOfRange {
                function,
                step,
                at,
                width,
            } => write!(
                f,
                "function {function}, step {step}: a {width}-byte access at index {at} lies outside the memory"
            ),
            JitError::BitNumber {
                function,
                step,
                bit,
            } => write!(f, "function {function}, step {step}: bit number {bit} is above 7"),
            JitError::Width {
                function,
                step,
                width,
            } => write!(f, "function {function}, step {step}: width {width} is not one this step has"),
            JitError::Layout { what } => write!(f, "layout: {what} lies outside the memory"),
            JitError::NoSuchCallee {
                function,
                step,
                callee,
            } => write!(f, "function {function}, step {step}: calls function {callee}, which does not exist"),
            JitError::Resolution { function, step } => {
                write!(f, "function {function}, step {step}: a timer of resolution 0 ms")
            }
            JitError::NoLabel {
                function,
                step,
                label,
            } => write!(
                f,
                "function {function}, step {step}: jump to label {label}, which does not follow it in the function"
            ),
            JitError::DuplicateLabel {
                function,
                step,
                label,
            } => write!(f, "function {function}, step {step}: label {label} is already defined"),
            JitError::Recursion { function } => {
                write!(f, "function {function} calls itself through a cycle of calls")
            }
            JitError::Cranelift(message) => write!(f, "code generation failed: {message}"),
        }
    }
}

impl std::error::Error for JitError {}

/// Compiled code for a set of functions; `run` calls one of them.
pub struct Module {
    code: call::Code,
    memory_len: u32,
    code_bytes: usize,
}

impl fmt::Debug for Module {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Module")
            .field("functions", &self.code.len())
            .field("memory_len", &self.memory_len)
            .field("code_bytes", &self.code_bytes)
            .finish()
    }
}

/// Check `functions` against `layout` (every access inside the memory, widths, no
/// recursion) and compile them, one native function per `Function`.
pub fn compile(layout: &Layout, functions: &[Function]) -> Result<Module, JitError> {
    check::check(layout, functions)?;
    let compiled = lower::lower(layout, functions)?;
    Ok(Module {
        code_bytes: compiled.code_bytes,
        code: compiled.code,
        memory_len: layout.memory_len,
    })
}

impl Module {
    /// Run function `f` on `memory` (len must equal layout.memory_len, else panic with
    /// a message; checked before any code runs), with the logic stack `stack` (bit 0 the
    /// top; read at entry, written at return). Returns the instructions executed: every
    /// Step except Network counts 1, a Call counts 1 plus whatever the callee executed,
    /// a Call without power flow counts 1 and does not run the callee.
    pub fn run(&self, f: usize, memory: &mut [u8], stack: &mut u32) -> u64 {
        assert!(
            memory.len() == self.memory_len as usize,
            "gutta-jit: the memory is {} bytes, the module was compiled for {}",
            memory.len(),
            self.memory_len
        );
        assert!(
            f < self.code.len(),
            "gutta-jit: function {f} of a module of {}",
            self.code.len()
        );
        self.code.run(f, memory, stack)
    }

    /// Machine code size of all functions, for the memory figures.
    pub fn code_bytes(&self) -> usize {
        self.code_bytes
    }
}

/// The VM moves its module across threads: a compile error here if it cannot.
const _: () = {
    const fn send_and_sync<T: Send + Sync>() {}
    send_and_sync::<Module>();
};
