//! textDocument/semanticTokens/full and /range: the analysis's semantic tokens of the
//! document's part of its program (gutta_analysis::tokens), encoded as LSP's
//! relative integers. The legend is the analysis's (`TokenKind::ALL`, `MODIFIERS`).

use gutta_analysis::tokens::{semantic_tokens, TokenKind, MODIFIERS};
use gutta_compiler::source::Span;
use lsp_types::{
    Range, SemanticToken, SemanticTokenModifier, SemanticTokenType, SemanticTokens,
    SemanticTokensFullOptions, SemanticTokensLegend, SemanticTokensOptions, SemanticTokensParams,
    SemanticTokensRangeParams, SemanticTokensRangeResult, SemanticTokensResult,
    SemanticTokensServerCapabilities, Uri,
};

use crate::server::{HandlerError, State};

/// The capability, with the legend.
pub fn capability() -> SemanticTokensServerCapabilities {
    SemanticTokensServerCapabilities::SemanticTokensOptions(SemanticTokensOptions {
        work_done_progress_options: Default::default(),
        legend: SemanticTokensLegend {
            token_types: TokenKind::ALL
                .iter()
                .map(|k| SemanticTokenType::new(k.lsp_name()))
                .collect(),
            token_modifiers: MODIFIERS
                .iter()
                .map(|m| SemanticTokenModifier::new(m))
                .collect(),
        },
        range: Some(true),
        full: Some(SemanticTokensFullOptions::Bool(true)),
    })
}

pub fn full(
    state: &mut State,
    params: SemanticTokensParams,
) -> Result<Option<SemanticTokensResult>, HandlerError> {
    Ok(encode(state, &params.text_document.uri, None).map(SemanticTokensResult::Tokens))
}

pub fn range(
    state: &mut State,
    params: SemanticTokensRangeParams,
) -> Result<Option<SemanticTokensRangeResult>, HandlerError> {
    Ok(encode(state, &params.text_document.uri, Some(params.range))
        .map(SemanticTokensRangeResult::Tokens))
}

/// The tokens of `uri` (within `range`), relative-encoded; None when no program has it.
fn encode(state: &State, uri: &Uri, range: Option<Range>) -> Option<SemanticTokens> {
    let program = state.workspace.program_of(uri)?;
    let part = program.parts.get(program.part_of(uri)?)?;
    let part_span = Span::new(part.start, part.end);
    let wanted = match range {
        Some(r) => Span::new(program.offset(uri, r.start)?, program.offset(uri, r.end)?),
        None => part_span,
    };
    let text = program.text();
    let mut data = Vec::new();
    let (mut line, mut character) = (0, 0);
    for t in semantic_tokens(&program.checked, part_span, wanted) {
        let (_, at) = program.position(t.span.start as usize);
        let length = text[t.span.range()].encode_utf16().count() as u32;
        let delta_line = at.line.saturating_sub(line);
        let delta_start = if delta_line == 0 {
            at.character.saturating_sub(character)
        } else {
            at.character
        };
        (line, character) = (at.line, at.character);
        data.push(SemanticToken {
            delta_line,
            delta_start,
            length,
            token_type: t.kind.index(),
            token_modifiers_bitset: t.modifiers,
        });
    }
    Some(SemanticTokens {
        result_id: None,
        data,
    })
}
