//! Target descriptions of GUTTA PLC types: `PlcType.xml`, `ManagerVar.xml` and
//! `ManagerFun.xml` loaded into validated, typed tables.
//!
//! This crate is the only place in the workspace that reads XML. It does no file or
//! network I/O itself: callers hand it bytes (see [`TargetSources`]); the stdlib
//! targets are embedded at build time ([`stdlib`]). The compiler, the VM and the
//! language server are all driven by the tables it returns; [`rules`] holds the rules
//! on those tables that both the compiler's checker and the image verifier apply;
//! [`choose_target`] is the one rule for which PLC type applies.

mod address;
mod choice;
pub mod docs;
mod error;
mod instruction_kinds;
mod instructions;
mod memory;
pub mod modbus;
mod plc_type;
pub mod plural;
pub mod rules;
pub mod s7200;
pub mod s7200_eno;
pub mod s7200_io;
pub mod s7200_timers;
pub mod stdlib;
mod suggest;
mod text;
mod timer_duration;
mod types;
mod value;
mod xml_util;

pub use address::{is_address_shaped, parse_value, Address, AddressError};
pub use choice::{choose_target, ChosenTarget, OwnName, TargetInputs, TargetOrigin, TargetSpec};
pub use error::{CatalogError, CatalogErrorCode};
pub use instruction_kinds::{CompareOp, Join, LadderClass, Logic, LoopRole, TimerCounterKind};
pub use instructions::{
    BlockKind, Flow, InstrId, Instruction, InstructionSet, OperandKind, OperandSpec, Role,
    UnitScope,
};
pub use memory::{
    Area, AreaKind, InterruptEvent, MemoryMap, ModbusMapping, ModbusTable, SystemBit,
    TimerResolution,
};
pub use modbus::{ModbusCell, ModbusLocation, ModbusPiece, ModbusSpan};
pub use plc_type::{ExchSupport, PlcType};
pub use suggest::edit_distance;
pub use text::decode_xml_text;
pub use timer_duration::timer_duration;
pub use types::{DataType, Width};
pub use value::ValueFormat;

/// The three description files of one PLC type, as raw bytes (UTF-8 or UTF-16 with BOM).
#[derive(Debug, Clone, Copy)]
pub struct TargetSources<'a> {
    pub plc_type: &'a [u8],
    pub manager_var: &'a [u8],
    pub manager_fun: &'a [u8],
}

/// A fully loaded and cross-checked PLC type.
#[derive(Debug, Clone)]
pub struct Target {
    pub plc: PlcType,
    pub memory: MemoryMap,
    pub instructions: InstructionSet,
}

impl Target {
    /// Parse and validate the three files; the files must agree on the PLC type's name.
    pub fn load(sources: TargetSources<'_>) -> Result<Target, CatalogError> {
        let plc = PlcType::parse(sources.plc_type)?;
        let memory = MemoryMap::parse(sources.manager_var)?;
        let instructions = InstructionSet::parse(sources.manager_fun)?;
        if let Some(name) = &memory.plc_type {
            if name != &plc.name {
                return Err(CatalogError::new(
                    CatalogErrorCode::Mismatch,
                    "ManagerVar.xml",
                    format!(
                        "ManagerVar.xml describes PLC type `{name}` but PlcType.xml names `{}`",
                        plc.name
                    ),
                ));
            }
        }
        instructions.validate_against(&memory)?;
        Ok(Target {
            plc,
            memory,
            instructions,
        })
    }

    /// The PLC type's identity (`PlcType.xml` `Name`).
    pub fn name(&self) -> &str {
        &self.plc.name
    }

    /// How many milliseconds one unit of timer `number` lasts when an instruction of
    /// `kind` drives it: the target's `<Timers>` row holding the number (on GUTTA the
    /// resolution depends on the number alone). `None` for a counter kind or a number
    /// the target has no row for.
    pub fn timer_resolution(&self, kind: TimerCounterKind, number: u32) -> Option<u32> {
        if !kind.is_timer() {
            return None;
        }
        self.memory.timer_resolution(number)
    }
}
