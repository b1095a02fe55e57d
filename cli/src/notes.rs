//! Notes: what a tool did that the user should know and that is no diagnostic (a file
//! read in GBK, where a Micro/WIN export's S7-200 interrupts went). Human format: one
//! `note: ...` line on stderr, as before; `--message-format json`: one JSON object per
//! note (`{"severity":"note","kind":"code-page","file":...,"message":...}`, the
//! compiler's `diagnostics::json::note_to_json_line`) and nothing on stderr. Which notes
//! a command has is the command's business; this module only prints them.

use std::io::Write;

use gutta_compiler::diagnostics::json::note_to_json_line;
use gutta_compiler::microwin::NoteKind;
use gutta_compiler::CheckedFile;

use crate::fatal::MessageFormat;

/// One note about a file (or the program its first source stands for).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Note {
    pub kind: NoteKind,
    pub file: String,
    pub message: String,
}

impl Note {
    /// The note as `--message-format json` prints it: one line with its newline.
    pub fn json_line(&self) -> String {
        note_to_json_line(self.kind.as_str(), &self.file, &self.message)
    }
}

/// Where JSON notes go: stdout, unless the command writes its result there (`-o -`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JsonTo {
    Stdout,
    Stderr,
}

/// Print `notes` as `format` asks: `note: MESSAGE` lines on stderr, or JSON lines.
pub fn print(notes: &[Note], format: MessageFormat, json_to: JsonTo) {
    match format {
        MessageFormat::Human => {
            let mut err = std::io::stderr().lock();
            for n in notes {
                let _ = writeln!(err, "note: {}", n.message);
            }
        }
        MessageFormat::Json => {
            let text: String = notes.iter().map(Note::json_line).collect();
            let _ = match json_to {
                JsonTo::Stdout => std::io::stdout().lock().write_all(text.as_bytes()),
                JsonTo::Stderr => std::io::stderr().lock().write_all(text.as_bytes()),
            };
        }
    }
}

/// The notes of a checked Micro/WIN export (`CheckedFile::microwin_notes`: interrupts,
/// events, the S area, L60-L63), each about the program's first source file.
pub fn program_notes(checked: &CheckedFile) -> Vec<Note> {
    let file = checked
        .file
        .parts()
        .first()
        .map_or_else(|| checked.file.name.clone(), |p| p.name.clone());
    checked
        .microwin_notes()
        .into_iter()
        .map(|n| Note {
            kind: n.kind,
            file: file.clone(),
            message: n.message,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_code_page_note_is_a_json_object_without_code() {
        let note = Note {
            kind: NoteKind::CodePage,
            file: "MAIN.awl".into(),
            message: "MAIN.awl is not UTF-8; read as GBK".into(),
        };
        let v: serde_json::Value = serde_json::from_str(note.json_line().trim_end()).unwrap();
        assert_eq!(v["severity"], "note");
        assert_eq!(v["kind"], "code-page");
        assert_eq!(v["file"], "MAIN.awl");
        assert_eq!(v["message"], "MAIN.awl is not UTF-8; read as GBK");
        assert!(v.get("code").is_none());
    }
}
