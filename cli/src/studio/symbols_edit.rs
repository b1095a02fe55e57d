//! The symbol table in the studio (docs/studio.md, "STL and symbols"): every symbol of
//! the program with where it is declared (a table file, a file's SYMBOLS block) and
//! every block's variables; a symbol added (to the project's first table, else to the
//! first file's SYMBOLS block), its address or comment changed in the row that declares
//! it, or renamed everywhere (`gutta_analysis::rename` over the files and tables checked
//! as one program). A changed source file takes one step of its undo history; a changed
//! table stays in memory, marked dirty, until it is saved (atomically, inside the
//! project only). Each change answers the `Update`s of the files whose drawings it may
//! have changed. No I/O here.

use gutta_compiler::syntax::ast::SymbolDecl;
use gutta_compiler::CheckedFile;
use gutta_ladder::json::{ModelError, ModelErrorCode};
use serde::{Deserialize, Serialize};

use super::session::Session;
use super::{StudioError, Update};

type Studio<T> = Result<T, StudioError>;

/// One row of the symbol table the page lists.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct SymbolRow {
    pub name: String,
    /// As written (a variable has none).
    pub address: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub data_type: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub comment: Option<String>,
    /// `table` (a symbol table file), `symbols` (a SYMBOLS block of a source file) or
    /// `var` (a block's variable).
    pub declared: String,
    /// The file that declares it, as the session names files.
    pub file: String,
    /// A variable's block and section (`VAR_INPUT`, `VAR_IN_OUT`, `VAR_OUTPUT`, `VAR`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub block: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub section: Option<String>,
}

/// A change to the symbol table: `POST /api/symbols`'s body.
#[derive(Debug, Clone, PartialEq, Eq, Deserialize)]
#[serde(tag = "op", rename_all = "lowercase", deny_unknown_fields)]
pub enum SymbolChange {
    /// A new symbol: `{"op":"add","name":"Start","address":"I0.0","comment":"..."}`.
    Add {
        name: String,
        address: String,
        #[serde(default)]
        comment: Option<String>,
    },
    /// A symbol's address and/or comment: `{"op":"set","name":"Start","address":"I0.1"}`.
    Set {
        name: String,
        #[serde(default)]
        address: Option<String>,
        #[serde(default)]
        comment: Option<String>,
    },
    /// A symbol renamed everywhere: `{"op":"rename","name":"Start","to":"StartButton"}`.
    Rename { name: String, to: String },
}

/// Which buffer a part of the joined program is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Buffer {
    File(usize),
    Table(usize),
}

/// A text edit in one buffer: bytes replaced by a text.
type Edit = (Buffer, std::ops::Range<usize>, String);

impl Session {
    /// The program's symbols (each with the file that declares it) in declaration
    /// order, then every block's variables.
    pub fn symbol_table(&self) -> Vec<SymbolRow> {
        let program = self.program();
        let text = &program.file.text;
        let slice = |s: gutta_compiler::source::Span| text.get(s.range()).unwrap_or("").trim();
        let mut rows = Vec::new();
        for d in &program.ast.symbols {
            let (buffer, _) = self.buffer_at(&program, d.name.start as usize);
            let (declared, file) = match buffer {
                Buffer::File(i) => ("symbols", self.files[i].name.clone()),
                Buffer::Table(j) => ("table", self.tables[j].name.clone()),
            };
            rows.push(SymbolRow {
                name: slice(d.name).to_string(),
                address: slice(d.address).to_string(),
                data_type: d.data_type.map(|t| slice(t).to_string()),
                comment: d.comment_text(text).filter(|c| !c.is_empty()),
                declared: declared.to_string(),
                file,
                block: None,
                section: None,
            });
        }
        for f in &self.files {
            for block in &f.editor.model().blocks {
                let sections = [
                    ("VAR_INPUT", &block.var_input),
                    ("VAR_IN_OUT", &block.var_in_out),
                    ("VAR_OUTPUT", &block.var_output),
                    ("VAR", &block.var),
                ];
                for (section, vars) in sections {
                    for v in vars {
                        rows.push(SymbolRow {
                            name: v.name.clone(),
                            address: String::new(),
                            data_type: Some(v.data_type.clone()),
                            comment: v.comment.clone(),
                            declared: "var".to_string(),
                            file: f.name.clone(),
                            block: Some(block.name.clone()),
                            section: Some(section.to_string()),
                        });
                    }
                }
            }
        }
        rows
    }

    /// `change` made: the files' Updates (every file when a table changed, else the
    /// files whose text changed). A refused change (an unknown symbol, a name that is
    /// taken or not a name, an address that does not read) changes nothing.
    pub fn change_symbols(&mut self, change: &SymbolChange) -> Studio<Vec<Update>> {
        let program = self.program();
        let edits = match change {
            SymbolChange::Add {
                name,
                address,
                comment,
            } => self.add_edits(&program, name, address, comment.as_deref())?,
            SymbolChange::Set {
                name,
                address,
                comment,
            } => self.set_edits(&program, name, address.as_deref(), comment.as_deref())?,
            SymbolChange::Rename { name, to } => {
                let d = declaration(&program, name)?;
                let edits = gutta_analysis::rename::rename(&program, d.name.start as usize, to)
                    .map_err(|e| refused(&e.to_string()))?;
                edits
                    .into_iter()
                    .map(|(span, text)| {
                        let (buffer, base) = self.buffer_at(&program, span.start as usize);
                        (
                            buffer,
                            span.start as usize - base..span.end as usize - base,
                            text,
                        )
                    })
                    .collect()
            }
        };
        Ok(self.apply_edits(edits))
    }

    /// A table's text as the session holds it.
    pub fn table_text(&self, table: &str) -> Studio<&str> {
        Ok(&self.tables[self.table_index(table)?].text)
    }

    /// Whether a table's text differs from the file on disk.
    pub fn table_is_dirty(&self, table: &str) -> Studio<bool> {
        let j = self.table_index(table)?;
        Ok(self.tables[j].text != self.table_saved[j])
    }

    /// The table `table` written to its file atomically, inside the studio's folder only.
    pub fn save_table(&mut self, table: &str) -> Studio<()> {
        let j = self.table_index(table)?;
        let path = self.root.confine(&self.table_paths[j])?;
        if path != self.table_paths[j] {
            return Err(StudioError::Escape {
                path: self.table_paths[j].display().to_string(),
                root: self.root.dir().display().to_string(),
            });
        }
        let mut bytes = Vec::new();
        if self.table_bom[j] {
            bytes.extend_from_slice("\u{feff}".as_bytes());
        }
        bytes.extend_from_slice(self.tables[j].text.as_bytes());
        gutta_io::write_file_atomically(&path, &bytes).map_err(|e| StudioError::Io {
            path: self.tables[j].name.clone(),
            message: format!("cannot write: {e}"),
        })?;
        self.table_saved[j] = self.tables[j].text.clone();
        Ok(())
    }

    pub(super) fn table_index(&self, table: &str) -> Studio<usize> {
        let name = self.root.plain_name(table)?;
        self.tables
            .iter()
            .position(|t| t.name == name)
            .ok_or_else(|| StudioError::NotOpen {
                file: table.to_string(),
            })
    }

    /// The buffer holding byte `offset` of the joined program, and where it starts.
    fn buffer_at(&self, program: &CheckedFile, offset: usize) -> (Buffer, usize) {
        let part = program.file.part_index(offset);
        let base = program.file.parts().get(part).map_or(0, |p| p.start);
        if part < self.files.len() {
            (Buffer::File(part), base)
        } else {
            (Buffer::Table(part - self.files.len()), base)
        }
    }

    fn add_edits(
        &self,
        program: &CheckedFile,
        name: &str,
        address: &str,
        comment: Option<&str>,
    ) -> Studio<Vec<Edit>> {
        let name = name.trim();
        if !gutta_compiler::syntax::table::is_word(name)
            || gutta_compiler::syntax::is_reserved(name)
            || gutta_compiler::check::reads_as_address(&program.target, name)
        {
            return Err(refused(&format!(
                "`{name}` is not a symbol name: a letter or `_`, then letters, digits and `_`, not a reserved word or an address"
            )));
        }
        if declaration(program, name).is_ok() {
            return Err(refused(&format!("`{name}` is already a symbol")));
        }
        let address = checked_address(program, address)?;
        let comment = comment.map(str::trim).filter(|c| !c.is_empty());
        if let Some(table) = self.tables.first() {
            let text = &table.text;
            let tab = separator_is_tab(text);
            let ending = if text.contains("\r\n") { "\r\n" } else { "\n" };
            let mut row = String::new();
            if !text.is_empty() && !text.ends_with('\n') {
                row.push_str(ending);
            }
            row.push_str(name);
            row.push_str(if tab { "\t" } else { "," });
            row.push_str(&address);
            if let Some(c) = comment {
                row.push_str(if tab { "\t" } else { "," });
                row.push_str(&table_cell(c, tab));
            }
            row.push_str(ending);
            return Ok(vec![(Buffer::Table(0), text.len()..text.len(), row)]);
        }
        let Some(f) = self.files.first() else {
            return Err(refused("no file to declare the symbol in"));
        };
        let text = &f.text;
        let ending = if text.contains("\r\n") { "\r\n" } else { "\n" };
        let mut row = format!("  {name} : {address}");
        if let Some(c) = comment {
            row.push_str(" // ");
            row.push_str(&c.replace(['\r', '\n'], " "));
        }
        row.push_str(ending);
        let lines = line_starts(text);
        if let Some(&at) = lines
            .iter()
            .find(|&&s| line_of(text, s).trim().eq_ignore_ascii_case("END_SYMBOLS"))
        {
            return Ok(vec![(Buffer::File(0), at..at, row)]);
        }
        let block = format!("SYMBOLS{ending}{row}END_SYMBOLS{ending}{ending}");
        let after_plc = lines.iter().copied().find(|&s| {
            line_of(text, s)
                .trim_start()
                .to_ascii_uppercase()
                .starts_with("PLC_TYPE")
        });
        Ok(match after_plc {
            Some(s) => {
                let end = s + line_of(text, s).len();
                let next = (end + 1).min(text.len());
                let sep = if text[..next].ends_with('\n') {
                    ""
                } else {
                    ending
                };
                vec![(Buffer::File(0), next..next, format!("{sep}{ending}{block}"))]
            }
            None => vec![(Buffer::File(0), 0..0, block)],
        })
    }

    fn set_edits(
        &self,
        program: &CheckedFile,
        name: &str,
        address: Option<&str>,
        comment: Option<&str>,
    ) -> Studio<Vec<Edit>> {
        let d = declaration(program, name)?;
        let (buffer, base) = self.buffer_at(program, d.name.start as usize);
        let text = &program.file.text;
        let mut edits = Vec::new();
        if let Some(address) = address {
            let address = checked_address(program, address)?;
            let s = d.address;
            edits.push((
                buffer,
                s.start as usize - base..s.end as usize - base,
                address,
            ));
        }
        if let Some(comment) = comment {
            let comment = comment.trim().replace(['\r', '\n'], " ");
            let tab = match buffer {
                Buffer::Table(j) => Some(separator_is_tab(&self.tables[j].text)),
                Buffer::File(_) => None,
            };
            match (d.comment, tab) {
                (Some(c), Some(tab)) => {
                    // Inside quotes (escaped or not) the cell keeps them.
                    let quoted =
                        d.comment_escaped || text[..c.start as usize].trim_end().ends_with('"');
                    let cell = if quoted {
                        comment.replace('"', "\"\"")
                    } else {
                        table_cell(&comment, tab)
                    };
                    edits.push((buffer, c.start as usize - base..c.end as usize - base, cell));
                }
                (Some(c), None) => {
                    edits.push((
                        buffer,
                        c.start as usize - base..c.end as usize - base,
                        comment,
                    ));
                }
                (None, _) if comment.is_empty() => {}
                (None, tab) => {
                    let last = [Some(d.address), d.data_type]
                        .into_iter()
                        .flatten()
                        .map(|s| s.end as usize)
                        .max()
                        .unwrap_or(d.address.end as usize);
                    // After the last field, past a closing quote.
                    let last = if text[last..].starts_with('"') {
                        last + 1
                    } else {
                        last
                    };
                    let added = match tab {
                        Some(true) => format!("\t{}", table_cell(&comment, true)),
                        Some(false) => format!(",{}", table_cell(&comment, false)),
                        None => format!(" // {comment}"),
                    };
                    edits.push((buffer, last - base..last - base, added));
                }
            }
        }
        Ok(edits)
    }

    /// `edits` made in their buffers: each changed source file one step of its undo
    /// history; when a table changed, every file checked again with it.
    fn apply_edits(&mut self, mut edits: Vec<Edit>) -> Vec<Update> {
        edits.sort_by_key(|(b, r, _)| {
            (
                matches!(b, Buffer::Table(_)),
                buffer_key(*b),
                std::cmp::Reverse(r.start),
            )
        });
        let mut files: Vec<(usize, String)> = Vec::new();
        let mut table_changed = false;
        for (buffer, range, text) in edits {
            match buffer {
                Buffer::File(i) => {
                    let at = match files.iter().position(|(j, _)| *j == i) {
                        Some(at) => at,
                        None => {
                            files.push((i, self.files[i].text.clone()));
                            files.len() - 1
                        }
                    };
                    files[at].1.replace_range(range, &text);
                }
                Buffer::Table(j) => {
                    self.tables[j].text.replace_range(range, &text);
                    table_changed = true;
                }
            }
        }
        let mut updates = Vec::new();
        for i in 0..self.files.len() {
            match files.iter().position(|(j, _)| *j == i) {
                Some(at) => {
                    let text = std::mem::take(&mut files[at].1);
                    updates.push(self.replace_text(i, text));
                }
                None if table_changed => updates.push(self.rebuild(i)),
                None => {}
            }
        }
        updates
    }
}

fn buffer_key(b: Buffer) -> usize {
    match b {
        Buffer::File(i) | Buffer::Table(i) => i,
    }
}

/// The symbol `name` (any case) declared in a SYMBOLS block or a table.
fn declaration<'p>(program: &'p CheckedFile, name: &str) -> Studio<&'p SymbolDecl> {
    let text = &program.file.text;
    program
        .ast
        .symbols
        .iter()
        .find(|d| {
            text.get(d.name.range())
                .is_some_and(|n| n.trim().eq_ignore_ascii_case(name.trim()))
        })
        .ok_or_else(|| {
            StudioError::Edit(ModelError::new(
                ModelErrorCode::NoSuchPath,
                "symbols",
                format!("`{name}` is not a symbol of the program"),
            ))
        })
}

/// `address` as the target writes it, or the refusal.
fn checked_address(program: &CheckedFile, address: &str) -> Studio<String> {
    let address = address.trim();
    let parsed = program.target.memory.parse_address(address).map_err(|e| {
        refused(&format!(
            "`{address}` is not an address of {}: {e}",
            program.target.name()
        ))
    })?;
    Ok(program.target.memory.format_address(&parsed))
}

fn refused(message: &str) -> StudioError {
    StudioError::Edit(ModelError::new(
        ModelErrorCode::WrongTarget,
        "symbols",
        message,
    ))
}

/// Whether a table's rows are tab-separated (as `parse_table` decides).
fn separator_is_tab(text: &str) -> bool {
    text.lines()
        .find(|l| !l.trim().is_empty())
        .is_some_and(|l| l.contains('\t'))
}

/// A comment as one cell of a table row.
fn table_cell(comment: &str, tab: bool) -> String {
    if tab {
        comment.replace('\t', " ")
    } else if comment.contains([',', '"']) {
        format!("\"{}\"", comment.replace('"', "\"\""))
    } else {
        comment.to_string()
    }
}

fn line_starts(text: &str) -> Vec<usize> {
    std::iter::once(0)
        .chain(text.match_indices('\n').map(|(i, _)| i + 1))
        .filter(|&s| s < text.len())
        .collect()
}

/// The line starting at `start`, without its line break.
fn line_of(text: &str, start: usize) -> &str {
    let rest = &text[start..];
    let line = rest.split('\n').next().unwrap_or("");
    line.strip_suffix('\r').unwrap_or(line)
}
