//! Folding ranges of one .lad text: every block (program, data, system, SYMBOLS), every
//! VAR section, every network, every run of comment lines. Reads the text through the
//! formatter's line classifier, so it works on text with syntax errors too. Byte spans
//! of whole lines; no LSP types.

use crate::format::{classify, LineInfo, LineKind, Section};
use gutta_compiler::source::Span;

/// What a folding range holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FoldKind {
    /// A program block, data block, system block or SYMBOLS section.
    Block,
    /// A VAR section of a program block.
    Vars,
    /// A network: its `NETWORK` line to its last instruction.
    Network,
    /// Two or more comment lines in a row.
    Comment,
}

/// A foldable range: from the start of its first line to the end of its last.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Fold {
    pub span: Span,
    pub kind: FoldKind,
}

/// The folding ranges of `text`, ordered by their first line; each spans two lines or
/// more.
pub fn folding_ranges(text: &str) -> Vec<Fold> {
    let lines = classify(text);
    let mut folds = Vec::new();
    let mut open: Vec<(Section, usize)> = Vec::new();
    let mut network: Option<usize> = None;
    let mut comments: Option<usize> = None;
    let mut last_code = 0;
    for (i, line) in lines.iter().enumerate() {
        if line.kind != LineKind::Comment {
            if let Some(start) = comments.take() {
                push(&mut folds, &lines, start, i - 1, FoldKind::Comment);
            }
        } else if comments.is_none() {
            comments = Some(i);
        }
        match line.kind {
            LineKind::Open(section) => open.push((section, i)),
            LineKind::Close(section) => {
                if section == Section::Unit {
                    if let Some(start) = network.take() {
                        push(&mut folds, &lines, start, last_code, FoldKind::Network);
                    }
                }
                if let Some(at) = open.iter().rposition(|(s, _)| *s == section) {
                    let start = open[at].1;
                    open.truncate(at);
                    let kind = match section {
                        Section::Vars => FoldKind::Vars,
                        _ => FoldKind::Block,
                    };
                    push(&mut folds, &lines, start, i, kind);
                }
            }
            LineKind::Network => {
                if let Some(start) = network.replace(i) {
                    push(&mut folds, &lines, start, last_code, FoldKind::Network);
                }
            }
            _ => {}
        }
        if !matches!(line.kind, LineKind::Blank | LineKind::Comment) {
            last_code = i;
        }
    }
    if let Some(start) = comments {
        push(
            &mut folds,
            &lines,
            start,
            lines.len() - 1,
            FoldKind::Comment,
        );
    }
    if let Some(start) = network {
        push(&mut folds, &lines, start, last_code, FoldKind::Network);
    }
    folds.sort_by_key(|f| (f.span.start, std::cmp::Reverse(f.span.end)));
    folds
}

fn push(folds: &mut Vec<Fold>, lines: &[LineInfo], first: usize, last: usize, kind: FoldKind) {
    if last > first {
        folds.push(Fold {
            span: lines[first].span.to(lines[last].span),
            kind,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folds(text: &str) -> Vec<(usize, usize, FoldKind)> {
        let line = |offset: u32| text[..offset as usize].matches('\n').count();
        folding_ranges(text)
            .into_iter()
            .map(|f| (line(f.span.start), line(f.span.end), f.kind))
            .collect()
    }

    #[test]
    fn blocks_sections_networks_and_comment_runs() {
        let text = "// one\n// two\nSYMBOLS\n  A : I0.0\nEND_SYMBOLS\n\nSUBROUTINE_BLOCK S\nVAR_INPUT\n  a : INT;\nEND_VAR\nBEGIN\nNETWORK 1\nLD A\n= Q0.0\n\nNETWORK 2 // one line\nLD A\nEND_SUBROUTINE_BLOCK\n";
        assert_eq!(
            folds(text),
            [
                (0, 1, FoldKind::Comment),
                (2, 4, FoldKind::Block),
                (6, 17, FoldKind::Block),
                (7, 9, FoldKind::Vars),
                (11, 13, FoldKind::Network),
                (15, 16, FoldKind::Network),
            ]
        );
    }

    #[test]
    fn unterminated_blocks_still_fold_their_networks() {
        let text = "ORGANIZATION_BLOCK MAIN\nBEGIN\nNETWORK 1\nLD I0.0\n= Q0.0\n";
        assert_eq!(folds(text), [(2, 4, FoldKind::Network)]);
    }
}
