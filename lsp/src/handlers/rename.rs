//! textDocument/prepareRename and textDocument/rename: the analysis's rename as a
//! workspace edit over every file of the program; a refusal answers an error whose
//! message says why. Also the one conversion of byte-span edits to a `WorkspaceEdit`
//! (code actions use it too).

use std::collections::HashMap;

use gutta_analysis::rename;
use gutta_compiler::source::Span;
use lsp_types::{
    OneOf, PrepareRenameResponse, RenameOptions, RenameParams, TextDocumentPositionParams,
    TextEdit, Uri, WorkDoneProgressOptions, WorkspaceEdit,
};

use crate::convert;
use crate::server::{HandlerError, State};
use crate::workspace::Program;

/// What `initialize` announces: rename, with prepareRename.
pub fn capability() -> OneOf<bool, RenameOptions> {
    OneOf::Right(RenameOptions {
        prepare_provider: Some(true),
        work_done_progress_options: WorkDoneProgressOptions::default(),
    })
}

pub fn prepare_rename(
    state: &mut State,
    params: TextDocumentPositionParams,
) -> Result<Option<PrepareRenameResponse>, HandlerError> {
    let uri = &params.text_document.uri;
    let Some((program, offset)) = state.workspace.at(uri, params.position) else {
        return Ok(None);
    };
    let (span, placeholder) = rename::prepare_rename(&program.checked, offset)
        .map_err(|e| HandlerError::failed(e.to_string()))?;
    let (_, range) = convert::range(program, span);
    Ok(Some(PrepareRenameResponse::RangeWithPlaceholder {
        range,
        placeholder,
    }))
}

pub fn rename(
    state: &mut State,
    params: RenameParams,
) -> Result<Option<WorkspaceEdit>, HandlerError> {
    let at = &params.text_document_position;
    let uri = &at.text_document.uri;
    let Some((program, offset)) = state.workspace.at(uri, at.position) else {
        return Ok(None);
    };
    let edits = rename::rename(&program.checked, offset, &params.new_name)
        .map_err(|e| HandlerError::failed(e.to_string()))?;
    Ok(Some(workspace_edit(program, &edits)))
}

/// Edits in the program's joined text, grouped by the file each lands in.
// `WorkspaceEdit::changes` is lsp-types' map keyed by `Uri` (whose parsed parts cache
// lazily); keys are never changed after insertion.
#[allow(clippy::mutable_key_type)]
pub fn workspace_edit(program: &Program, edits: &[(Span, String)]) -> WorkspaceEdit {
    let mut changes: HashMap<Uri, Vec<TextEdit>> = HashMap::new();
    for (span, text) in edits {
        let (file, range) = convert::range(program, *span);
        if let Some(uri) = program.files.get(file) {
            changes
                .entry(uri.clone())
                .or_default()
                .push(TextEdit::new(range, text.clone()));
        }
    }
    WorkspaceEdit {
        changes: Some(changes),
        ..WorkspaceEdit::default()
    }
}
