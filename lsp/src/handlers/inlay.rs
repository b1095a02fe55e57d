//! textDocument/inlayHint: the compiler's inlay hints (gutta_compiler::analysis::inlay)
//! for the requested range, converted to LSP positions. Which hints are shown comes from
//! `initializationOptions.inlayHints` (docs/editors.md): `false` for none, or
//! `{ "symbolAddresses": bool, "modbus": bool }` (both default true).

use gutta_compiler::analysis::inlay::{inlay_hints, InlayKind, InlayOptions};
use gutta_compiler::source::Span;
use lsp_types::{InlayHint, InlayHintKind, InlayHintLabel, InlayHintParams};
use serde_json::Value;

use crate::server::{HandlerError, State};

pub fn inlay_hint(
    state: &mut State,
    params: InlayHintParams,
) -> Result<Option<Vec<InlayHint>>, HandlerError> {
    let uri = &params.text_document.uri;
    let options = options(state.init.initialization_options.as_ref());
    let Some(program) = state.workspace.program_of(uri) else {
        return Ok(None);
    };
    let (Some(start), Some(end)) = (
        program.offset(uri, params.range.start),
        program.offset(uri, params.range.end),
    ) else {
        return Ok(None);
    };
    let hints = inlay_hints(&program.checked, Span::new(start, end), options)
        .into_iter()
        .map(|h| InlayHint {
            position: program.position(h.offset).1,
            label: InlayHintLabel::String(h.label),
            kind: Some(match h.kind {
                InlayKind::SymbolAddress => InlayHintKind::TYPE,
                InlayKind::Modbus => InlayHintKind::PARAMETER,
            }),
            text_edits: None,
            tooltip: None,
            padding_left: Some(h.kind == InlayKind::Modbus),
            padding_right: None,
            data: None,
        })
        .collect();
    Ok(Some(hints))
}

/// The hints asked for at `initialize` (all when nothing was said).
pub fn options(init: Option<&Value>) -> InlayOptions {
    let mut options = InlayOptions::default();
    match init.and_then(|v| v.get("inlayHints")) {
        Some(Value::Bool(on)) => {
            options.symbol_addresses = *on;
            options.modbus = *on;
        }
        Some(Value::Object(o)) => {
            if let Some(on) = o.get("symbolAddresses").and_then(Value::as_bool) {
                options.symbol_addresses = on;
            }
            if let Some(on) = o.get("modbus").and_then(Value::as_bool) {
                options.modbus = on;
            }
        }
        _ => {}
    }
    options
}
