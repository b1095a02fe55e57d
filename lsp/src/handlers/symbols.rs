//! Document symbols (the outline of one file: SYMBOLS, blocks > locals and networks,
//! data blocks, the system block) and workspace symbols (every definition of every
//! open program, fuzzy-matched), from gutta-analysis's `outline` and
//! `workspace_symbols`.

use gutta_analysis::outline::{outline, OutlineItem, OutlineKind};
use gutta_analysis::workspace_symbols;
use gutta_compiler::check::DefKind;
use lsp_types::{
    DocumentSymbol, DocumentSymbolParams, DocumentSymbolResponse, OneOf, SymbolKind,
    WorkspaceSymbol, WorkspaceSymbolParams, WorkspaceSymbolResponse,
};

use crate::convert;
use crate::server::{HandlerError, State};
use crate::workspace::Program;

/// At most this many workspace symbols per answer (best first).
const WORKSPACE_LIMIT: usize = 256;

pub fn document_symbols(
    state: &mut State,
    params: DocumentSymbolParams,
) -> Result<Option<DocumentSymbolResponse>, HandlerError> {
    let uri = &params.text_document.uri;
    let Some(program) = state.workspace.program_of(uri) else {
        return Ok(None);
    };
    let Some(part) = program.part_of(uri) else {
        return Ok(None);
    };
    let items = outline(&program.checked, part);
    Ok(Some(DocumentSymbolResponse::Nested(
        items.iter().map(|i| document_symbol(program, i)).collect(),
    )))
}

#[allow(deprecated)] // `DocumentSymbol::deprecated` must be written to build one.
fn document_symbol(program: &Program, item: &OutlineItem) -> DocumentSymbol {
    let children: Vec<DocumentSymbol> = item
        .children
        .iter()
        .map(|c| document_symbol(program, c))
        .collect();
    DocumentSymbol {
        name: item.name.clone(),
        detail: item.detail.clone(),
        kind: match item.kind {
            OutlineKind::Symbols => SymbolKind::NAMESPACE,
            OutlineKind::Symbol => SymbolKind::VARIABLE,
            OutlineKind::Main => SymbolKind::MODULE,
            OutlineKind::Interrupt => SymbolKind::EVENT,
            OutlineKind::Subroutine => SymbolKind::FUNCTION,
            OutlineKind::Local => SymbolKind::VARIABLE,
            OutlineKind::Network => SymbolKind::OBJECT,
            OutlineKind::DataBlock => SymbolKind::ARRAY,
            OutlineKind::SystemBlock => SymbolKind::PACKAGE,
            OutlineKind::Setting => SymbolKind::KEY,
        },
        tags: None,
        deprecated: None,
        range: convert::range(program, item.span).1,
        selection_range: convert::range(program, item.selection).1,
        children: (!children.is_empty()).then_some(children),
    }
}

pub fn workspace_symbols(
    state: &mut State,
    params: WorkspaceSymbolParams,
) -> Result<Option<WorkspaceSymbolResponse>, HandlerError> {
    let mut found: Vec<(u32, WorkspaceSymbol)> = Vec::new();
    for program in state.workspace.programs() {
        let defs = &program.checked.output.definitions;
        for (d, score) in workspace_symbols::search(&program.checked, &params.query) {
            let Some(location) = convert::location(program, d.span) else {
                continue;
            };
            let container = d
                .unit
                .and_then(|u| defs.iter().filter(|x| x.kind == DefKind::Unit).nth(u))
                .map(|u| u.name.clone());
            found.push((
                score,
                WorkspaceSymbol {
                    name: match d.kind {
                        DefKind::Local => format!("#{}", d.name),
                        _ => d.name.clone(),
                    },
                    kind: match d.kind {
                        DefKind::Symbol => SymbolKind::VARIABLE,
                        DefKind::Local => SymbolKind::VARIABLE,
                        DefKind::Unit => SymbolKind::FUNCTION,
                        DefKind::DataBlock => SymbolKind::ARRAY,
                        DefKind::Label => SymbolKind::KEY,
                    },
                    tags: None,
                    container_name: container,
                    location: OneOf::Left(location),
                    data: None,
                },
            ));
        }
    }
    found.sort_by(|a, b| {
        a.0.cmp(&b.0)
            .then_with(|| a.1.name.cmp(&b.1.name))
            .then_with(|| location_key(&a.1).cmp(&location_key(&b.1)))
    });
    found.truncate(WORKSPACE_LIMIT);
    Ok(Some(WorkspaceSymbolResponse::Nested(
        found.into_iter().map(|(_, s)| s).collect(),
    )))
}

fn location_key(s: &WorkspaceSymbol) -> (String, u32, u32) {
    match &s.location {
        OneOf::Left(l) => (
            l.uri.as_str().to_string(),
            l.range.start.line,
            l.range.start.character,
        ),
        OneOf::Right(w) => (w.uri.as_str().to_string(), 0, 0),
    }
}
