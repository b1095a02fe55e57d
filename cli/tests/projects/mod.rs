//! Shared by the project tests (`project_*.rs`): a fresh folder, a project made in it by
//! the real `gutta-cc new`, and gutta.toml edits. It does not run sims or tmux (the
//! tests and tests/common do).

#![allow(dead_code)]

use std::path::{Path, PathBuf};

use gutta_compiler::source::SourceFile;
use gutta_compiler::{check_program, ProgramSources};

/// An empty folder of this test process, named after `tag`.
pub fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gutta-project-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("creates the scratch folder");
    dir
}

/// `gutta-cc new NAME` run in a fresh scratch folder: the project's folder. Until the
/// compiler reads symbol tables (the "multifile" work of issue 11), the table's rows
/// move into the program's SYMBOLS block, so the project still builds from one source.
pub fn new_project(tag: &str, name: &str) -> PathBuf {
    let parent = scratch(tag);
    let o = crate::common::cc_in(&parent, &["new", name]);
    assert!(o.status.success(), "{}", crate::common::text(&o));
    let dir = parent.join(name);
    if !compiler_reads_symbol_tables() {
        fold_table_into_source(&dir);
    }
    dir
}

/// Whether `check_program` takes symbol tables yet (it panics before the multifile work).
fn compiler_reads_symbol_tables() -> bool {
    let program = ProgramSources {
        sources: vec![SourceFile::new("probe.lad", "")],
        symbol_tables: vec![SourceFile::new("probe.csv", "Symbol,Address,Comment\n")],
    };
    std::panic::catch_unwind(|| check_program(program, None)).is_ok()
}

/// The project's symbols.csv rows declared in src/main.lad's SYMBOLS block instead, and
/// gutta.toml's `symbols` key removed.
fn fold_table_into_source(dir: &Path) {
    let table = read(&dir.join("symbols.csv"));
    let declarations: String = table
        .lines()
        .skip(1)
        .filter_map(|row| {
            let mut fields = row.split(',');
            Some(format!("  {} : {}\n", fields.next()?, fields.next()?))
        })
        .collect();
    let main = dir.join("src/main.lad");
    let source = read(&main).replacen("SYMBOLS\n", &format!("SYMBOLS\n{declarations}"), 1);
    write(&main, &source);
    edit_manifest(dir, |text| {
        text.lines()
            .filter(|l| !l.starts_with("symbols ="))
            .map(|l| format!("{l}\n"))
            .collect()
    });
}

/// gutta.toml of the project in `dir`, rewritten by `edit`.
pub fn edit_manifest(dir: &Path, edit: impl FnOnce(&str) -> String) {
    let path = dir.join("gutta.toml");
    let text = edit(&read(&path));
    write(&path, &text);
}

/// The `[connection]` of the project in `dir` pointed at `address` (Modbus TCP).
pub fn connect_to(dir: &Path, address: &str) {
    edit_manifest(dir, |text| text.replace("127.0.0.1:5020", address));
}

pub fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

pub fn write(path: &Path, text: &str) {
    std::fs::write(path, text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
}
