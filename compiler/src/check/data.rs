//! Data blocks: numbering (DATn), rows against their address and type, the areas a
//! data block may initialise, overlaps, and the PlcType page limits.

use std::collections::BTreeMap;

use gutta_catalog::{rules, DataType, Width};

use super::{CheckedDataBlock, Checker, ConstValue, DataItem, DefKind};
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
use crate::syntax::ast::{self, BlockPrefix, OperandKind};

/// Memory the data rows initialise: (slot, byte, bit) -> the row that sets it.
pub(super) type Initialised = BTreeMap<(u8, u32, u8), Span>;

impl Checker<'_> {
    /// Whether a data block may initialise `area` (E0503 at `at`, with
    /// `help`, when it may not): a DATA_BLOCK row or a Micro/WIN data block export's.
    pub(super) fn initialisable(
        &mut self,
        at: Span,
        area: &gutta_catalog::Area,
        help: &str,
    ) -> bool {
        if rules::INITIALISABLE.contains(&area.kind) {
            return true;
        }
        self.report(
            Diagnostic::new(
                Code::DataArea,
                at,
                format!("data blocks cannot initialise area {}", area.name),
            )
            .label(format!(
                "{} is {}",
                area.name,
                area.description.to_lowercase()
            ))
            .help(help.to_string()),
        );
        false
    }

    pub(super) fn data_blocks(&mut self) -> Vec<CheckedDataBlock> {
        let ast = self.ast;
        let numbers = self.data_block_numbers();
        let mut used: BTreeMap<u32, Span> = BTreeMap::new();
        let mut initialised = Initialised::new();
        let mut out = Vec::new();
        for (d, number) in ast.data_blocks.iter().zip(numbers) {
            out.push(self.data_block(d, number, &mut used, &mut initialised));
        }
        // Micro/WIN data block exports take the numbers left free (data_block_tab.rs).
        for tab in &ast.data_block_tabs {
            out.extend(self.data_block_tab(tab, &mut used, &mut initialised));
        }
        out.sort_by_key(|d| d.number);
        out
    }

    /// Every data block's number: `DATn` as written, else the next free one from 0.
    fn data_block_numbers(&mut self) -> Vec<u32> {
        let ast = self.ast;
        let mut numbers = Vec::new();
        for d in &ast.data_blocks {
            let n = match d.header.number {
                Some((b, _)) if b.prefix == BlockPrefix::Dat => Some(b.number),
                Some((b, span)) => {
                    self.report(
                        Diagnostic::new(
                            Code::BadBlockHeader,
                            span,
                            format!(
                                "`{}{}` does not fit a data block",
                                b.prefix.as_str(),
                                b.number
                            ),
                        )
                        .help("data blocks are numbered DAT0, DAT1, ..."),
                    );
                    None
                }
                None => None,
            };
            numbers.push(n);
        }
        for i in 0..numbers.len() {
            if numbers[i].is_none() {
                numbers[i] = (0..).find(|n| !numbers.contains(&Some(*n)));
            }
        }
        numbers.into_iter().map(|n| n.unwrap_or(0)).collect()
    }

    /// One data block: its number (unique, in range), definition and rows.
    fn data_block(
        &mut self,
        d: &ast::DataBlock,
        number: u32,
        used: &mut BTreeMap<u32, Span>,
        initialised: &mut Initialised,
    ) -> CheckedDataBlock {
        let plc = &self.target.plc;
        let name_text = self.slice(d.header.name);
        let name = if name_text.is_empty() {
            format!("DAT{number}")
        } else {
            name_text.to_string()
        };
        let span = if d.header.name.is_empty() {
            d.header.span
        } else {
            d.header.name
        };
        if let Some(&first) = used.get(&number) {
            self.report(
                Diagnostic::new(
                    Code::DuplicateBlock,
                    span,
                    format!("DAT{number} is defined twice"),
                )
                .with_secondary(first, "first defined here"),
            );
        }
        used.insert(number, span);
        if number >= plc.data_block_page_size {
            self.report(Diagnostic::new(Code::BlockNumberRange, span, format!("DAT{number} is out of range: {} allows {} data blocks, DAT0..DAT{} (DataBlockPageSize)", plc.name, plc.data_block_page_size, plc.data_block_page_size.saturating_sub(1))));
        }
        let def = self.define(
            name.clone(),
            DefKind::DataBlock,
            span,
            format!("DAT{number} {name}: {} rows", d.rows.len()),
            None,
        );
        self.data_names.insert(name.to_ascii_uppercase(), def);
        let mut items = Vec::new();
        for (k, row) in d.rows.iter().enumerate() {
            if k as u32 == plc.data_block_page_item_size {
                self.report(
                    Diagnostic::new(
                        Code::DataBlockTooLarge,
                        row.span,
                        format!(
                            "a data block holds at most {} rows on {} (DataBlockPageItemSize)",
                            plc.data_block_page_item_size, plc.name
                        ),
                    )
                    .label("first row too many"),
                );
            }
            if let Some(item) = self.data_row(row) {
                if self.no_overlap(row.address, &item, initialised) {
                    items.push(item);
                }
            }
        }
        CheckedDataBlock {
            number,
            name,
            items,
        }
    }

    /// The item (of the row whose address is at `at`) sets no bit another row already
    /// sets; marks its bits.
    pub(super) fn no_overlap(
        &mut self,
        at: Span,
        item: &DataItem,
        initialised: &mut Initialised,
    ) -> bool {
        let a = item.address;
        let cells: Vec<(u8, u32, u8)> = if a.width == Width::Bit {
            vec![(a.slot, a.offset, a.bit)]
        } else {
            (0..a.width.bytes())
                .flat_map(|b| (0..8).map(move |bit| (a.slot, a.offset + b, bit)))
                .collect()
        };
        if let Some(prev) = cells.iter().find_map(|c| initialised.get(c)).copied() {
            self.report(
                Diagnostic::new(
                    Code::DataOverlap,
                    at,
                    "this row initialises memory another row already sets",
                )
                .with_secondary(prev, "first set here"),
            );
            return false;
        }
        for c in cells {
            initialised.insert(c, item.span);
        }
        true
    }

    fn data_row(&mut self, row: &ast::DataRow) -> Option<DataItem> {
        // A row names its variable by address or by symbol.
        let key = self.slice(row.address).to_ascii_uppercase();
        let address = match self.symbols.get(&key) {
            Some(&(address, def)) => {
                self.reference(row.address, def);
                address
            }
            None => self.direct_address(row.address, Some("a data row"))?,
        };
        let area = self.target.memory.area_by_slot(address.slot)?.clone();
        if !self.initialisable(
            row.address,
            &area,
            "data blocks initialise M, V, Q, AQ, T and C",
        ) {
            return None;
        }
        let ty = match row.ty {
            Some(t) => {
                let text = self.slice(t);
                match text.parse::<DataType>() {
                    Ok(ty) => ty,
                    Err(()) => {
                        self.report(Diagnostic::new(
                            Code::UnknownDataType,
                            t,
                            format!("unknown data type `{text}`"),
                        ));
                        return None;
                    }
                }
            }
            None => DataType::bit_string(address.width),
        };
        if ty.width() != address.width {
            self.report(
                Diagnostic::new(Code::DataTypeWidth, row.ty.unwrap_or(row.address), format!("{ty} has {} bits; `{}` has {}", ty.width().bits(), self.slice(row.address), address.width.bits()))
                    .help("the type must match the address width: B with BYTE/USINT/SINT, W with WORD/INT/UINT, D with DWORD/DINT/UDINT/REAL"),
            );
            return None;
        }
        let value = self.data_value(row, ty)?;
        Some(DataItem {
            address,
            ty,
            value,
            span: row.span,
        })
    }

    /// A row's value: a number its type holds.
    fn data_value(&mut self, row: &ast::DataRow, ty: DataType) -> Option<ConstValue> {
        let value = match (row.value.kind, ty) {
            (OperandKind::Error, _) => return None,
            (OperandKind::Real(v), DataType::Real) => ConstValue::Real(v as f32),
            (OperandKind::Integer(v), DataType::Real) => ConstValue::Real(v as f32),
            (OperandKind::Integer(v), _) => {
                let (lo, hi) = ty.integer_range().unwrap_or((i64::MIN, i64::MAX));
                if !(lo..=hi).contains(&v) {
                    self.report(
                        Diagnostic::new(
                            Code::DataValueRange,
                            row.value.span,
                            format!("{v} does not fit {ty}"),
                        )
                        .label(format!("{ty} holds {lo}..{hi}")),
                    );
                    return None;
                }
                ConstValue::Integer(v)
            }
            _ => {
                self.report(Diagnostic::new(
                    Code::DataValueRange,
                    row.value.span,
                    format!("{ty} needs a whole number"),
                ));
                return None;
            }
        };
        Some(value)
    }
}
