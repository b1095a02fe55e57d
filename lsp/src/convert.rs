//! Compiler data (byte spans in a program's joined text, our `Diagnostic`) to LSP types
//! (URIs, UTF-16 ranges, `lsp_types::Diagnostic`). Only conversion: what to say comes
//! from gutta-analysis, positions from the program (workspace.rs).

use std::path::{Path, PathBuf};

use gutta_compiler::diagnostics::{Diagnostic, Severity};
use gutta_compiler::source::Span;
use lsp_types::{
    CodeDescription, DiagnosticRelatedInformation, DiagnosticSeverity, Location, NumberOrString,
    Range, Uri,
};

use crate::workspace::Program;

/// The file (index into `program.files`) and range of a span.
pub fn range(program: &Program, span: Span) -> (usize, Range) {
    let (file, start) = program.position(span.start as usize);
    let (_, end) = program.position(span.end as usize);
    // A span never crosses files; if it did, end it where it starts.
    let end = if program.checked.file.part_index(span.end as usize) == file {
        end
    } else {
        start
    };
    (file, Range::new(start, end))
}

/// The location of a span (its file's URI and range).
pub fn location(program: &Program, span: Span) -> Option<Location> {
    let (file, range) = range(program, span);
    Some(Location::new(program.files.get(file)?.clone(), range))
}

/// One diagnostic of `program`, with the index of the file it belongs in.
/// `docs`: the `file:` URI of docs/diagnostics.md, when found.
pub fn diagnostic(
    program: &Program,
    d: &Diagnostic,
    docs: Option<&str>,
) -> (usize, lsp_types::Diagnostic) {
    let (file, range) = range(program, d.primary.span);
    let mut message = d.message.clone();
    if let Some(help) = &d.help {
        message.push_str("\nhelp: ");
        message.push_str(help);
    }
    let related: Vec<DiagnosticRelatedInformation> = d
        .secondary
        .iter()
        .filter_map(|label| {
            Some(DiagnosticRelatedInformation {
                location: location(program, label.span)?,
                message: label.message.clone().unwrap_or_default(),
            })
        })
        .collect();
    let code = d.code.as_str();
    let code_description = docs
        .and_then(|base| {
            format!("{base}#{}", code.to_ascii_lowercase())
                .parse::<Uri>()
                .ok()
        })
        .map(|href| CodeDescription { href });
    let lsp = lsp_types::Diagnostic {
        range,
        severity: Some(match d.severity {
            Severity::Error => DiagnosticSeverity::ERROR,
            Severity::Warning => DiagnosticSeverity::WARNING,
        }),
        code: Some(NumberOrString::String(code.to_string())),
        code_description,
        source: Some("gutta".into()),
        message,
        related_information: (!related.is_empty()).then_some(related),
        tags: None,
        data: None,
    };
    (file, lsp)
}

/// Where docs/diagnostics.md is, as a `file:` URI: `$GUTTA_DOCS/diagnostics.md`, else
/// `share/doc/gutta/diagnostics.md` beside the installed binary's folder, else
/// `docs/diagnostics.md` in a folder above the binary (a build in the repository).
pub fn find_diagnostics_doc() -> Option<String> {
    let exe = std::env::current_exe().ok();
    let env = std::env::var_os("GUTTA_DOCS").map(PathBuf::from);
    diagnostics_doc_in(env.as_deref(), exe.as_deref())
}

fn diagnostics_doc_in(env: Option<&Path>, exe: Option<&Path>) -> Option<String> {
    let mut candidates = Vec::new();
    if let Some(dir) = env {
        candidates.push(dir.join("diagnostics.md"));
    }
    for dir in exe.into_iter().flat_map(Path::ancestors).skip(1).take(5) {
        candidates.push(dir.join("share/doc/gutta/diagnostics.md"));
        candidates.push(dir.join("docs/diagnostics.md"));
    }
    let found = candidates.into_iter().find(|p| p.is_file())?;
    let found = std::fs::canonicalize(&found).unwrap_or(found);
    crate::documents::path_to_uri(&found).map(|u| u.as_str().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_docs_folder_of_gutta_docs_wins_and_nothing_found_is_none() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("diagnostics.md"), "# x").unwrap();
        let found = diagnostics_doc_in(Some(dir.path()), None).unwrap();
        assert!(found.starts_with("file:///") && found.ends_with("/diagnostics.md"));
        let empty = tempfile::tempdir().unwrap();
        assert_eq!(
            diagnostics_doc_in(None, Some(&empty.path().join("bin/gutta-lsp"))),
            None
        );
    }
}
