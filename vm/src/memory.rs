//! PLC memory: one little-endian byte array per area (slot) at its ManagerVar.xml size,
//! widths overlapping (MB0 and MW0 share a byte). Locations come from packed operands;
//! pointer values (`&`) are SLOT << 24 | byte offset. Every access is bounds-checked.

use gutta_catalog::{MemoryMap, Width};
use gutta_format::{pointer_value, PackedOperand, Use};

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
    areas: Vec<Vec<u8>>,
}

/// An access outside an area, or to a slot that does not exist.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AccessError(pub String);

impl Memory {
    pub fn new(map: &MemoryMap) -> Memory {
        let slots = map
            .areas
            .iter()
            .map(|a| a.slot as usize + 1)
            .max()
            .unwrap_or(0);
        let mut areas = vec![Vec::new(); slots];
        for a in &map.areas {
            areas[a.slot as usize] = vec![0; a.size as usize];
        }
        Memory { areas }
    }

    /// A memory holding one area's bytes (for terminal images).
    pub(crate) fn from_area(slot: u8, bytes: Vec<u8>) -> Memory {
        let mut areas = vec![Vec::new(); slot as usize + 1];
        areas[slot as usize] = bytes;
        Memory { areas }
    }

    /// Take the area's bytes back.
    pub(crate) fn into_area(mut self, slot: u8) -> Vec<u8> {
        self.areas
            .get_mut(slot as usize)
            .map(std::mem::take)
            .unwrap_or_default()
    }

    pub fn area(&self, slot: u8) -> Option<&[u8]> {
        self.areas.get(slot as usize).map(Vec::as_slice)
    }

    pub fn area_mut(&mut self, slot: u8) -> Option<&mut Vec<u8>> {
        self.areas.get_mut(slot as usize)
    }

    fn bytes(&self, loc: Location) -> Result<&[u8], AccessError> {
        let area = self
            .areas
            .get(loc.slot as usize)
            .ok_or_else(|| AccessError(format!("no area in slot {}", loc.slot)))?;
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

    /// Read a location, zero-extended to 32 bits (bits read as 0 or 1).
    pub fn read(&self, loc: Location) -> Result<u32, AccessError> {
        let b = self.bytes(loc)?;
        Ok(match loc.width {
            Width::Bit => ((b[0] >> (loc.bit & 7)) & 1) as u32,
            Width::Byte => b[0] as u32,
            Width::Word => u16::from_le_bytes([b[0], b[1]]) as u32,
            Width::Dword => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        })
    }

    /// Write a location (the value truncated to its width; bits take value & 1).
    pub fn write(&mut self, loc: Location, value: u32) -> Result<(), AccessError> {
        self.bytes(loc)?;
        let area = &mut self.areas[loc.slot as usize];
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
            Some(Use::AddressOf) => Ok(pointer_value(op.slot(), op.offset() as u32)),
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
