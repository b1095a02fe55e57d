//! Document sync and diagnostics: didOpen/didChange/didClose/didSave update the open
//! documents, the workspace analyses the document's program once, and every file of
//! that program gets its diagnostics published (an empty list for a clean file, and
//! for a file no program covers any more).

use lsp_types::notification::PublishDiagnostics;
use lsp_types::request::RegisterCapability;
use lsp_types::{
    DidChangeTextDocumentParams, DidChangeWatchedFilesParams,
    DidChangeWatchedFilesRegistrationOptions, DidCloseTextDocumentParams,
    DidOpenTextDocumentParams, DidSaveTextDocumentParams, FileSystemWatcher, GlobPattern,
    MessageType, PublishDiagnosticsParams, Registration, RegistrationParams,
};

use crate::convert;
use crate::documents::Document;
use crate::server::{HandlerError, State};
use crate::workspace::Update;

pub fn did_open(state: &mut State, params: DidOpenTextDocumentParams) -> Result<(), HandlerError> {
    let doc = params.text_document;
    state.documents.open(
        doc.uri.clone(),
        Document {
            text: doc.text,
            version: doc.version,
            language_id: doc.language_id,
        },
    );
    let update = state.workspace.opened(&state.documents, &doc.uri);
    publish(state, update);
    Ok(())
}

pub fn did_change(
    state: &mut State,
    params: DidChangeTextDocumentParams,
) -> Result<(), HandlerError> {
    let uri = params.text_document.uri;
    if !state
        .documents
        .change(&uri, params.text_document.version, params.content_changes)
    {
        return Err(HandlerError::invalid_params(format!(
            "didChange for {} which is not open",
            uri.as_str()
        )));
    }
    let update = state.workspace.changed(&state.documents, &uri);
    publish(state, update);
    Ok(())
}

pub fn did_close(
    state: &mut State,
    params: DidCloseTextDocumentParams,
) -> Result<(), HandlerError> {
    let uri = params.text_document.uri;
    state.documents.close(&uri);
    let update = state.workspace.closed(&state.documents, &uri);
    publish(state, update);
    Ok(())
}

/// A save may have changed the project around the file (gutta.toml, tables on disk):
/// find it again.
pub fn did_save(state: &mut State, params: DidSaveTextDocumentParams) -> Result<(), HandlerError> {
    let uri = params.text_document.uri;
    if !state.documents.is_open(&uri) {
        return Ok(());
    }
    let update = state.workspace.opened(&state.documents, &uri);
    publish(state, update);
    Ok(())
}

/// Files changed on disk (watched by the client): programs holding them are analysed
/// again, and every open document finds its project again when a gutta.toml changed.
pub fn did_change_watched_files(
    state: &mut State,
    params: DidChangeWatchedFilesParams,
) -> Result<(), HandlerError> {
    let changed: Vec<_> = params.changes.into_iter().map(|c| c.uri).collect();
    for update in state.workspace.files_changed(&state.documents, &changed) {
        publish(state, update);
    }
    Ok(())
}

/// Ask the client to watch the files a program is made of, when it can register
/// watchers dynamically (else saves and reopening catch changes on disk).
pub fn watch_project_files(state: &mut State) {
    let can = state
        .init
        .capabilities
        .workspace
        .as_ref()
        .and_then(|w| w.did_change_watched_files.as_ref())
        .and_then(|d| d.dynamic_registration)
        .unwrap_or(false);
    if !can {
        return;
    }
    let watchers = ["**/gutta.toml", "**/*.lad", "**/*.csv", "**/*.tsv"]
        .into_iter()
        .map(|glob| FileSystemWatcher {
            glob_pattern: GlobPattern::String(glob.into()),
            kind: None,
        })
        .collect();
    let options = DidChangeWatchedFilesRegistrationOptions { watchers };
    state.request_client::<RegisterCapability>(RegistrationParams {
        registrations: vec![Registration {
            id: "gutta-watched-files".into(),
            method: "workspace/didChangeWatchedFiles".into(),
            register_options: serde_json::to_value(options).ok(),
        }],
    });
}

/// Publish what `update` changed: every file of the analysed program, and empty lists
/// for the files it cleared; warnings go to the person, each once.
pub fn publish(state: &mut State, update: Update) {
    for warning in update.warnings {
        if state.warned.insert(warning.clone()) {
            state.show_message(MessageType::WARNING, format!("gutta-lsp: {warning}"));
        }
    }
    for uri in update.cleared {
        state.notify::<PublishDiagnostics>(PublishDiagnosticsParams::new(uri, Vec::new(), None));
    }
    let Some(key) = update.analysed else { return };
    let Some(program) = state.workspace.program(&key) else {
        return;
    };
    let mut per_file = vec![Vec::new(); program.files.len()];
    for d in program.checked.diagnostics() {
        let (file, lsp) = convert::diagnostic(program, d, state.diagnostics_doc.as_deref());
        if let Some(list) = per_file.get_mut(file) {
            list.push(lsp);
        }
    }
    let several_files = program.files.len() > 1;
    for (uri, diagnostics) in program.files.iter().zip(per_file) {
        let version = state.documents.get(uri).map(|d| d.version);
        state.notify::<PublishDiagnostics>(PublishDiagnosticsParams::new(
            uri.clone(),
            diagnostics,
            version,
        ));
    }
    if several_files {
        refresh_views(state);
    }
}

/// A change in one file of a program changes what the others show (a symbol declared in
/// symbols.csv colours and labels its uses in main.lad): ask the client to fetch their
/// semantic tokens and inlay hints again, where it supports the refresh requests. The
/// changed document itself the editor asks for anyway.
fn refresh_views(state: &mut State) {
    let workspace = state
        .init
        .capabilities
        .workspace
        .as_ref()
        .map(|w| {
            (
                w.semantic_tokens
                    .as_ref()
                    .and_then(|t| t.refresh_support)
                    .unwrap_or(false),
                w.inlay_hint
                    .as_ref()
                    .and_then(|i| i.refresh_support)
                    .unwrap_or(false),
            )
        })
        .unwrap_or((false, false));
    if workspace.0 {
        state.request_client::<lsp_types::request::SemanticTokensRefresh>(());
    }
    if workspace.1 {
        state.request_client::<lsp_types::request::InlayHintRefreshRequest>(());
    }
}
