//! S7-200 interrupt event numbers in the Micro/WIN dialect (docs/microwin.md, "Interrupt
//! events"): the event operand of `ATCH`, `DTCH` and `CEVNT` in an export names an
//! S7-200 event, translated to the target's GUTTA event through the target's data
//! (`<Event MicroWin=>`, `MemoryMap::event_for_s7200`); E0223 where the target has no
//! such event. The S7-200's event table is the catalog's (`s7200::S7200_EVENTS`); no
//! event number is written here.

use gutta_catalog::s7200::{s7200_event, S7200_EVENTS};
use gutta_catalog::OperandSpec;

use super::Checker;
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;

/// An event operand of a Micro/WIN export: the S7-200 event it names, the GUTTA event
/// it compiles to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EventTranslation {
    pub span: Span,
    pub s7200: u32,
    pub gutta: u32,
}

impl Checker<'_> {
    /// The GUTTA event an S7-200 event number `n` of a Micro/WIN export means on the
    /// target, recorded for the summary; None (reported) when `n` is no S7-200 event
    /// (E0307) or the target has no event that means it (E0223).
    pub(super) fn s7200_event_operand(
        &mut self,
        span: Span,
        n: i64,
        spec: &OperandSpec,
        mnemonic: &str,
    ) -> Option<i64> {
        let Some(s7) = s7200_event(n) else {
            let last = S7200_EVENTS.len() - 1;
            self.report(
                Diagnostic::new(
                    Code::ConstantOutOfRange,
                    span,
                    format!(
                        "{} of {mnemonic} must be an S7-200 event number 0..{last}",
                        spec.name
                    ),
                )
                .label(format!("{n} is out of range")),
            );
            return None;
        };
        let memory = &self.target.memory;
        let Some(event) = memory.event_for_s7200(s7.number) else {
            let has: Vec<String> = S7200_EVENTS
                .iter()
                .filter(|e| memory.event_for_s7200(e.number).is_some())
                .map(|e| format!("{} ({})", e.number, e.meaning))
                .collect();
            let help = if has.is_empty() {
                format!("{} maps no S7-200 event", self.target.name())
            } else {
                format!(
                    "S7-200 events {} has: {}",
                    self.target.name(),
                    has.join(", ")
                )
            };
            self.report(
                Diagnostic::new(
                    Code::S7200Event,
                    span,
                    format!(
                        "S7-200 event {} ({}) does not exist on {}",
                        s7.number,
                        s7.meaning,
                        self.target.name()
                    ),
                )
                .label("an S7-200 event number")
                .help(help),
            );
            return None;
        };
        self.out.s7200_events.push(EventTranslation {
            span,
            s7200: s7.number,
            gutta: event.number,
        });
        Some(i64::from(event.number))
    }
}

/// The event translations that change a number, as one part of the summary line:
/// `S7-200 events: 10 -> 20 (TIMED0)`; None when every event keeps its number.
pub fn event_summary(
    translations: &[EventTranslation],
    target: &gutta_catalog::Target,
) -> Option<String> {
    let mut pairs: Vec<(u32, u32)> = translations
        .iter()
        .filter(|t| t.s7200 != t.gutta)
        .map(|t| (t.s7200, t.gutta))
        .collect();
    pairs.sort_unstable();
    pairs.dedup();
    if pairs.is_empty() {
        return None;
    }
    let parts: Vec<String> = pairs
        .iter()
        .map(
            |(s7, gutta)| match target.memory.events.iter().find(|e| e.number == *gutta) {
                Some(e) => format!("{s7} -> {gutta} ({})", e.name),
                None => format!("{s7} -> {gutta}"),
            },
        )
        .collect();
    Some(format!("S7-200 events: {}", parts.join(", ")))
}
