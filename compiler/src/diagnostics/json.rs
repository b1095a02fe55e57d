//! `--message-format json`: one JSON object per diagnostic, one per line, with
//! 1-based lines and character columns, each position in its own file.

use serde::Serialize;

use crate::diagnostics::Diagnostic;
use crate::source::{LineIndex, SourceFile};

#[derive(Debug, Serialize)]
pub struct JsonDiagnostic<'a> {
    pub code: &'static str,
    pub severity: &'static str,
    pub message: &'a str,
    pub file: &'a str,
    pub line: u32,
    pub column: u32,
    pub end_line: u32,
    pub end_column: u32,
    pub help: Option<&'a str>,
    /// Byte offsets of the primary span in its file.
    pub start_offset: u32,
    pub end_offset: u32,
    pub labels: Vec<JsonLabel<'a>>,
    /// Machine-applicable fixes (the did-you-mean's replacement, a missing `END_`...),
    /// left out when there are none.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub fixes: Vec<JsonFix<'a>>,
}

/// A fix: a title and text edits, each over a span of one file.
#[derive(Debug, Serialize)]
pub struct JsonFix<'a> {
    pub title: &'a str,
    pub edits: Vec<JsonEdit<'a>>,
}

/// Replace the text from (line, column) to (end_line, end_column) of `file` (byte offsets
/// `start_offset..end_offset` in it) with `replacement`; an empty span inserts.
#[derive(Debug, Serialize)]
pub struct JsonEdit<'a> {
    pub file: &'a str,
    pub line: u32,
    pub column: u32,
    pub end_line: u32,
    pub end_column: u32,
    pub start_offset: u32,
    pub end_offset: u32,
    pub replacement: &'a str,
}

#[derive(Debug, Serialize)]
pub struct JsonLabel<'a> {
    /// The label's file: another one than the diagnostic's when a program has several.
    pub file: &'a str,
    pub line: u32,
    pub column: u32,
    pub end_line: u32,
    pub end_column: u32,
    pub message: Option<&'a str>,
}

/// One line of JSON per diagnostic.
pub fn to_json_lines(file: &SourceFile, index: &LineIndex, diagnostics: &[Diagnostic]) -> String {
    let mut out = String::new();
    for d in diagnostics {
        let at = |off: u32| file.locate(index, off as usize);
        let (s, e) = (at(d.primary.span.start), at(d.primary.span.end));
        let labels = d
            .secondary
            .iter()
            .map(|l| {
                let (s, e) = (at(l.span.start), at(l.span.end));
                JsonLabel {
                    file: s.file,
                    line: s.line,
                    column: s.column,
                    end_line: e.line,
                    end_column: e.column,
                    message: l.message.as_deref(),
                }
            })
            .collect();
        let fixes = d
            .fixes
            .iter()
            .map(|f| JsonFix {
                title: &f.title,
                edits: f
                    .edits
                    .iter()
                    .map(|(span, replacement)| {
                        let (s, e) = (at(span.start), at(span.end));
                        JsonEdit {
                            file: s.file,
                            line: s.line,
                            column: s.column,
                            end_line: e.line,
                            end_column: e.column,
                            start_offset: s.offset as u32,
                            end_offset: e.offset as u32,
                            replacement,
                        }
                    })
                    .collect(),
            })
            .collect();
        let j = JsonDiagnostic {
            code: d.code.as_str(),
            severity: d.severity.as_str(),
            message: &d.message,
            file: s.file,
            line: s.line,
            column: s.column,
            end_line: e.line,
            end_column: e.column,
            help: d.help.as_deref(),
            start_offset: s.offset as u32,
            end_offset: e.offset as u32,
            labels,
            fixes,
        };
        if let Ok(line) = serde_json::to_string(&j) {
            out.push_str(&line);
            out.push('\n');
        }
    }
    out
}

/// A note (`--message-format json`): something a tool did that the user should know and
/// that is no diagnostic, such as the code page a file was read in or where a Micro/WIN
/// export's S7-200 interrupts went. It has no `code`, so the consumers that read
/// diagnostics (problem matchers keyed on `code`) pass over it.
#[derive(Debug, Serialize)]
pub struct JsonNote<'a> {
    /// Always `note`.
    pub severity: &'static str,
    /// What the note is about (`code-page`, `interrupts`, `events`, `s-area`,
    /// `l-temporaries`: `microwin::NoteKind::as_str`).
    pub kind: &'a str,
    /// The file it is about, as named on the command line (the program's first source
    /// for a note about the whole program).
    pub file: &'a str,
    pub message: &'a str,
}

/// One note as one line of JSON, with its newline.
pub fn note_to_json_line(kind: &str, file: &str, message: &str) -> String {
    let note = JsonNote {
        severity: "note",
        kind,
        file,
        message,
    };
    serde_json::to_string(&note).map_or_else(|_| String::new(), |line| line + "\n")
}

#[cfg(test)]
mod note_tests {
    use super::*;

    #[test]
    fn a_note_is_one_line_with_severity_kind_file_and_message() {
        let line = note_to_json_line(
            "code-page",
            "MAIN.awl",
            "MAIN.awl is not UTF-8; read as \"GBK\"",
        );
        assert_eq!(
            line,
            "{\"severity\":\"note\",\"kind\":\"code-page\",\"file\":\"MAIN.awl\",\"message\":\"MAIN.awl is not UTF-8; read as \\\"GBK\\\"\"}\n"
        );
    }
}
