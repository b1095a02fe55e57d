//! The Modbus view of a memory map: which coils, discrete inputs or registers a direct
//! address covers (and which bits of each), which memory a Modbus object reaches, and
//! the ranges each table serves. Plain data only: no frames, no CRC, no I/O (the
//! simulator and the CLI do those).
//!
//! Facts used (IN1001, AN2002): every mapped area starts at its `ModbusStart`
//! reference; a bit table (coils, discrete inputs) gives each bit of the area one
//! object, byte `n` bit `b` being object `8n + b`; a register table gives each two
//! consecutive bytes one register, byte `2r` being its low half (bits 0..7) and byte
//! `2r + 1` its high half (bits 8..15), because GUTTA memory is little-endian. So the
//! value of register `r` equals the word at byte offset `2r` (`MW0` is 400009 on
//! CPU-EC20). Modbus sends a register's high byte first; that is the framer's business.

use std::fmt;
use std::ops::RangeInclusive;

use crate::{
    Address, Area, CatalogError, CatalogErrorCode, MemoryMap, ModbusMapping, ModbusTable, Width,
};

/// One Modbus object (coil, discrete input or register) and the bits of it that an
/// address covers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct ModbusPiece {
    /// Six-digit reference number: 400024, 100005, 25 (printed `000025`).
    pub reference: u32,
    /// 0-based address on the wire (reference 400024 is wire address 23).
    pub wire: u16,
    /// First bit of the object covered: 0..=15 in a register, always 0 in a coil.
    pub first_bit: u8,
    /// Last bit of the object covered (inclusive).
    pub last_bit: u8,
    /// The bit of the variable's value that sits in `first_bit`: object bits
    /// `first_bit..=last_bit` hold value bits `value_bit..`.
    pub value_bit: u8,
}

impl ModbusPiece {
    /// How many bits of the object the piece covers.
    pub fn bit_count(&self) -> u32 {
        u32::from(self.last_bit.saturating_sub(self.first_bit)) + 1
    }

    /// Whether the piece is a whole object (all 16 bits of a register, or a coil).
    pub fn is_whole(&self, table: ModbusTable) -> bool {
        let last = if table.is_bits() { 0 } else { 15 };
        self.first_bit == 0 && self.last_bit == last
    }
}

/// Where a direct address appears in Modbus: its table and the objects it covers, in
/// the order of the variable's bits (lowest first). `MW1` on CPU-EC20 is two pieces:
/// 400009 bits 8..15 (value bits 0..7) and 400010 bits 0..7 (value bits 8..15).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ModbusLocation {
    /// The address in canonical form (`MB31`), for display.
    pub variable: String,
    pub table: ModbusTable,
    pub pieces: Vec<ModbusPiece>,
}

/// The memory behind one Modbus object.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct ModbusCell {
    /// Slot of the area.
    pub slot: u8,
    /// Byte offset in the area: the coil's byte, or the register's low byte (a
    /// register is bytes `offset` (bits 0..7) and `offset + 1` (bits 8..15)).
    pub offset: u32,
    /// Bit in the byte for coils and discrete inputs; `None` for registers.
    pub bit: Option<u8>,
}

impl ModbusCell {
    /// The memory as an address: a bit for coils and discrete inputs, the word at
    /// `offset` for registers. That word is a location, not necessarily a width the
    /// area lets programs use (a register of `J` or `HC`).
    pub fn address(&self) -> Address {
        match self.bit {
            Some(bit) => Address {
                slot: self.slot,
                width: Width::Bit,
                offset: self.offset,
                bit,
            },
            None => Address {
                slot: self.slot,
                width: Width::Word,
                offset: self.offset,
                bit: 0,
            },
        }
    }
}

/// The objects of one table that one area serves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct ModbusSpan {
    pub table: ModbusTable,
    /// 0-based wire address of the first object.
    pub first_wire: u16,
    /// 0-based wire address of the last object (inclusive).
    pub last_wire: u16,
    /// Slot of the area.
    pub slot: u8,
}

impl ModbusSpan {
    /// Reference number of the first object (400009 for M on CPU-EC20).
    pub fn first_reference(&self) -> u32 {
        reference(self.table, self.first_wire)
    }

    /// Reference number of the last object (400072 for M on CPU-EC20).
    pub fn last_reference(&self) -> u32 {
        reference(self.table, self.last_wire)
    }

    /// Number of objects.
    pub fn count(&self) -> u32 {
        u32::from(self.last_wire).saturating_sub(u32::from(self.first_wire)) + 1
    }
}

/// The six-digit reference number of a table's 0-based wire address.
pub fn reference(table: ModbusTable, wire: u16) -> u32 {
    table.prefix() * 100_000 + u32::from(wire) + 1
}

/// A reference number printed the vendor's way, six digits: `000025`, `400024`.
pub fn format_reference(reference: u32) -> String {
    format!("{reference:06}")
}

/// 0-based wire address of a mapping's first object, `None` if `start` is below the
/// table's first reference (only possible for a hand-built map).
fn wire_start(mapping: &ModbusMapping) -> Option<u32> {
    mapping
        .start
        .checked_sub(mapping.table.prefix() * 100_000 + 1)
}

/// Number of objects an area occupies in its table: a bit per bit, a register per
/// two bytes.
fn object_count(table: ModbusTable, size: u32) -> u32 {
    if table.is_bits() {
        size.saturating_mul(8)
    } else {
        size / 2
    }
}

/// The span of an area, `None` if it has no mapping or does not fit the wire's 16 bits.
fn span_of(area: &Area) -> Option<ModbusSpan> {
    let mapping = area.modbus?;
    let first = wire_start(&mapping)?;
    let count = object_count(mapping.table, area.size);
    let last = first.checked_add(count.checked_sub(1)?)?;
    Some(ModbusSpan {
        table: mapping.table,
        first_wire: u16::try_from(first).ok()?,
        last_wire: u16::try_from(last).ok()?,
        slot: area.slot,
    })
}

/// Check the Modbus mappings of a map's areas: an area on registers has an even size
/// (a register is two bytes), every area's objects fit in the 65536 wire addresses
/// of its table, and no two areas share an object. Called by `MemoryMap::parse`.
pub(crate) fn check_layout(areas: &[Area], file: &str) -> Result<(), CatalogError> {
    let mut spans = Vec::new();
    for area in areas {
        let Some(mapping) = area.modbus else {
            continue;
        };
        if !mapping.table.is_bits() && area.size % 2 != 0 {
            return Err(CatalogError::new(
                CatalogErrorCode::Value,
                file,
                format!(
                    "area {} is mapped to {} registers, two bytes each, but has an odd Size {}",
                    area.name,
                    mapping.table.keyword(),
                    area.size
                ),
            ));
        }
        let span = span_of(area).ok_or_else(|| {
            CatalogError::new(
                CatalogErrorCode::Value,
                file,
                format!(
                    "the Modbus objects of area {} (from {}) run past the table's last reference",
                    area.name,
                    format_reference(mapping.start)
                ),
            )
        })?;
        spans.push((span, area.name.as_str()));
    }
    spans.sort();
    for pair in spans.windows(2) {
        let ((a, a_name), (b, b_name)) = (pair[0], pair[1]);
        if a.table == b.table && b.first_wire <= a.last_wire {
            return Err(CatalogError::new(
                CatalogErrorCode::Duplicate,
                file,
                format!(
                    "areas {a_name} ({}..{}) and {b_name} ({}..{}) share Modbus references",
                    format_reference(a.first_reference()),
                    format_reference(a.last_reference()),
                    format_reference(b.first_reference()),
                    format_reference(b.last_reference()),
                ),
            ));
        }
    }
    Ok(())
}

impl MemoryMap {
    /// Where a direct address appears in Modbus; `None` for areas without a mapping
    /// (K, L), for an address outside its area, or an unknown slot.
    pub fn modbus_location(&self, address: &Address) -> Option<ModbusLocation> {
        let area = self.area_by_slot(address.slot)?;
        let mapping = area.modbus?;
        let wire0 = wire_start(&mapping)?;
        let bytes = address.width.bytes();
        if address.offset.checked_add(bytes)? > area.size || address.bit > 7 {
            return None;
        }
        let table = mapping.table;
        let wire = |index: u32| u16::try_from(wire0.checked_add(index)?).ok();
        let mut pieces: Vec<ModbusPiece> = Vec::new();
        if table.is_bits() {
            let first_bit = address.offset.checked_mul(8)?;
            let (first, count) = match address.width {
                Width::Bit => (first_bit + u32::from(address.bit), 1),
                _ => (first_bit, bytes * 8),
            };
            for i in 0..count {
                let w = wire(first.checked_add(i)?)?;
                pieces.push(ModbusPiece {
                    reference: reference(table, w),
                    wire: w,
                    first_bit: 0,
                    last_bit: 0,
                    value_bit: i as u8,
                });
            }
        } else {
            for i in 0..bytes {
                let byte = address.offset + i;
                if byte / 2 >= object_count(table, area.size) {
                    return None; // the odd last byte of a hand-built map
                }
                let w = wire(byte / 2)?;
                let half = (byte % 2) as u8 * 8;
                let (first_bit, last_bit) = match address.width {
                    Width::Bit => (half + address.bit, half + address.bit),
                    _ => (half, half + 7),
                };
                match pieces.last_mut() {
                    Some(last) if last.wire == w && last.last_bit + 1 == first_bit => {
                        last.last_bit = last_bit;
                    }
                    _ => pieces.push(ModbusPiece {
                        reference: reference(table, w),
                        wire: w,
                        first_bit,
                        last_bit,
                        value_bit: i as u8 * 8,
                    }),
                }
            }
        }
        Some(ModbusLocation {
            variable: self.format_address(address),
            table,
            pieces,
        })
    }

    /// The memory behind the object at 0-based wire address `wire` of `table`; `None`
    /// if no area serves it (past an area, or an area without that table).
    pub fn modbus_cell(&self, table: ModbusTable, wire: u16) -> Option<ModbusCell> {
        self.areas.iter().find_map(|area| {
            let span = span_of(area).filter(|s| s.table == table)?;
            if !(span.first_wire..=span.last_wire).contains(&wire) {
                return None;
            }
            let index = u32::from(wire - span.first_wire);
            Some(if table.is_bits() {
                ModbusCell {
                    slot: area.slot,
                    offset: index / 8,
                    bit: Some((index % 8) as u8),
                }
            } else {
                ModbusCell {
                    slot: area.slot,
                    offset: index * 2,
                    bit: None,
                }
            })
        })
    }

    /// Every area's span, sorted by table, then wire address.
    pub fn modbus_spans(&self) -> Vec<ModbusSpan> {
        let mut spans: Vec<ModbusSpan> = self.areas.iter().filter_map(span_of).collect();
        spans.sort();
        spans
    }

    /// The runs of consecutive wire addresses `table` serves, ascending; adjacent
    /// areas (AQ then M then T ... in the holding registers) form one run.
    pub fn modbus_ranges(&self, table: ModbusTable) -> Vec<RangeInclusive<u16>> {
        let mut ranges: Vec<RangeInclusive<u16>> = Vec::new();
        for span in self.modbus_spans().into_iter().filter(|s| s.table == table) {
            match ranges.last_mut() {
                Some(last) if u32::from(*last.end()) + 1 >= u32::from(span.first_wire) => {
                    *last = *last.start()..=span.last_wire.max(*last.end());
                }
                _ => ranges.push(span.first_wire..=span.last_wire),
            }
        }
        ranges
    }

    /// Whether a request for `count` objects from wire address `first` stays inside
    /// one served run (otherwise a slave answers exception 02, illegal data address).
    pub fn modbus_serves(&self, table: ModbusTable, first: u16, count: u16) -> bool {
        let Some(last) = (u32::from(first) + u32::from(count)).checked_sub(1) else {
            return false;
        };
        count > 0
            && self
                .modbus_ranges(table)
                .iter()
                .any(|r| u32::from(*r.start()) <= u32::from(first) && last <= u32::from(*r.end()))
    }
}

fn table_noun(table: ModbusTable, plural: bool) -> &'static str {
    match (table, plural) {
        (ModbusTable::Coil, false) => "coil",
        (ModbusTable::Coil, true) => "coils",
        (ModbusTable::DiscreteInput, false) => "discrete input",
        (ModbusTable::DiscreteInput, true) => "discrete inputs",
        (ModbusTable::InputRegister, false) => "input register",
        (ModbusTable::InputRegister, true) => "input registers",
        (ModbusTable::HoldingRegister, false) => "holding register",
        (ModbusTable::HoldingRegister, true) => "holding registers",
    }
}

/// `MB31: holding register 400024 bits 8..15 (wire address 23)`,
/// `MD2: holding registers 400010..400011 (wire addresses 9..10)`,
/// `QB1: coils 000009..000016 (wire addresses 8..15)`.
impl fmt::Display for ModbusLocation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (Some(first), Some(last)) = (self.pieces.first(), self.pieces.last()) else {
            return write!(f, "{}: no Modbus address", self.variable);
        };
        // Consecutive whole objects print as one range; partial ones with their bits.
        let mut parts: Vec<String> = Vec::new();
        let mut run: Option<(u32, u32)> = None;
        let flush = |run: &mut Option<(u32, u32)>, parts: &mut Vec<String>| {
            if let Some((a, b)) = run.take() {
                parts.push(if a == b {
                    format_reference(a)
                } else {
                    format!("{}..{}", format_reference(a), format_reference(b))
                });
            }
        };
        for p in &self.pieces {
            if p.is_whole(self.table) {
                match &mut run {
                    Some((_, b)) if *b + 1 == p.reference => *b = p.reference,
                    _ => {
                        flush(&mut run, &mut parts);
                        run = Some((p.reference, p.reference));
                    }
                }
            } else {
                flush(&mut run, &mut parts);
                parts.push(if p.first_bit == p.last_bit {
                    format!("{} bit {}", format_reference(p.reference), p.first_bit)
                } else {
                    format!(
                        "{} bits {}..{}",
                        format_reference(p.reference),
                        p.first_bit,
                        p.last_bit
                    )
                });
            }
        }
        flush(&mut run, &mut parts);
        let plural = first.wire != last.wire;
        write!(
            f,
            "{}: {} {} ",
            self.variable,
            table_noun(self.table, plural),
            parts.join(", ")
        )?;
        if plural {
            write!(f, "(wire addresses {}..{})", first.wire, last.wire)
        } else {
            write!(f, "(wire address {})", first.wire)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ec20() -> MemoryMap {
        let (_, _, var) = crate::stdlib::TARGETS[0];
        MemoryMap::parse(var).expect("CPU-EC20 ManagerVar.xml parses")
    }

    fn location(map: &MemoryMap, text: &str) -> ModbusLocation {
        let address = map.parse_address(text).expect("address parses");
        map.modbus_location(&address)
            .expect("address has a Modbus location")
    }

    fn piece(reference: u32, bits: RangeInclusive<u8>, value_bit: u8) -> ModbusPiece {
        ModbusPiece {
            reference,
            wire: (reference % 100_000 - 1) as u16,
            first_bit: *bits.start(),
            last_bit: *bits.end(),
            value_bit,
        }
    }

    #[test]
    fn mb31_is_the_high_byte_of_400024() {
        let loc = location(&ec20(), "MB31");
        assert_eq!(loc.table, ModbusTable::HoldingRegister);
        assert_eq!(loc.pieces, [piece(400024, 8..=15, 0)]);
        assert_eq!(loc.pieces[0].wire, 23);
        assert_eq!(
            loc.to_string(),
            "MB31: holding register 400024 bits 8..15 (wire address 23)"
        );
    }

    #[test]
    fn mw20_is_400019() {
        let loc = location(&ec20(), "MW20");
        assert_eq!(loc.pieces, [piece(400019, 0..=15, 0)]);
        assert_eq!(
            loc.to_string(),
            "MW20: holding register 400019 (wire address 18)"
        );
    }

    #[test]
    fn q3_0_is_coil_000025() {
        let loc = location(&ec20(), "Q3.0");
        assert_eq!(loc.table, ModbusTable::Coil);
        assert_eq!(loc.pieces, [piece(25, 0..=0, 0)]);
        assert_eq!(loc.to_string(), "Q3.0: coil 000025 (wire address 24)");
    }

    #[test]
    fn i0_4_is_discrete_input_100005() {
        let loc = location(&ec20(), "I0.4");
        assert_eq!(loc.table, ModbusTable::DiscreteInput);
        assert_eq!(loc.pieces, [piece(100005, 0..=0, 0)]);
        assert_eq!(
            loc.to_string(),
            "I0.4: discrete input 100005 (wire address 4)"
        );
    }

    #[test]
    fn unaligned_and_wide_accesses_split_into_pieces() {
        let map = ec20();
        let loc = location(&map, "MW1");
        assert_eq!(
            loc.pieces,
            [piece(400009, 8..=15, 0), piece(400010, 0..=7, 8)]
        );
        assert_eq!(
            loc.to_string(),
            "MW1: holding registers 400009 bits 8..15, 400010 bits 0..7 (wire addresses 8..9)"
        );
        let loc = location(&map, "MD2");
        assert_eq!(
            loc.pieces,
            [piece(400010, 0..=15, 0), piece(400011, 0..=15, 16)]
        );
        assert_eq!(
            loc.to_string(),
            "MD2: holding registers 400010..400011 (wire addresses 9..10)"
        );
        let loc = location(&map, "M3.2");
        assert_eq!(loc.pieces, [piece(400010, 10..=10, 0)]);
        assert_eq!(
            loc.to_string(),
            "M3.2: holding register 400010 bit 10 (wire address 9)"
        );
        let loc = location(&map, "QB1");
        let expected: Vec<ModbusPiece> = (0..8).map(|i| piece(9 + i, 0..=0, i as u8)).collect();
        assert_eq!(loc.pieces, expected);
        assert_eq!(
            loc.to_string(),
            "QB1: coils 000009..000016 (wire addresses 8..15)"
        );
        assert_eq!(location(&map, "T5").pieces, [piece(400078, 0..=15, 0)]);
        assert_eq!(location(&map, "AIW0").pieces, [piece(300001, 0..=15, 0)]);
    }
}
