//! Shared by the tests that drive external programs against the real `gutta-lsp`
//! binary or the editor files (npm for the VS Code extension, the .ci venv's pytest-lsp,
//! Neovim): whether a tool is there, and the rule for when it is not. Holds no LSP
//! logic; the in-process helper is `tests/common`.

#![allow(dead_code)]

#[path = "../../../cli/tests/common/external.rs"]
mod rule;

use std::path::{Path, PathBuf};
use std::process::Command;

/// How to get every external tool these tests use (`.ci/run` does all of it).
pub const INSTALL: &str = "run `bash .ci/run`, or: apt-get install neovim; Node.js 20 or \
     newer with npm; python3 -m venv .ci/venv && .ci/venv/bin/pip install pytest==9.2.0 \
     pytest-lsp==1.0.1; export GUTTA_PYTHON=$PWD/.ci/venv/bin/python";

/// A tool the test needs is missing: fail with the install hint (or skip, see
/// `external.rs`).
pub fn tool_missing(why: &str) {
    rule::tool_missing(INSTALL, why);
}

/// Whether a command is on PATH (`tool_missing` when not).
pub fn have(tool: &str) -> bool {
    rule::have(INSTALL, tool)
}

/// The repository's root folder.
pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("lsp/ has a parent")
        .to_path_buf()
}

/// A fresh, empty scratch folder for `tag`, unique to this process.
pub fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gutta-lsp-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

/// Copy the folder `from` into `to`, leaving out folders named in `skip`.
pub fn copy_tree(from: &Path, to: &Path, skip: &[&str]) {
    std::fs::create_dir_all(to).expect("creates");
    for entry in std::fs::read_dir(from).expect("reads") {
        let entry = entry.expect("entry");
        let name = entry.file_name();
        if skip.iter().any(|s| name == **s) {
            continue;
        }
        let path = entry.path();
        if entry.file_type().expect("type").is_dir() {
            copy_tree(&path, &to.join(&name), skip);
        } else {
            std::fs::copy(&path, to.join(&name)).expect("copies");
        }
    }
}

/// Run `command`, panicking with its output when it fails; its stdout.
pub fn run(command: &mut Command, what: &str) -> String {
    let out = command
        .output()
        .unwrap_or_else(|e| panic!("{what}: could not start: {e}"));
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{what} failed ({}):\n--- stdout\n{stdout}\n--- stderr\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

/// The workspace's `gutta-sim` (another package's binary, so no CARGO_BIN_EXE; the
/// workspace's `cargo test` builds it).
pub fn sim_binary() -> PathBuf {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| repo_root().join("target"));
    let path = target.join("debug/gutta-sim");
    assert!(
        path.exists(),
        "{} is missing: build it first with `cargo build -p gutta-cli --bin gutta-sim`",
        path.display()
    );
    path
}
