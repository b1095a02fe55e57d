//! The decoded operations: what a record of a unit becomes at load (`decode.rs`) and
//! what the fast path runs (`fast.rs`), including the steps of fused bit-logic chains
//! (`fuse.rs`). Plain data: no behaviour beyond a compare's relation.

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
    /// CALL with plain arguments whose widths match the parameters: `Unit::calls[plan]`.
    Call {
        plan: u32,
    },
    /// Any other instruction: its semantic runs with the record's operands. `boxed`:
    /// it runs only with power flow.
    Generic {
        boxed: bool,
    },
    /// A breakpoint patched over the op (the original: `Unit::plain_op`).
    Break,
}

impl Op {
    /// A network record.
    pub fn is_network(self) -> bool {
        self == Op::Network
    }
}

/// What a chain step does (`ChainStep::kind`).
pub(crate) const STEP_AND: u8 = 0;
pub(crate) const STEP_OR: u8 = 1;
pub(crate) const STEP_LOAD: u8 = 2;
pub(crate) const STEP_STORE: u8 = 3;

/// One step of a fused chain. Only the top of the logic stack changes in a chain, so
/// it is kept apart as `t` (0 or 1). With v the bit `bit` of the byte at `at` (inverted
/// for LDN/AN/ON): a network's LD/LDN (`STEP_LOAD`) starts the network, t := v with the
/// rest of the stack empty; A/AN (`STEP_AND`) make t := t AND v; O/ON (`STEP_OR`) make
/// t := t OR v; a `=` (`STEP_STORE`) writes t into that bit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct ChainStep {
    pub at: u32,
    /// The bit's number in its byte.
    pub bit: u8,
    pub invert: u8,
    pub kind: u8,
    /// Arithmetic form of the kind, for t in {0, 1}: t := ((t AND keep) + v + or) / 2
    /// is t AND v for A (keep 1, or 0), t OR v for O (keep 1, or 1) and v for a
    /// network's LD (keep 0, or 1).
    pub keep_or: u8,
}
