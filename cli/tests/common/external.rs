//! The one rule for tests that need an external tool (a Modbus client, tmux, a shell,
//! Neovim, npm, a Python venv): when the tool is missing the test fails and says how to
//! install it, unless `GUTTA_SKIP_EXTERNAL=1` declares the tools absent. Shared by the
//! CLI tests (`tests/common`) and the language server's (`lsp/tests/external`, by path).

use std::io::Write;

/// The environment variable that declares the external tools absent.
pub const SKIP_EXTERNAL: &str = "GUTTA_SKIP_EXTERNAL";

/// A tool the test needs is missing: the test fails and says how to install it
/// (`install`), unless the environment declares the external tools absent; then it says
/// that it skipped, on the real stderr (not captured), and the caller returns.
pub fn tool_missing(install: &str, why: &str) {
    if std::env::var(SKIP_EXTERNAL).is_ok_and(|v| v == "1") {
        let _ = writeln!(
            std::io::stderr(),
            "skipped: {why} ({SKIP_EXTERNAL}=1 declares the external tools absent)"
        );
        return;
    }
    panic!(
        "{why}. This test needs external tools: {install}. \
         Or set {SKIP_EXTERNAL}=1 to skip the tests that need them."
    );
}

/// Whether a command is on PATH (`tool_missing` when not).
pub fn have(install: &str, tool: &str) -> bool {
    let found = std::process::Command::new("sh")
        .args(["-c", &format!("command -v {tool}")])
        .output()
        .is_ok_and(|o| o.status.success());
    if !found {
        tool_missing(install, &format!("{tool} is not installed"));
    }
    found
}
