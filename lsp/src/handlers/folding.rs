//! textDocument/foldingRange: the analysis's folding ranges of the open document
//! (gutta_analysis::folding) as LSP line ranges. Only conversion.

use gutta_analysis::folding::{folding_ranges, FoldKind};
use lsp_types::{FoldingRange, FoldingRangeKind, FoldingRangeParams};

use crate::documents::Lines;
use crate::server::{HandlerError, State};

pub fn folding_range(
    state: &mut State,
    params: FoldingRangeParams,
) -> Result<Option<Vec<FoldingRange>>, HandlerError> {
    let Some(doc) = state.documents.get(&params.text_document.uri) else {
        return Ok(None);
    };
    let text = &doc.text;
    let lines = Lines::new(text);
    let ranges = folding_ranges(text)
        .into_iter()
        .map(|f| FoldingRange {
            start_line: lines.line_of(f.span.start as usize) as u32,
            start_character: None,
            end_line: lines.line_of(f.span.end as usize) as u32,
            end_character: None,
            kind: Some(match f.kind {
                FoldKind::Comment => FoldingRangeKind::Comment,
                FoldKind::Block | FoldKind::Vars | FoldKind::Network => FoldingRangeKind::Region,
            }),
            collapsed_text: None,
        })
        .collect();
    Ok(Some(ranges))
}
