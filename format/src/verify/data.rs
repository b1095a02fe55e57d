//! Data pages (items in initialisable areas, values that fit their width) and the
//! system page (layout, port count, port settings in the ranges of docs/language.md
//! section 11, password). System bytes are checked raw, before decoding, so each bad
//! setting gets its own typed error and offset.

use std::collections::{BTreeMap, BTreeSet};

use gutta_catalog::rules::{self, port, DataRules};
use gutta_catalog::{Target, Width};

use super::error::{Location, VerifyError};
use super::operand::{malformed, OperandChecker, Site};
use super::program::kind_range;
use crate::{
    decode_data, DataItem, Image, PageId, PageKind, SystemPage, BAUD_RATES, SYSTEM_LAYOUT_VERSION,
};

/// Decode and check every data page.
pub(super) fn verify_data_pages(
    image: &Image,
    target: &Target,
) -> Result<BTreeMap<u8, Vec<DataItem>>, VerifyError> {
    let no_units = BTreeSet::new();
    let checker = OperandChecker {
        target,
        unit_pages: &no_units,
    };
    let max = u64::from(target.plc.data_block_page_item_size);
    let mut pages = BTreeMap::new();
    for (id, bytes) in image.pages.range(kind_range(PageKind::Data)) {
        let items = decode_data(bytes).map_err(|error| VerifyError::Decode { page: *id, error })?;
        if items.len() as u64 > max {
            return Err(VerifyError::SizeLimit {
                page: Some(*id),
                what: "data items",
                size: items.len() as u64,
                limit: "DataBlockPageItemSize".to_string(),
                max,
            });
        }
        for (i, item) in items.iter().enumerate() {
            let at = Location {
                page: *id,
                offset: 8 * i,
            };
            let site = Site::DataItem { index: i };
            let op = item.operand;
            // The item's width is its word's; `check_data` then wants a value (USE 0).
            let Ok(variable) = op.variable() else {
                return Err(malformed(at, site, op, "WIDTH is 0..3"));
            };
            let width = variable.width;
            checker.check_data(at, site, op, DataRules::data_item(width))?;
            if !fits(item.value, width) {
                return Err(VerifyError::DataValue {
                    at: Location {
                        page: *id,
                        offset: 8 * i + 4,
                    },
                    item: i,
                    value: item.value,
                    width,
                });
            }
        }
        pages.insert(id.number, items);
    }
    Ok(pages)
}

/// Whether a 32-bit value is a `width` value zero- or sign-extended (BOOL: 0 or 1).
fn fits(value: u32, width: Width) -> bool {
    match width {
        Width::Bit => value <= 1,
        Width::Dword => true,
        Width::Byte | Width::Word => {
            let bits = width.bits();
            let upper = value >> bits;
            let negative = (value >> (bits - 1)) & 1 == 1;
            upper == 0 || (negative && upper == u32::MAX >> bits)
        }
    }
}

/// Check and decode system page 0, if the image has one.
pub(super) fn verify_system_page(
    image: &Image,
    target: &Target,
) -> Result<Option<SystemPage>, VerifyError> {
    let id = PageId::new(PageKind::System, 0);
    let Some(b) = image.page(PageKind::System, 0) else {
        return Ok(None);
    };
    let max = u64::from(target.plc.system_block_binary_size);
    if b.len() as u64 > max {
        return Err(VerifyError::SizeLimit {
            page: Some(id),
            what: "bytes",
            size: b.len() as u64,
            limit: "SystemBlockBinarySize".to_string(),
            max,
        });
    }
    let at = |offset| Location { page: id, offset };
    if let Some(&version) = b.first() {
        if version != SYSTEM_LAYOUT_VERSION {
            return Err(VerifyError::SystemVersion {
                at: at(0),
                found: version,
            });
        }
    }
    let expected = target.memory.serial_ports;
    if let Some(&ports) = b.get(1) {
        if ports != expected {
            return Err(VerifyError::SystemPortCount {
                at: at(1),
                found: ports,
                expected,
            });
        }
    }
    let ports = usize::from(expected);
    if b.len() == 18 + 8 * ports {
        for p in 0..ports {
            check_port(b, p, id)?;
        }
        check_password(b.get(2 + 8 * ports..).unwrap_or(&[]), at(2 + 8 * ports))?;
    }
    SystemPage::decode(b)
        .map(Some)
        .map_err(|error| VerifyError::Decode { page: id, error })
}

/// (byte in the port entry, field name, test, allowed values in words).
type PortRule = (usize, &'static str, fn(u8) -> bool, &'static str);

/// The settings of port `p`, raw (the page has the right length).
fn check_port(b: &[u8], p: usize, id: PageId) -> Result<(), VerifyError> {
    let rules: [PortRule; 7] = [
        (0, "protocol", |v| v == 0, "0 (Modbus RTU)"),
        (
            2,
            "baud code",
            |v| usize::from(v) < BAUD_RATES.len(),
            "0..4",
        ),
        (3, "data bits", |v| v == port::DATA_BITS, "8"),
        (4, "parity", |v| v <= 2, "0..2"),
        (5, "stop bits", |v| port::STOP_BITS.contains(&v), "1 or 2"),
        (6, "timeout", |v| port::TIMEOUT.contains(&v), "1..255"),
        (7, "frame gap", |v| port::FRAME_GAP.contains(&v), "1..255"),
    ];
    for (field_offset, field, ok, allowed) in rules {
        let offset = 2 + 8 * p + field_offset;
        let Some(&value) = b.get(offset) else {
            continue;
        };
        if !ok(value) {
            return Err(VerifyError::SystemValue {
                at: Location { page: id, offset },
                port: p,
                field,
                value,
                allowed,
            });
        }
    }
    Ok(())
}

/// 16 x 0xFF, or 1..16 ASCII characters (not NUL) padded with zeros.
fn check_password(password: &[u8], at: Location) -> Result<(), VerifyError> {
    if password.iter().all(|&b| b == 0xFF) {
        return Ok(());
    }
    // The characters, then zeros.
    let text = password.iter().take_while(|&&b| b != 0).count();
    let (chars, padding) = password.split_at(text);
    if rules::password_allowed(chars) && padding.iter().all(|&b| b == 0) {
        Ok(())
    } else {
        Err(VerifyError::SystemPassword { at })
    }
}
