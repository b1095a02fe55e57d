//! The program's timer and counter boxes as an editor explains them: each TON, TOF,
//! TONR, CTU, CTD or CTUD with its timer (or counter), its kind, a timer's resolution on
//! the target (`Target::timer_resolution`) and a constant preset as a duration
//! (`gutta_catalog::timer_duration`, the wording the drawing uses too). Feeds the hover
//! and the inlay hints. Plain data over byte spans of the program text; no LSP types.

use std::collections::HashMap;

use gutta_catalog::{timer_duration, Address, TimerCounterKind};
use gutta_compiler::source::Span;
use gutta_compiler::syntax::ast::OperandKind;
use gutta_compiler::CheckedFile;

use crate::inlay::symbol_addresses;

/// One timer or counter instruction of the program.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TimerBox {
    pub kind: TimerCounterKind,
    /// The mnemonic as the catalog spells it (`TON`).
    pub mnemonic: String,
    /// The first operand (`T37`, or a symbol naming it).
    pub counted: Span,
    /// The timer's or counter's address.
    pub address: Address,
    /// Its number (`T37`: 37).
    pub number: u32,
    /// The preset operand (the last one).
    pub preset: Span,
    /// The preset when it is a constant.
    pub preset_value: Option<i64>,
    /// A timer's time unit on the target, in ms (None for a counter).
    pub resolution_ms: Option<u32>,
}

impl TimerBox {
    /// A constant preset as a duration: `10.0 s` (timers only).
    pub fn duration(&self) -> Option<String> {
        timer_duration(self.resolution_ms?, self.preset_value?)
    }

    /// One Markdown line: `TON (on-delay timer) `T37`: counts 100 ms; preset 100 = 10.0 s`.
    pub fn describe(&self, checked: &CheckedFile) -> String {
        let memory = &checked.target.memory;
        let text = &checked.file.text;
        let name = memory.format_address(&self.address);
        let written = text.get(self.counted.range()).unwrap_or("").trim();
        let shown = if written.eq_ignore_ascii_case(&name) {
            format!("`{name}`")
        } else {
            format!("`{written}` (`{name}`)")
        };
        let mut line = format!("**{}** ({}) {shown}", self.mnemonic, kind_words(self.kind));
        if let Some(ms) = self.resolution_ms {
            line.push_str(&format!(": counts {}", unit(ms)));
        }
        let preset = text.get(self.preset.range()).unwrap_or("").trim();
        match (self.duration(), self.resolution_ms) {
            (Some(d), _) => line.push_str(&format!("; preset {preset} = {d}")),
            (None, Some(ms)) => {
                line.push_str(&format!("; preset `{preset}` in units of {}", unit(ms)))
            }
            (None, None) => line.push_str(&format!("; preset {preset}")),
        }
        line
    }
}

/// `100 ms`, `1 s`.
fn unit(ms: u32) -> String {
    timer_duration(ms, 1).unwrap_or_else(|| format!("{ms} ms"))
}

fn kind_words(kind: TimerCounterKind) -> &'static str {
    match kind {
        TimerCounterKind::OnDelay => "on-delay timer",
        TimerCounterKind::OffDelay => "off-delay timer",
        TimerCounterKind::RetentiveOnDelay => "retentive on-delay timer",
        TimerCounterKind::CountUp => "up counter",
        TimerCounterKind::CountDown => "down counter",
        TimerCounterKind::CountUpDown => "up/down counter",
    }
}

/// Every timer and counter instruction whose first operand resolves to an address, in
/// text order.
pub fn timer_boxes(checked: &CheckedFile) -> Vec<TimerBox> {
    let set = &checked.target.instructions;
    let mnemonics: HashMap<Span, _> = checked.output.mnemonics.iter().copied().collect();
    let symbols = symbol_addresses(checked);
    let address_in = |span: Span| -> Option<Address> {
        let inside = |s: &Span| s.start >= span.start && s.end <= span.end;
        let out = &checked.output;
        out.addresses
            .iter()
            .find(|(s, _)| inside(s))
            .map(|(_, a)| *a)
            .or_else(|| {
                out.references
                    .iter()
                    .filter(|r| inside(&r.span))
                    .find_map(|r| symbols.get(&r.definition).copied())
            })
    };
    let mut found = Vec::new();
    for network in checked.ast.units.iter().flat_map(|u| &u.networks) {
        for ins in &network.instructions {
            let Some(id) = mnemonics.get(&ins.mnemonic) else {
                continue;
            };
            let spec = set.get(*id);
            let Some(kind) = spec.kind else { continue };
            let (a, b) = (ins.operands.0 as usize, ins.operands.1 as usize);
            let Some(ops) = network.operands.get(a..b) else {
                continue;
            };
            let (Some(first), Some(last)) = (ops.first(), ops.last()) else {
                continue;
            };
            if ops.len() < 2 {
                continue;
            }
            let Some(address) = address_in(first.span) else {
                continue;
            };
            let number = address.offset / 2;
            found.push(TimerBox {
                kind,
                mnemonic: spec.mnemonic.clone(),
                counted: first.span,
                address,
                number,
                preset: last.span,
                preset_value: match last.kind {
                    OperandKind::Integer(v) => Some(v),
                    _ => None,
                },
                resolution_ms: checked.target.timer_resolution(kind, number),
            });
        }
    }
    found
}

/// What the timer boxes say about the text at `offset`: the boxes whose timer or preset
/// operand is there, or that count `address` (the hovered address, `T37` in `LDW>= T37,
/// 50` or a symbol's). One line per box, without repeats; None when none.
pub fn timer_note(
    checked: &CheckedFile,
    offset: usize,
    address: Option<Address>,
) -> Option<String> {
    let mut lines: Vec<String> = Vec::new();
    for b in timer_boxes(checked) {
        let at = |s: Span| s.start as usize <= offset && offset <= s.end as usize;
        if at(b.counted) || at(b.preset) || address == Some(b.address) {
            let line = b.describe(checked);
            if !lines.contains(&line) {
                lines.push(line);
            }
        }
    }
    (!lines.is_empty()).then(|| lines.join("\n\n"))
}

/// The preset operand of a timer box at `offset`, when it is a constant (a hover there
/// has no other item to explain).
pub fn preset_at(checked: &CheckedFile, offset: usize) -> Option<Span> {
    timer_boxes(checked)
        .into_iter()
        .map(|b| b.preset)
        .find(|s| s.start as usize <= offset && offset <= s.end as usize)
}

#[cfg(test)]
mod tests {
    use super::*;
    use gutta_compiler::source::SourceFile;

    const TEXT: &str = "SYMBOLS\n  RunTimer : T4 // pump run time\n  Limit : MW10\nEND_SYMBOLS\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD I0.0\nTON RunTimer, 100\nNETWORK 2\nLD I0.1\nTONR T2, 25\nNETWORK 3\nLD I0.2\nTOF T5, Limit\nNETWORK 4\nLD I0.3\nLD I0.4\nCTU C3, 10\nNETWORK 5\nLDW>= T4, 50\n= Q0.0\nEND_ORGANIZATION_BLOCK\n";

    fn checked() -> CheckedFile {
        gutta_compiler::check_source(SourceFile::new("t.lad", TEXT), None)
    }

    #[test]
    fn every_box_with_its_kind_resolution_and_duration() {
        let c = checked();
        assert!(!c.has_errors(), "{:?}", c.diagnostics());
        let lines: Vec<String> = timer_boxes(&c).iter().map(|b| b.describe(&c)).collect();
        insta::assert_snapshot!(lines.join("\n"));
    }

    #[test]
    fn notes_at_the_timer_its_preset_and_its_address_elsewhere() {
        let c = checked();
        let at = |needle: &str| TEXT.find(needle).expect("in the text") + 1;
        let preset = timer_note(&c, at("100\n"), None).expect("at the preset");
        assert!(preset.contains("preset 100 = 10.0 s"), "{preset}");
        assert_eq!(
            preset_at(&c, at("100\n")).map(|s| &TEXT[s.range()]),
            Some("100")
        );
        let t37 = c.target.memory.parse_address("T4").expect("T4");
        let elsewhere = timer_note(&c, at("T4, 50"), Some(t37)).expect("by address");
        assert_eq!(elsewhere, preset);
        assert!(timer_note(&c, at("I0.1"), None).is_none());
        assert!(preset_at(&c, at("I0.1")).is_none());
    }

    #[test]
    fn the_hover_of_a_timer_its_symbol_and_its_preset() {
        let c = checked();
        let at = |needle: &str| TEXT.find(needle).expect("in the text") + 1;
        let (span, text) = crate::navigation::hover(&c, at("100\n")).expect("a preset hover");
        assert_eq!(&TEXT[span.range()], "100");
        assert_eq!(
            text,
            "**TON** (on-delay timer) `RunTimer` (`T4`): counts 100 ms; preset 100 = 10.0 s"
        );
        // The symbol's declaration, and the timer's address in a compare.
        let (_, text) = crate::navigation::hover(&c, at("RunTimer :")).expect("a symbol hover");
        assert!(text.starts_with("symbol `RunTimer`"), "{text}");
        assert!(text.ends_with("preset 100 = 10.0 s"), "{text}");
        let (_, text) = crate::navigation::hover(&c, at("T4, 50")).expect("an address hover");
        assert!(text.ends_with("preset 100 = 10.0 s"), "{text}");
        // A counter says its kind; a number that is no preset has no hover.
        let (_, text) = crate::navigation::hover(&c, at("C3")).expect("a counter hover");
        assert!(
            text.ends_with("**CTU** (up counter) `C3`; preset 10"),
            "{text}"
        );
        assert!(crate::navigation::hover(&c, at("50\n")).is_none());
    }
}
