//! The end-to-end suite (lsp/tests/e2e, pytest-lsp) against the real `gutta-lsp` binary:
//! `$GUTTA_PYTHON -m pytest lsp/tests/e2e -q` with `GUTTA_LSP` set to this package's
//! binary. GUTTA_PYTHON is the .ci venv's Python with pytest-lsp; without it the test
//! fails saying how to make one, unless GUTTA_SKIP_EXTERNAL=1.

mod external;

use std::process::Command;

/// The Python that has pytest-lsp: `$GUTTA_PYTHON` (or `tool_missing`).
fn python() -> Option<String> {
    let Ok(python) = std::env::var("GUTTA_PYTHON") else {
        external::tool_missing("GUTTA_PYTHON is not set (the Python of a venv with pytest-lsp)");
        return None;
    };
    let has = Command::new(&python)
        .args(["-c", "import pytest, pytest_lsp"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !has {
        external::tool_missing(&format!("{python} cannot import pytest and pytest_lsp"));
        return None;
    }
    Some(python)
}

#[test]
fn pytest_lsp_suite_passes_against_the_binary() {
    let Some(python) = python() else { return };
    let root = external::repo_root();
    let out = Command::new(python)
        .args(["-m", "pytest", "lsp/tests/e2e", "-q", "-p", "no:cacheprovider"])
        .current_dir(&root)
        .env("GUTTA_LSP", env!("CARGO_BIN_EXE_gutta-lsp"))
        .env("PYTHONDONTWRITEBYTECODE", "1")
        .output()
        .expect("pytest starts");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "the pytest-lsp suite failed ({}):\n{stdout}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains(" passed"), "pytest ran no test:\n{stdout}");
}
