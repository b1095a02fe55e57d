//! Direct addresses (`I0.0`, `MW20`, `AIW0`, `T5`, `HC1`) parsed and printed against a
//! target's memory map. The syntax is data-driven: area names, widths and offset
//! units all come from ManagerVar.xml.

use std::fmt;

use crate::{MemoryMap, Width};

/// A resolved direct address: area slot, access width, byte offset, bit in byte.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Address {
    pub slot: u8,
    pub width: Width,
    /// Offset in bytes from the start of the area (`T5` is 10, `MW20` is 20).
    pub offset: u32,
    /// Bit in the byte, 0..7; 0 unless `width` is `Bit`.
    pub bit: u8,
}

/// Why a text is not a valid address on the target.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum AddressError {
    /// Not of address shape at all (letters, digits, optional `.bit`).
    NotAnAddress,
    /// Address-shaped, but no area of the target has this prefix.
    UnknownArea { prefix: String },
    /// The area has one width only and its addresses take no width letter (`T5`, not `TW5`).
    LetterNotAllowed { area: String, example: String },
    /// A multi-width area needs a width letter or a bit (`MB3`, `M3.0`).
    MissingWidth { area: String },
    /// The area does not allow this width (`AI0.0`, `JW0`).
    WidthNotAllowed {
        area: String,
        width: Width,
        allowed: Vec<Width>,
    },
    /// A bit number above 7.
    BitOutOfRange { bit: u32 },
    /// The access does not fit in the area (`MB200` on CPU-EC20).
    OutOfRange {
        area: String,
        offset: u64,
        width: Width,
        size: u32,
        last: String,
    },
}

impl fmt::Display for AddressError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            AddressError::NotAnAddress => write!(f, "not an address"),
            AddressError::UnknownArea { prefix } => write!(f, "no memory area `{prefix}`"),
            AddressError::LetterNotAllowed { area, example } => {
                write!(
                    f,
                    "area {area} has one width and takes no width letter (write `{example}`)"
                )
            }
            AddressError::MissingWidth { area } => {
                write!(
                    f,
                    "area {area} needs a width letter (B, W, D) or a bit number"
                )
            }
            AddressError::WidthNotAllowed {
                area,
                width,
                allowed,
            } => {
                let list: Vec<&str> = allowed.iter().map(|w| w.keyword()).collect();
                write!(
                    f,
                    "area {area} has no {width} access (allowed: {})",
                    list.join(", ")
                )
            }
            AddressError::BitOutOfRange { bit } => write!(f, "bit number {bit} is not 0..7"),
            AddressError::OutOfRange {
                area, size, last, ..
            } => {
                write!(
                    f,
                    "outside area {area}, which has {size} bytes (last: {last})"
                )
            }
        }
    }
}

/// The pieces of an address-shaped word: `AIW` `0` `.3`.
struct Shape<'a> {
    letters: &'a str,
    number: &'a str,
    bit: Option<&'a str>,
}

fn shape(text: &str) -> Option<Shape<'_>> {
    let split = text.find(|c: char| !c.is_ascii_alphabetic())?;
    let (letters, rest) = text.split_at(split);
    if letters.is_empty() {
        return None;
    }
    let (number, bit) = match rest.split_once('.') {
        Some((n, b)) => (n, Some(b)),
        None => (rest, None),
    };
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    if !digits(number) || bit.is_some_and(|b| !digits(b)) {
        return None;
    }
    Some(Shape {
        letters,
        number,
        bit,
    })
}

/// Whether `text` has the shape of an address (`[A-Z]+[0-9]+(.[0-9]+)?`), whatever the target.
pub fn is_address_shaped(text: &str) -> bool {
    shape(text).is_some()
}

fn parse_num(s: &str) -> u64 {
    // Saturate: anything this large is out of range anyway.
    s.bytes().fold(0u64, |n, d| {
        n.saturating_mul(10).saturating_add((d - b'0') as u64)
    })
}

impl MemoryMap {
    /// Parse a direct address for this target.
    pub fn parse_address(&self, text: &str) -> Result<Address, AddressError> {
        let s = shape(text).ok_or(AddressError::NotAnAddress)?;
        let letters = s.letters;
        // Longest area name first: `SMB0` is SM + B, `AIW0` is AI + W.
        let mut best: Option<(&crate::Area, Option<Width>)> = None;
        for area in &self.areas {
            let n = area.name.len();
            if letters.len() < n || !letters[..n].eq_ignore_ascii_case(&area.name) {
                continue;
            }
            let rest = &letters[n..];
            let letter = match rest.len() {
                0 => None,
                1 => match Width::from_letter(rest.chars().next().unwrap_or(' ')) {
                    Some(w) => Some(w),
                    None => continue,
                },
                _ => continue,
            };
            if best.is_none_or(|(b, _)| b.name.len() < n) {
                best = Some((area, letter));
            }
        }
        let Some((area, letter)) = best else {
            let prefix = letters.trim_end_matches(['B', 'W', 'D', 'b', 'w', 'd']);
            let prefix = if prefix.is_empty() { letters } else { prefix };
            return Err(AddressError::UnknownArea {
                prefix: letters_to_area_guess(letters, prefix),
            });
        };
        let number = parse_num(s.number);
        let (width, offset) = match (area.fixed_width(), letter, s.bit) {
            (Some(w), None, None) => (w, number.saturating_mul(area.unit.bytes() as u64)),
            (Some(_), Some(_), _) => {
                return Err(AddressError::LetterNotAllowed {
                    area: area.name.clone(),
                    example: format!("{}{}", area.name, s.number),
                })
            }
            (_, None, Some(_)) => (Width::Bit, number),
            (_, Some(w), None) => (w, number),
            (_, Some(_), Some(_)) => return Err(AddressError::NotAnAddress),
            (None, None, None) => {
                return Err(AddressError::MissingWidth {
                    area: area.name.clone(),
                })
            }
        };
        if !area.allows(width) {
            return Err(AddressError::WidthNotAllowed {
                area: area.name.clone(),
                width,
                allowed: area.widths.iter().copied().collect(),
            });
        }
        let bit = match s.bit {
            Some(b) => {
                let b = parse_num(b);
                if b > 7 {
                    return Err(AddressError::BitOutOfRange {
                        bit: b.min(u32::MAX as u64) as u32,
                    });
                }
                b as u8
            }
            None => 0,
        };
        // Saturating: a huge number saturates `offset` (parse_num) and must stay out of range.
        if offset.saturating_add(width.bytes() as u64) > area.size as u64 {
            let last = self.format_address(&Address {
                slot: area.slot,
                width,
                offset: area.size.saturating_sub(width.bytes()),
                bit: if width == Width::Bit { 7 } else { 0 },
            });
            return Err(AddressError::OutOfRange {
                area: area.name.clone(),
                offset,
                width,
                size: area.size,
                last,
            });
        }
        Ok(Address {
            slot: area.slot,
            width,
            offset: offset as u32,
            bit,
        })
    }

    /// Print an address in its canonical form (`MW20`, `I0.4`, `T5`).
    pub fn format_address(&self, a: &Address) -> String {
        let Some(area) = self.area_by_slot(a.slot) else {
            return format!("?{}:{}", a.slot, a.offset);
        };
        match (a.width, area.fixed_width()) {
            (Width::Bit, _) => format!("{}{}.{}", area.name, a.offset, a.bit),
            (w, Some(fw)) if w == fw => format!("{}{}", area.name, a.offset / area.unit.bytes()),
            (w, _) => format!("{}{}{}", area.name, w.letter().unwrap_or('?'), a.offset),
        }
    }
}

/// For an unknown prefix such as `VB`, guess the area name the user meant (`V`).
fn letters_to_area_guess(letters: &str, stripped: &str) -> String {
    if letters.len() > 1 && stripped.len() < letters.len() {
        stripped.to_ascii_uppercase()
    } else {
        letters.to_ascii_uppercase()
    }
}

/// `100`, `-1`, `16#FF`, `2#1010` (`-16#1` too), checked against the width and
/// returned as the variable's bits.
pub fn parse_value(text: &str, width: Width) -> Result<u32, String> {
    let (negative, digits) = match text.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, text.strip_prefix('+').unwrap_or(text)),
    };
    let (radix, digits) = if let Some(d) = digits.strip_prefix("16#") {
        (16, d)
    } else if let Some(d) = digits.strip_prefix("2#") {
        (2, d)
    } else {
        (10, digits)
    };
    let digits = digits.replace('_', "");
    let bad = || format!("`{text}` is not a number (decimal, 16#FF, 2#1010)");
    if digits.is_empty() || digits.starts_with(['+', '-']) {
        return Err(bad());
    }
    let magnitude = i64::from_str_radix(&digits, radix).map_err(|_| bad())?;
    let value = if negative { -magnitude } else { magnitude };
    let bits = width.bits();
    let (min, max) = if width == Width::Bit {
        (0, 1)
    } else {
        (-(1i64 << (bits - 1)), (1i64 << bits) - 1)
    };
    if value < min || value > max {
        return Err(format!(
            "{text} does not fit a {bits}-bit variable ({min}..{max})"
        ));
    }
    let mask = if bits == 32 {
        u32::MAX as i64
    } else {
        (1i64 << bits) - 1
    };
    Ok((value & mask) as u32)
}

#[cfg(test)]
mod value_tests {
    use super::*;

    #[test]
    fn values() {
        assert_eq!(parse_value("1", Width::Bit), Ok(1));
        assert!(parse_value("2", Width::Bit).is_err());
        assert_eq!(parse_value("-1", Width::Word), Ok(0xFFFF));
        assert_eq!(parse_value("16#0E01", Width::Word), Ok(0x0E01));
        assert_eq!(parse_value("2#1010", Width::Byte), Ok(10));
        assert_eq!(parse_value("-2147483648", Width::Dword), Ok(0x8000_0000));
        assert_eq!(parse_value("16#FFFFFFFF", Width::Dword), Ok(u32::MAX));
        assert!(parse_value("65536", Width::Word).is_err());
        assert!(parse_value("--1", Width::Word).is_err());
        assert!(parse_value("x", Width::Word).is_err());
    }
}
