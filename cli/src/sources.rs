//! Reading a program's files for the compiler: the sources and symbol tables as text,
//! with the encoding rules of docs/cli.md (UTF-8; a table, a Micro/WIN export or a data
//! block export may be GBK or Windows-1252, said by a code-page note the caller prints:
//! `notes.rs`). What to compile and how to report it is the commands' business, not
//! this module's.

use std::path::{Path, PathBuf};

use gutta_compiler::microwin::NoteKind;
use gutta_compiler::source::{SourceEncoding, SourceFile};
use gutta_compiler::ProgramSources;

use crate::fatal::Fatal;
use crate::notes::Note;

/// The program: every source file, and the `--symbols` files that are tables (a `.lad`
/// there is a usage error: its blocks would be half a program). A file read in another
/// code page than UTF-8 adds a note to `notes`.
pub fn read_program(
    files: &[PathBuf],
    tables: &[PathBuf],
    notes: &mut Vec<Note>,
) -> Result<ProgramSources, Fatal> {
    read_program_in(Path::new(""), files, tables, notes)
}

/// [`read_program`] with the paths relative to `base` (a project's folder), each file
/// named as given (`src/main.lad`), as diagnostics and the source map show it.
pub fn read_program_in(
    base: &Path,
    files: &[PathBuf],
    tables: &[PathBuf],
    notes: &mut Vec<Note>,
) -> Result<ProgramSources, Fatal> {
    if let Some(lad) = tables
        .iter()
        .find(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("lad")))
    {
        return Err(Fatal::usage(format!(
            "--symbols {0}: a .lad file is a source of the program; list it with the sources instead (`gutta-cc ... {0}`)",
            lad.display()
        )));
    }
    let mut program = ProgramSources::default();
    for path in files {
        program.sources.push(read_named(base, path, false, notes)?);
    }
    for path in tables {
        program
            .symbol_tables
            .push(read_named(base, path, true, notes)?);
    }
    Ok(program)
}

/// A file as text (BOM dropped), named as given: UTF-8; a symbol table, a Micro/WIN
/// export (`.awl`, or the dialect's marker line) or a data block export (its
/// `DATA_BLOCK_TAB` line, any name) may also be GBK or Windows-1252
/// (`SourceFile::from_code_page_bytes`; a note in `notes` says which).
pub fn read_source(path: &Path, table: bool, notes: &mut Vec<Note>) -> Result<SourceFile, Fatal> {
    read_named(Path::new(""), path, table, notes)
}

/// `base/path` read, named `path`.
fn read_named(
    base: &Path,
    path: &Path,
    table: bool,
    notes: &mut Vec<Note>,
) -> Result<SourceFile, Fatal> {
    let name = path.display().to_string();
    let bytes = std::fs::read(base.join(path))
        .map_err(|e| Fatal::io(format!("cannot read {name}: {e}")))?;
    let (file, encoding) =
        SourceFile::from_program_file_bytes(&name, bytes, table).map_err(|e| {
            Fatal::io(format!(
                "{name} is not UTF-8 text (invalid byte at offset {})",
                e.offset
            ))
        })?;
    if encoding != SourceEncoding::Utf8 {
        notes.push(Note {
            kind: NoteKind::CodePage,
            message: format!("{name} is not UTF-8; read as {}", encoding.as_str()),
            file: name,
        });
    }
    Ok(file)
}
