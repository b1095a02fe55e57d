//! `PlcType.xml`: the overall limits of a PLC type (UM4001 section "PlcType.xml").

use serde::Deserialize;

use crate::text::decode_xml_text;
use crate::xml_util::{attr_int, from_xml};
use crate::{CatalogError, CatalogErrorCode};

const FILE: &str = "PlcType.xml";

/// The overall description of a PLC type, every attribute of the vendor's file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlcType {
    /// The PLC type's identity, 1..16 characters.
    pub name: String,
    pub information: String,
    pub system_block_dll: String,
    pub communication_dll: String,
    /// Maximum system block bytes.
    pub system_block_binary_size: u32,
    /// Maximum number of data pages.
    pub data_block_page_size: u32,
    /// Maximum items (8 bytes each) per data page.
    pub data_block_page_item_size: u32,
    /// Maximum interrupt routines, MAIN (INT0) included.
    pub program_block_page_int_size: u32,
    /// Maximum subroutines.
    pub program_block_page_sbr_size: u32,
    /// Maximum arguments of an interrupt routine.
    pub program_block_page_arg_int_size: u32,
    /// Maximum arguments of a subroutine.
    pub program_block_page_arg_sbr_size: u32,
    /// Maximum const (K) bytes.
    pub program_block_const_binary_size: u32,
    /// Maximum instruction bytes.
    pub program_block_instruction_binary_size: u32,
    /// Maximum payload bytes of one protocol packet, 64..1024 (exclusive).
    pub exch_pack_size: u32,
    pub exch_support: ExchSupport,
}

/// Which protocol function codes the PLC supports: `M1|V1|...|Mn|Vn` in hex; a
/// function F is supported iff `F & Mi == Vi` for some i (`0000|0000` = all).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExchSupport {
    pub rules: Vec<(u16, u16)>,
}

impl ExchSupport {
    pub fn parse(text: &str) -> Option<ExchSupport> {
        let parts: Vec<&str> = text.split('|').map(str::trim).collect();
        if parts.is_empty() || !parts.len().is_multiple_of(2) {
            return None;
        }
        let mut rules = Vec::with_capacity(parts.len() / 2);
        for pair in parts.chunks_exact(2) {
            let mask = u16::from_str_radix(pair[0], 16).ok()?;
            let value = u16::from_str_radix(pair[1], 16).ok()?;
            rules.push((mask, value));
        }
        Some(ExchSupport { rules })
    }

    pub fn supports(&self, function: u16) -> bool {
        self.rules
            .iter()
            .any(|&(mask, value)| function & mask == value)
    }
}

#[derive(Deserialize)]
struct Raw {
    #[serde(rename = "@Name")]
    name: Option<String>,
    #[serde(rename = "@Information")]
    information: Option<String>,
    #[serde(rename = "@SystemBlockDll")]
    system_block_dll: Option<String>,
    #[serde(rename = "@CommunicationDll")]
    communication_dll: Option<String>,
    #[serde(rename = "@SystemBlockBinarySize")]
    system_block_binary_size: Option<String>,
    #[serde(rename = "@DataBlockPageSize")]
    data_block_page_size: Option<String>,
    #[serde(rename = "@DataBlockPageItemSize")]
    data_block_page_item_size: Option<String>,
    #[serde(rename = "@ProgramBlockPageIntSize")]
    program_block_page_int_size: Option<String>,
    #[serde(rename = "@ProgramBlockPageSbrSize")]
    program_block_page_sbr_size: Option<String>,
    #[serde(rename = "@ProgramBlockPageArgIntSize")]
    program_block_page_arg_int_size: Option<String>,
    #[serde(rename = "@ProgramBlockPageArgSbrSize")]
    program_block_page_arg_sbr_size: Option<String>,
    #[serde(rename = "@ProgramBlockConstBinarySize")]
    program_block_const_binary_size: Option<String>,
    #[serde(rename = "@ProgramBlockInstructionBinarySize")]
    program_block_instruction_binary_size: Option<String>,
    #[serde(rename = "@ExchPackSize")]
    exch_pack_size: Option<String>,
    #[serde(rename = "@ExchSupport")]
    exch_support: Option<String>,
}

fn required(value: Option<String>, attr: &str) -> Result<String, CatalogError> {
    value.ok_or_else(|| {
        CatalogError::new(
            CatalogErrorCode::Syntax,
            FILE,
            format!("<PlcType> lacks attribute `{attr}`"),
        )
    })
}

fn text_attr(value: Option<String>, attr: &str, max: usize) -> Result<String, CatalogError> {
    let value = required(value, attr)?;
    let chars = value.chars().count();
    if chars == 0 || chars > max {
        return Err(CatalogError::new(
            CatalogErrorCode::Value,
            FILE,
            format!("`{attr}` must be 1..{max} characters, `{value}` has {chars}"),
        ));
    }
    Ok(value)
}

fn int_attr(value: Option<String>, attr: &str, min: u32, max: u32) -> Result<u32, CatalogError> {
    let value = required(value, attr)?;
    attr_int(FILE, attr, &value, min as i64, max as i64).map(|v| v as u32)
}

impl PlcType {
    pub fn parse(bytes: &[u8]) -> Result<PlcType, CatalogError> {
        let text = decode_xml_text(bytes, FILE)?;
        let raw: Raw = from_xml(&text, FILE)?;
        let exch_text = required(raw.exch_support, "ExchSupport")?;
        let exch_support = ExchSupport::parse(&exch_text).ok_or_else(|| {
            CatalogError::new(
                CatalogErrorCode::Value,
                FILE,
                format!("`ExchSupport` must be pairs of hex words `M1|V1|...`, not `{exch_text}`"),
            )
        })?;
        const BIG: u32 = 16 * 1024 * 1024;
        let plc = PlcType {
            name: text_attr(raw.name, "Name", 16)?,
            information: text_attr(raw.information, "Information", 64)?,
            system_block_dll: text_attr(raw.system_block_dll, "SystemBlockDll", 260)?,
            communication_dll: text_attr(raw.communication_dll, "CommunicationDll", 260)?,
            system_block_binary_size: int_attr(
                raw.system_block_binary_size,
                "SystemBlockBinarySize",
                0,
                BIG,
            )?,
            data_block_page_size: int_attr(raw.data_block_page_size, "DataBlockPageSize", 0, 16)?,
            data_block_page_item_size: int_attr(
                raw.data_block_page_item_size,
                "DataBlockPageItemSize",
                0,
                BIG,
            )?,
            program_block_page_int_size: int_attr(
                raw.program_block_page_int_size,
                "ProgramBlockPageIntSize",
                1,
                256,
            )?,
            program_block_page_sbr_size: int_attr(
                raw.program_block_page_sbr_size,
                "ProgramBlockPageSbrSize",
                0,
                256,
            )?,
            program_block_page_arg_int_size: int_attr(
                raw.program_block_page_arg_int_size,
                "ProgramBlockPageArgIntSize",
                0,
                BIG,
            )?,
            program_block_page_arg_sbr_size: int_attr(
                raw.program_block_page_arg_sbr_size,
                "ProgramBlockPageArgSbrSize",
                0,
                BIG,
            )?,
            program_block_const_binary_size: int_attr(
                raw.program_block_const_binary_size,
                "ProgramBlockConstBinarySize",
                0,
                BIG,
            )?,
            program_block_instruction_binary_size: int_attr(
                raw.program_block_instruction_binary_size,
                "ProgramBlockInstructionBinarySize",
                0,
                u32::MAX,
            )?,
            exch_pack_size: int_attr(raw.exch_pack_size, "ExchPackSize", 64, 1023)?,
            exch_support,
        };
        // Program pages are numbered INTn -> n, SBRn -> IntSize + n (docs/image-format.md).
        let units = plc.program_block_page_int_size + plc.program_block_page_sbr_size;
        if units > 256 {
            return Err(CatalogError::new(
                CatalogErrorCode::Value,
                FILE,
                format!("ProgramBlockPageIntSize + ProgramBlockPageSbrSize = {units}; program pages allow 256"),
            ));
        }
        Ok(plc)
    }

    /// Bytes a data block may hold: pages x items x 8.
    pub fn data_block_bytes(&self) -> u32 {
        self.data_block_page_size * self.data_block_page_item_size * 8
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exch_support_all_and_masks() {
        let all = ExchSupport::parse("0000|0000").unwrap();
        assert!(all.supports(0x0A10));
        let some = ExchSupport::parse("FF00|0100|FF00|0A00").unwrap();
        assert!(some.supports(0x0110));
        assert!(some.supports(0x0A31));
        assert!(!some.supports(0x0310));
        assert!(ExchSupport::parse("0000").is_none());
        assert!(ExchSupport::parse("00G0|0000").is_none());
    }
}
