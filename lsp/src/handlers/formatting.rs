//! textDocument/formatting: the open document's text through the compiler's formatter
//! (gutta_compiler::analysis::format), answered as one edit of the whole text. A text
//! with syntax errors is left as it is (no edits) and the reason logged. No layout
//! rule lives here.

use gutta_compiler::analysis::format::format;
use lsp_types::notification::LogMessage;
use lsp_types::{
    DocumentFormattingParams, LogMessageParams, MessageType, Position, Range, TextEdit,
};

use crate::documents::Lines;
use crate::server::{HandlerError, State};

pub fn formatting(
    state: &mut State,
    params: DocumentFormattingParams,
) -> Result<Option<Vec<TextEdit>>, HandlerError> {
    let uri = params.text_document.uri;
    let Some(doc) = state.documents.get(&uri) else {
        return Err(HandlerError::invalid_params(format!(
            "formatting {} which is not open",
            uri.as_str()
        )));
    };
    let text = &doc.text;
    match format(text) {
        Ok(formatted) if formatted == *text => Ok(Some(Vec::new())),
        Ok(formatted) => {
            let end = Lines::new(text).position(text, text.len());
            Ok(Some(vec![TextEdit::new(
                Range::new(Position::new(0, 0), end),
                formatted,
            )]))
        }
        Err(refusal) => {
            let at = Lines::new(text).position(text, refusal.span.start as usize);
            state.notify::<LogMessage>(LogMessageParams {
                typ: MessageType::INFO,
                message: format!(
                    "gutta-lsp: not formatting {}: line {}: {}",
                    uri.as_str(),
                    at.line + 1,
                    refusal.message
                ),
            });
            Ok(None)
        }
    }
}
