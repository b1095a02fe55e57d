//! textDocument/signatureHelp: the instruction whose operands the cursor is in, from the
//! analysis, as one LSP signature (parameter labels as UTF-16 offsets into it).

use gutta_analysis::signature;
use lsp_types::{
    Documentation, ParameterInformation, ParameterLabel, SignatureHelp, SignatureHelpOptions,
    SignatureHelpParams, SignatureInformation,
};

use crate::server::{HandlerError, State};

/// What `initialize` announces: signature help after a blank or a comma.
pub fn capability() -> SignatureHelpOptions {
    SignatureHelpOptions {
        trigger_characters: Some([" ", ","].map(String::from).to_vec()),
        ..SignatureHelpOptions::default()
    }
}

pub fn signature_help(
    state: &mut State,
    params: SignatureHelpParams,
) -> Result<Option<SignatureHelp>, HandlerError> {
    let at = &params.text_document_position_params;
    let uri = &at.text_document.uri;
    let Some((program, offset)) = state.workspace.at(uri, at.position) else {
        return Ok(None);
    };
    let Some(s) = signature::signature_help(&program.checked, offset) else {
        return Ok(None);
    };
    let utf16 = |byte: usize| s.label.get(..byte).map_or(0, |t| t.encode_utf16().count()) as u32;
    let parameters = s
        .parameters
        .iter()
        .map(|p| ParameterInformation {
            label: ParameterLabel::LabelOffsets([utf16(p.label.0), utf16(p.label.1)]),
            documentation: Some(Documentation::String(p.documentation.clone())),
        })
        .collect();
    let active = s.active.map(|a| a as u32);
    Ok(Some(SignatureHelp {
        signatures: vec![SignatureInformation {
            label: s.label,
            documentation: Some(Documentation::String(s.documentation)),
            parameters: Some(parameters),
            active_parameter: active,
        }],
        active_signature: Some(0),
        active_parameter: active,
    }))
}
