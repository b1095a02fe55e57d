//! The end-to-end suite (lsp/tests/e2e, pytest-lsp) against the real `gutta-lsp` binary:
//! `$GUTTA_PYTHON -m pytest lsp/tests/e2e -q` with `GUTTA_LSP` set to this package's
//! binary, `GUTTA_DOCS` to docs/ (the diagnostics' links), `GUTTA_SIM` to the
//! workspace's `gutta-sim` and `GUTTA_E2E_IMAGE` to lsp/tests/e2e/data/live/main.lad
//! compiled (for the live-values tests). GUTTA_PYTHON is the .ci venv's Python with
//! pytest-lsp; without it the test fails saying how to make one, unless
//! GUTTA_SKIP_EXTERNAL=1. gutta-sim is built by the workspace's `cargo test`; alone:
//! `cargo build -p gutta-cli --bin gutta-sim`.

mod external;

use std::path::{Path, PathBuf};
use std::process::Command;

use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};

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

/// The live-values program compiled into an image folder in `dir`.
fn live_image(root: &Path, dir: &Path) -> PathBuf {
    let name = "lsp/tests/e2e/data/live/main.lad";
    let text = std::fs::read_to_string(root.join(name)).expect("reads the live program");
    let explicit = ExplicitTarget {
        target: gutta_catalog::stdlib::shared("CPU-EC20").expect("stdlib target"),
        origin: "test".into(),
    };
    let compiled = compile(SourceFile::new(name, &text), Some(&explicit));
    let image = compiled
        .image
        .unwrap_or_else(|| panic!("{name}: {:?}", compiled.checked.diagnostics()));
    let out = dir.join("image");
    gutta_io::write_image(&out, &image).expect("writes the image");
    out
}

#[test]
fn pytest_lsp_suite_passes_against_the_binary() {
    let Some(python) = python() else { return };
    let root = external::repo_root();
    let work = external::scratch("pytest");
    let image = live_image(&root, &work);
    let out = Command::new(python)
        .args([
            "-m",
            "pytest",
            "lsp/tests/e2e",
            "-q",
            "-p",
            "no:cacheprovider",
        ])
        .current_dir(&root)
        .env("GUTTA_LSP", env!("CARGO_BIN_EXE_gutta-lsp"))
        .env("GUTTA_DOCS", root.join("docs"))
        .env("GUTTA_SIM", external::sim_binary())
        .env("GUTTA_E2E_IMAGE", &image)
        .env_remove("GUTTA_PASSWORD")
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
    let _ = std::fs::remove_dir_all(&work);
}
