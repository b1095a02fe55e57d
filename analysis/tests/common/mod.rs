//! Shared helpers of the analysis's integration tests: where the repository is, and
//! which programs the tests run over.

#![allow(clippy::disallowed_methods, reason = "tests read their data files")]
#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// The repository root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The `.lad` files of a directory, sorted.
pub fn lad_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("dir entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "lad"))
        .collect();
    files.sort();
    files
}
