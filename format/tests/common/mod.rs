//! Builders of hand-made images for the format tests, on the stdlib targets: operands
//! from address text, instruction records from mnemonics, whole images from units.
//! Built with the crate's own encoders only; no compiler involved.
#![allow(dead_code)]

use std::collections::BTreeMap;
use std::sync::Arc;

use gutta_catalog::{stdlib, DataType, Target, Width};
use gutta_format::{
    encode_data, encode_instructions, ArgumentPage, DataItem, Image, LocalEntry, LocalSection,
    PackedOperand, PageId, PageKind, PortEntry, Record, SystemPage, UnitRef, Use,
};

pub fn target() -> Arc<Target> {
    stdlib::shared(stdlib::DEFAULT).expect("the default target loads")
}

pub fn target_named(name: &str) -> Arc<Target> {
    stdlib::shared(name).expect("a stdlib target loads")
}

/// The default target with its ManagerFun.xml edited (`edit` gets and returns the text),
/// to test what the stdlib files do not show, such as operand names in lower case.
pub fn target_with_manager_fun(edit: impl Fn(&str) -> String) -> Target {
    let (_, plc_type, manager_var) = stdlib::TARGETS[0];
    let text = std::str::from_utf8(stdlib::MANAGER_FUN).expect("UTF-8");
    let manager_fun = edit(text);
    Target::load(gutta_catalog::TargetSources {
        plc_type,
        manager_var,
        manager_fun: manager_fun.as_bytes(),
    })
    .expect("the edited target loads")
}

/// `MW20` as a value operand (USE 0) with the address's width.
pub fn val(t: &Target, text: &str) -> PackedOperand {
    let a = t.memory.parse_address(text).expect("a valid address");
    PackedOperand::memory(a, Use::Value, a.width)
}

/// `*MD4` accessed with `width`.
pub fn ptr(t: &Target, text: &str, width: Width) -> PackedOperand {
    let a = t.memory.parse_address(text).expect("a valid address");
    PackedOperand::memory(a, Use::Pointer, width)
}

/// `&MB24`.
pub fn addr_of(t: &Target, text: &str) -> PackedOperand {
    let a = t.memory.parse_address(text).expect("a valid address");
    PackedOperand::memory(a, Use::AddressOf, Width::Dword)
}

pub fn label(n: u16) -> PackedOperand {
    PackedOperand::special(Use::Label, 0, n)
}

pub fn lit(n: u16) -> PackedOperand {
    PackedOperand::special(Use::Literal, 0, n)
}

pub fn sbr(n: u16) -> PackedOperand {
    PackedOperand::special(Use::Unit, 1, n)
}

pub fn int(n: u16) -> PackedOperand {
    PackedOperand::special(Use::Unit, 0, n)
}

pub fn ins(t: &Target, mnemonic: &str, operands: Vec<PackedOperand>) -> Record {
    let id = t.instructions.lookup(mnemonic).expect("a known mnemonic");
    Record::Instruction {
        opcode: t.instructions.get(id).opcode,
        operands,
    }
}

pub fn local(t: &Target, text: &str, section: LocalSection, data_type: DataType) -> LocalEntry {
    LocalEntry {
        operand: val(t, text),
        section,
        data_type,
    }
}

/// One program unit: its argument page and its records.
#[derive(Debug, Clone)]
pub struct UnitSpec {
    pub arguments: ArgumentPage,
    pub records: Vec<Record>,
}

/// Pages of an image before encoding.
#[derive(Debug, Clone)]
pub struct ImageSpec {
    pub plc_type: String,
    pub consts: Vec<u8>,
    /// By page number.
    pub units: BTreeMap<u8, UnitSpec>,
    pub data: BTreeMap<u8, Vec<DataItem>>,
    pub system: Option<SystemPage>,
}

impl ImageSpec {
    /// MAIN only, with these records and no locals.
    pub fn main(t: &Target, records: Vec<Record>) -> ImageSpec {
        let mut units = BTreeMap::new();
        units.insert(
            0,
            UnitSpec {
                arguments: ArgumentPage {
                    subroutine: false,
                    unit_number: 0,
                    locals: Vec::new(),
                },
                records,
            },
        );
        ImageSpec {
            plc_type: t.plc.name.clone(),
            consts: Vec::new(),
            units,
            data: BTreeMap::new(),
            system: None,
        }
    }

    /// Add a unit: interrupt routine `INTn` or subroutine `SBRn`.
    pub fn unit(
        mut self,
        t: &Target,
        subroutine: bool,
        number: u8,
        locals: Vec<LocalEntry>,
        records: Vec<Record>,
    ) -> ImageSpec {
        let unit = if subroutine {
            UnitRef::subroutine(u16::from(number))
        } else {
            UnitRef::interrupt(u16::from(number))
        };
        let page = unit.page(&t.plc).expect("the target has the unit");
        self.units.insert(
            page,
            UnitSpec {
                arguments: ArgumentPage {
                    subroutine,
                    unit_number: number,
                    locals,
                },
                records,
            },
        );
        self
    }

    pub fn build(&self) -> Image {
        let mut pages = BTreeMap::new();
        pages.insert(PageId::new(PageKind::Const, 0), self.consts.clone());
        for (page, u) in &self.units {
            pages.insert(PageId::new(PageKind::Argument, *page), u.arguments.encode());
            pages.insert(
                PageId::new(PageKind::Instruction, *page),
                encode_instructions(&u.records),
            );
        }
        for (page, items) in &self.data {
            pages.insert(PageId::new(PageKind::Data, *page), encode_data(items));
        }
        if let Some(s) = &self.system {
            pages.insert(PageId::new(PageKind::System, 0), s.encode());
        }
        Image {
            plc_type: self.plc_type.clone(),
            pages,
        }
    }
}

pub fn port() -> PortEntry {
    PortEntry {
        protocol: 0,
        address: 20,
        baud: 38400,
        data_bits: 8,
        parity: 1,
        stop_bits: 1,
        timeout: 10,
        frame_gap: 10,
    }
}

/// A system page with the target's number of ports.
pub fn system(t: &Target) -> SystemPage {
    SystemPage {
        ports: vec![port(); usize::from(t.memory.serial_ports)],
        password: *b"1234\0\0\0\0\0\0\0\0\0\0\0\0",
    }
}

/// A program using every kind of operand on CPU-EC20-like targets: bit logic,
/// constants in K, pointers and address-of, labels, a CALL with arguments, an
/// interrupt routine attached to an event, a timer, a data block and a system block.
pub fn full_program(t: &Target) -> ImageSpec {
    use LocalSection::*;
    let main = vec![
        Record::Network(1),
        ins(t, "LD", vec![val(t, "SM0.5")]),
        ins(t, "=", vec![val(t, "Q0.0")]),
        Record::Network(2),
        ins(t, "LD", vec![val(t, "SM0.0")]),
        ins(t, "MOVW", vec![val(t, "KW0"), val(t, "MW20")]),
        ins(t, "MOVD", vec![addr_of(t, "MB24"), val(t, "MD4")]),
        ins(t, "MOVW", vec![val(t, "KW2"), ptr(t, "MD4", Width::Word)]),
        ins(t, "JMP", vec![label(3)]),
        Record::Network(3),
        ins(t, "LD", vec![val(t, "I0.0")]),
        ins(t, "TON", vec![val(t, "T5"), val(t, "KW0")]),
        ins(
            t,
            "CALL",
            vec![sbr(0), val(t, "MW10"), val(t, "MW12"), val(t, "MD14")],
        ),
        ins(t, "ATCH", vec![int(1), lit(10)]),
        ins(t, "ENI", vec![]),
        Record::Network(4),
        ins(t, "LBL", vec![label(3)]),
    ];
    let sbr0 = vec![
        Record::Network(1),
        ins(t, "LD", vec![val(t, "SM0.0")]),
        ins(t, "+I", vec![val(t, "LW0"), val(t, "LW2")]),
        ins(t, "MOVD", vec![val(t, "KD4"), val(t, "LD4")]),
        ins(t, "=", vec![val(t, "L8.0")]),
        ins(t, "RET", vec![]),
    ];
    let int1 = vec![
        Record::Network(1),
        ins(t, "LD", vec![val(t, "SM0.0")]),
        ins(t, "MOVB", vec![val(t, "LB0"), val(t, "MB30")]),
    ];
    let mut spec = ImageSpec::main(t, main)
        .unit(
            t,
            true,
            0,
            vec![
                local(t, "LW0", Input, DataType::Int),
                local(t, "LW2", InOut, DataType::Word),
                local(t, "LD4", Output, DataType::Dint),
                local(t, "L8.0", Temp, DataType::Bool),
            ],
            sbr0,
        )
        .unit(
            t,
            false,
            1,
            vec![local(t, "LB0", Temp, DataType::Usint)],
            int1,
        );
    spec.consts = vec![0x05, 0x00, 0x01, 0x0E, 0x90, 0xEE, 0xFE, 0xFF];
    spec.data.insert(
        0,
        vec![
            DataItem {
                operand: val(t, "MW22"),
                value: 6,
            },
            DataItem {
                operand: val(t, "MB30"),
                value: 1,
            },
            DataItem {
                operand: val(t, "M40.0"),
                value: 1,
            },
            DataItem {
                operand: val(t, "MD44"),
                value: (-70000i32) as u32,
            },
            DataItem {
                operand: val(t, "MB31"),
                value: 0xFFFF_FFFB,
            },
        ],
    );
    spec.system = Some(system(t));
    spec
}
