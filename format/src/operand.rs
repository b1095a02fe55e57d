//! The packed 32-bit operand: OFFSET<<16 | BIT_OFFSET<<12 | WIDTH<<8 | SLOT<<4 | USE.

use std::fmt;

use gutta_catalog::{Address, Width};

/// How an operand is used (the USE field).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Use {
    /// The variable's value (constants are variables in K).
    Value = 0,
    /// `&MB24`: the pointer value of that byte.
    AddressOf = 1,
    /// `*MD4`: the variable the pointer in MD4 points to.
    Pointer = 2,
    /// A label number (OFFSET).
    Label = 3,
    /// A program unit: SLOT 0 interrupt, 1 subroutine; OFFSET its number.
    Unit = 4,
    /// A literal number (OFFSET).
    Literal = 5,
}

impl Use {
    pub fn from_code(code: u8) -> Option<Use> {
        Some(match code {
            0 => Use::Value,
            1 => Use::AddressOf,
            2 => Use::Pointer,
            3 => Use::Label,
            4 => Use::Unit,
            5 => Use::Literal,
            _ => return None,
        })
    }
}

/// One packed operand, as stored (little-endian) in pages.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct PackedOperand(pub u32);

impl PackedOperand {
    /// A memory operand.
    pub fn memory(address: Address, use_: Use, width: Width) -> PackedOperand {
        let bit = if width == Width::Bit {
            address.bit as u32 & 7
        } else {
            0
        };
        PackedOperand(
            ((address.offset & 0xFFFF) << 16)
                | (bit << 12)
                | ((width as u32) << 8)
                | ((address.slot as u32 & 0xF) << 4)
                | use_ as u32,
        )
    }

    /// A label, unit or literal operand.
    pub fn special(use_: Use, slot: u8, value: u16) -> PackedOperand {
        PackedOperand(((value as u32) << 16) | ((slot as u32 & 0xF) << 4) | use_ as u32)
    }

    pub fn offset(self) -> u16 {
        (self.0 >> 16) as u16
    }

    pub fn bit(self) -> u8 {
        ((self.0 >> 12) & 0xF) as u8
    }

    pub fn width_code(self) -> u8 {
        ((self.0 >> 8) & 0xF) as u8
    }

    pub fn width(self) -> Option<Width> {
        Width::from_code(self.width_code())
    }

    pub fn slot(self) -> u8 {
        ((self.0 >> 4) & 0xF) as u8
    }

    pub fn use_code(self) -> u8 {
        (self.0 & 0xF) as u8
    }

    pub fn use_(self) -> Option<Use> {
        Use::from_code(self.use_code())
    }

    /// The address this operand names (memory uses only; for `Pointer`, where the pointer is).
    pub fn address(self) -> Option<Address> {
        let width = match self.use_()? {
            Use::Value => self.width()?,
            Use::AddressOf => gutta_catalog::Width::Byte,
            Use::Pointer => Width::Dword,
            _ => return None,
        };
        Some(Address {
            slot: self.slot(),
            width,
            offset: self.offset() as u32,
            bit: if width == Width::Bit { self.bit() } else { 0 },
        })
    }

    pub fn to_le_bytes(self) -> [u8; 4] {
        self.0.to_le_bytes()
    }

    pub fn from_le_bytes(b: [u8; 4]) -> PackedOperand {
        PackedOperand(u32::from_le_bytes(b))
    }
}

impl fmt::Debug for PackedOperand {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "PackedOperand(0x{:08X}: use {} slot {} width {} bit {} offset {})",
            self.0,
            self.use_code(),
            self.slot(),
            self.width_code(),
            self.bit(),
            self.offset()
        )
    }
}

/// The pointer value `&` produces for a byte: SLOT in bits 31..24, byte offset below.
pub fn pointer_value(slot: u8, offset: u32) -> u32 {
    ((slot as u32) << 24) | (offset & 0x00FF_FFFF)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn documented_examples() {
        let mw20 = Address {
            slot: 4,
            width: Width::Word,
            offset: 20,
            bit: 0,
        };
        assert_eq!(
            PackedOperand::memory(mw20, Use::Value, Width::Word).0,
            0x0014_0240
        );
        assert_eq!(
            PackedOperand::memory(mw20, Use::Value, Width::Word).to_le_bytes(),
            [0x40, 0x02, 0x14, 0x00]
        );
        let m03 = Address {
            slot: 4,
            width: Width::Bit,
            offset: 0,
            bit: 3,
        };
        assert_eq!(
            PackedOperand::memory(m03, Use::Value, Width::Bit).0,
            0x0000_3040
        );
        let md4 = Address {
            slot: 4,
            width: Width::Dword,
            offset: 4,
            bit: 0,
        };
        assert_eq!(
            PackedOperand::memory(md4, Use::Pointer, Width::Word).0,
            0x0004_0242
        );
        let mb24 = Address {
            slot: 4,
            width: Width::Byte,
            offset: 24,
            bit: 0,
        };
        assert_eq!(
            PackedOperand::memory(mb24, Use::AddressOf, Width::Dword).0,
            0x0018_0341
        );
        assert_eq!(pointer_value(4, 24), 0x0400_0018);
    }
}
