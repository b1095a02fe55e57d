//! Numeric literals: `6`, `1_000`, `16#0E01`, `2#1010`, `8#17`, `1.5`, `2.0e-3`, with an
//! optional sign. Conversion errors name what is wrong (E0104).

/// A converted literal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Number {
    Integer(i64),
    Real(f64),
}

/// Why a literal is malformed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum NumberError {
    /// The base is not 2, 8, 10 or 16.
    Base(String),
    /// A digit the base does not have, or no digits.
    Digit { base: u32, text: String },
    /// More than 64 bits.
    TooLarge,
}

impl std::fmt::Display for NumberError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            NumberError::Base(b) => write!(f, "base {b} is not supported (use 2#, 8#, 10# or 16#)"),
            NumberError::Digit { base, text } if text.is_empty() => {
                write!(f, "no digits after {base}#")
            }
            NumberError::Digit { base, text } => write!(f, "`{text}` is not a base-{base} number"),
            NumberError::TooLarge => write!(f, "number does not fit in 64 bits"),
        }
    }
}

fn digits(text: &str, base: u32) -> Result<i64, NumberError> {
    let clean: String = text.chars().filter(|c| *c != '_').collect();
    if clean.is_empty() || !clean.chars().all(|c| c.is_digit(base)) {
        return Err(NumberError::Digit {
            base,
            text: text.to_string(),
        });
    }
    // Accept up to 64 bits unsigned (16#FFFF_FFFF_FFFF_FFFF reads as -1).
    u64::from_str_radix(&clean, base)
        .map(|v| v as i64)
        .map_err(|_| NumberError::TooLarge)
}

/// Convert the text of an `Int`, `Based` or `Real` token, negated if `negative`.
pub fn convert(text: &str, negative: bool) -> Result<Number, NumberError> {
    if let Some((base, rest)) = text.split_once('#') {
        let base: u32 = match base {
            "2" => 2,
            "8" => 8,
            "10" => 10,
            "16" => 16,
            other => return Err(NumberError::Base(other.to_string())),
        };
        let v = digits(rest, base)?;
        return Ok(Number::Integer(if negative { v.wrapping_neg() } else { v }));
    }
    if text.contains(['.', 'e', 'E']) {
        let clean: String = text.chars().filter(|c| *c != '_').collect();
        let v: f64 = clean.parse().map_err(|_| NumberError::Digit {
            base: 10,
            text: text.to_string(),
        })?;
        return Ok(Number::Real(if negative { -v } else { v }));
    }
    let v = digits(text, 10)?;
    if v < 0 {
        return Err(NumberError::TooLarge);
    }
    Ok(Number::Integer(if negative { -v } else { v }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn literals() {
        assert_eq!(convert("16#0E01", false), Ok(Number::Integer(0x0E01)));
        assert_eq!(convert("2#1010", true), Ok(Number::Integer(-10)));
        assert_eq!(convert("1_000", false), Ok(Number::Integer(1000)));
        assert_eq!(convert("1.5", false), Ok(Number::Real(1.5)));
        assert!(matches!(
            convert("2#102", false),
            Err(NumberError::Digit { base: 2, .. })
        ));
        assert!(matches!(convert("3#1", false), Err(NumberError::Base(_))));
        assert!(matches!(
            convert("16#", false),
            Err(NumberError::Digit { .. })
        ));
        assert_eq!(
            convert("99999999999999999999", false),
            Err(NumberError::TooLarge)
        );
    }
}
