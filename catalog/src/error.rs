//! Coded errors for malformed target description files. Never panics on bad input.

use std::fmt;

/// Stable codes of target-description errors (documented in docs/diagnostics.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum CatalogErrorCode {
    /// T0001: the bytes are not valid UTF-8 or UTF-16 text.
    Encoding,
    /// T0002: the XML is malformed or does not have the schema's shape.
    Syntax,
    /// T0003: a value is out of its allowed range or malformed.
    Value,
    /// T0004: two entries collide (slot, area name, mnemonic, opcode, ...).
    Duplicate,
    /// T0005: the files disagree with each other (names, areas an instruction refers to).
    Mismatch,
    /// T0006: a target folder or stdlib target could not be found or read.
    NotFound,
}

impl CatalogErrorCode {
    /// Every code, in number order.
    pub const ALL: &'static [CatalogErrorCode] = &[
        CatalogErrorCode::Encoding,
        CatalogErrorCode::Syntax,
        CatalogErrorCode::Value,
        CatalogErrorCode::Duplicate,
        CatalogErrorCode::Mismatch,
        CatalogErrorCode::NotFound,
    ];

    /// What the code means, in one line: docs/diagnostics.md's "T codes" table is
    /// generated from it.
    pub fn summary(self) -> &'static str {
        match self {
            CatalogErrorCode::Encoding => "the file is not valid UTF-8 or UTF-16 text",
            CatalogErrorCode::Syntax => {
                "the XML is malformed or lacks a required element or attribute"
            }
            CatalogErrorCode::Value => "a value is out of range or malformed",
            CatalogErrorCode::Duplicate => {
                "two entries collide (slot, area, mnemonic, opcode, Modbus object)"
            }
            CatalogErrorCode::Mismatch => {
                "the files disagree (PLC type names, areas an instruction names)"
            }
            CatalogErrorCode::NotFound => {
                "a target folder, file or stdlib PLC type cannot be found"
            }
        }
    }

    pub fn as_str(self) -> &'static str {
        match self {
            CatalogErrorCode::Encoding => "T0001",
            CatalogErrorCode::Syntax => "T0002",
            CatalogErrorCode::Value => "T0003",
            CatalogErrorCode::Duplicate => "T0004",
            CatalogErrorCode::Mismatch => "T0005",
            CatalogErrorCode::NotFound => "T0006",
        }
    }
}

/// An error in a target description file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CatalogError {
    pub code: CatalogErrorCode,
    /// Which file (`PlcType.xml`, `ManagerVar.xml`, `ManagerFun.xml`, or a folder).
    pub file: String,
    pub message: String,
}

impl CatalogError {
    pub fn new(
        code: CatalogErrorCode,
        file: impl Into<String>,
        message: impl Into<String>,
    ) -> Self {
        CatalogError {
            code,
            file: file.into(),
            message: message.into(),
        }
    }
}

impl fmt::Display for CatalogError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "[{}] {}: {}",
            self.code.as_str(),
            self.file,
            self.message
        )
    }
}

impl std::error::Error for CatalogError {}

#[cfg(test)]
mod tests {
    use super::CatalogErrorCode;

    #[test]
    fn all_lists_the_codes_in_number_order_each_with_a_summary() {
        for (i, code) in CatalogErrorCode::ALL.iter().enumerate() {
            assert_eq!(code.as_str(), format!("T{:04}", i + 1));
            assert!(!code.summary().is_empty());
        }
    }
}
