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
