//! The studio's browser suite (cli/tests/studio_e2e, docs/studio.md "Tests"): pytest with
//! Playwright driving Debian's Chromium (`executable_path`, never Playwright's own
//! browser download) against the real `gutta-cc studio` and `gutta-sim` binaries:
//! `$GUTTA_PYTHON -m pytest cli/tests/studio_e2e -q`. GUTTA_PYTHON is the .ci venv's
//! Python with pytest and playwright; without it, or without `chromium`, the test fails
//! saying how to install them, unless GUTTA_SKIP_EXTERNAL=1. The suite writes its
//! screenshots into this build's test folder, and into docs/images/studio/ (the ones
//! docs/studio.md shows) when GUTTA_UPDATE_SCREENSHOTS=1.

mod common;

use std::process::Command;

/// The Python that has pytest and playwright: `$GUTTA_PYTHON` (or `tool_missing`).
fn python() -> Option<String> {
    let Ok(python) = std::env::var("GUTTA_PYTHON") else {
        common::tool_missing(
            "GUTTA_PYTHON is not set (the Python of a venv with pytest and playwright, .ci/run)",
        );
        return None;
    };
    let has = Command::new(&python)
        .args(["-c", "import pytest, playwright.sync_api"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !has {
        common::tool_missing(&format!("{python} cannot import pytest and playwright"));
        return None;
    }
    Some(python)
}

#[test]
fn the_studio_browser_suite_passes() {
    let Some(python) = python() else { return };
    if !common::have("chromium") {
        return;
    }
    let root = common::root();
    let shots = if std::env::var("GUTTA_UPDATE_SCREENSHOTS").is_ok_and(|v| v == "1") {
        root.join("docs/images/studio")
    } else {
        std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("studio-screenshots")
    };
    std::fs::create_dir_all(&shots).expect("creates the screenshot folder");
    let out = Command::new(python)
        .args([
            "-m",
            "pytest",
            "cli/tests/studio_e2e",
            "-q",
            "-p",
            "no:cacheprovider",
        ])
        .current_dir(&root)
        .env("GUTTA_CC", env!("CARGO_BIN_EXE_gutta-cc"))
        .env("GUTTA_SIM", env!("CARGO_BIN_EXE_gutta-sim"))
        .env("GUTTA_SCREENSHOTS", &shots)
        .env_remove("GUTTA_PASSWORD")
        .env("PYTHONDONTWRITEBYTECODE", "1")
        .output()
        .expect("pytest starts");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "the studio's browser suite failed ({}):\n{stdout}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains(" passed"), "pytest ran no test:\n{stdout}");
}

/// The screenshots docs/studio.md shows are the suite's: every `images/studio/NAME.png`
/// the docs name is in docs/images/studio and is taken by a `shoot(page, "NAME")` of
/// the suite, and every PNG there is shown by the docs (none left over).
#[test]
fn the_docs_screenshots_are_the_suites() {
    let root = common::root();
    let mut docs = String::new();
    for page in ["docs/studio.md", "docs/editors.md", "docs/ladder.md"] {
        docs.push_str(&std::fs::read_to_string(root.join(page)).expect("reads the docs"));
    }
    let mut suite = String::new();
    for entry in std::fs::read_dir(root.join("cli/tests/studio_e2e")).expect("the suite") {
        let path = entry.expect("entry").path();
        if path.extension().is_some_and(|e| e == "py") {
            suite.push_str(&std::fs::read_to_string(&path).expect("reads a test file"));
        }
    }
    let shown: std::collections::BTreeSet<&str> = docs
        .split("images/studio/")
        .skip(1)
        .filter_map(|rest| rest.split_once(".png").map(|(name, _)| name))
        .collect();
    assert!(!shown.is_empty(), "docs/studio.md shows no screenshot");
    for name in &shown {
        assert!(
            root.join(format!("docs/images/studio/{name}.png"))
                .is_file(),
            "docs show images/studio/{name}.png, which is not in docs/images/studio"
        );
        assert!(
            suite.contains(&format!("shoot(page, \"{name}\")")),
            "no test of cli/tests/studio_e2e takes the screenshot {name:?}"
        );
    }
    for entry in std::fs::read_dir(root.join("docs/images/studio")).expect("the images") {
        let path = entry.expect("entry").path();
        let name = path
            .file_stem()
            .expect("a name")
            .to_string_lossy()
            .into_owned();
        assert!(
            shown.contains(name.as_str()),
            "docs/images/studio/{name}.png is shown by no page of the docs"
        );
    }
}
