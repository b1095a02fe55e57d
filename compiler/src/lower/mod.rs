//! Lowering: a checked program to the image's structures, without bytes yet: the
//! constant pool, each unit's page number, locals and records (networks and steps
//! with packed operands), data items and the system page. Only `check` output comes
//! in; no source text or tokens.

pub mod consts;

use gutta_catalog::{Address, AreaKind, BlockKind, Target};
use gutta_format::{
    ArgumentPage, DataItem, LocalEntry, LocalSection, Operand, PackedOperand, PortEntry, Record,
    SystemPage, UnitRef, Use,
};

use crate::check::{CheckedOperand, CheckedProgram, ConstValue, SystemConfig};
use crate::source::Span;
use crate::syntax::ast::VarSection;
use consts::{const_bytes, ConstPool};

/// One unit, ready to encode.
#[derive(Debug, Clone)]
pub struct LoweredUnit {
    /// Function index = argument and instruction page number.
    pub page: u32,
    pub name: String,
    pub arguments: ArgumentPage,
    /// Records with the source span they come from (the unit header for networks).
    pub records: Vec<(Record, Span)>,
    /// The unit's header, for diagnostics.
    pub span: Span,
}

/// A data block, ready to encode.
#[derive(Debug, Clone)]
pub struct LoweredData {
    pub number: u32,
    pub items: Vec<DataItem>,
    /// Source row of each item.
    pub spans: Vec<Span>,
}

/// The whole program in image structures.
#[derive(Debug, Clone)]
pub struct Lowered {
    pub consts: ConstPool,
    pub units: Vec<LoweredUnit>,
    pub data: Vec<LoweredData>,
    pub system: Option<SystemPage>,
    /// The SYSTEM_BLOCK line, for listings.
    pub system_span: Option<Span>,
}

/// The packed operand of a checked operand; constants are values in K at `consts`.
fn packed(o: &CheckedOperand, consts: &ConstPool, k_slot: u8) -> PackedOperand {
    let operand = match *o {
        CheckedOperand::Memory {
            address,
            use_,
            width,
        } => match use_ {
            Use::AddressOf => Operand::AddressOf {
                byte: address,
                width,
            },
            Use::Pointer => Operand::Pointer {
                holder: address,
                width,
            },
            // The checker writes Value, AddressOf or Pointer here.
            _ => Operand::Value(Address { width, ..address }),
        },
        CheckedOperand::Constant { value, width } => Operand::Value(Address {
            slot: k_slot,
            width,
            offset: consts.offset(&const_bytes(value, width)).unwrap_or(0),
            bit: 0,
        }),
        CheckedOperand::Label(n) => Operand::Label(n),
        CheckedOperand::Unit { kind, number } => Operand::Unit(UnitRef {
            kind,
            number: u16::try_from(number).unwrap_or(u16::MAX),
        }),
        CheckedOperand::Literal(v) => {
            Operand::Literal(u16::try_from(v.clamp(0, i64::from(u16::MAX))).unwrap_or(0))
        }
    };
    PackedOperand::encode(operand)
}

pub fn lower(program: &CheckedProgram, target: &Target) -> Lowered {
    let k_slot = target
        .memory
        .area_of_kind(AreaKind::Constant)
        .map(|a| a.slot)
        .unwrap_or(0);
    // Constants first: their place in K is part of every operand that uses them.
    let all_consts = program
        .units
        .iter()
        .flat_map(|u| &u.networks)
        .flat_map(|n| &n.instructions)
        .flat_map(|i| &i.operands)
        .filter_map(|o| match o {
            CheckedOperand::Constant { value, width } => Some(const_bytes(*value, *width)),
            _ => None,
        });
    let consts = ConstPool::build(all_consts);
    let operand = |o: &CheckedOperand| packed(o, &consts, k_slot);
    let mut units = Vec::with_capacity(program.units.len());
    for u in &program.units {
        let locals = u
            .locals
            .iter()
            .map(|l| LocalEntry {
                operand: PackedOperand::encode(Operand::Value(l.address)),
                section: match l.section {
                    VarSection::Input => LocalSection::Input,
                    VarSection::InOut => LocalSection::InOut,
                    VarSection::Output => LocalSection::Output,
                    VarSection::Temp => LocalSection::Temp,
                },
                data_type: l.ty,
            })
            .collect();
        let arguments = ArgumentPage {
            subroutine: u.kind == BlockKind::Subroutine,
            unit_number: u.number.min(255) as u8,
            locals,
        };
        let mut records = Vec::new();
        for n in &u.networks {
            records.push((
                Record::Network(n.number.min(u16::MAX as u32) as u16),
                n.span,
            ));
            for i in &n.instructions {
                let opcode = target.instructions.get(i.id).opcode;
                records.push((
                    Record::Instruction {
                        opcode,
                        operands: i.operands.iter().map(operand).collect(),
                    },
                    i.span,
                ));
            }
        }
        units.push(LoweredUnit {
            // The checker refused units the target cannot have (E0403, E0413).
            page: u.unit_ref().page(&target.plc).map_or(u32::MAX, u32::from),
            name: u.numbered_name(),
            arguments,
            records,
            span: u.span,
        });
    }
    units.sort_by_key(|u| u.page);
    let data = program
        .data_blocks
        .iter()
        .map(|d| LoweredData {
            number: d.number,
            items: d
                .items
                .iter()
                .map(|i| DataItem {
                    operand: PackedOperand::encode(Operand::Value(i.address)),
                    value: match i.value {
                        ConstValue::Integer(v) => v as u32,
                        ConstValue::Real(r) => r.to_bits(),
                    },
                })
                .collect(),
            spans: d.items.iter().map(|i| i.span).collect(),
        })
        .collect();
    Lowered {
        consts,
        units,
        data,
        system: program.system.as_ref().map(system_page),
        system_span: program.system_span,
    }
}

fn system_page(s: &SystemConfig) -> SystemPage {
    let ports = s
        .ports
        .iter()
        .map(|p| PortEntry {
            protocol: 0,
            address: p.address,
            baud: p.baud,
            data_bits: p.data_bits,
            parity: p.parity.code(),
            stop_bits: p.stop_bits,
            timeout: p.timeout,
            frame_gap: p.frame_gap,
        })
        .collect();
    let password = gutta_format::password_bytes(s.password.as_deref());
    SystemPage { ports, password }
}
