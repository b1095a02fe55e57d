//! Values of the run corpus's header: numbers (`16#0E01`, `-5`), texts (`"1A2f"`),
//! `VAR = VALUE` assignments, and their resolution against a target into addresses and
//! unsigned bits. It knows no header keys and never runs a VM.

use gutta_catalog::{Address, Target, Width};

/// A value as written: a number, or a text for consecutive bytes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Value {
    Number(i64),
    /// ASCII bytes from the named byte variable on (`MB40 = "  12,345"`).
    Text(Vec<u8>),
}

/// `VAR = VALUE` from a `set`, `expect` or `force` line.
#[derive(Debug, Clone)]
pub struct Assignment {
    pub line: usize,
    pub var: String,
    pub value: Value,
}

/// What an assignment stands for on one target.
#[derive(Debug, Clone)]
pub enum Bits {
    /// The value as the variable's unsigned bits.
    Word(u32),
    /// One byte per address, from the variable's byte on.
    Bytes(Vec<(Address, u8)>),
}

/// An assignment whose variable exists on the program's target.
#[derive(Debug, Clone)]
pub struct Resolved {
    pub var: String,
    pub address: Address,
    pub bits: Bits,
}

/// A number as the harness reads it: decimal, `16#..`, `2#..`, optional sign, `_` allowed.
pub fn parse_number(text: &str) -> Result<i64, String> {
    let (negative, rest) = match text.strip_prefix('-') {
        Some(r) => (true, r),
        None => (false, text.strip_prefix('+').unwrap_or(text)),
    };
    let (radix, digits) = if let Some(d) = rest.strip_prefix("16#") {
        (16, d)
    } else if let Some(d) = rest.strip_prefix("2#") {
        (2, d)
    } else {
        (10, rest)
    };
    let digits: String = digits.chars().filter(|&c| c != '_').collect();
    if digits.is_empty() || !digits.chars().all(|c| c.is_digit(radix)) {
        return Err(format!(
            "`{text}` is not a number (decimal, 16#FF, 2#1010, signed)"
        ));
    }
    let magnitude =
        i64::from_str_radix(&digits, radix).map_err(|_| format!("`{text}` is too large"))?;
    Ok(if negative { -magnitude } else { magnitude })
}

/// A number, or a text in double quotes (printable ASCII, no `"` inside).
pub fn parse_value(text: &str) -> Result<Value, String> {
    let Some(inner) = text.strip_prefix('"') else {
        return parse_number(text).map(Value::Number);
    };
    let inner = inner
        .strip_suffix('"')
        .ok_or_else(|| format!("`{text}`: a text ends with `\"`"))?;
    if inner.is_empty() || inner.contains('"') || !inner.bytes().all(|b| (0x20..0x7F).contains(&b))
    {
        return Err(format!(
            "`{text}`: a text is one or more printable ASCII characters without `\"`"
        ));
    }
    Ok(Value::Text(inner.as_bytes().to_vec()))
}

/// One variable name: no spaces, not empty.
pub fn parse_variable(text: &str) -> Result<String, String> {
    let var = text.trim();
    if var.is_empty() || var.contains(char::is_whitespace) {
        return Err(format!("`{text}` is not one variable"));
    }
    Ok(var.to_string())
}

/// `VAR = VALUE`; spaces around `=` optional.
pub fn parse_assignment(line: usize, text: &str) -> Result<Assignment, String> {
    let (var, value) = text
        .split_once('=')
        .ok_or_else(|| format!("`{text}` is not VAR = VALUE"))?;
    let var =
        parse_variable(var).map_err(|_| format!("`{text}`: no single variable before `=`"))?;
    Ok(Assignment {
        line,
        var,
        value: parse_value(value.trim())?,
    })
}

/// The address of `var` on `target`.
pub fn address(target: &Target, line: usize, var: &str) -> Result<Address, String> {
    target
        .memory
        .parse_address(var)
        .map_err(|e| format!("line {line}: `{var}` is no variable here: {e:?}"))
}

/// The variable's address on `target` and the value as its unsigned bits (or bytes);
/// a number that fits neither the signed nor the unsigned reading of the width, or a
/// text on a variable that is not a byte, is an error.
pub fn resolve(target: &Target, a: &Assignment) -> Result<Resolved, String> {
    let address = address(target, a.line, &a.var)?;
    let bits = match &a.value {
        Value::Number(value) => Bits::Word(fit(*value, address.width).ok_or_else(|| {
            format!(
                "line {}: {value} does not fit {} ({} bits)",
                a.line,
                a.var,
                address.width.bits()
            )
        })?),
        Value::Text(bytes) if address.width == Width::Byte => Bits::Bytes(
            (0u32..)
                .zip(bytes)
                .map(|(k, &b)| {
                    let at = Address {
                        offset: address.offset + k,
                        ..address
                    };
                    (at, b)
                })
                .collect(),
        ),
        Value::Text(_) => {
            return Err(format!(
                "line {}: a text needs a byte variable (`MB40`), not `{}`",
                a.line, a.var
            ))
        }
    };
    Ok(Resolved {
        var: a.var.clone(),
        address,
        bits,
    })
}

/// `value` as the unsigned bits of `width`, if it fits the signed or unsigned reading.
fn fit(value: i64, width: Width) -> Option<u32> {
    let bits = width.bits();
    let (low, high) = if bits == 1 {
        (0, 1)
    } else {
        (-(1i64 << (bits - 1)), (1i64 << bits) - 1)
    };
    if !(low..=high).contains(&value) {
        return None;
    }
    let mask = if bits == 32 {
        u32::MAX
    } else {
        (1u32 << bits) - 1
    };
    Some((value as u32) & mask)
}

/// `123 (16#7B)`, with the hex digits of the width.
pub fn show(value: u32, width: Width) -> String {
    match width {
        Width::Bit => value.to_string(),
        _ => format!(
            "{value} (16#{value:0digits$X})",
            digits = width.bytes() as usize * 2
        ),
    }
}

/// Bytes as a quoted text, non-printable bytes escaped.
pub fn show_text(bytes: &[u8]) -> String {
    let text: String = bytes.iter().map(|&b| char::from(b)).collect();
    format!("{text:?}")
}
