//! Widths and data types of GUTTA variables (IN1001), with the numbers the compiler,
//! the encoder and the VM share: WIDTH codes of the packed operand, bit counts, ranges.

use std::fmt;
use std::str::FromStr;

/// Access width of a variable. The discriminant is the WIDTH field of the packed
/// 32-bit operand (0 bit, 1 byte, 2 word, 3 dword).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Width {
    Bit = 0,
    Byte = 1,
    Word = 2,
    Dword = 3,
}

impl Width {
    pub const ALL: [Width; 4] = [Width::Bit, Width::Byte, Width::Word, Width::Dword];

    pub fn bits(self) -> u32 {
        match self {
            Width::Bit => 1,
            Width::Byte => 8,
            Width::Word => 16,
            Width::Dword => 32,
        }
    }

    /// Bytes the access covers (a bit lives in one byte).
    pub fn bytes(self) -> u32 {
        match self {
            Width::Bit | Width::Byte => 1,
            Width::Word => 2,
            Width::Dword => 4,
        }
    }

    /// The letter used in addresses (`MB`, `MW`, `MD`); bits have none.
    pub fn letter(self) -> Option<char> {
        match self {
            Width::Bit => None,
            Width::Byte => Some('B'),
            Width::Word => Some('W'),
            Width::Dword => Some('D'),
        }
    }

    pub fn from_letter(c: char) -> Option<Width> {
        match c.to_ascii_uppercase() {
            'B' => Some(Width::Byte),
            'W' => Some(Width::Word),
            'D' => Some(Width::Dword),
            _ => None,
        }
    }

    /// Name used in the XML files and in messages.
    pub fn keyword(self) -> &'static str {
        match self {
            Width::Bit => "BIT",
            Width::Byte => "BYTE",
            Width::Word => "WORD",
            Width::Dword => "DWORD",
        }
    }

    pub fn from_code(code: u8) -> Option<Width> {
        Width::ALL.get(code as usize).copied()
    }
}

impl fmt::Display for Width {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.keyword())
    }
}

impl FromStr for Width {
    type Err = ();
    fn from_str(s: &str) -> Result<Self, ()> {
        Width::ALL
            .into_iter()
            .find(|w| w.keyword().eq_ignore_ascii_case(s))
            .ok_or(())
    }
}

/// Data types of IN1001, plus REAL (32-bit IEEE 754) for the real-math instructions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum DataType {
    Bool,
    Byte,
    Word,
    Dword,
    Sint,
    Int,
    Dint,
    Usint,
    Uint,
    Udint,
    Real,
}

impl DataType {
    pub const ALL: [DataType; 11] = [
        DataType::Bool,
        DataType::Byte,
        DataType::Word,
        DataType::Dword,
        DataType::Sint,
        DataType::Int,
        DataType::Dint,
        DataType::Usint,
        DataType::Uint,
        DataType::Udint,
        DataType::Real,
    ];

    pub fn width(self) -> Width {
        match self {
            DataType::Bool => Width::Bit,
            DataType::Byte | DataType::Sint | DataType::Usint => Width::Byte,
            DataType::Word | DataType::Int | DataType::Uint => Width::Word,
            DataType::Dword | DataType::Dint | DataType::Udint | DataType::Real => Width::Dword,
        }
    }

    pub fn keyword(self) -> &'static str {
        match self {
            DataType::Bool => "BOOL",
            DataType::Byte => "BYTE",
            DataType::Word => "WORD",
            DataType::Dword => "DWORD",
            DataType::Sint => "SINT",
            DataType::Int => "INT",
            DataType::Dint => "DINT",
            DataType::Usint => "USINT",
            DataType::Uint => "UINT",
            DataType::Udint => "UDINT",
            DataType::Real => "REAL",
        }
    }

    /// Whether the type is signed two's complement.
    pub fn is_signed(self) -> bool {
        matches!(self, DataType::Sint | DataType::Int | DataType::Dint)
    }

    /// Inclusive range of integer literals the type accepts; `None` for REAL.
    ///
    /// Bit-string types (BYTE, WORD, DWORD) accept both the signed and the unsigned
    /// reading of their bits, so `MOVW -1, MW0` and `MOVW 16#FFFF, MW0` are both legal.
    pub fn integer_range(self) -> Option<(i64, i64)> {
        Some(match self {
            DataType::Bool => (0, 1),
            DataType::Byte => (-128, 255),
            DataType::Usint => (0, 255),
            DataType::Sint => (-128, 127),
            DataType::Word => (-32768, 65535),
            DataType::Uint => (0, 65535),
            DataType::Int => (-32768, 32767),
            DataType::Dword => (-2_147_483_648, 4_294_967_295),
            DataType::Udint => (0, 4_294_967_295),
            DataType::Dint => (-2_147_483_648, 2_147_483_647),
            DataType::Real => return None,
        })
    }
}

impl DataType {
    /// The untyped type of a width: BOOL, BYTE, WORD or DWORD.
    pub fn bit_string(width: Width) -> DataType {
        match width {
            Width::Bit => DataType::Bool,
            Width::Byte => DataType::Byte,
            Width::Word => DataType::Word,
            Width::Dword => DataType::Dword,
        }
    }

    /// BYTE, WORD or DWORD: raw bits without a numeric reading.
    pub fn is_bit_string(self) -> bool {
        matches!(self, DataType::Byte | DataType::Word | DataType::Dword)
    }

    /// Whether a variable declared with this type may stand where `types` are accepted.
    /// Besides the listed types, a bit string stands for any integer of its width and any
    /// integer for a bit string of its width (so `+D 4, #p` moves a DWORD pointer local);
    /// REAL never mixes with integers, nor signed with unsigned integers.
    pub fn accepted_by(self, types: &[DataType]) -> bool {
        types.contains(&self)
            || (self != DataType::Real
                && types.iter().any(|t| {
                    *t != DataType::Real
                        && t.width() == self.width()
                        && (self.is_bit_string() || t.is_bit_string())
                }))
    }

    /// The integer literals an operand accepting `types` takes: the union of their
    /// ranges (`None` when none of them is an integer type).
    pub fn union_range(types: &[DataType]) -> Option<(i64, i64)> {
        types
            .iter()
            .filter_map(|t| t.integer_range())
            .reduce(|(lo, hi), (a, b)| (lo.min(a), hi.max(b)))
    }
}

impl fmt::Display for DataType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.keyword())
    }
}

impl FromStr for DataType {
    type Err = ();
    fn from_str(s: &str) -> Result<Self, ()> {
        DataType::ALL
            .into_iter()
            .find(|t| t.keyword().eq_ignore_ascii_case(s))
            .ok_or(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bit_strings_have_the_width_they_stand_for() {
        for width in Width::ALL {
            let ty = DataType::bit_string(width);
            assert_eq!(ty.width(), width);
            assert!(ty == DataType::Bool || ty.is_bit_string());
        }
    }
}
