//! Micro/WIN data block exports (`DATA_BLOCK_TAB` files; docs/microwin.md, "Data block
//! exports") as GUTTA data blocks: each value of a row at the next address (a byte per
//! character), of the address's width, checked as a `DATA_BLOCK` row is (its area, its
//! range, overlaps with every other row); the values of one export fill data blocks of
//! `DataBlockPageItemSize` rows in order, numbered with the next free DATn. Knows no
//! text syntax: the rows come parsed (`syntax/data_block_tab.rs`).

use std::collections::BTreeMap;

use gutta_catalog::{Address, DataType, Width};

use super::data::Initialised;
use super::{CheckedDataBlock, Checker, ConstValue, DataItem, DefKind};
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
use crate::syntax::ast::{DataBlockTab, TabRow, TabValueKind};

impl Checker<'_> {
    /// The data blocks of one export: its values in rows of the target's data blocks,
    /// each block with the next number `used` leaves free.
    pub(super) fn data_block_tab(
        &mut self,
        tab: &DataBlockTab,
        used: &mut BTreeMap<u32, Span>,
        initialised: &mut Initialised,
    ) -> Vec<CheckedDataBlock> {
        let mut items = Vec::new();
        for row in &tab.rows {
            self.tab_row(row, initialised, &mut items);
        }
        let plc = &self.target.plc;
        let (per_block, blocks) = (
            plc.data_block_page_item_size.max(1) as usize,
            plc.data_block_page_size,
        );
        let plc_name = plc.name.clone();
        let span = tab.name.unwrap_or(tab.header);
        let written = tab.name.map(|s| self.slice(s).to_string());
        let count = items.len();
        let mut out = Vec::new();
        for (k, chunk) in items.chunks(per_block).enumerate() {
            let number = (0..).find(|n| !used.contains_key(n)).unwrap_or(0);
            used.insert(number, span);
            if number >= blocks {
                self.report(
                    Diagnostic::new(
                        Code::BlockNumberRange,
                        span,
                        format!("this data block export needs DAT{number}, out of range: {plc_name} allows {blocks} data blocks, DAT0..DAT{} (DataBlockPageSize)", blocks.saturating_sub(1)),
                    )
                    .label(format!("{count} values, at most {per_block} in each data block (DataBlockPageItemSize)"))
                    .help("the values of an export fill the data blocks the program leaves free; set fewer values, or initialise memory in the program"),
                );
                break;
            }
            let name = match (&written, k) {
                (Some(n), 0) => n.clone(),
                (Some(n), _) => format!("{n}_{}", k + 1),
                (None, _) => format!("DAT{number}"),
            };
            let def = self.define(
                name.clone(),
                DefKind::DataBlock,
                span,
                format!(
                    "DAT{number} {name}: {} values of a Micro/WIN data block export",
                    chunk.len()
                ),
                None,
            );
            self.data_names.insert(name.to_ascii_uppercase(), def);
            out.push(CheckedDataBlock {
                number,
                name,
                items: chunk.to_vec(),
            });
        }
        out
    }

    /// A row's values as data items at consecutive addresses from its own; a value
    /// that does not fit, or lies outside the area or on memory another row sets, is
    /// reported and ends the row.
    fn tab_row(&mut self, row: &TabRow, initialised: &mut Initialised, items: &mut Vec<DataItem>) {
        let Some(address) = self.direct_address(row.address, Some("a data block row")) else {
            return;
        };
        let written = self.slice(row.address);
        if address.width == Width::Bit {
            self.report(
                Diagnostic::new(
                    Code::S7200DataBlock,
                    row.address,
                    format!("`{written}` is a bit: the rows of a data block are bytes, words and double words"),
                )
                .help(format!("set the bit's byte instead, e.g. `VB{} 16#01`", address.offset)),
            );
            return;
        }
        let Some(area) = self.target.memory.area_by_slot(address.slot).cloned() else {
            return;
        };
        if !self.initialisable(row.address, &area, "a Micro/WIN data block sets V memory") {
            return;
        }
        let width = address.width;
        let mut cursor = address.offset;
        for value in &row.values {
            let cells: Vec<(DataType, ConstValue)> = match &value.kind {
                TabValueKind::Integer(v) => {
                    let ty = DataType::bit_string(width);
                    let (lo, hi) = ty.integer_range().unwrap_or((i64::MIN, i64::MAX));
                    if !(lo..=hi).contains(v) {
                        self.report(
                            Diagnostic::new(Code::DataValueRange, value.span, format!("{v} does not fit {}", width_name(width)))
                                .label(format!("`{written}` holds {lo}..{hi}"))
                                .help("each value of a row is as wide as its address: VB a byte, VW a word, VD a double word"),
                        );
                        return;
                    }
                    vec![(ty, ConstValue::Integer(*v))]
                }
                TabValueKind::Real(v) => {
                    if width != Width::Dword {
                        self.report(
                            Diagnostic::new(
                                Code::DataValueRange,
                                value.span,
                                format!("a REAL does not fit {}", width_name(width)),
                            )
                            .help("a REAL is a double word: write its row as VD"),
                        );
                        return;
                    }
                    vec![(DataType::Real, ConstValue::Real(*v as f32))]
                }
                TabValueKind::Chars(bytes) | TabValueKind::String(bytes) => {
                    if width != Width::Byte {
                        self.report(
                            Diagnostic::new(
                                Code::DataValueRange,
                                value.span,
                                format!(
                                    "quoted characters do not fit {}: each is a byte",
                                    width_name(width)
                                ),
                            )
                            .help("write the row of characters as VB"),
                        );
                        return;
                    }
                    let length =
                        matches!(value.kind, TabValueKind::String(_)).then_some(bytes.len() as u8);
                    length
                        .into_iter()
                        .chain(bytes.iter().copied())
                        .map(|b| (DataType::Byte, ConstValue::Integer(i64::from(b))))
                        .collect()
                }
            };
            for (ty, constant) in cells {
                let at = Address {
                    offset: cursor,
                    ..address
                };
                let text = self.target.memory.format_address(&at);
                if let Err(e) = self.target.memory.parse_address(&text) {
                    self.address_error(value.span, &text, e, None);
                    return;
                }
                let item = DataItem {
                    address: at,
                    ty,
                    value: constant,
                    span: value.span,
                };
                if !self.no_overlap(value.span, &item, initialised) {
                    return;
                }
                items.push(item);
                cursor += width.bytes();
            }
        }
    }
}

/// "a byte", "a word", "a double word".
fn width_name(width: Width) -> &'static str {
    match width {
        Width::Bit => "a bit",
        Width::Byte => "a byte",
        Width::Word => "a word",
        Width::Dword => "a double word",
    }
}
