//! Hover, go to definition, references and document highlight: the position becomes a
//! byte offset in the document's program, gutta-analysis's `navigation`
//! answers, and the spans become locations in whichever file of the program they lie.

use gutta_analysis::navigation::{self, Access};
use lsp_types::{
    DocumentHighlight, DocumentHighlightKind, DocumentHighlightParams, GotoDefinitionParams,
    GotoDefinitionResponse, Hover, HoverContents, HoverParams, Location, MarkupContent, MarkupKind,
    ReferenceParams,
};

use crate::convert;
use crate::server::{HandlerError, State};

pub fn hover(state: &mut State, params: HoverParams) -> Result<Option<Hover>, HandlerError> {
    let p = params.text_document_position_params;
    let Some((program, offset)) = state.workspace.at(&p.text_document.uri, p.position) else {
        return Ok(None);
    };
    let Some((span, text)) = navigation::hover(&program.checked, offset) else {
        return Ok(None);
    };
    Ok(Some(Hover {
        contents: HoverContents::Markup(MarkupContent {
            kind: MarkupKind::Markdown,
            value: text,
        }),
        range: Some(convert::range(program, span).1),
    }))
}

pub fn definition(
    state: &mut State,
    params: GotoDefinitionParams,
) -> Result<Option<GotoDefinitionResponse>, HandlerError> {
    let p = params.text_document_position_params;
    let Some((program, offset)) = state.workspace.at(&p.text_document.uri, p.position) else {
        return Ok(None);
    };
    let Some((_, def)) = navigation::definition_at(&program.checked, offset) else {
        return Ok(None);
    };
    let span = program.checked.output.definitions[def].span;
    Ok(convert::location(program, span).map(GotoDefinitionResponse::Scalar))
}

pub fn references(
    state: &mut State,
    params: ReferenceParams,
) -> Result<Option<Vec<Location>>, HandlerError> {
    let p = params.text_document_position;
    let Some((program, offset)) = state.workspace.at(&p.text_document.uri, p.position) else {
        return Ok(None);
    };
    let with_declaration = params.context.include_declaration;
    let found = navigation::references_at(&program.checked, offset)
        .into_iter()
        .filter(|(_, access)| with_declaration || *access != Access::Declaration)
        .filter_map(|(span, _)| convert::location(program, span))
        .collect();
    Ok(Some(found))
}

/// The definition's uses in the requesting document only, read or written.
pub fn highlight(
    state: &mut State,
    params: DocumentHighlightParams,
) -> Result<Option<Vec<DocumentHighlight>>, HandlerError> {
    let p = params.text_document_position_params;
    let uri = &p.text_document.uri;
    let Some((program, offset)) = state.workspace.at(uri, p.position) else {
        return Ok(None);
    };
    let here = program.part_of(uri);
    let found = navigation::references_at(&program.checked, offset)
        .into_iter()
        .filter_map(|(span, access)| {
            let (file, range) = convert::range(program, span);
            (Some(file) == here).then_some(DocumentHighlight {
                range,
                kind: Some(match access {
                    Access::Declaration => DocumentHighlightKind::TEXT,
                    Access::Read => DocumentHighlightKind::READ,
                    Access::Write => DocumentHighlightKind::WRITE,
                }),
            })
        })
        .collect();
    Ok(Some(found))
}
