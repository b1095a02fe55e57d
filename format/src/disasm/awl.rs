//! The STEP 7-Micro/WIN layout of `gutta-cc dis --format awl` (docs/microwin.md, "The
//! way back"): Micro/WIN's block names (`SBR_n:SBRn`, `INT_n:INTn`, also in `CALL` and
//! `ATCH`), its VAR lines, and
//! the note before the data and system blocks, which Micro/WIN exports separately. The
//! rest of the layout (`TITLE=`, `Network n`, no step comments, CRLF) is chosen where
//! the shared writer prints (`units.rs`, `Disassembler::line`).

use gutta_catalog::{BlockKind, DataType};

use super::{Disassembler, Format};
use crate::{PageKind, UnitRef};

/// `SBR_0`, `INT_1`: Micro/WIN's default name of a block. The number is GUTTA's (MAIN
/// is INT0, so the first interrupt routine is INT_1:INT1), which is what compiles back
/// to the same page today.
fn block_name(unit: UnitRef) -> String {
    match unit.kind {
        BlockKind::Interrupt => format!("INT_{}", unit.number),
        BlockKind::Subroutine => format!("SBR_{}", unit.number),
    }
}

/// `SBR_0:SBR0`, `INT_1:INT1`: the name, then the number.
pub(super) fn block_header(unit: UnitRef) -> String {
    format!("{}:{unit}", block_name(unit))
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
        if self.format == Format::Awl && held && unit != UnitRef::MAIN {
            block_name(unit)
        } else {
            unit.to_string()
        }
    }

    /// The comment between the program and the data and system blocks.
    pub(super) fn awl_data_note(&mut self) {
        self.line("");
        self.line("// Micro/WIN exports data blocks (and keeps the system block) apart from the");
        self.line("// program; gutta-cc reads them in the same file, in its own layout, below.");
    }
}
