//! Inlay hints: after a symbol's use, the address it stands for (`Start` -> `: I0.0`);
//! after a SYMBOLS declaration's address and a word operand, its Modbus reference; after
//! a timer's constant preset, the time it stands for (`TON T37, 100` -> `10.0 s`). Also
//! the hook for live values ([`operand_addresses`]): the operands of a range with the
//! address each reads. Plain data over byte spans of the program text; no LSP types.

use std::collections::HashMap;

use gutta_catalog::{Address, ModbusLocation, Width};

use gutta_compiler::check::DefKind;
use gutta_compiler::source::Span;
use gutta_compiler::CheckedFile;

/// Which hints to give (the server's `initializationOptions.inlayHints`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InlayOptions {
    /// `: I0.0` after each use of a symbol.
    pub symbol_addresses: bool,
    /// The Modbus reference after SYMBOLS declarations and word operands.
    pub modbus: bool,
    /// `10.0 s` after a timer's constant preset.
    pub timer_durations: bool,
}

impl Default for InlayOptions {
    fn default() -> Self {
        InlayOptions {
            symbol_addresses: true,
            modbus: true,
            timer_durations: true,
        }
    }
}

/// What a hint says.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InlayKind {
    /// The address a symbol stands for.
    SymbolAddress,
    /// A Modbus reference.
    Modbus,
    /// A timer preset as a duration.
    TimerDuration,
}

/// One hint: its text, shown at `offset` (after the thing it describes).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Inlay {
    pub offset: usize,
    pub label: String,
    pub kind: InlayKind,
}

/// The hints for what lies in `range` (bytes of the program text), in text order.
pub fn inlay_hints(checked: &CheckedFile, range: Span, options: InlayOptions) -> Vec<Inlay> {
    let memory = &checked.target.memory;
    let out = &checked.output;
    let symbols = symbol_addresses(checked);
    let inside = |s: Span| s.start >= range.start && s.end <= range.end;
    let mut hints = Vec::new();
    if options.symbol_addresses {
        for r in out.references.iter().filter(|r| inside(r.span)) {
            if let Some(a) = symbols.get(&r.definition) {
                hints.push(Inlay {
                    offset: r.span.end as usize,
                    label: format!(": {}", memory.format_address(a)),
                    kind: InlayKind::SymbolAddress,
                });
            }
        }
    }
    if options.modbus {
        let declared = checked.ast.symbols.iter().filter_map(|d| {
            let a = memory
                .parse_address(checked.file.text.get(d.address.range())?.trim())
                .ok()?;
            Some((d.address, a))
        });
        let words = out
            .addresses
            .iter()
            .filter(|(_, a)| matches!(a.width, Width::Word | Width::Dword))
            .map(|(s, a)| (*s, *a));
        for (span, a) in declared.chain(words).filter(|(s, _)| inside(*s)) {
            if let Some(m) = memory.modbus_location(&a) {
                hints.push(Inlay {
                    offset: span.end as usize,
                    label: modbus_label(&m),
                    kind: InlayKind::Modbus,
                });
            }
        }
    }
    if options.timer_durations {
        for b in crate::timers::timer_boxes(checked) {
            if let Some(d) = b.duration().filter(|_| inside(b.preset)) {
                hints.push(Inlay {
                    offset: b.preset.end as usize,
                    // No `=`: live values are ` = value` hints (lsp handlers/live.rs).
                    label: d,
                    kind: InlayKind::TimerDuration,
                });
            }
        }
    }
    hints.sort_by_key(|h| (h.offset, h.kind == InlayKind::Modbus));
    hints
}

/// `400019`, `400019..400020`, `400009 bit 3`: the references only.
fn modbus_label(m: &ModbusLocation) -> String {
    let (Some(first), Some(last)) = (m.pieces.first(), m.pieces.last()) else {
        return String::new();
    };
    let reference = gutta_catalog::modbus::format_reference;
    let mut label = reference(first.reference);
    if last.reference != first.reference {
        label = format!("{label}..{}", reference(last.reference));
    } else if !first.is_whole(m.table) {
        label = if first.first_bit == first.last_bit {
            format!("{label} bit {}", first.first_bit)
        } else {
            format!("{label} bits {}..{}", first.first_bit, first.last_bit)
        };
    }
    format!("Modbus {label}")
}

/// The operands in `range` with the address each reads: direct addresses and uses of
/// symbols, in text order. The live-values hook: attach a value to each span.
pub fn operand_addresses(checked: &CheckedFile, range: Span) -> Vec<(Span, Address)> {
    let out = &checked.output;
    let symbols = symbol_addresses(checked);
    let inside = |s: &Span| s.start >= range.start && s.end <= range.end;
    let mut found: Vec<(Span, Address)> = out
        .addresses
        .iter()
        .filter(|(s, _)| inside(s))
        .copied()
        .chain(
            out.references
                .iter()
                .filter(|r| inside(&r.span))
                .filter_map(|r| Some((r.span, *symbols.get(&r.definition)?))),
        )
        .collect();
    found.sort_by_key(|(s, _)| (s.start, s.end));
    found
}

/// The address of every symbol definition (by index into `definitions`) whose address
/// parses on the target.
pub(crate) fn symbol_addresses(checked: &CheckedFile) -> HashMap<usize, Address> {
    let text = &checked.file.text;
    let memory = &checked.target.memory;
    let by_name: HashMap<u32, Span> = checked
        .ast
        .symbols
        .iter()
        .map(|d| (d.name.start, d.address))
        .collect();
    checked
        .output
        .definitions
        .iter()
        .enumerate()
        .filter(|(_, d)| d.kind == DefKind::Symbol)
        .filter_map(|(i, d)| {
            let address = by_name.get(&d.span.start)?;
            let a = memory
                .parse_address(text.get(address.range())?.trim())
                .ok()?;
            Some((i, a))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use gutta_compiler::source::SourceFile;

    const TEXT: &str = "SYMBOLS\n  Start : I0.0\n  Speed : MW20\nEND_SYMBOLS\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD Start\nMOVW Speed, MW22\n= Q0.0\nEND_ORGANIZATION_BLOCK\n";

    fn hints(options: InlayOptions) -> Vec<String> {
        let checked = gutta_compiler::check_source(SourceFile::new("t.lad", TEXT), None);
        inlay_hints(&checked, Span::new(0, TEXT.len()), options)
            .into_iter()
            .map(|h| {
                format!(
                    "{}|{}",
                    &TEXT[..h.offset].rsplit(['\n', ' ']).next().unwrap_or(""),
                    h.label
                )
            })
            .collect()
    }

    #[test]
    fn symbols_show_their_address_and_words_their_register() {
        assert_eq!(
            hints(InlayOptions::default()),
            [
                "I0.0|Modbus 100001",
                "MW20|Modbus 400019",
                "Start|: I0.0",
                "Speed|: MW20",
                "MW22|Modbus 400020",
            ]
        );
    }

    #[test]
    fn each_kind_can_be_turned_off() {
        let off = InlayOptions {
            symbol_addresses: false,
            modbus: false,
            timer_durations: false,
        };
        assert!(hints(off).is_empty());
        let modbus_only = InlayOptions {
            symbol_addresses: false,
            modbus: true,
            timer_durations: false,
        };
        assert_eq!(hints(modbus_only).len(), 3);
    }

    #[test]
    fn a_timer_preset_shows_its_duration() {
        // CPU-EC20: T4 counts 100 ms, T2 10 ms; a preset in memory has no duration.
        let text = "SYMBOLS\n  Delay : T4\nEND_SYMBOLS\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD I0.0\nTON Delay, 100\nTONR T2, 1234\nTOF T5, MW10\nCTU C0, 5\nEND_ORGANIZATION_BLOCK\n";
        let checked = gutta_compiler::check_source(SourceFile::new("t.lad", text), None);
        let only = InlayOptions {
            symbol_addresses: false,
            modbus: false,
            timer_durations: true,
        };
        let found: Vec<String> = inlay_hints(&checked, Span::new(0, text.len()), only)
            .into_iter()
            .map(|h| {
                format!(
                    "{}|{}",
                    &text[..h.offset].rsplit(' ').next().unwrap_or(""),
                    h.label
                )
            })
            .collect();
        assert_eq!(found, ["100|10.0 s", "1234|12.34 s"]);
        let none = inlay_hints(&checked, Span::new(0, text.find("TONR").unwrap_or(0)), only);
        assert_eq!(none.len(), 1, "only the hints inside the range: {none:?}");
    }

    #[test]
    fn operands_with_their_addresses_for_live_values() {
        let checked = gutta_compiler::check_source(SourceFile::new("t.lad", TEXT), None);
        let found: Vec<String> = operand_addresses(&checked, Span::new(0, TEXT.len()))
            .iter()
            .map(|(s, a)| {
                format!(
                    "{}={}",
                    &TEXT[s.range()],
                    checked.target.memory.format_address(a)
                )
            })
            .collect();
        assert_eq!(
            found,
            ["Start=I0.0", "Speed=MW20", "MW22=MW22", "Q0.0=Q0.0"]
        );
    }
}
