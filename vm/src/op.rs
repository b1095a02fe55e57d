//! The decoded operations: what a record of a unit becomes at load (`decode.rs`) and
//! what the fast path runs (`fast.rs`), including the steps of fused bit-logic chains
//! (`fuse.rs`). Plain data: no behaviour beyond a compare's relation.

/// Which timer (TON, TOF, TONR).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum TimerKind {
    On,
    Off,
    Retentive,
}

/// Which counter (CTU, CTD, CTUD).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum CounterKind {
    Up,
    Down,
    UpDown,
}

/// A timer's or counter's preset: a constant, or the signed INT at a flat index (read
/// at each execution).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Preset {
    Const(i16),
    Word(u32),
}

/// A timer on a plain T operand (`ops/timers.rs`): `at` the T word, `state` its hidden
/// state (`Memory::cell_state_at`), `preset` a constant or a plain INT, `res` ms per
/// unit (at least 1), `scan_ms` the virtual milliseconds each execution counts
/// (`VmConfig::scan_ms`). Flow Stack: runs whatever the power flow.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct TimerOp {
    pub kind: TimerKind,
    pub at: u32,
    pub state: u32,
    pub preset: Preset,
    pub res: u32,
    pub scan_ms: u32,
}

/// A counter on a plain C operand (`ops/timers.rs`); `max` the count's limit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct CounterOp {
    pub kind: CounterKind,
    pub at: u32,
    pub state: u32,
    pub preset: Preset,
    pub max: i16,
}

/// A bit of memory: byte index into the flat memory and the bit's mask.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Bit {
    pub at: u32,
    pub mask: u8,
}

/// Which stack operation a compare feeds (LD pushes, A ands, O ors).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Combine {
    Load,
    And,
    Or,
}

/// A compare's relation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Rel {
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
}

impl Rel {
    #[inline(always)]
    pub fn holds<T: PartialOrd>(self, a: T, b: T) -> bool {
        match self {
            Rel::Eq => a == b,
            Rel::Ne => a != b,
            Rel::Lt => a < b,
            Rel::Le => a <= b,
            Rel::Gt => a > b,
            Rel::Ge => a >= b,
        }
    }
}

/// Integer math the fast path knows (OUT := OUT op IN1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Arith {
    Add,
    Sub,
    Mul,
}

/// How the fast path runs a generic record (`Op::Generic`) without its handler, with
/// exactly its effect (`ops/`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Quick {
    /// Only through its handler (the engine's slow path).
    Handler,
    /// A box (`Flow::Box`) other than FOR: without power flow it does nothing; with
    /// power flow its handler runs.
    Box,
    /// Nothing at all (LBL, NOP).
    Nothing,
    /// JMP to a label after it: with power flow, continue at record `to` (the one after
    /// the LBL, or the unit's end when the label is missing); `to` > the JMP's record.
    Jump { to: u32 },
    /// INCB/INCW/INCD (`up`) and DECB/DECW/DECD on a plain variable of `width` bytes:
    /// with power flow, OUT := OUT +- 1 with the SM1 flags of the handler.
    Step { at: u32, width: u8, up: bool },
    /// /I (width 2) and /D (4) on plain variables: `Unit::divides[index]`.
    Divide { index: u32 },
    /// ENI (`value` 1) and DISI (0): the byte at flat index `at` (the interrupt enable,
    /// `Memory::enable_at`) := `value`, whatever the power flow.
    Store { at: u32, value: u8 },
}

/// /I or /D on plain variables (`Quick::Divide`): OUT (`dst`) := OUT / IN1 (`src`),
/// `width` bytes, signed, truncated, with the handler's SM1 flags.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct DivideOp {
    pub src: u32,
    pub dst: u32,
    pub width: u8,
}

/// One decoded record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Op {
    /// A network record: the logic stack starts empty.
    Network,
    /// Bit logic fused (see `build`): `Unit::chain[first..]` run in order; it covers
    /// `records` records, `networks` of them network records and each other one a step.
    Chain {
        first: u32,
        records: u32,
        networks: u16,
    },
    /// A network record and the LD (`invert` 0) or LDN (1) after it, fused: the two
    /// records run as one (a network whose LD is followed by boxes, e.g. `LD SM0.0`).
    NetworkLoad {
        bit: Bit,
        invert: u8,
    },
    Ld(Bit),
    Ldn(Bit),
    A(Bit),
    An(Bit),
    O(Bit),
    On(Bit),
    Not,
    Assign(Bit),
    Ald,
    Old,
    Lps,
    Lrd,
    Lpp,
    /// MOVB/MOVW/MOVD/MOVR between plain variables (bytes `width`).
    Move {
        src: u32,
        dst: u32,
        width: u8,
    },
    /// +I -I *I (width 2) and +D -D *D (width 4) on plain variables, with the SM1 flags.
    Math {
        op: Arith,
        src: u32,
        dst: u32,
        width: u8,
    },
    /// Signed compares of INT (width 2) and DINT (width 4), unsigned of BYTE (width 1).
    Compare {
        combine: Combine,
        rel: Rel,
        a: u32,
        b: u32,
        width: u8,
    },
    /// `Move`, `Math` and `Compare` by width (the fast operations `fuse::build` makes
    /// of them; `plain` keeps the forms above): one dispatch, no width at run time.
    MoveB {
        src: u32,
        dst: u32,
    },
    MoveW {
        src: u32,
        dst: u32,
    },
    MoveD {
        src: u32,
        dst: u32,
    },
    MathW {
        op: Arith,
        src: u32,
        dst: u32,
    },
    MathD {
        op: Arith,
        src: u32,
        dst: u32,
    },
    CompareB {
        combine: Combine,
        rel: Rel,
        a: u32,
        b: u32,
    },
    CompareW {
        combine: Combine,
        rel: Rel,
        a: u32,
        b: u32,
    },
    CompareD {
        combine: Combine,
        rel: Rel,
        a: u32,
        b: u32,
    },
    /// TON/TOF/TONR on a plain T operand: `Unit::timers[index]` (a side table keeps
    /// `Op` small).
    Timer {
        index: u32,
    },
    /// CTU/CTD/CTUD on a plain C operand: `Unit::counters[index]`.
    Counter {
        index: u32,
    },
    /// EU (`rising`) / ED: `state` this record's edge byte (`Unit::edge_state`).
    Edge {
        rising: bool,
        state: u32,
    },
    /// S/R/SI/RI with a constant N whose bits lie inside the area: while the top is 1,
    /// `n` bits from bit `bit` of the byte at `at` on take `value`.
    SetBits {
        at: u32,
        bit: u8,
        n: u16,
        value: bool,
    },
    /// CALL with plain arguments whose widths match the parameters: `Unit::calls[plan]`.
    Call {
        plan: u32,
    },
    /// Any other instruction: its semantic runs with the record's operands. `boxed`:
    /// it runs only with power flow. `quick`: what the fast path does instead, when the
    /// record allows (the record stays generic for everything else: single steps, the
    /// reference engine, the compiled tier's `tier_generic`).
    Generic {
        boxed: bool,
        quick: Quick,
    },
    /// A breakpoint patched over the op (the original: `Unit::plain_op`).
    Break,
}

impl Op {
    /// A network record.
    pub fn is_network(self) -> bool {
        self == Op::Network
    }

    /// The plain form of a per-width operation (`MoveW` -> `Move` of width 2, ...);
    /// any other operation as it is.
    pub fn widened(self) -> Op {
        match self {
            Op::MoveB { src, dst } => Op::Move { src, dst, width: 1 },
            Op::MoveW { src, dst } => Op::Move { src, dst, width: 2 },
            Op::MoveD { src, dst } => Op::Move { src, dst, width: 4 },
            Op::MathW { op, src, dst } => Op::Math {
                op,
                src,
                dst,
                width: 2,
            },
            Op::MathD { op, src, dst } => Op::Math {
                op,
                src,
                dst,
                width: 4,
            },
            Op::CompareB { combine, rel, a, b } => Op::Compare {
                combine,
                rel,
                a,
                b,
                width: 1,
            },
            Op::CompareW { combine, rel, a, b } => Op::Compare {
                combine,
                rel,
                a,
                b,
                width: 2,
            },
            Op::CompareD { combine, rel, a, b } => Op::Compare {
                combine,
                rel,
                a,
                b,
                width: 4,
            },
            op => op,
        }
    }
}

/// What a chain step does (`ChainStep::kind`). With v the bit `bit` of the byte at
/// `at`: a network's LD/LDN starts the network (t := v, resp. NOT v, the rest of the
/// stack empty); A/AN make t := t AND v (NOT v); O/ON make t := t OR v (NOT v); a `=`
/// writes t into that bit. A network's start sets t without reading it, so the
/// networks of a chain overlap in the CPU; the other logic steps look t up in
/// `STEP_TABLE`, without a branch on the kind.
pub(crate) const STEP_LOAD: u8 = 0;
pub(crate) const STEP_LOADN: u8 = 1;
pub(crate) const STEP_AND: u8 = 2;
pub(crate) const STEP_ANDN: u8 = 3;
pub(crate) const STEP_OR: u8 = 4;
pub(crate) const STEP_ORN: u8 = 5;
pub(crate) const STEP_STORE: u8 = 6;

/// The logic steps as one table: bit `kind * 4 + v * 2 + t` is the new t.
pub(crate) const STEP_TABLE: u32 = {
    let mut table = 0u32;
    let mut kind = 0;
    while kind < STEP_STORE {
        let mut i = 0;
        while i < 4 {
            let (v, t) = (i >> 1, i & 1);
            let new = match kind {
                STEP_LOAD => v,
                STEP_LOADN => v ^ 1,
                STEP_AND => t & v,
                STEP_ANDN => t & (v ^ 1),
                STEP_OR => t | v,
                _ => t | (v ^ 1),
            };
            table |= (new as u32) << (kind * 4 + i);
            i += 1;
        }
        kind += 1;
    }
    table
};

/// One step of a fused chain. Only the top of the logic stack changes in a chain, so
/// it is kept apart as `t` (0 or 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct ChainStep {
    pub at: u32,
    /// The bit's number in its byte.
    pub bit: u8,
    pub kind: u8,
}

#[cfg(test)]
mod tests {
    use super::Op;

    /// The interpreter walks `Op`s: 12 bytes each (the largest, a compare, is two flat
    /// indices and three bytes). Timers and counters sit in side tables to keep it so.
    #[test]
    fn an_op_is_twelve_bytes() {
        assert_eq!(std::mem::size_of::<Op>(), 12);
    }
}
