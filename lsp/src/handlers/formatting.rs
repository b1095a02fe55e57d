//! textDocument/formatting: the open document's text through the analysis's formatter
//! (gutta_analysis::format), answered as one edit of the lines that change
//! (so the editor keeps the cursor and folds elsewhere); textDocument/rangeFormatting:
//! the formatter's line edits that touch the range. A text with syntax errors is left
//! as it is (no edits) and the reason logged. No layout rule lives here.

use gutta_analysis::format::{format, format_edits, FormatRefusal};
use lsp_types::notification::LogMessage;
use lsp_types::{
    DocumentFormattingParams, DocumentRangeFormattingParams, LogMessageParams, MessageType, Range,
    TextEdit, Uri,
};

use crate::documents::Lines;
use crate::server::{HandlerError, State};

pub fn formatting(
    state: &mut State,
    params: DocumentFormattingParams,
) -> Result<Option<Vec<TextEdit>>, HandlerError> {
    let uri = params.text_document.uri;
    let text = open_text(state, &uri)?;
    let text = &text;
    match format(text) {
        Ok(formatted) if formatted == *text => Ok(Some(Vec::new())),
        Ok(formatted) => Ok(Some(vec![changed_lines(text, &formatted)])),
        Err(refusal) => {
            let message = refused(&uri, text, &refusal);
            state.notify::<LogMessage>(message);
            Ok(None)
        }
    }
}

/// The text of the open document `uri` (formatting a closed one is a bad request).
fn open_text(state: &State, uri: &Uri) -> Result<String, HandlerError> {
    match state.documents.get(uri) {
        Some(doc) => Ok(doc.text.clone()),
        None => Err(HandlerError::invalid_params(format!(
            "formatting {} which is not open",
            uri.as_str()
        ))),
    }
}

/// One edit that turns `old` into `new`: the lines between their common first and last
/// lines replaced.
fn changed_lines(old: &str, new: &str) -> TextEdit {
    let prefix = common_lines(old.split_inclusive('\n'), new.split_inclusive('\n'));
    let (old_rest, new_rest) = (&old[prefix..], &new[prefix..]);
    let suffix = common_lines(
        old_rest.split_inclusive('\n').rev(),
        new_rest.split_inclusive('\n').rev(),
    );
    let lines = Lines::new(old);
    let range = Range::new(
        lines.position(old, prefix),
        lines.position(old, old.len() - suffix),
    );
    TextEdit::new(range, new_rest[..new_rest.len() - suffix].to_string())
}

/// Bytes of the whole lines two line sequences share at their start.
fn common_lines<'a>(a: impl Iterator<Item = &'a str>, b: impl Iterator<Item = &'a str>) -> usize {
    a.zip(b)
        .take_while(|(x, y)| x == y && x.ends_with('\n'))
        .map(|(x, _)| x.len())
        .sum()
}

pub fn range_formatting(
    state: &mut State,
    params: DocumentRangeFormattingParams,
) -> Result<Option<Vec<TextEdit>>, HandlerError> {
    let uri = params.text_document.uri;
    let text = open_text(state, &uri)?;
    let text = &text;
    let lines = Lines::new(text);
    let (start, end) = (
        lines.offset(text, params.range.start),
        lines.offset(text, params.range.end),
    );
    match format_edits(text) {
        Ok(edits) => Ok(Some(
            edits
                .into_iter()
                .filter(|e| e.span.end as usize >= start && e.span.start as usize <= end)
                .map(|e| {
                    let range = Range::new(
                        lines.position(text, e.span.start as usize),
                        lines.position(text, e.span.end as usize),
                    );
                    TextEdit::new(range, e.text)
                })
                .collect(),
        )),
        Err(refusal) => {
            let message = refused(&uri, text, &refusal);
            state.notify::<LogMessage>(message);
            Ok(None)
        }
    }
}

/// The log line for a text the formatter refused.
fn refused(uri: &Uri, text: &str, refusal: &FormatRefusal) -> LogMessageParams {
    let at = Lines::new(text).position(text, refusal.span.start as usize);
    LogMessageParams {
        typ: MessageType::INFO,
        message: format!(
            "gutta-lsp: not formatting {}: line {}: {}",
            uri.as_str(),
            at.line + 1,
            refusal.message
        ),
    }
}
