//! Direct addresses in operands, symbols and data rows: parsed by the target's memory
//! map (`MemoryMap::parse_address`), with a diagnostic that says why a text is not an
//! address on this target (and on which stdlib target the area exists). Knows no
//! operand specs: what an operand accepts is `memory.rs`'s.

use std::sync::OnceLock;

use gutta_catalog::{stdlib, Address, AddressError, MemoryMap, Width};

use super::Checker;
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;

/// The memory map of every stdlib target (`None` if it does not load), in
/// `stdlib::names()` order. Loaded once per process: loading them for every unknown-area
/// error cost milliseconds per diagnostic.
pub(super) fn stdlib_memory_maps() -> &'static [(&'static str, Option<MemoryMap>)] {
    static MAPS: OnceLock<Vec<(&'static str, Option<MemoryMap>)>> = OnceLock::new();
    MAPS.get_or_init(|| {
        stdlib::names()
            .map(|n| (n, stdlib::load(n).ok().map(|t| t.memory)))
            .collect()
    })
}

impl Checker<'_> {
    /// Parse a direct address, reporting why it is not one on this target. `span` is the
    /// address text; `context` says what it is for (symbol, data row).
    pub(super) fn direct_address(&mut self, span: Span, context: Option<&str>) -> Option<Address> {
        let text = self.slice(span);
        match self.target.memory.parse_address(text) {
            Ok(a) => Some(a),
            Err(e) => {
                self.address_error(span, text, e, context);
                None
            }
        }
    }

    /// What area `area` holds, as E0306's message says it: `M has 128 bytes, MB0..MB127`
    /// for an access of `width`, `T has 16 numbers, T0..T15` for an area of numbers.
    fn area_extent(&self, area: &str, width: Width) -> String {
        let memory = &self.target.memory;
        let Some(a) = memory.area(area) else {
            return format!("it has no area {area}");
        };
        let at = |offset: u32, bit: u8| {
            memory.format_address(&Address {
                slot: a.slot,
                width,
                offset,
                bit,
            })
        };
        let (first, last) = (at(0, 0), at(a.size.saturating_sub(width.bytes()), 7));
        if a.fixed_width().is_some() {
            format!("{area} has {} numbers, {first}..{last}", a.unit_count())
        } else {
            format!("{area} has {} bytes, {first}..{last}", a.size)
        }
    }

    pub(super) fn address_error(
        &mut self,
        span: Span,
        text: &str,
        e: AddressError,
        context: Option<&str>,
    ) {
        let plc = self.target.name().to_string();
        let d = match &e {
            AddressError::NotAnAddress => Diagnostic::new(Code::MalformedAddress, span, format!("`{text}` is not an address"))
                .help(context.map(|c| format!("{c} needs a direct address such as I0.0, MW10 or T5")).unwrap_or_default()),
            AddressError::UnknownArea { prefix } => {
                let elsewhere: Vec<&str> = stdlib_memory_maps()
                    .iter()
                    .filter(|(n, _)| !n.eq_ignore_ascii_case(&plc))
                    .filter(|(_, m)| m.as_ref().is_some_and(|m| m.area(prefix).is_some()))
                    .map(|(n, _)| *n)
                    .collect();
                let d = Diagnostic::new(Code::AddressOutOfTarget, span, format!("{plc} has no memory area {prefix}")).label("unknown area");
                if elsewhere.is_empty() {
                    let names: Vec<&str> = self.target.memory.areas.iter().map(|a| a.name.as_str()).collect();
                    d.help(format!("the areas of {plc} are {}", names.join(", ")))
                } else {
                    d.help(format!("area {prefix} exists on {}; select it with --plc or PLC_TYPE", elsewhere.join(", ")))
                }
            }
            AddressError::OutOfRange { area, last, width, .. } => {
                let elsewhere: Vec<&str> = stdlib_memory_maps()
                    .iter()
                    .filter(|(n, _)| !n.eq_ignore_ascii_case(&plc))
                    .filter(|(_, m)| m.as_ref().is_some_and(|m| m.parse_address(text).is_ok()))
                    .map(|(n, _)| *n)
                    .collect();
                let extent = self.area_extent(area, *width);
                let d = Diagnostic::new(Code::AddressOutOfTarget, span, format!("`{text}` is outside area {area} of {plc}: {extent}"))
                    .label(format!("past {last}, the end of {area}"));
                if elsewhere.is_empty() {
                    d
                } else {
                    d.help(format!("`{text}` exists on {}; select one with --plc or PLC_TYPE", elsewhere.join(", ")))
                }
            }
            AddressError::WidthNotAllowed { area, width, allowed } => {
                let list: Vec<&str> = allowed.iter().map(|w| w.keyword()).collect();
                Diagnostic::new(Code::AreaNotAllowed, span, format!("area {area} has no {} access", width.keyword().to_ascii_lowercase()))
                    .label(format!("{area} allows {}", list.join(", ")))
            }
            AddressError::LetterNotAllowed { example, .. } | AddressError::MissingWidth { area: example } if matches!(e, AddressError::LetterNotAllowed { .. }) => {
                Diagnostic::new(Code::MalformedAddress, span, e.to_string()).help(format!("write `{example}`"))
            }
            AddressError::MissingWidth { area } => Diagnostic::new(Code::MalformedAddress, span, e.to_string())
                .help(format!("for example `{area}B0` (byte), `{area}W0` (word), `{area}D0` (dword) or `{area}0.0` (bit)")),
            AddressError::BitOutOfRange { .. } | AddressError::LetterNotAllowed { .. } => Diagnostic::new(Code::MalformedAddress, span, e.to_string()),
        };
        let d = if d.help.as_deref() == Some("") {
            Diagnostic { help: None, ..d }
        } else {
            d
        };
        self.report(d);
    }
}
