//! Small helpers shared by the three description-file parsers: serde from XML text
//! with file-named errors, and integer attributes with ranges (decimal or 0x hex).

use serde::de::DeserializeOwned;

use crate::{CatalogError, CatalogErrorCode};

pub(crate) fn from_xml<T: DeserializeOwned>(text: &str, file: &str) -> Result<T, CatalogError> {
    quick_xml::de::from_str(text).map_err(|e| {
        CatalogError::new(
            CatalogErrorCode::Syntax,
            file,
            format!("malformed description: {e}"),
        )
    })
}

/// Parse an integer attribute (decimal, or hex with `0x`) and check its range.
pub(crate) fn attr_int(
    file: &str,
    attr: &str,
    value: &str,
    min: i64,
    max: i64,
) -> Result<i64, CatalogError> {
    let v = value.trim();
    let parsed = if let Some(hex) = v.strip_prefix("0x").or_else(|| v.strip_prefix("0X")) {
        i64::from_str_radix(hex, 16).ok()
    } else {
        v.parse::<i64>().ok()
    };
    match parsed {
        Some(n) if (min..=max).contains(&n) => Ok(n),
        Some(n) => Err(CatalogError::new(
            CatalogErrorCode::Value,
            file,
            format!("`{attr}` = {n} is outside {min}..={max}"),
        )),
        None => Err(CatalogError::new(
            CatalogErrorCode::Value,
            file,
            format!("`{attr}` must be an integer, not `{value}`"),
        )),
    }
}

pub(crate) fn attr_bool(
    file: &str,
    attr: &str,
    value: Option<&str>,
    default: bool,
) -> Result<bool, CatalogError> {
    match value.map(str::trim) {
        None => Ok(default),
        Some(v) if v.eq_ignore_ascii_case("true") || v == "1" => Ok(true),
        Some(v) if v.eq_ignore_ascii_case("false") || v == "0" => Ok(false),
        Some(v) => Err(CatalogError::new(
            CatalogErrorCode::Value,
            file,
            format!("`{attr}` must be true or false, not `{v}`"),
        )),
    }
}
