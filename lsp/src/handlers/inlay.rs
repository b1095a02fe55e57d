//! textDocument/inlayHint: the analysis's inlay hints (gutta_analysis::inlay)
//! for the requested range, converted to LSP positions. Which hints are shown comes from
//! `initializationOptions.inlayHints` (docs/editors.md): `false` for none, or
//! `{ "symbolAddresses": bool, "modbus": bool, "timerDurations": bool }` (all default
//! true).
//! `visible_operands` is the hook for live values: operands of a range and their
//! addresses.

use gutta_analysis::inlay::{inlay_hints, operand_addresses, InlayKind, InlayOptions};
use gutta_catalog::Address;
use gutta_compiler::source::Span;
use lsp_types::{InlayHint, InlayHintKind, InlayHintLabel, InlayHintParams, Range, Uri};
use serde_json::Value;

use crate::convert;
use crate::server::{HandlerError, State};
use crate::workspace::Program;

pub fn inlay_hint(
    state: &mut State,
    params: InlayHintParams,
) -> Result<Option<Vec<InlayHint>>, HandlerError> {
    let uri = &params.text_document.uri;
    let options = options(state.init.initialization_options.as_ref());
    let Some(program) = state.workspace.program_of(uri) else {
        return Ok(None);
    };
    let Some(range) = span_of(program, uri, params.range) else {
        return Ok(None);
    };
    let mut hints = address_hints(program, range, options);
    // Live values (opt-in, handlers/live.rs) follow the operands' addresses.
    hints.extend(super::live::hints(state, uri, params.range));
    Ok(Some(hints))
}

/// The byte span in the program's text of `range` in `uri`.
fn span_of(program: &Program, uri: &Uri, range: Range) -> Option<Span> {
    Some(Span::new(
        program.offset(uri, range.start)?,
        program.offset(uri, range.end)?,
    ))
}

/// Symbol addresses and Modbus references for `range` (bytes of the program's text).
fn address_hints(program: &Program, range: Span, options: InlayOptions) -> Vec<InlayHint> {
    inlay_hints(&program.checked, range, options)
        .into_iter()
        .map(|h| InlayHint {
            position: program.position(h.offset).1,
            label: InlayHintLabel::String(h.label),
            kind: Some(match h.kind {
                InlayKind::SymbolAddress => InlayHintKind::TYPE,
                InlayKind::Modbus | InlayKind::TimerDuration => InlayHintKind::PARAMETER,
            }),
            text_edits: None,
            tooltip: None,
            padding_left: Some(h.kind != InlayKind::SymbolAddress),
            padding_right: None,
            data: None,
        })
        .collect()
}

/// The operands visible in `range` of `uri` with the address each reads, as LSP ranges:
/// the hook live values attach their values to (one hint at each range's end).
pub fn visible_operands(program: &Program, uri: &Uri, range: Range) -> Vec<(Range, Address)> {
    let Some(span) = span_of(program, uri, range) else {
        return Vec::new();
    };
    operand_addresses(&program.checked, span)
        .into_iter()
        .map(|(s, a)| (convert::range(program, s).1, a))
        .collect()
}

/// The hints asked for at `initialize` (all when nothing was said).
pub fn options(init: Option<&Value>) -> InlayOptions {
    let mut options = InlayOptions::default();
    match init.and_then(|v| v.get("inlayHints")) {
        Some(Value::Bool(on)) => {
            options.symbol_addresses = *on;
            options.modbus = *on;
            options.timer_durations = *on;
        }
        Some(Value::Object(o)) => {
            if let Some(on) = o.get("symbolAddresses").and_then(Value::as_bool) {
                options.symbol_addresses = on;
            }
            if let Some(on) = o.get("modbus").and_then(Value::as_bool) {
                options.modbus = on;
            }
            if let Some(on) = o.get("timerDurations").and_then(Value::as_bool) {
                options.timer_durations = on;
            }
        }
        _ => {}
    }
    options
}
