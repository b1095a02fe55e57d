//! Live values (live.rs) as LSP: `textDocument/inlineValue` (`Lamp = 1` texts), the live
//! part of the inlay hints (` = 1` after each operand; `hints` is the hook the inlay-hint
//! handler calls), the `gutta.liveValues` setting (workspace/didChangeConfiguration)
//! and the `gutta.toggleLiveValues` command. Only conversion and the setting: which
//! operands and their values come from live.rs, which never waits for the PLC.

use lsp_types::{
    DidChangeConfigurationParams, ExecuteCommandParams, InlayHint, InlayHintLabel,
    InlayHintTooltip, InlineValue, InlineValueParams, InlineValueText, Range, Uri,
};
use serde_json::{json, Value};

use crate::convert;
use crate::live::{self, LinkSettings, TOGGLE_COMMAND};
use crate::server::{HandlerError, State};
use crate::workspace::ProgramKey;

/// One operand of the document with its value: where, how it is written, the value
/// shown, and its address (`Q0.0`).
struct Shown {
    range: Range,
    label: String,
    value: String,
    address: String,
}

/// The live values of the operands of `uri` in `range`; empty when live values are off,
/// the document is not open, or its project has no `[connection]`.
fn shown(state: &mut State, uri: &Uri, range: Range) -> Vec<Shown> {
    if !state.live.enabled() {
        return Vec::new();
    }
    let Some(program) = state.workspace.program_of(uri) else {
        return Vec::new();
    };
    let (ProgramKey::Project(manifest), Some(project)) = (&program.key, &program.project) else {
        return Vec::new();
    };
    let (Some(a), Some(b), Some(part)) = (
        program.offset(uri, range.start),
        program.offset(uri, range.end),
        program.part_of(uri),
    ) else {
        return Vec::new();
    };
    let checked = &program.checked;
    let settings =
        LinkSettings::from_connection(&project.connection, checked.target.plc.exch_pack_size);
    state
        .live
        .values(manifest, settings, checked, a.min(b)..a.max(b))
        .into_iter()
        .filter_map(|(operand, value)| {
            let (file, range) = convert::range(program, operand.span);
            (file == part).then(|| Shown {
                range,
                value: live::show(&operand.address, value),
                address: checked.target.memory.format_address(&operand.address),
                label: operand.label,
            })
        })
        .collect()
}

pub fn inline_value(
    state: &mut State,
    params: InlineValueParams,
) -> Result<Option<Vec<InlineValue>>, HandlerError> {
    let values = shown(state, &params.text_document.uri, params.range)
        .into_iter()
        .map(|s| {
            InlineValue::Text(InlineValueText {
                range: s.range,
                text: format!("{} = {}", s.label, s.value),
            })
        })
        .collect();
    Ok(Some(values))
}

/// The live-value inlay hints of `uri` in `range`: ` = 1` after each operand. The
/// inlay-hint handler appends these to its own hints.
pub fn hints(state: &mut State, uri: &Uri, range: Range) -> Vec<InlayHint> {
    shown(state, uri, range)
        .into_iter()
        .map(|s| InlayHint {
            position: s.range.end,
            label: InlayHintLabel::String(format!(" = {}", s.value)),
            kind: None,
            text_edits: None,
            tooltip: Some(InlayHintTooltip::String(format!(
                "{} ({}): live value from the PLC",
                s.label, s.address
            ))),
            padding_left: Some(false),
            padding_right: Some(false),
            data: None,
        })
        .collect()
}

/// `{"gutta": {"liveValues": true}}`; settings without the key change nothing.
pub fn did_change_configuration(
    state: &mut State,
    params: DidChangeConfigurationParams,
) -> Result<(), HandlerError> {
    if let Some(on) = live::setting(&params.settings) {
        state.live.set_enabled(on);
    }
    Ok(())
}

/// `gutta.toggleLiveValues`: live values on or off; answers `{"liveValues": bool}`.
pub fn execute_command(
    state: &mut State,
    params: ExecuteCommandParams,
) -> Result<Option<Value>, HandlerError> {
    if params.command != TOGGLE_COMMAND {
        return Err(HandlerError::invalid_params(format!(
            "unknown command `{}` (gutta-lsp has `{TOGGLE_COMMAND}`)",
            params.command
        )));
    }
    let on = !state.live.enabled();
    state.live.set_enabled(on);
    Ok(Some(json!({ "liveValues": on })))
}
