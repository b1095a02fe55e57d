//! Data pages as `DATA_BLOCK DATn` rows and the system page as `SYSTEM_BLOCK` keys,
//! each value spelled so the compiler writes the same bytes back.

use gutta_catalog::{plural, DataType, Width};

use super::operands::operand_name;
use super::Disassembler;
use crate::{decode_data, DataItem, Operand, PageId, SystemPage};

/// The text of a 16-byte password field: `None` for the factory password (16 x 0xFF),
/// else the characters before the zero padding, quoted; an error (byte, reason) when
/// `PASSWORD = "..."` cannot produce these bytes.
fn password_text(pw: &[u8; 16]) -> Result<Option<String>, (usize, String)> {
    if pw.iter().all(|b| *b == 0xFF) {
        return Ok(None);
    }
    let end = pw.iter().rposition(|b| *b != 0).map_or(0, |i| i + 1);
    let chars = &pw[..end];
    if chars.is_empty() {
        return Err((
            0,
            "the password is 16 zero bytes; PASSWORD takes 1..16 characters".to_string(),
        ));
    }
    if let Some(i) = chars.iter().position(|b| !(0x20..=0x7E).contains(b)) {
        return Err((
            i,
            format!(
                "password byte {i} is 0x{:02X}, not a printable ASCII character",
                chars[i]
            ),
        ));
    }
    let mut text = String::from("\"");
    for &b in chars {
        if b == b'"' || b == b'\\' {
            text.push('\\');
        }
        text.push(b as char);
    }
    text.push('"');
    Ok(Some(text))
}

impl Disassembler<'_> {
    pub(super) fn data_page(&mut self, id: PageId, bytes: &[u8]) {
        self.line(&format!("DATA_BLOCK DAT{0}:DAT{0}", id.number));
        let whole = bytes.len() - bytes.len() % 8;
        let items = bytes
            .get(..whole)
            .and_then(|b| decode_data(b).ok())
            .unwrap_or_default();
        for (i, item) in items.iter().enumerate() {
            match self.data_row(item) {
                Ok(row) => self.line(&row),
                Err((at, reason)) => {
                    self.cannot_decode("  ", &format!("item {i}"), id, 8 * i + at, &reason)
                }
            }
        }
        if whole < bytes.len() {
            let reason = format!(
                "{} after the last whole 8-byte item",
                plural::count(bytes.len() - whole, "byte")
            );
            self.cannot_decode("  ", "the end of the page", id, whole, &reason);
        }
        self.line("END_DATA_BLOCK");
    }

    /// `  MW22     WORD   6`: the type is the width's bit string; the value is the
    /// zero-extended one in unsigned decimal, or a sign-extended one as negative.
    fn data_row(&self, item: &DataItem) -> Result<String, (usize, String)> {
        let op = item.operand;
        let variable = match op.decode() {
            Ok(Operand::Value(variable)) => variable,
            Ok(other) => {
                return Err((
                    0,
                    format!(
                        "{} in a data item (must be a variable)",
                        operand_name(&other)
                    ),
                ))
            }
            Err(e) => return Err((0, e.to_string())),
        };
        let width = variable.width;
        let (address, _) = self.address(variable).map_err(|r| (0, r))?;
        let v = item.value;
        let value = match width {
            Width::Bit if v <= 1 => v.to_string(),
            Width::Bit => return Err((4, format!("initial value {v} of a bit is not 0 or 1"))),
            Width::Byte | Width::Word => {
                let bits = width.bits();
                let (low, high) = (v & ((1u32 << bits) - 1), v >> bits);
                if high == 0 {
                    low.to_string()
                } else if high == u32::MAX >> bits && low >> (bits - 1) == 1 {
                    (v as i32).to_string()
                } else {
                    return Err((
                        4,
                        format!(
                            "initial value 16#{v:08X} is neither a zero- nor a sign-extended {width}"
                        ),
                    ));
                }
            }
            Width::Dword => v.to_string(),
        };
        let at = self.target.memory.format_address(&address);
        let ty = DataType::bit_string(width).keyword();
        Ok(format!("  {at:<8} {ty:<6} {value}"))
    }

    pub(super) fn system_page(&mut self, id: PageId, bytes: &[u8]) {
        if id.number != 0 {
            self.cannot_decode(
                "",
                "the page",
                id,
                0,
                "a program has one system block, on system page 0",
            );
            return;
        }
        let page = match SystemPage::decode(bytes) {
            Ok(p) => p,
            Err(e) => {
                self.cannot_decode("", "the system block", id, e.offset, &e.reason);
                return;
            }
        };
        let ports = self.target.memory.serial_ports as usize;
        if page.ports.len() != ports {
            let reason = format!(
                "the page has {}, {} has {ports}",
                plural::count(page.ports.len(), "port"),
                self.target.name()
            );
            self.error(Some(id), 1, reason);
        }
        self.line("SYSTEM_BLOCK");
        for (p, port) in page.ports.iter().enumerate() {
            let at = 2 + 8 * p;
            let protocol = match port.protocol {
                0 => Ok("MODBUS".to_string()),
                k => Err(format!("protocol code {k} is not 0 (Modbus RTU)")),
            };
            let parity = match crate::Parity::from_code(port.parity) {
                Some(p) => Ok(p.name().to_uppercase()),
                None => Err(format!("parity code {} is not 0..2", port.parity)),
            };
            let keys = [
                ("PROTOCOL", at, protocol),
                ("ADDRESS", at + 1, Ok(port.address.to_string())),
                ("BAUD", at + 2, Ok(port.baud.to_string())),
                ("DATA_BITS", at + 3, Ok(port.data_bits.to_string())),
                ("PARITY", at + 4, parity),
                ("STOP_BITS", at + 5, Ok(port.stop_bits.to_string())),
                ("TIMEOUT", at + 6, Ok(port.timeout.to_string())),
                ("FRAME_GAP", at + 7, Ok(port.frame_gap.to_string())),
            ];
            for (key, offset, value) in keys {
                let key = format!("PORT{p}.{key}");
                match value {
                    Ok(v) => self.line(&format!("  {key:<15} = {v}")),
                    Err(reason) => self.cannot_decode("  ", &key, id, offset, &reason),
                }
            }
        }
        let at = 2 + 8 * page.ports.len();
        match password_text(&page.password) {
            Ok(None) => {}
            Ok(Some(text)) => self.line(&format!("  {:<15} = {text}", "PASSWORD")),
            Err((i, reason)) => self.cannot_decode("  ", "PASSWORD", id, at + i, &reason),
        }
        self.line("END_SYSTEM_BLOCK");
    }
}
