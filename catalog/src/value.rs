//! How a variable's value is shown and read back on the command line, in watch tables
//! and in the debugger: BOOL, signed or unsigned decimal, hexadecimal or REAL. A
//! symbol's declared type decides the format ([`ValueFormat::for_type`]); without one
//! the address width does ([`ValueFormat::default_for`]: words and double words are
//! signed, as Micro/WIN's status chart shows them); a `:suffix` after a variable
//! (`MW2:int`, `MD4:hex`, `MD8:real`) overrides both ([`ValueFormat::from_suffix`]).
//! Parsing and printing values in a format live here too, so every tool agrees.

use std::fmt;

use crate::{DataType, Width};

/// How a value is printed and parsed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ValueFormat {
    /// 0 or 1 (a bit); also accepts TRUE/FALSE, ON/OFF when parsing.
    Bool,
    /// Two's complement decimal of the address width (-1 for 16#FFFF in a word).
    Signed,
    /// Unsigned decimal.
    Unsigned,
    /// `16#` hexadecimal, zero-padded to the width.
    Hex,
    /// IEEE 754 single precision (double words only).
    Real,
}

impl ValueFormat {
    pub const ALL: [ValueFormat; 5] = [
        ValueFormat::Bool,
        ValueFormat::Signed,
        ValueFormat::Unsigned,
        ValueFormat::Hex,
        ValueFormat::Real,
    ];

    /// The format a declared type shows in: BOOL; SINT, INT, DINT signed; REAL; the
    /// others (BYTE, WORD, DWORD, USINT, UINT, UDINT) unsigned.
    pub fn for_type(t: DataType) -> ValueFormat {
        match t {
            DataType::Bool => ValueFormat::Bool,
            DataType::Real => ValueFormat::Real,
            t if t.is_signed() => ValueFormat::Signed,
            _ => ValueFormat::Unsigned,
        }
    }

    /// The format of an address without a declared type: bits BOOL, bytes unsigned,
    /// words and double words signed.
    pub fn default_for(width: Width) -> ValueFormat {
        match width {
            Width::Bit => ValueFormat::Bool,
            Width::Byte => ValueFormat::Unsigned,
            Width::Word | Width::Dword => ValueFormat::Signed,
        }
    }

    /// The name used as a suffix and in JSON: `bool`, `int`, `uint`, `hex`, `real`.
    pub fn name(self) -> &'static str {
        match self {
            ValueFormat::Bool => "bool",
            ValueFormat::Signed => "int",
            ValueFormat::Unsigned => "uint",
            ValueFormat::Hex => "hex",
            ValueFormat::Real => "real",
        }
    }

    /// A `:suffix` (case-insensitive): the names above, `signed`/`unsigned`, or a data
    /// type keyword (`INT`, `DWORD`, `REAL`...), which stands for its format.
    pub fn from_suffix(text: &str) -> Option<ValueFormat> {
        let lower = text.trim().to_ascii_lowercase();
        if let Some(f) = ValueFormat::ALL.iter().find(|f| f.name() == lower) {
            return Some(*f);
        }
        match lower.as_str() {
            "signed" => return Some(ValueFormat::Signed),
            "unsigned" => return Some(ValueFormat::Unsigned),
            _ => {}
        }
        DataType::ALL
            .iter()
            .find(|t| t.keyword().eq_ignore_ascii_case(&lower))
            .map(|t| ValueFormat::for_type(*t))
    }

    /// Whether values of this format fit a variable of `width`: BOOL only bits, REAL
    /// only double words, the others any width but bits.
    pub fn fits(self, width: Width) -> bool {
        match self {
            ValueFormat::Bool => width == Width::Bit,
            ValueFormat::Real => width == Width::Dword,
            _ => width != Width::Bit,
        }
    }
}

impl fmt::Display for ValueFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suffixes_and_type_names_name_formats() {
        assert_eq!(ValueFormat::from_suffix("int"), Some(ValueFormat::Signed));
        assert_eq!(ValueFormat::from_suffix("HEX"), Some(ValueFormat::Hex));
        assert_eq!(ValueFormat::from_suffix("real"), Some(ValueFormat::Real));
        assert_eq!(ValueFormat::from_suffix("DINT"), Some(ValueFormat::Signed));
        assert_eq!(
            ValueFormat::from_suffix("word"),
            Some(ValueFormat::Unsigned)
        );
        assert_eq!(ValueFormat::from_suffix("bool"), Some(ValueFormat::Bool));
        assert_eq!(ValueFormat::from_suffix("flt"), None);
        for f in ValueFormat::ALL {
            assert_eq!(ValueFormat::from_suffix(f.name()), Some(f));
        }
    }

    #[test]
    fn defaults_follow_the_width() {
        assert_eq!(ValueFormat::default_for(Width::Bit), ValueFormat::Bool);
        assert_eq!(ValueFormat::default_for(Width::Byte), ValueFormat::Unsigned);
        assert_eq!(ValueFormat::default_for(Width::Word), ValueFormat::Signed);
        assert_eq!(ValueFormat::default_for(Width::Dword), ValueFormat::Signed);
        assert!(ValueFormat::Real.fits(Width::Dword));
        assert!(!ValueFormat::Real.fits(Width::Word));
        assert!(!ValueFormat::Hex.fits(Width::Bit));
    }
}
