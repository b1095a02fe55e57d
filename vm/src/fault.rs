//! Run-time faults: what stops a scan. Typed, never a panic.

use std::fmt;

/// Why the VM stopped with ERROR set.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Fault {
    /// A pointer (`*MD4`) or computed access left its area, or named no area.
    BadAccess {
        page: u8,
        offset: usize,
        detail: String,
    },
    /// An instruction the VM has no semantics for (never for stdlib instructions).
    NoSemantics { mnemonic: String },
    /// The scan ran more instructions than the watchdog allows (a runaway loop).
    Watchdog { limit: u64 },
    /// Calls nested deeper than the target allows.
    CallDepth { limit: u8 },
}

impl Fault {
    /// The error code shown in SMB2 and the debug block (0 = none).
    pub fn code(&self) -> u8 {
        match self {
            Fault::BadAccess { .. } => 1,
            Fault::NoSemantics { .. } => 2,
            Fault::Watchdog { .. } => 3,
            Fault::CallDepth { .. } => 4,
        }
    }
}

impl fmt::Display for Fault {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Fault::BadAccess {
                page,
                offset,
                detail,
            } => write!(
                f,
                "bad memory access at instruction/{page:02X}.bin byte {offset}: {detail}"
            ),
            Fault::NoSemantics { mnemonic } => write!(f, "no semantics for `{mnemonic}`"),
            Fault::Watchdog { limit } => {
                write!(f, "watchdog: more than {limit} instructions in one scan")
            }
            Fault::CallDepth { limit } => write!(f, "calls nested deeper than {limit}"),
        }
    }
}

impl std::error::Error for Fault {}
