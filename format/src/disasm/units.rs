//! Program units: the block header from the page number, the VAR sections from the
//! argument page (laid out again as the language lays them out, so an argument page
//! the language cannot reproduce is reported), and the networks and steps of the
//! instruction page. Operand spelling is in `operands.rs`.

use gutta_catalog::rules::LocalLayout;
use gutta_catalog::{plural, Address, AreaKind, BlockKind, DataType};

use super::{Disassembler, Format};
use crate::{
    decode_instructions, ArgumentPage, LocalSection, Operand, PackedOperand, PageId, PageKind,
    Record, UnitRef,
};

/// One local as the text declares it.
#[derive(Debug, Clone)]
pub(super) struct Local {
    /// Generated: `in0`, `io0`, `out0`, `tmp0`, counted per section.
    pub name: String,
    pub section: LocalSection,
    pub data_type: DataType,
    /// Where the language places the declaration (what `#name` compiles to).
    pub address: Address,
    /// Where the argument page says the local is.
    pub recorded: PackedOperand,
    /// Byte offset of its entry in the argument page.
    pub entry: usize,
}

const SECTIONS: [(LocalSection, &str, &str); 4] = [
    (LocalSection::Input, "VAR_INPUT", "in"),
    (LocalSection::InOut, "VAR_IN_OUT", "io"),
    (LocalSection::Output, "VAR_OUTPUT", "out"),
    (LocalSection::Temp, "VAR", "tmp"),
];

/// The locals of an argument page in the order the text declares them (section by
/// section, page order within a section), each placed in L as the language places it
/// (`gutta_catalog::rules::LocalLayout`).
pub(super) fn locals_of(page: &ArgumentPage, l_slot: u8) -> Vec<Local> {
    let mut out = Vec::with_capacity(page.locals.len());
    let mut layout = LocalLayout::new();
    for (section, _, prefix) in SECTIONS {
        let mut count = 0;
        for (i, entry) in page.locals.iter().enumerate() {
            if entry.section != section {
                continue;
            }
            let width = entry.data_type.width();
            let (offset, bit) = layout.place(width);
            let address = Address {
                slot: l_slot,
                width,
                offset,
                bit,
            };
            out.push(Local {
                name: format!("{prefix}{count}"),
                section,
                data_type: entry.data_type,
                address,
                recorded: entry.operand,
                entry: 4 + 8 * i,
            });
            count += 1;
        }
    }
    out
}

impl Disassembler<'_> {
    /// The unit whose argument and instruction pages have this number.
    pub(super) fn unit(&mut self, number: u8) {
        let arg_id = PageId::new(PageKind::Argument, number);
        let code_id = PageId::new(PageKind::Instruction, number);
        let Some(unit) = UnitRef::from_page(number, &self.target.plc) else {
            let plc = &self.target.plc;
            let reason = format!(
                "page {number:02X} is no program unit of {}: it has {} and {}",
                plc.name,
                plural::count(plc.program_block_page_int_size, "interrupt routine"),
                plural::count(plc.program_block_page_sbr_size, "subroutine")
            );
            self.cannot_decode(
                "",
                &format!("program page {number:02X}"),
                code_id,
                0,
                &reason,
            );
            return;
        };
        let keyword = match unit.kind {
            BlockKind::Interrupt if unit.number == 0 => "ORGANIZATION_BLOCK",
            BlockKind::Interrupt => "INTERRUPT_BLOCK",
            BlockKind::Subroutine => "SUBROUTINE_BLOCK",
        };
        let header = match self.format {
            _ if unit == UnitRef::MAIN => "MAIN:OB1".to_string(),
            Format::Stl => format!("{unit}:{unit}"),
            Format::Awl => super::awl::block_header(unit),
        };
        self.line(&format!("{keyword} {header}"));
        if self.format == Format::Awl {
            self.line("TITLE=");
        }
        let locals = self.locals(arg_id, unit);
        self.line("BEGIN");
        match self.image.page(PageKind::Instruction, number) {
            Some(bytes) => self.code(code_id, bytes, &locals),
            None => self.cannot_decode(
                "",
                "the code",
                code_id,
                0,
                &format!("the image has no instruction page {number:02X}"),
            ),
        }
        self.line(&format!("END_{keyword}"));
    }

    /// Slot of the target's L area (`u8::MAX`, matching no operand, if it has none).
    fn l_slot(&self) -> u8 {
        self.target
            .memory
            .area_of_kind(AreaKind::Local)
            .map_or(u8::MAX, |a| a.slot)
    }

    /// The locals of argument page `number`, if it exists and decodes (for CALL).
    pub(super) fn decoded_locals(&self, number: u8) -> Option<Vec<Local>> {
        let bytes = self.image.page(PageKind::Argument, number)?;
        let page = ArgumentPage::decode(bytes).ok()?;
        Some(locals_of(&page, self.l_slot()))
    }

    /// Print the VAR sections of a unit and check its argument page.
    fn locals(&mut self, id: PageId, unit: UnitRef) -> Vec<Local> {
        let Some(bytes) = self.image.page(PageKind::Argument, id.number) else {
            self.cannot_decode(
                "",
                "the locals",
                id,
                0,
                &format!("the image has no argument page {:02X}", id.number),
            );
            return Vec::new();
        };
        let page = match ArgumentPage::decode(bytes) {
            Ok(page) => page,
            Err(e) => {
                self.cannot_decode("", "the locals", id, e.offset, &e.reason);
                return Vec::new();
            }
        };
        let locals = locals_of(&page, self.l_slot());
        self.check_argument_page(id, unit, &page, &locals);
        for (section, keyword, _) in SECTIONS {
            let mut any = false;
            for l in locals.iter().filter(|l| l.section == section) {
                if !any {
                    self.line(keyword);
                    any = true;
                }
                let at = self.target.memory.format_address(&l.address);
                let line = match self.format {
                    Format::Stl => {
                        format!("{:<20} // {at}", format!("  {} : {};", l.name, l.data_type))
                    }
                    Format::Awl => super::awl::var_line(&l.name, l.data_type, &at),
                };
                self.line(&line);
            }
            if any {
                self.line("END_VAR");
            }
        }
        locals
    }

    /// What the text cannot reproduce of an argument page: a header naming another
    /// unit, locals out of L order, a local where the language would not place it.
    fn check_argument_page(
        &mut self,
        id: PageId,
        unit: UnitRef,
        page: &ArgumentPage,
        locals: &[Local],
    ) {
        let says = UnitRef {
            kind: if page.subroutine {
                BlockKind::Subroutine
            } else {
                BlockKind::Interrupt
            },
            number: u16::from(page.unit_number),
        };
        if says != unit {
            self.error(
                Some(id),
                0,
                format!(
                    "the page header names {says}, but page {:02X} is {unit}",
                    id.number
                ),
            );
        }
        if let Some(i) = page
            .locals
            .windows(2)
            .position(|w| (w[1].section as u8) < (w[0].section as u8))
        {
            self.error(
                Some(id),
                4 + 8 * (i + 1),
                "locals are not in L order (VAR_INPUT, VAR_IN_OUT, VAR_OUTPUT, VAR)",
            );
        }
        for l in locals {
            let placed = PackedOperand::encode(Operand::Value(l.address));
            if placed != l.recorded {
                let reason = format!(
                    "local {} : {} is {} in the argument page, but the language places it at {}",
                    l.name,
                    l.data_type,
                    self.describe(l.recorded),
                    self.target.memory.format_address(&l.address)
                );
                self.error(Some(id), l.entry, reason);
            }
        }
    }

    /// An operand for a message: its address if it is a plain one, else its bits.
    pub(super) fn describe(&self, op: PackedOperand) -> String {
        match op.decode() {
            Ok(Operand::Value(variable)) => match self.address(variable) {
                Ok((a, _)) => self.target.memory.format_address(&a),
                Err(_) => format!("0x{:08X}", op.0),
            },
            _ => format!("0x{:08X}", op.0),
        }
    }

    /// Networks and steps of an instruction page; what follows a structural error is
    /// one comment.
    fn code(&mut self, id: PageId, bytes: &[u8], locals: &[Local]) {
        let (records, failure) = match decode_instructions(bytes) {
            Ok(r) => (r, None),
            Err(e) => {
                let before = bytes
                    .get(..e.offset)
                    .and_then(|b| decode_instructions(b).ok())
                    .unwrap_or_default();
                (before, Some(e))
            }
        };
        let mut step = 0usize;
        for (at, record) in records {
            match record {
                Record::Network(n) => {
                    self.line(&match self.format {
                        Format::Stl => format!("NETWORK {n}"),
                        Format::Awl => format!("Network {n}"),
                    });
                    step = 0;
                }
                Record::Instruction { opcode, operands } => {
                    self.instruction(id, at, step, opcode, &operands, locals);
                    step += 1;
                }
            }
        }
        if let Some(e) = failure {
            self.cannot_decode("", "the rest of the page", id, e.offset, &e.reason);
        }
    }

    fn instruction(
        &mut self,
        id: PageId,
        at: usize,
        step: usize,
        opcode: u16,
        operands: &[PackedOperand],
        locals: &[Local],
    ) {
        let target = self.target;
        let Some(ins) = target.instructions.by_opcode(opcode) else {
            let reason = format!(
                "opcode 0x{opcode:04X} is no instruction of {}",
                target.name()
            );
            self.cannot_decode("", &format!("step {step}"), id, at, &reason);
            return;
        };
        let ins = target.instructions.get(ins);
        match self.instruction_text(ins, operands, locals) {
            Ok(text) => match self.format {
                Format::Stl => self.line(&format!("{text:<28} // step {step}")),
                Format::Awl => self.line(&text),
            },
            Err((operand, reason)) => {
                let offset = at + operand.map_or(0, |i| 3 + 4 * i);
                self.cannot_decode(
                    "",
                    &format!("step {step} ({})", ins.mnemonic),
                    id,
                    offset,
                    &reason,
                );
            }
        }
    }
}
