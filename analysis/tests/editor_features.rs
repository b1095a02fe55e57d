//! The editor features never panic, wherever the cursor is: completion, signature
//! help, prepareRename and code actions at every character of the examples and the
//! error corpus (broken code is what an editor shows most), and their answers' spans
//! lie inside the text.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]

// The compiler tests' helpers (the same repository, the same programs).
#[path = "../../compiler/tests/common/mod.rs"]
mod common;

use common::{lad_files, root};
use gutta_analysis::{actions, completion, rename, signature};
use gutta_compiler::check_source;
use gutta_compiler::source::{SourceFile, Span};

#[test]
fn every_position_of_every_corpus_file() {
    let mut files = lad_files(&root().join("examples"));
    files.extend(lad_files(&root().join("tests/data/check/err")));
    let mut positions = 0;
    for path in files {
        let text = std::fs::read_to_string(&path).expect("read");
        let checked = check_source(SourceFile::new("t.lad", text.as_str()), None);
        let len = checked.file.text.len();
        let inside = |s: Span| s.start <= s.end && s.end as usize <= len;
        // Every character of small files; every 7th of large ones.
        let step = if len > 20_000 { 7 } else { 1 };
        for offset in (0..=len)
            .step_by(step)
            .filter(|o| checked.file.text.is_char_boundary(*o))
        {
            positions += 1;
            let c = completion::completions(&checked, offset);
            assert!(inside(c.replace), "{}:{offset}", path.display());
            if let Some(s) = signature::signature_help(&checked, offset) {
                assert!(s.parameters.iter().all(|p| p.label.1 <= s.label.len()));
            }
            if let Ok((span, _)) = rename::prepare_rename(&checked, offset) {
                assert!(inside(span));
            }
            for a in actions::code_actions(&checked, Span::new(offset, offset)) {
                assert!(
                    a.edits.iter().all(|(s, _)| inside(*s)),
                    "{}: {a:?}",
                    path.display()
                );
            }
        }
    }
    assert!(positions > 10_000, "{positions}");
}
