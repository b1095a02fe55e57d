//! gutta-lsp: the language server for GUTTA PLC programs (docs/editors.md). The server
//! loop (server.rs) runs over any `lsp_server::Connection` (stdio in the binary, memory
//! in tests) and dispatches to handlers/ through one table; documents.rs holds the open
//! texts and converts UTF-16 positions, workspace.rs knows which program a document
//! belongs to, convert.rs turns compiler data into LSP types. Every answer comes from
//! gutta-analysis (the editor analysis over the compiler); only this crate knows LSP types and UTF-16 positions.

pub mod convert;
pub mod documents;
pub mod handlers;
pub mod live;
pub mod server;
pub mod workspace;

use lsp_server::Connection;
use lsp_types::{
    ExecuteCommandOptions, FoldingRangeProviderCapability, HoverProviderCapability, OneOf,
    SaveOptions, ServerCapabilities, TextDocumentSyncCapability, TextDocumentSyncKind,
    TextDocumentSyncOptions, TextDocumentSyncSaveOptions,
};

/// What the server can do, as told to the client in `initialize`: one line per feature.
pub fn capabilities() -> ServerCapabilities {
    ServerCapabilities {
        text_document_sync: Some(text_sync()),
        completion_provider: Some(handlers::completion::capability()),
        signature_help_provider: Some(handlers::signature::capability()),
        rename_provider: Some(handlers::rename::capability()),
        code_action_provider: Some(handlers::actions::capability()),
        hover_provider: Some(HoverProviderCapability::Simple(true)),
        definition_provider: Some(OneOf::Left(true)),
        references_provider: Some(OneOf::Left(true)),
        document_highlight_provider: Some(OneOf::Left(true)),
        document_symbol_provider: Some(OneOf::Left(true)),
        workspace_symbol_provider: Some(OneOf::Left(true)),
        document_formatting_provider: Some(OneOf::Left(true)),
        document_range_formatting_provider: Some(OneOf::Left(true)),
        folding_range_provider: Some(FoldingRangeProviderCapability::Simple(true)),
        semantic_tokens_provider: Some(handlers::tokens::capability()),
        inlay_hint_provider: Some(OneOf::Left(true)),
        inline_value_provider: Some(OneOf::Left(true)),
        execute_command_provider: Some(ExecuteCommandOptions {
            commands: vec![live::TOGGLE_COMMAND.into()],
            ..ExecuteCommandOptions::default()
        }),
        ..ServerCapabilities::default()
    }
}

/// Open/close, incremental changes, and saves (which look for the project again).
fn text_sync() -> TextDocumentSyncCapability {
    TextDocumentSyncCapability::Options(TextDocumentSyncOptions {
        open_close: Some(true),
        change: Some(TextDocumentSyncKind::INCREMENTAL),
        will_save: None,
        will_save_wait_until: None,
        save: Some(TextDocumentSyncSaveOptions::SaveOptions(SaveOptions {
            include_text: Some(false),
        })),
    })
}

/// Serve `connection` until the client says `exit`: the handshake, then every message.
pub fn serve(connection: &Connection) -> Result<(), String> {
    server::run(connection)
}
