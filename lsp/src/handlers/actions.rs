//! textDocument/codeAction: the analysis's quick fixes for the diagnostics in the
//! range, each with the LSP diagnostic it fixes and its edit; preferred when it is its
//! diagnostic's only fix. No fix is computed here.

use gutta_analysis::actions;
use gutta_compiler::source::Span;
use lsp_types::{
    CodeAction, CodeActionKind, CodeActionOptions, CodeActionOrCommand, CodeActionParams,
    CodeActionProviderCapability, CodeActionResponse,
};

use super::rename::workspace_edit;
use crate::convert;
use crate::server::{HandlerError, State};

/// What `initialize` announces: quick fixes.
pub fn capability() -> CodeActionProviderCapability {
    CodeActionProviderCapability::Options(CodeActionOptions {
        code_action_kinds: Some(vec![CodeActionKind::QUICKFIX]),
        ..CodeActionOptions::default()
    })
}

pub fn code_action(
    state: &mut State,
    params: CodeActionParams,
) -> Result<Option<CodeActionResponse>, HandlerError> {
    if let Some(only) = &params.context.only {
        if !only
            .iter()
            .any(|k| CodeActionKind::QUICKFIX.as_str().starts_with(k.as_str()))
        {
            return Ok(None);
        }
    }
    let uri = &params.text_document.uri;
    let Some(program) = state.workspace.program_of(uri) else {
        return Ok(None);
    };
    let (Some(start), Some(end)) = (
        program.offset(uri, params.range.start),
        program.offset(uri, params.range.end),
    ) else {
        return Ok(None);
    };
    let found = actions::code_actions(&program.checked, Span::new(start, end.max(start)));
    let docs = state.diagnostics_doc.as_deref();
    let answer = found
        .into_iter()
        .map(|a| {
            let diagnostic = program
                .checked
                .diagnostics()
                .get(a.diagnostic)
                .map(|d| convert::diagnostic(program, d, docs).1);
            CodeActionOrCommand::CodeAction(CodeAction {
                title: a.title,
                kind: Some(CodeActionKind::QUICKFIX),
                diagnostics: diagnostic.map(|d| vec![d]),
                edit: Some(workspace_edit(program, &a.edits)),
                is_preferred: Some(a.preferred),
                ..CodeAction::default()
            })
        })
        .collect();
    Ok(Some(answer))
}
