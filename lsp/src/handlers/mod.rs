//! The dispatch table: one row per LSP method, each pointing at a handler in this
//! folder (one file per feature group). A feature adds its rows here and one line to
//! `capabilities()` in lib.rs. Handlers only convert: the logic lives in
//! gutta-analysis.

pub mod actions;
pub mod completion;
pub mod diagnostics;
pub mod folding;
pub mod formatting;
pub mod inlay;
pub mod live;
pub mod navigation;
pub mod rename;
pub mod signature;
pub mod symbols;
pub mod tokens;

use lsp_types::notification as note;
use lsp_types::request as req;

use crate::server::{notification, request, Row, State};

/// Every request the server answers.
pub fn requests() -> Vec<Row> {
    vec![
        request::<req::Completion>(completion::completion),
        request::<req::SignatureHelpRequest>(signature::signature_help),
        request::<req::PrepareRenameRequest>(rename::prepare_rename),
        request::<req::Rename>(rename::rename),
        request::<req::CodeActionRequest>(actions::code_action),
        request::<req::HoverRequest>(navigation::hover),
        request::<req::GotoDefinition>(navigation::definition),
        request::<req::References>(navigation::references),
        request::<req::DocumentHighlightRequest>(navigation::highlight),
        request::<req::DocumentSymbolRequest>(symbols::document_symbols),
        request::<req::WorkspaceSymbolRequest>(symbols::workspace_symbols),
        request::<req::Formatting>(formatting::formatting),
        request::<req::RangeFormatting>(formatting::range_formatting),
        request::<req::FoldingRangeRequest>(folding::folding_range),
        request::<req::SemanticTokensFullRequest>(tokens::full),
        request::<req::SemanticTokensRangeRequest>(tokens::range),
        request::<req::InlayHintRequest>(inlay::inlay_hint),
        request::<req::InlineValueRequest>(live::inline_value),
        request::<req::ExecuteCommand>(live::execute_command),
    ]
}

/// Every notification the server acts on.
pub fn notifications() -> Vec<Row> {
    vec![
        notification::<note::DidOpenTextDocument>(diagnostics::did_open),
        notification::<note::DidChangeTextDocument>(diagnostics::did_change),
        notification::<note::DidCloseTextDocument>(diagnostics::did_close),
        notification::<note::DidSaveTextDocument>(diagnostics::did_save),
        notification::<note::DidChangeWatchedFiles>(diagnostics::did_change_watched_files),
        notification::<note::DidChangeConfiguration>(live::did_change_configuration),
    ]
}

/// The client is ready (`initialized` was received during the handshake): what each
/// feature does first, one line each.
pub fn initialized(state: &mut State) {
    diagnostics::watch_project_files(state);
}
