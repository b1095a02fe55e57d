//! Shared by the project tests (`project_*.rs`): a fresh folder, a project made in it by
//! the real `gutta-cc new`, and gutta.toml edits. It does not run sims or tmux (the
//! tests and tests/common do).

#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// An empty folder of this test process, named after `tag`.
pub fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gutta-project-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("creates the scratch folder");
    dir
}

/// `gutta-cc new NAME` run in a fresh scratch folder: the project's folder.
pub fn new_project(tag: &str, name: &str) -> PathBuf {
    let parent = scratch(tag);
    let o = crate::common::cc_in(&parent, &["new", name]);
    assert!(o.status.success(), "{}", crate::common::text(&o));
    parent.join(name)
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
