//! STL editing in the studio (docs/studio.md, "STL and symbols"): a block's STL, header
//! to END (what `view-stl` shows), or one network's lines (a network that is not one
//! rung is shown as STL with its reason and edited here) replaced in the buffer; the
//! buffer changes only there, the file is checked again and its model rebuilt from the
//! text (`Session::replace_text`: one step of the file's undo history, as a ladder edit
//! is). Diagnostics, hover and completion on the text come from the editor analysis
//! (`gutta_analysis`) over the whole program as its buffers hold it. No I/O.

use gutta_analysis::completion::completions;
use gutta_analysis::navigation::hover;
use gutta_compiler::source::{LineIndex, SourceFile};
use gutta_compiler::{check_program, CheckedFile, ProgramSources};
use gutta_ladder::edit::{Change, NetworkPath};
use serde::Serialize;

use super::session::Session;
use super::{StudioError, Update};

type Studio<T> = Result<T, StudioError>;

/// A block's or a network's STL and where it starts in the file's buffer.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct StlText {
    pub file: String,
    pub block: usize,
    /// The byte offset of `text` in the buffer: hover and completion take offsets of
    /// the buffer.
    pub offset: usize,
    pub text: String,
}

/// A diagnostic on a block's STL: lines and columns from 1 in the block's text, byte
/// offsets in it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct StlDiagnostic {
    pub line: usize,
    pub column: usize,
    pub end_line: usize,
    pub end_column: usize,
    pub start: usize,
    pub end: usize,
    pub code: String,
    pub severity: String,
    pub message: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub help: Option<String>,
}

/// What hovering at an offset of a buffer explains (Markdown) and the span it explains.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct StlHover {
    pub start: usize,
    pub end: usize,
    pub markdown: String,
}

/// Completion at an offset of a buffer: the span the chosen item replaces, best first.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct StlCompletions {
    pub start: usize,
    pub end: usize,
    pub items: Vec<StlCompletion>,
}

#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct StlCompletion {
    pub label: String,
    /// `mnemonic`, `symbol`, `address`, `keyword`, ...
    pub kind: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub detail: Option<String>,
    pub insert: String,
}

impl Session {
    /// Block `block`'s STL (header line to END line) with its offset in the buffer.
    pub fn stl_text(&self, file: &str, block: usize) -> Studio<StlText> {
        let index = self.index(file)?;
        let range = self.block_range(index, block)?;
        Ok(self.stl_at(index, block, range))
    }

    /// Network `network` of block `block` as STL: its NETWORK line through its last
    /// line that is not blank, with its offset in the buffer.
    pub fn network_stl(&self, file: &str, block: usize, network: usize) -> Studio<StlText> {
        let index = self.index(file)?;
        let range = self.network_range(index, block, network)?;
        Ok(self.stl_at(index, block, range))
    }

    /// Block `block`'s STL (as [`Session::stl`] gives it) replaced by `text`: the
    /// buffer changes only there; the file is checked again and its model rebuilt, and
    /// every network of the block is redrawn.
    pub fn set_stl(&mut self, file: &str, block: usize, text: &str) -> Studio<Update> {
        let index = self.index(file)?;
        let range = self.block_range(index, block)?;
        Ok(self.splice(index, block, range, text))
    }

    /// Network `network` of block `block` (as [`Session::network_stl`] gives it)
    /// replaced by `text`; as [`Session::set_stl`].
    pub fn set_network_stl(
        &mut self,
        file: &str,
        block: usize,
        network: usize,
        text: &str,
    ) -> Studio<Update> {
        let index = self.index(file)?;
        let range = self.network_range(index, block, network)?;
        Ok(self.splice(index, block, range, text))
    }

    /// The diagnostics that lie in block `block`'s STL, the files checked as one
    /// program with the project's tables, at lines and columns of the block's text.
    pub fn stl_diagnostics(&self, file: &str, block: usize) -> Studio<Vec<StlDiagnostic>> {
        let index = self.index(file)?;
        let range = self.block_range(index, block)?;
        let program = self.program();
        let parts = program.file.parts();
        let Some(part) = parts.get(index) else {
            return Ok(Vec::new());
        };
        let text = &self.files[index].text[range.clone()];
        let lines = LineIndex::new(text);
        let base = part.start + range.start;
        let mut out = Vec::new();
        for d in program.diagnostics() {
            let span = d.primary.span;
            let (start, end) = (span.start as usize, span.end as usize);
            if start < base || start >= base + text.len() {
                continue;
            }
            let start = start - base;
            let end = end.saturating_sub(base).clamp(start, text.len());
            let at = lines.line_col(text, start);
            let to = lines.line_col(text, end);
            out.push(StlDiagnostic {
                line: at.line as usize,
                column: at.column as usize,
                end_line: to.line as usize,
                end_column: to.column as usize,
                start,
                end,
                code: d.code.as_str().to_string(),
                severity: d.severity.as_str().to_string(),
                message: d.message.clone(),
                help: d.help.clone(),
            });
        }
        Ok(out)
    }

    /// What the editor analysis says about the item at byte `offset` of `file`'s
    /// buffer, if anything.
    pub fn stl_hover(&self, file: &str, offset: usize) -> Studio<Option<StlHover>> {
        let index = self.index(file)?;
        let (program, base) = self.program_at(index, offset)?;
        Ok(
            hover(&program, base + offset).map(|(span, markdown)| StlHover {
                start: (span.start as usize).saturating_sub(base),
                end: (span.end as usize).saturating_sub(base),
                markdown,
            }),
        )
    }

    /// The editor analysis's completion at byte `offset` of `file`'s buffer.
    pub fn stl_complete(&self, file: &str, offset: usize) -> Studio<StlCompletions> {
        let index = self.index(file)?;
        let (program, base) = self.program_at(index, offset)?;
        let found = completions(&program, base + offset);
        Ok(StlCompletions {
            start: (found.replace.start as usize).saturating_sub(base),
            end: (found.replace.end as usize).saturating_sub(base),
            items: found
                .items
                .into_iter()
                .map(|i| StlCompletion {
                    label: i.label,
                    kind: format!("{:?}", i.kind).to_ascii_lowercase(),
                    detail: i.detail,
                    insert: i.insert,
                })
                .collect(),
        })
    }

    /// Every open file's buffer and the project's tables checked as one program, as
    /// `gutta-cc build` checks them: the files in order (file `i` is part `i` of the
    /// joined text), then the tables.
    pub(super) fn program(&self) -> CheckedFile {
        check_program(
            ProgramSources {
                sources: self
                    .files
                    .iter()
                    .map(|f| SourceFile::new(f.name.clone(), f.text.clone()))
                    .collect(),
                symbol_tables: self.tables.clone(),
                options: self.options.clone(),
            },
            self.target.as_ref(),
        )
    }

    /// [`Session::program`] and where file `index` starts in it; `offset` must lie in
    /// the buffer.
    fn program_at(&self, index: usize, offset: usize) -> Studio<(CheckedFile, usize)> {
        let f = &self.files[index];
        if offset > f.text.len() || !f.text.is_char_boundary(offset) {
            return Err(StudioError::Edit(gutta_ladder::json::ModelError::new(
                gutta_ladder::json::ModelErrorCode::OutOfRange,
                "",
                format!(
                    "offset {offset} is not a place in {} ({} bytes)",
                    f.name,
                    f.text.len()
                ),
            )));
        }
        let program = self.program();
        let base = program.file.parts().get(index).map_or(0, |p| p.start);
        Ok((program, base))
    }

    /// `text` in place of `range` of file `index`'s buffer: one step of its history,
    /// every network of `block` redrawn.
    fn splice(
        &mut self,
        index: usize,
        block: usize,
        range: std::ops::Range<usize>,
        text: &str,
    ) -> Update {
        let old = &self.files[index].text;
        let mut new_text = text.replace("\r\n", "\n");
        if old.contains("\r\n") {
            new_text = new_text.replace('\n', "\r\n");
        }
        let ending = if old.contains("\r\n") { "\r\n" } else { "\n" };
        if old[..range.end].ends_with('\n') && !new_text.ends_with('\n') && !new_text.is_empty() {
            new_text.push_str(ending);
        }
        let mut buffer = String::with_capacity(old.len() + new_text.len());
        buffer.push_str(&old[..range.start]);
        buffer.push_str(&new_text);
        buffer.push_str(&old[range.end..]);
        let mut update = self.replace_text(index, buffer);
        // Every network of the block is drawn again (the page replaces them all).
        let whole = [Change::Inserted(NetworkPath { block, network: 0 })];
        let again = self.update(index, &whole);
        let mut networks = again.networks;
        for n in update.networks.drain(..) {
            if n.block != block {
                networks.push(n);
            }
        }
        networks.sort_by_key(|n| (n.block, n.network));
        update.networks = networks;
        update
    }

    fn stl_at(&self, index: usize, block: usize, range: std::ops::Range<usize>) -> StlText {
        let f = &self.files[index];
        StlText {
            file: f.name.clone(),
            block,
            offset: range.start,
            text: f.text[range].to_string(),
        }
    }

    /// The bytes of block `block` in file `index`'s buffer: its header line's start to
    /// the end of its END line (with the line break), as [`Session::stl`] gives them.
    pub(super) fn block_range(&self, index: usize, block: usize) -> Studio<std::ops::Range<usize>> {
        let f = &self.files[index];
        let unit = f.unit(block)?;
        let text = &f.text;
        let start = line_start(text, unit.header.span.start as usize);
        let end = unit
            .end
            .map(|s| s.end as usize)
            .or_else(|| unit.networks.last().map(last_end))
            .unwrap_or(unit.header.span.end as usize)
            .min(text.len());
        let end = text[end..].find('\n').map_or(text.len(), |i| end + i + 1);
        Ok(start..end)
    }

    /// The bytes of network `network` of block `block`: its first line's start through
    /// its last line that is not blank (with the line break).
    fn network_range(
        &self,
        index: usize,
        block: usize,
        network: usize,
    ) -> Studio<std::ops::Range<usize>> {
        let f = &self.files[index];
        let no_network = || {
            StudioError::Edit(gutta_ladder::json::ModelError::new(
                gutta_ladder::json::ModelErrorCode::NoSuchPath,
                &format!("blocks[{block}].networks[{network}]"),
                format!("{} has no network {network} in block {block}", f.name),
            ))
        };
        let unit = f.unit(block)?;
        let net = unit.networks.get(network).ok_or_else(no_network)?;
        let text = &f.text;
        let start = line_start(text, net.span.start as usize);
        let limit = match (unit.networks.get(network + 1), unit.end) {
            (Some(next), _) => line_start(text, next.span.start as usize),
            (None, Some(end)) => line_start(text, end.start as usize),
            (None, None) => {
                let end = last_end(net).min(text.len());
                text[end..].find('\n').map_or(text.len(), |i| end + i + 1)
            }
        };
        // Trailing blank lines stay between the networks.
        let mut end = limit.max(start);
        while end > start {
            let line_from = line_start(text, end - 1);
            if text[line_from..end].trim().is_empty() {
                end = line_from;
            } else {
                break;
            }
        }
        Ok(start..end.max(start))
    }
}

/// Where the last line of a network's text ends.
fn last_end(net: &gutta_compiler::syntax::ast::Network) -> usize {
    net.instructions.last().map_or(net.span.end, |i| i.span.end) as usize
}

/// The start of the line holding `offset`.
fn line_start(text: &str, offset: usize) -> usize {
    let offset = offset.min(text.len());
    text[..offset].rfind('\n').map_or(0, |i| i + 1)
}
