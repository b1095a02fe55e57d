//! The checked program: what the back end (lower/encode) consumes. Every operand is
//! resolved to an address, a constant, a label or a unit; every unit has its number;
//! locals have their place in L. Only a program without errors is ever built.

use gutta_catalog::{Address, BlockKind, DataType, InstrId, Width};
use gutta_format::UnitRef;

use crate::source::Span;
use crate::syntax::ast::VarSection;

/// How a memory operand is used: `Value`, `AddressOf` or `Pointer` (the format's USE).
pub use gutta_format::Use;

/// A constant operand (lives in K after lowering).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ConstValue {
    Integer(i64),
    Real(f32),
}

/// A resolved operand.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CheckedOperand {
    /// `address` is where the variable (or, for `Pointer`, the pointer) lives;
    /// `width` is the access width the instruction uses. `use_` is `Value`,
    /// `AddressOf` or `Pointer` (the USE values of a memory operand).
    Memory {
        address: Address,
        use_: Use,
        width: Width,
    },
    Constant {
        value: ConstValue,
        width: Width,
    },
    Label(u16),
    Unit {
        kind: BlockKind,
        number: u32,
    },
    Literal(i64),
}

#[derive(Debug, Clone, PartialEq)]
pub struct CheckedInstruction {
    pub id: InstrId,
    pub operands: Vec<CheckedOperand>,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct CheckedNetwork {
    /// As written, or the previous network's number + 1.
    pub number: u32,
    pub title: Option<String>,
    pub span: Span,
    pub instructions: Vec<CheckedInstruction>,
}

/// A local variable with its place in L.
#[derive(Debug, Clone, PartialEq)]
pub struct Local {
    pub name: String,
    pub section: VarSection,
    pub ty: DataType,
    pub address: Address,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct CheckedUnit {
    pub kind: BlockKind,
    /// INTn or SBRn; MAIN is INT0.
    pub number: u32,
    pub name: String,
    pub title: Option<String>,
    pub span: Span,
    pub locals: Vec<Local>,
    pub networks: Vec<CheckedNetwork>,
}

impl CheckedUnit {
    /// The unit as the image names it (a checked unit's number fits: E0413).
    pub fn unit_ref(&self) -> UnitRef {
        UnitRef {
            kind: self.kind,
            number: u16::try_from(self.number).unwrap_or(u16::MAX),
        }
    }

    /// `MAIN`, `INT1`, `SBR0`.
    pub fn numbered_name(&self) -> String {
        self.unit_ref().to_string()
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct DataItem {
    pub address: Address,
    pub ty: DataType,
    pub value: ConstValue,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub struct CheckedDataBlock {
    pub number: u32,
    pub name: String,
    pub items: Vec<DataItem>,
}

/// Parity of a serial port: gutta-format's, the one type of it.
pub use gutta_format::Parity;

/// One serial port's settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PortConfig {
    pub port: u8,
    pub address: u8,
    pub baud: u32,
    pub data_bits: u8,
    pub parity: Parity,
    pub stop_bits: u8,
    /// Response timeout in 100 ms units.
    pub timeout: u8,
    /// Frame gap in 1 ms units.
    pub frame_gap: u8,
}

impl PortConfig {
    /// The GUTTA editor's defaults (AN2002): Modbus, address 1, 38400, 8 RTU, EVEN, 1
    /// stop bit, timeout 10 x 100 ms, frame gap 10 x 1 ms.
    pub fn editor_default(port: u8) -> PortConfig {
        PortConfig {
            port,
            address: 1,
            baud: 38400,
            data_bits: 8,
            parity: Parity::Even,
            stop_bits: 1,
            timeout: 10,
            frame_gap: 10,
        }
    }
}

/// The system block: one entry per port of the target, and the login password.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SystemConfig {
    pub ports: Vec<PortConfig>,
    pub password: Option<String>,
}

/// A program that checked without errors.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckedProgram {
    pub target_name: String,
    /// Interrupt routines by number (MAIN first), then subroutines by number.
    pub units: Vec<CheckedUnit>,
    pub data_blocks: Vec<CheckedDataBlock>,
    /// `None` when the program has no SYSTEM_BLOCK (the PLC keeps its settings).
    pub system: Option<SystemConfig>,
    /// The SYSTEM_BLOCK line.
    pub system_span: Option<Span>,
}
