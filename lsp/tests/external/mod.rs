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

/// Headless Neovim as both Neovim tests run it: `nvim --headless --clean -u SCRIPT FILE`
/// in `work` (its caches there too), the built `gutta-lsp` first on PATH, the
/// repository's editors/neovim config and runtime named for the script
/// (`GUTTA_NVIM_CONFIG`, `GUTTA_NVIM_RUNTIME`), the answer to write to `out`
/// (`GUTTA_NVIM_OUT`) within 20 s (`GUTTA_NVIM_TIMEOUT_MS`). `script` is relative to
/// lsp/tests/neovim.
pub fn nvim(script: &str, file: &Path, work: &Path, out: &Path) -> Command {
    let root = repo_root();
    let server = Path::new(env!("CARGO_BIN_EXE_gutta-lsp"));
    let path = format!(
        "{}:{}",
        server.parent().expect("bin folder").display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let mut nvim = Command::new("nvim");
    nvim.args(["--headless", "--clean", "-u"])
        .arg(root.join("lsp/tests/neovim").join(script))
        .arg(file)
        .current_dir(work)
        .env("PATH", path)
        .env("XDG_CACHE_HOME", work.join("cache"))
        .env("XDG_STATE_HOME", work.join("state"))
        .env("XDG_DATA_HOME", work.join("data"))
        .env("GUTTA_NVIM_RUNTIME", root.join("editors/neovim"))
        .env(
            "GUTTA_NVIM_CONFIG",
            root.join("editors/neovim/gutta-lsp.lua"),
        )
        .env("GUTTA_NVIM_OUT", out)
        .env("GUTTA_NVIM_TIMEOUT_MS", "20000");
    nvim
}

/// Run headless Neovim as `nvim` sets it up (a script that writes its answer as JSON
/// to `out` and quits), at most 60 s, and return that answer; fails with Neovim's stderr
/// when it does not quit, quits with an error or writes no answer.
pub fn nvim_answer(nvim: &mut Command, out: &Path) -> serde_json::Value {
    use std::process::Stdio;
    use std::time::{Duration, Instant};
    let mut child = nvim
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("nvim starts");
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("waits") {
            break status;
        }
        if started.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("nvim did not quit within 60 s");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let mut stderr = String::new();
    if let Some(mut e) = child.stderr.take() {
        let _ = std::io::Read::read_to_string(&mut e, &mut stderr);
    }
    assert!(status.success(), "nvim: {status}\n{stderr}");
    let answer = std::fs::read_to_string(out)
        .unwrap_or_else(|e| panic!("nvim wrote no answer ({e}); stderr:\n{stderr}"));
    serde_json::from_str(&answer).expect("JSON")
}
