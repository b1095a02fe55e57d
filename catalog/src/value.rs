//! How a variable's value is shown and read back on the command line, in watch tables
//! and in the debugger: BOOL, signed or unsigned decimal, hexadecimal or REAL. A
//! symbol's declared type decides the format ([`ValueFormat::for_type`]); without one
//! the address width does ([`ValueFormat::default_for`]: words and double words are
//! signed, as Micro/WIN's status chart shows them); a `:suffix` after a variable
//! (`MW2:int`, `MD4:hex`, `MD8:real`) overrides both ([`ValueFormat::from_suffix`]).
//! Parsing and printing values in a format live here too, so every tool agrees.

use std::fmt;

use crate::address::parse_value;
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

    /// `text` as the raw bits of a variable of `width` in this format.
    ///
    /// Every format takes raw bits as `16#..` or `2#..`. BOOL takes 0/1, TRUE/FALSE and
    /// ON/OFF; the integer formats a decimal that fits the width either signed or
    /// unsigned (`-1` into a word is 16#FFFF); REAL (double words only) a decimal or
    /// exponent (`-3.5`, `1e3`, `inf`, `nan`). Errors name the range.
    pub fn parse(self, text: &str, width: Width) -> Result<u32, String> {
        let text = text.trim();
        if !self.fits(width) {
            return Err(self.misfit(width));
        }
        let raw_bits = text.starts_with("16#") || text.starts_with("2#");
        match self {
            ValueFormat::Bool => match text.to_ascii_uppercase().as_str() {
                "TRUE" | "ON" => Ok(1),
                "FALSE" | "OFF" => Ok(0),
                _ => parse_value(text, width)
                    .map_err(|e| format!("{e}; a BOOL is 0, 1, TRUE, FALSE, ON or OFF")),
            },
            ValueFormat::Real if raw_bits => parse_value(text, width),
            ValueFormat::Real => parse_real(text),
            ValueFormat::Signed | ValueFormat::Unsigned | ValueFormat::Hex => {
                parse_value(text, width).map_err(|e| {
                    if text.parse::<i64>().is_err() && text.parse::<f64>().is_ok() {
                        format!(
                            "`{text}` is not an integer (a REAL needs a double word and `:real`)"
                        )
                    } else {
                        e
                    }
                })
            }
        }
    }

    /// The raw bits of a variable of `width` as text in this format: `1`, `-1`,
    /// `65535`, `16#FFFF`, `21.5` (REAL: the shortest text that reads back to the same
    /// value; `nan`, `inf`, `-inf`). A format that does not fit the width shows the
    /// width's default format.
    pub fn show(self, raw: u32, width: Width) -> String {
        let format = if self.fits(width) {
            self
        } else {
            ValueFormat::default_for(width)
        };
        let bits = width.bits();
        let raw = if bits == 32 {
            raw
        } else {
            raw & ((1u32 << bits) - 1)
        };
        match format {
            ValueFormat::Bool | ValueFormat::Unsigned => raw.to_string(),
            ValueFormat::Signed => {
                let shift = 32 - bits;
                (((raw << shift) as i32) >> shift).to_string()
            }
            ValueFormat::Hex => format!("16#{raw:0digits$X}", digits = width.bytes() as usize * 2),
            ValueFormat::Real => show_real(f32::from_bits(raw)),
        }
    }

    /// Why this format cannot be used on a variable of `width`.
    pub fn misfit(self, width: Width) -> String {
        let needs = match self {
            ValueFormat::Bool => "a bit (I0.0, Q0.0, M0.0)",
            ValueFormat::Real => "a double word (MD, VD...)",
            _ => "a byte, word or double word",
        };
        format!(
            "a `{}` value needs {needs}, not a {}",
            self.name(),
            width_name(width)
        )
    }
}

fn width_name(width: Width) -> &'static str {
    match width {
        Width::Bit => "bit",
        Width::Byte => "byte",
        Width::Word => "word",
        Width::Dword => "double word",
    }
}

/// A REAL from decimal or exponent text; a finite text beyond REAL's range is an error.
fn parse_real(text: &str) -> Result<u32, String> {
    let value: f32 = text.parse().map_err(|_| {
        format!("`{text}` is not a REAL (e.g. 21.5, -3.5, 1e3, or raw bits 16#41AC0000)")
    })?;
    let spelled_infinite = text.to_ascii_lowercase().contains("inf");
    if value.is_infinite() && !spelled_infinite {
        return Err(format!(
            "{text} does not fit a REAL (-3.4028235e38..3.4028235e38)"
        ));
    }
    Ok(value.to_bits())
}

/// The shortest text that reads back to `value`: plain decimals between 1e-5 and 1e7,
/// exponents outside; a whole number keeps `.0` so it reads as a REAL.
fn show_real(value: f32) -> String {
    if value.is_nan() {
        return "nan".into();
    }
    if value.is_infinite() {
        return if value > 0.0 { "inf" } else { "-inf" }.into();
    }
    let magnitude = value.abs();
    if magnitude != 0.0 && !(1e-5..1e7).contains(&magnitude) {
        return format!("{value:e}");
    }
    let text = value.to_string();
    if text.contains('.') {
        text
    } else {
        text + ".0"
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

    #[test]
    fn values_parse_and_show_in_their_formats() {
        use ValueFormat::*;
        assert_eq!(Signed.show(0xFFFF, Width::Word), "-1");
        assert_eq!(Unsigned.show(0xFFFF, Width::Word), "65535");
        assert_eq!(Hex.show(0xFF, Width::Word), "16#00FF");
        assert_eq!(Signed.show(4_294_897_296, Width::Dword), "-70000");
        assert_eq!(Real.show(21.5f32.to_bits(), Width::Dword), "21.5");
        assert_eq!(Real.show(1.0f32.to_bits(), Width::Dword), "1.0");
        assert_eq!(Real.show(1e30f32.to_bits(), Width::Dword), "1e30");
        assert_eq!(Real.show(f32::NAN.to_bits(), Width::Dword), "nan");
        assert_eq!(Real.show(f32::NEG_INFINITY.to_bits(), Width::Dword), "-inf");
        assert_eq!(Bool.show(1, Width::Bit), "1");
        assert_eq!(Signed.parse("-1", Width::Word), Ok(0xFFFF));
        assert_eq!(Unsigned.parse("-1", Width::Word), Ok(0xFFFF));
        assert_eq!(Signed.parse("-70000", Width::Dword), Ok(4_294_897_296));
        assert_eq!(Real.parse("21.5", Width::Dword), Ok(21.5f32.to_bits()));
        assert_eq!(Real.parse("1e3", Width::Dword), Ok(1000f32.to_bits()));
        assert_eq!(Real.parse("16#41AC0000", Width::Dword), Ok(0x41AC_0000));
        assert_eq!(Bool.parse("on", Width::Bit), Ok(1));
        assert_eq!(Bool.parse("FALSE", Width::Bit), Ok(0));
        let range = Signed.parse("65536", Width::Word).unwrap_err();
        assert!(range.contains("-32768..65535"), "{range}");
        let real = Signed.parse("21.5", Width::Dword).unwrap_err();
        assert!(real.contains(":real"), "{real}");
        assert!(Real.parse("1e39", Width::Dword).is_err());
        let misfit = Real.parse("1.5", Width::Word).unwrap_err();
        assert!(misfit.contains("double word"), "{misfit}");
        assert!(Bool.parse("2", Width::Bit).is_err());
    }

    fn width() -> impl proptest::strategy::Strategy<Value = Width> {
        proptest::sample::select(vec![Width::Bit, Width::Byte, Width::Word, Width::Dword])
    }

    proptest::proptest! {
        #[test]
        fn every_value_reads_back_in_every_format_that_fits(raw: u32, w in width()) {
            let raw = if w.bits() == 32 { raw } else { raw & ((1 << w.bits()) - 1) };
            for f in ValueFormat::ALL.into_iter().filter(|f| f.fits(w)) {
                let text = f.show(raw, w);
                let back = f.parse(&text, w);
                if f == ValueFormat::Real && f32::from_bits(raw).is_nan() {
                    proptest::prop_assert!(back.is_ok_and(|b| f32::from_bits(b).is_nan()));
                } else {
                    proptest::prop_assert_eq!(back, Ok(raw), "{} as {}", text, f);
                }
            }
        }
    }
}
