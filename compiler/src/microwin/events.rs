//! S7-200 interrupt event numbers (docs/microwin.md, "Interrupt events"): the event
//! operand of `ATCH`, `DTCH` and `CEVNT` in an export names an S7-200 event, translated
//! here to the target's GUTTA event through the target's data (`<Event MicroWin=>`,
//! `MemoryMap::event_for_s7200`); E0223 where the target has no such event. The checker
//! then checks the GUTTA number it is given. The S7-200's event table is the catalog's
//! (`s7200::S7200_EVENTS`); no event number is written here.

use std::collections::HashMap;

use gutta_catalog::rules;
use gutta_catalog::s7200::{s7200_event, S7200_EVENTS};
use gutta_catalog::{OperandSpec, Target};

use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
use crate::syntax::ast::{OperandKind, Program};

/// An event operand of a Micro/WIN export: the S7-200 event it names, the GUTTA event
/// it compiles to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EventTranslation {
    pub span: Span,
    pub s7200: u32,
    pub gutta: u32,
}

/// The event operands of the program's code, translated: every literal event operand
/// the checker will check (an instruction of the target, its operand count right, no
/// operand in error) maps to its GUTTA number, or to None when it was refused (reported
/// in `diags`). `translations` lists the ones that translated, in program order.
pub(super) fn translate(
    program: &Program,
    text: &str,
    target: &Target,
    diags: &mut Vec<Diagnostic>,
    translations: &mut Vec<EventTranslation>,
) -> HashMap<Span, Option<i64>> {
    let set = &target.instructions;
    let mut renumbered = HashMap::new();
    for net in program.units.iter().flat_map(|u| &u.networks) {
        for ins in &net.instructions {
            let Some(id) = set.lookup(text.get(ins.mnemonic.range()).unwrap_or("")) else {
                continue;
            };
            let spec = set.get(id);
            let ops = net.operands_of(ins);
            let fixed = spec.operands.len();
            let count_ok = if spec.call_arguments {
                ops.len() >= fixed
            } else {
                ops.len() == fixed
            };
            if !count_ok || ops.iter().any(|o| o.kind == OperandKind::Error) {
                continue;
            }
            for (op, os) in ops.iter().zip(&spec.operands) {
                let OperandKind::Integer(n) = op.kind else {
                    continue;
                };
                if !rules::is_event_operand(os) {
                    continue;
                }
                let gutta = event_operand(op.span, n, os, &spec.mnemonic, target, diags);
                if let Some((s7200, gutta)) = gutta {
                    translations.push(EventTranslation {
                        span: op.span,
                        s7200,
                        gutta,
                    });
                }
                renumbered.insert(op.span, gutta.map(|(_, g)| i64::from(g)));
            }
        }
    }
    renumbered
}

/// The S7-200 event an event number `n` names and the GUTTA event it means on the
/// target; None (reported) when `n` is no S7-200 event (E0307) or the target has no
/// event that means it (E0223).
fn event_operand(
    span: Span,
    n: i64,
    spec: &OperandSpec,
    mnemonic: &str,
    target: &Target,
    diags: &mut Vec<Diagnostic>,
) -> Option<(u32, u32)> {
    let Some(s7) = s7200_event(n) else {
        let last = S7200_EVENTS.len() - 1;
        diags.push(
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
    let memory = &target.memory;
    let Some(event) = memory.event_for_s7200(s7.number) else {
        let has: Vec<String> = S7200_EVENTS
            .iter()
            .filter(|e| memory.event_for_s7200(e.number).is_some())
            .map(|e| format!("{} ({})", e.number, e.meaning))
            .collect();
        let help = if has.is_empty() {
            format!("{} maps no S7-200 event", target.name())
        } else {
            format!("S7-200 events {} has: {}", target.name(), has.join(", "))
        };
        diags.push(
            Diagnostic::new(
                Code::S7200Event,
                span,
                format!(
                    "S7-200 event {} ({}) does not exist on {}",
                    s7.number,
                    s7.meaning,
                    target.name()
                ),
            )
            .label("an S7-200 event number")
            .help(help),
        );
        return None;
    };
    Some((s7.number, event.number))
}

/// The event translations that change a number, as one part of the summary line:
/// `S7-200 events: 10 -> 20 (TIMED0)`; None when every event keeps its number.
pub fn event_summary(translations: &[EventTranslation], target: &Target) -> Option<String> {
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
