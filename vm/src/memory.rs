//! PLC memory: the areas (slots) of a target at their ManagerVar.xml sizes, little-endian,
//! widths overlapping (MB0 and MW0 share a byte). All areas live in one byte array, so a
//! pre-decoded operation addresses a byte by one index (docs/vm.md, "Speed"). Locations
//! come from packed operands; pointer values (`&`) are SLOT << 24 | byte offset. Every
//! access is bounds-checked.

use gutta_catalog::{MemoryMap, Width};
use gutta_format::{PackedOperand, Pointer, Use};

/// A resolved place in memory.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Location {
    pub slot: u8,
    pub offset: u32,
    pub width: Width,
    pub bit: u8,
}

impl From<gutta_catalog::Address> for Location {
    fn from(a: gutta_catalog::Address) -> Location {
        Location {
            slot: a.slot,
            offset: a.offset,
            width: a.width,
            bit: a.bit,
        }
    }
}

/// The areas of a target.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Memory {
    /// Every area, in slot order.
    pub(crate) bytes: Vec<u8>,
    /// Slot -> (start in `bytes`, length); slots without an area have length 0.
    spans: Vec<(usize, usize)>,
}

/// An access outside an area, or to a slot that does not exist.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AccessError(pub String);

/// Read a location's bytes from an area, zero-extended (bits read as 0 or 1).
pub(crate) fn read_in(area: &[u8], loc: Location) -> Result<u32, AccessError> {
    let b = bytes_of(area, loc)?;
    Ok(match loc.width {
        Width::Bit => ((b[0] >> (loc.bit & 7)) & 1) as u32,
        Width::Byte => b[0] as u32,
        Width::Word => u16::from_le_bytes([b[0], b[1]]) as u32,
        Width::Dword => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
    })
}

/// Write a location into an area (the value truncated to its width; bits take value & 1).
pub(crate) fn write_in(area: &mut [u8], loc: Location, value: u32) -> Result<(), AccessError> {
    bytes_of(area, loc)?;
    let at = loc.offset as usize;
    match loc.width {
        Width::Bit => {
            let mask = 1u8 << (loc.bit & 7);
            if value & 1 == 1 {
                area[at] |= mask;
            } else {
                area[at] &= !mask;
            }
        }
        Width::Byte => area[at] = value as u8,
        Width::Word => area[at..at + 2].copy_from_slice(&(value as u16).to_le_bytes()),
        Width::Dword => area[at..at + 4].copy_from_slice(&value.to_le_bytes()),
    }
    Ok(())
}

fn bytes_of(area: &[u8], loc: Location) -> Result<&[u8], AccessError> {
    let start = loc.offset as usize;
    let end = start + loc.width.bytes() as usize;
    area.get(start..end).ok_or_else(|| {
        AccessError(format!(
            "slot {} bytes {start}..{end} outside its {} bytes",
            loc.slot,
            area.len()
        ))
    })
}

impl Memory {
    pub fn new(map: &MemoryMap) -> Memory {
        let slots = map
            .areas
            .iter()
            .map(|a| a.slot as usize + 1)
            .max()
            .unwrap_or(0);
        let mut spans = vec![(0, 0); slots];
        let mut sorted: Vec<_> = map.areas.iter().collect();
        sorted.sort_by_key(|a| a.slot);
        let mut total = 0usize;
        for a in sorted {
            spans[a.slot as usize] = (total, a.size as usize);
            total += a.size as usize;
        }
        Memory {
            bytes: vec![0; total],
            spans,
        }
    }

    /// Clear every area.
    pub(crate) fn clear(&mut self) {
        self.bytes.fill(0);
    }

    /// Where slot `slot` starts in the flat byte array, and its length.
    pub(crate) fn span(&self, slot: u8) -> Option<(usize, usize)> {
        self.spans.get(slot as usize).copied()
    }

    /// The index in the flat byte array of a location's first byte, if it lies inside
    /// its area.
    pub(crate) fn index_of(&self, loc: Location) -> Option<usize> {
        let (start, len) = self.span(loc.slot)?;
        let end = loc.offset as usize + loc.width.bytes() as usize;
        (end <= len).then_some(start + loc.offset as usize)
    }

    pub fn area(&self, slot: u8) -> Option<&[u8]> {
        let (start, len) = self.span(slot)?;
        Some(&self.bytes[start..start + len])
    }

    pub fn area_mut(&mut self, slot: u8) -> Option<&mut [u8]> {
        let (start, len) = self.span(slot)?;
        Some(&mut self.bytes[start..start + len])
    }

    fn area_of(&self, slot: u8) -> Result<&[u8], AccessError> {
        self.area(slot)
            .ok_or_else(|| AccessError(format!("no area in slot {slot}")))
    }

    /// Read a location, zero-extended to 32 bits (bits read as 0 or 1).
    pub fn read(&self, loc: Location) -> Result<u32, AccessError> {
        read_in(self.area_of(loc.slot)?, loc)
    }

    /// Write a location (the value truncated to its width; bits take value & 1).
    pub fn write(&mut self, loc: Location, value: u32) -> Result<(), AccessError> {
        let area = self
            .area_mut(loc.slot)
            .ok_or_else(|| AccessError(format!("no area in slot {}", loc.slot)))?;
        write_in(area, loc, value)
    }

    /// Where a memory operand points: itself, or (USE 2) the target of the pointer it
    /// holds. Other uses have no location.
    pub fn locate(&self, op: PackedOperand) -> Result<Location, AccessError> {
        let width = op
            .width()
            .ok_or_else(|| AccessError(format!("bad width in {op:?}")))?;
        match op.use_() {
            Some(Use::Value) => Ok(Location {
                slot: op.slot(),
                offset: op.offset() as u32,
                width,
                bit: op.bit(),
            }),
            Some(Use::Pointer) => {
                let holder = Location {
                    slot: op.slot(),
                    offset: op.offset() as u32,
                    width: Width::Dword,
                    bit: 0,
                };
                let ptr = self.read(holder)?;
                Ok(Location {
                    slot: (ptr >> 24) as u8,
                    offset: ptr & 0x00FF_FFFF,
                    width,
                    bit: 0,
                })
            }
            _ => Err(AccessError(format!("{op:?} is not a memory operand"))),
        }
    }

    /// The value an operand stands for: a variable's value, or a pointer value for `&`.
    pub fn value(&self, op: PackedOperand) -> Result<u32, AccessError> {
        match op.use_() {
            Some(Use::AddressOf) => op
                .address()
                .map(|byte| Pointer::to(byte).0)
                .ok_or_else(|| AccessError(format!("{op:?} has no address"))),
            Some(Use::Value) | Some(Use::Pointer) => self.read(self.locate(op)?),
            Some(Use::Literal) | Some(Use::Label) => Ok(op.offset() as u32),
            _ => Err(AccessError(format!("{op:?} has no value"))),
        }
    }

    /// Store into an operand's location.
    pub fn store(&mut self, op: PackedOperand, value: u32) -> Result<(), AccessError> {
        let loc = self.locate(op)?;
        self.write(loc, value)
    }
}
