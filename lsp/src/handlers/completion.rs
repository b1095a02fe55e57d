//! textDocument/completion: the analysis's completions at the cursor as LSP items. Each
//! item replaces the word being typed (a text edit), keeps the analysis's order through
//! `sortText`, and inserts plain text (no snippets). No completion logic here.

use gutta_analysis::completion::{self, CompletionKind};
use lsp_types::{
    CompletionItem, CompletionItemKind, CompletionList, CompletionOptions, CompletionParams,
    CompletionResponse, CompletionTextEdit, Documentation, InsertTextFormat, MarkupContent,
    MarkupKind, TextEdit,
};

use crate::convert;
use crate::server::{HandlerError, State};

/// What `initialize` announces: completion, asked for again after a blank, a comma,
/// `#`, `&` or `*`.
pub fn capability() -> CompletionOptions {
    CompletionOptions {
        trigger_characters: Some([" ", ",", "#", "&", "*"].map(String::from).to_vec()),
        ..CompletionOptions::default()
    }
}

pub fn completion(
    state: &mut State,
    params: CompletionParams,
) -> Result<Option<CompletionResponse>, HandlerError> {
    let at = &params.text_document_position;
    let uri = &at.text_document.uri;
    let Some((program, offset)) = state.workspace.at(uri, at.position) else {
        return Ok(None);
    };
    let found = completion::completions(&program.checked, offset);
    let (_, range) = convert::range(program, found.replace);
    let items = found
        .items
        .into_iter()
        .enumerate()
        .map(|(i, item)| CompletionItem {
            kind: Some(kind(item.kind)),
            detail: item.detail,
            documentation: item.documentation.map(|value| {
                Documentation::MarkupContent(MarkupContent {
                    kind: MarkupKind::Markdown,
                    value,
                })
            }),
            sort_text: Some(format!("{i:05}")),
            insert_text_format: Some(InsertTextFormat::PLAIN_TEXT),
            text_edit: Some(CompletionTextEdit::Edit(TextEdit::new(range, item.insert))),
            label: item.label,
            ..CompletionItem::default()
        })
        .collect();
    Ok(Some(CompletionResponse::List(CompletionList {
        is_incomplete: false,
        items,
    })))
}

fn kind(k: CompletionKind) -> CompletionItemKind {
    match k {
        CompletionKind::Keyword => CompletionItemKind::KEYWORD,
        CompletionKind::Mnemonic => CompletionItemKind::FUNCTION,
        CompletionKind::Local => CompletionItemKind::VARIABLE,
        CompletionKind::Symbol => CompletionItemKind::CONSTANT,
        CompletionKind::Block => CompletionItemKind::MODULE,
        CompletionKind::Label => CompletionItemKind::REFERENCE,
        CompletionKind::Address => CompletionItemKind::FIELD,
        CompletionKind::Constant => CompletionItemKind::VALUE,
        CompletionKind::Type => CompletionItemKind::TYPE_PARAMETER,
        CompletionKind::Value => CompletionItemKind::ENUM_MEMBER,
    }
}
