//! gutta-jit: compiles runs of the VM's operations (bit logic, moves, integer math,
//! compares, planned CALLs, timers, counters, edges, S/R, forward jumps, escapes back to
//! the interpreter at the boxes it keeps) to native code
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
/// A BOOL parameter has `bits: Some((var_bit, param_bit))` and width 1: `var` and
/// `param` are then the bytes holding the bits; an input copies the variable's bit into
/// the parameter's, an output the parameter's bit back into the variable's, each
/// leaving the other bits of its byte as they are (`vm/src/ops/control.rs`, CALL).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Arg {
    pub var: u32,
    pub param: u32,
    pub width: u8,
    pub input: bool,
    pub output: bool,
    /// A BOOL argument: the bit (0..8) of `var` and the bit of `param`.
    pub bits: Option<(u8, u8)>,
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

/// Word logic (dst := dst op src; `vm/src/ops/math.rs` ANDx, ORx, XORx).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Logic {
    And,
    Or,
    Xor,
}

/// A shift or rotate (`vm/src/ops/shift.rs` SRx, SLx, RRx, RLx).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shift {
    Right,
    Left,
    RotateRight,
    RotateLeft,
}

/// A conversion (`vm/src/ops/convert.rs`), each with its own fixed widths (source ->
/// destination bytes): Bti 1 -> 2, Itb 2 -> 1, Itd 2 -> 4, Dti 4 -> 2, Dtr 4 -> 4,
/// Round 4 -> 4, Trunc 4 -> 4, Bcdi 2 -> 2, Ibcd 2 -> 2, Seg 1 -> 1, Deco 1 -> 2,
/// Enco 2 -> 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Convert {
    Bti,
    Itb,
    Itd,
    Dti,
    Dtr,
    Round,
    Trunc,
    Bcdi,
    Ibcd,
    Seg,
    Deco,
    Enco,
}

impl Convert {
    /// Every conversion, in declaration order (for tests and fuzzing).
    pub const ALL: [Convert; 12] = [
        Convert::Bti,
        Convert::Itb,
        Convert::Itd,
        Convert::Dti,
        Convert::Dtr,
        Convert::Round,
        Convert::Trunc,
        Convert::Bcdi,
        Convert::Ibcd,
        Convert::Seg,
        Convert::Deco,
        Convert::Enco,
    ];

    /// (source, destination) widths in bytes.
    pub fn widths(self) -> (u8, u8) {
        match self {
            Convert::Bti => (1, 2),
            Convert::Itb => (2, 1),
            Convert::Itd => (2, 4),
            Convert::Dti => (4, 2),
            Convert::Dtr | Convert::Round | Convert::Trunc => (4, 4),
            Convert::Bcdi | Convert::Ibcd => (2, 2),
            Convert::Seg => (1, 1),
            Convert::Deco => (1, 2),
            Convert::Enco => (2, 1),
        }
    }
}

/// REAL math (dst := dst op src; `vm/src/ops/math.rs` +R, -R, *R, /R).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RealOp {
    Add,
    Sub,
    Mul,
    Div,
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
    // ---- Generic families (vm/src/tier_generic.rs) -------------------------
    // Every one below but CompareReal, Lds, Nop and Store runs only while the top of the
    // logic stack is 1 and leaves the stack unchanged (ManagerFun.xml Flow="Box"); "flags"
    // are bits of the byte at `Layout::flags_at` (SMB1: 0 zero, 1 overflow, 2 negative,
    // 3 divide by zero, 6 BCD error), each written after the result's store, the bits a
    // step does not name kept. Values are little-endian; INT and DINT signed.
    /// ANDx/ORx/XORx: dst := dst op src in `width` bytes (1, 2, 4); flags 0 := result
    /// zero, 1 := 0, 2 := 0.
    Logic {
        op: Logic,
        src: u32,
        dst: u32,
        width: u8,
    },
    /// INVx: the `width` bytes at `at` inverted; flags 0 := result zero, 1 := 0, 2 := 0.
    Invert {
        at: u32,
        width: u8,
    },
    /// INCx (`up`) / DECx: the value at `at` plus or minus 1, wrapped. Width 1 is
    /// unsigned: flags 0 := zero, 1 := wrapped, 2 := 0. Widths 2 and 4 are signed:
    /// flags 0 := zero, 1 := signed overflow, 2 := negative.
    IncDec {
        at: u32,
        width: u8,
        up: bool,
    },
    /// /I (width 2), /D (width 4): dst := dst / src, truncated, signed, both read first.
    /// src = 0: flags 0..2 := 0, 3 := 1, dst unchanged. Else flag 3 := 0, then MIN / -1:
    /// dst unchanged, flags 0 := 0, 1 := 1, 2 := 0; else dst := the quotient and flags
    /// 0 := zero, 1 := 0, 2 := negative.
    Divide {
        src: u32,
        dst: u32,
        width: u8,
    },
    /// MUL: the DINT at `dst` := the INT at `src` times the INT in the low word of the
    /// DINT at `dst`; flags 0 := zero, 1 := 0, 2 := negative.
    MulWide {
        src: u32,
        dst: u32,
    },
    /// DIV: n := the INT in the low word of the DINT at `dst`, d := the INT at `src`
    /// (both read first). d = 0: as Divide by 0. Else flag 3 := 0; n = -32768 and
    /// d = -1: dst unchanged, flags 0 := 0, 1 := 1, 2 := 0; else dst := remainder << 16
    /// | quotient (16 bits each, truncated division), flags 0 := quotient zero, 1 := 0,
    /// 2 := quotient negative.
    DivWide {
        src: u32,
        dst: u32,
    },
    /// SRx/SLx/RRx/RLx: the `width`-byte value v at `at` shifted by n, the byte at
    /// `count`. Shifts: n >= 8 * width gives 0; flag 1 := the last bit moved out (for
    /// 1 <= n <= 8 * width: bit n - 1 of v right, bit 8 * width - n left; else 0).
    /// Rotates by n mod 8 * width: 0 leaves v and flag 1 := 0; else flag 1 := the top
    /// bit (right) or bit 0 (left) of the result. Then flag 0 := result zero; flag 2
    /// kept.
    Shift {
        op: Shift,
        at: u32,
        width: u8,
        count: u32,
    },
    /// A conversion from `src` to `dst` (widths: `Convert::widths`). Bti: the byte to
    /// an INT. Itd: sign extension. Dtr: the DINT to the nearest REAL (ties to even).
    /// Itb (INT in 0..=255), Dti (DINT fits an INT), Round (the REAL to the nearest
    /// integer, halves away from zero), Trunc (toward zero; both then fit a DINT:
    /// finite and in -2^31..2^31): when it fits, dst := the value; flag 1 := it did not
    /// fit (dst unchanged). Bcdi: four BCD digits (15..12 thousands) to their value,
    /// Ibcd: an INT in 0..=9999 to four BCD digits; when the digits are all <= 9 (the
    /// INT in range), dst := the value; flag 6 := it was not. Seg: the seven-segment
    /// pattern of the low nibble (bit 0 segment a .. bit 6 segment g; 0..F as
    /// `vm/src/ops/convert.rs` SEGMENTS). Deco: 1 << the low nibble. Enco: the number of
    /// the lowest set bit of the word; a word of 0 leaves dst; flag 1 := the word was 0.
    Convert {
        op: Convert,
        src: u32,
        dst: u32,
    },
    /// +R -R *R /R on the REALs at `dst` (a) and `src` (b): dst := a op b (IEEE single,
    /// round to nearest), flags 0 := result == 0, 1 := not finite, 2 := result < 0.
    /// Div: b == 0 (either sign): flags 0..2 := 0, 3 := 1, dst unchanged; else flag 3
    /// := 0 first, then a and b read again and as above.
    RealMath {
        op: RealOp,
        src: u32,
        dst: u32,
    },
    /// SQRT: dst := sqrt(src) (REAL), flags 0 := result == 0, 1 := not finite, 2 := 0.
    Sqrt {
        src: u32,
        dst: u32,
    },
    /// LDR/AR/OR compares of the REALs at `a` and `b` (IEEE: with a NaN only Ne holds),
    /// combined with the stack as Compare; runs whatever the power flow.
    CompareReal {
        combine: Combine,
        rel: Rel,
        a: u32,
        b: u32,
    },
    /// A MOVx whose source is a constant (an address, `&VB100`): the low `width` bytes
    /// (1, 2, 4) of `value` stored at `dst`.
    Const {
        value: u32,
        dst: u32,
        width: u8,
    },
    /// SWAP: the two bytes of the word at `at` exchanged.
    Swap {
        at: u32,
    },
    /// LDS n: push level n of the stack (0 the top, before the push; 0 for n >= 32);
    /// runs whatever the power flow.
    Lds {
        n: u16,
    },
    /// NOP: nothing (counts 1), whatever the power flow.
    Nop,
    /// ENI (`value` 1) and DISI (0): the byte at `at` (the VM's interrupt enable) :=
    /// `value`, whatever the power flow; the stack unchanged.
    Store {
        at: u32,
        value: u8,
    },
    /// A box the VM runs interpreted (EXCH, ATCH, DTCH, ...; `vm/src/tier.rs`). Without
    /// power flow (top 0): nothing, counts 1. With power flow: the function returns at
    /// once, the logic stack as it is, its count the instructions executed before this
    /// step (the escape itself not counted), and `Module::enter` reports `id`. Only in a
    /// function no other function Calls (the VM could not resume inside a callee).
    Escape {
        id: u16,
    },
}

impl Step {
    /// Whether the step runs only while the top of the logic stack is 1 and leaves the
    /// stack as it was (ManagerFun.xml Flow="Box"; a Call restores the caller's): Move,
    /// Math, Call, SetBits and the generic families but CompareReal, Lds, Nop and Store.
    /// The lowering tests the top once for a run of them; the VM checks a generic
    /// record's flow against it. Every step is named, so a new one must say.
    pub fn is_box(&self) -> bool {
        match self {
            Step::Move { .. }
            | Step::Math { .. }
            | Step::Call { .. }
            | Step::SetBits { .. }
            | Step::Logic { .. }
            | Step::Invert { .. }
            | Step::IncDec { .. }
            | Step::Divide { .. }
            | Step::MulWide { .. }
            | Step::DivWide { .. }
            | Step::Shift { .. }
            | Step::Convert { .. }
            | Step::RealMath { .. }
            | Step::Sqrt { .. }
            | Step::Const { .. }
            | Step::Swap { .. } => true,
            Step::Network
            | Step::Ld { .. }
            | Step::Ldn { .. }
            | Step::A { .. }
            | Step::An { .. }
            | Step::O { .. }
            | Step::On { .. }
            | Step::Assign { .. }
            | Step::Not
            | Step::Ald
            | Step::Old
            | Step::Lps
            | Step::Lrd
            | Step::Lpp
            | Step::Compare { .. }
            | Step::Timer { .. }
            | Step::Counter { .. }
            | Step::Edge { .. }
            | Step::Jump { .. }
            | Step::Label { .. }
            | Step::CompareReal { .. }
            | Step::Lds { .. }
            | Step::Nop
            | Step::Store { .. }
            | Step::Escape { .. } => false,
        }
    }
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
    /// An Escape in a function that a Call of function `caller` enters (an early
    /// return could not be resumed inside a callee).
    EscapeInCallee {
        function: usize,
        step: usize,
        caller: usize,
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
            JitError::EscapeInCallee {
                function,
                step,
                caller,
            } => write!(
                f,
                "function {function}, step {step}: an escape in a function that function {caller} calls"
            ),
            JitError::Cranelift(message) => write!(f, "code generation failed: {message}"),
        }
    }
}

impl std::error::Error for JitError {}

/// How a run of a function ended (`Module::enter`, `reference::enter`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Exit {
    /// Instructions executed (an Escape taken not counted).
    pub executed: u64,
    /// The id of the Escape the function returned at, None when it ran to its end.
    pub escape: Option<u16>,
}

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
    /// a Call without power flow counts 1 and does not run the callee. An Escape taken
    /// ends the run (`enter` says which one).
    pub fn run(&self, f: usize, memory: &mut [u8], stack: &mut u32) -> u64 {
        self.enter(f, memory, stack).executed
    }

    /// As `run`, and whether the function returned early at an Escape with power flow
    /// (`Exit::escape`: its id; `executed` then counts the steps before it, and `stack`
    /// is the logic stack the Escape found).
    #[inline]
    pub fn enter(&self, f: usize, memory: &mut [u8], stack: &mut u32) -> Exit {
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
        let (executed, exit) = self.code.run(f, memory, stack);
        Exit {
            executed,
            escape: exit.checked_sub(1).and_then(|id| u16::try_from(id).ok()),
        }
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
