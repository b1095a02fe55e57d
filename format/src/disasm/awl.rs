//! The STEP 7-Micro/WIN layout of `gutta-cc dis --format awl` (docs/microwin.md, "The
//! way back"): Micro/WIN's block names (`SBR_n:SBRn`, `INT_n:INTn`, also in `CALL` and
//! `ATCH`), numbered as S7-200 numbers them (GUTTA's INT1 is S7-200's INT0), interrupt
//! events by their S7-200 numbers (the target's `<Event MicroWin=>`), its VAR
//! lines, and the note before the data and system blocks, which Micro/WIN exports separately. The
//! rest of the layout (`TITLE=`, `Network n`, no step comments, CRLF) is chosen where
//! the shared writer prints (`units.rs`, `Disassembler::line`).

use gutta_catalog::{BlockKind, DataType};

use super::{Disassembler, Format};
use crate::{PageKind, UnitRef};

/// The number S7-200 gives a unit: subroutines keep GUTTA's; GUTTA's interrupt routine
/// INTn is S7-200's INT(n-1), since GUTTA's MAIN is INT0 and the Micro/WIN dialect
/// places S7-200's INTn on GUTTA's INT(n+1) (docs/microwin.md), so the text compiles
/// back to the same pages.
fn s7200_number(unit: UnitRef) -> u16 {
    match unit.kind {
        BlockKind::Interrupt => unit.number.saturating_sub(1),
        BlockKind::Subroutine => unit.number,
    }
}

/// `SBR_0`, `INT_0`: Micro/WIN's default name of a block, by its S7-200 number.
fn block_name(unit: UnitRef) -> String {
    match unit.kind {
        BlockKind::Interrupt => format!("INT_{}", s7200_number(unit)),
        BlockKind::Subroutine => format!("SBR_{}", s7200_number(unit)),
    }
}

/// `SBR_0`, `INT0`: a block's numbered name as S7-200 numbers it.
fn numbered_name(unit: UnitRef) -> String {
    match unit.kind {
        BlockKind::Interrupt => format!("INT{}", s7200_number(unit)),
        BlockKind::Subroutine => format!("SBR{}", s7200_number(unit)),
    }
}

/// `SBR_0:SBR0`, `INT_0:INT0` (GUTTA's INT1): the name, then the number.
pub(super) fn block_header(unit: UnitRef) -> String {
    format!("{}:{}", block_name(unit), numbered_name(unit))
}

/// `in0:INT;<TAB>// LW0`: Micro/WIN's declaration (no blanks, a tab before the comment);
/// the comment says where the local is in L.
pub(super) fn var_line(name: &str, data_type: DataType, at: &str) -> String {
    format!("{name}:{data_type};\t// {at}")
}

impl Disassembler<'_> {
    /// A unit as an operand (`CALL`, `ATCH`): `SBR0`, or in Micro/WIN's layout its
    /// block name `SBR_0` when the image holds the unit (else the name would be
    /// undeclared in the text).
    pub(super) fn unit_name(&self, unit: UnitRef) -> String {
        let held = self.image.pages.keys().any(|id| {
            id.kind == PageKind::Instruction
                && UnitRef::from_page(id.number, &self.target.plc) == Some(unit)
        });
        match self.format {
            Format::Awl if unit == UnitRef::MAIN => unit.to_string(),
            Format::Awl if held => block_name(unit),
            Format::Awl => numbered_name(unit),
            Format::Stl => unit.to_string(),
        }
    }

    /// The event operand of `ATCH`, `DTCH`, `CEVNT` in Micro/WIN's layout: the S7-200
    /// event number the target maps onto GUTTA's event `number`, which the dialect
    /// translates back (docs/microwin.md, "Interrupt events"). An event the target
    /// gives no S7-200 number cannot be written so that it compiles back.
    pub(super) fn s7200_event(&self, number: u16) -> Result<String, String> {
        let event = self
            .target
            .memory
            .events
            .iter()
            .find(|e| e.number == u32::from(number));
        match event.map(|e| (e, e.microwin)) {
            Some((_, Some(s7))) => Ok(s7.to_string()),
            Some((e, None)) => Err(format!(
                "event {number} ({}) of {} has no S7-200 number (no MicroWin attribute)",
                e.name,
                self.target.name()
            )),
            None => Err(format!(
                "{} raises no interrupt event {number}",
                self.target.name()
            )),
        }
    }

    /// The comment between the program and the data and system blocks.
    pub(super) fn awl_data_note(&mut self) {
        self.line("");
        self.line("// Micro/WIN exports data blocks (and keeps the system block) apart from the");
        self.line("// program; gutta-cc reads them in the same file, in its own layout, below.");
    }
}
