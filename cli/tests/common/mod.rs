//! Shared by the tests that run the binaries: compile a program for CPU-EC20, write it
//! as an image directory for a `gutta-sim` process, read its listener lines, and check
//! for the external tools (Modbus clients) some tests drive.

#![allow(dead_code)]

use std::io::Write;
use std::path::PathBuf;

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_format::Image;

/// How to get every external tool these tests use.
pub const INSTALL: &str = "run `bash .ci/run`, or: apt-get install mbpoll socat \
     tmux libmodbus-dev pkg-config; python3 -m venv .ci/venv && .ci/venv/bin/pip install \
     pymodbus==3.6.9; export GUTTA_PYTHON=$PWD/.ci/venv/bin/python";

/// The environment variable that declares the external tools absent.
pub const SKIP_EXTERNAL: &str = "GUTTA_SKIP_EXTERNAL";

/// `text` compiled for CPU-EC20 (it must compile).
pub fn image(name: &str, text: &str) -> Image {
    let target = stdlib::shared("CPU-EC20").expect("target");
    let c = compile(
        SourceFile::new(name, text),
        Some(&ExplicitTarget {
            target,
            origin: "test".into(),
        }),
    );
    c.image
        .unwrap_or_else(|| panic!("{name} does not compile: {:?}", c.checked.diagnostics()))
}

/// An example of examples/ compiled for CPU-EC20.
pub fn example(name: &str) -> Image {
    let path = format!("{}/../examples/{name}", env!("CARGO_MANIFEST_DIR"));
    image(name, &std::fs::read_to_string(path).expect("example"))
}

/// `image` written to a fresh directory named after `tag` and this process.
pub fn image_dir(tag: &str, image: &Image) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gutta-sim-test-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    gutta_io::write_image(&dir, image).expect("writes");
    dir
}

/// A tool the test needs is missing: the test fails and says how to install it, unless
/// the environment declares the external tools absent (`GUTTA_SKIP_EXTERNAL=1`); then it
/// says that it skipped, on the real stderr (not captured), and the caller returns.
pub fn tool_missing(why: &str) {
    if std::env::var(SKIP_EXTERNAL).is_ok_and(|v| v == "1") {
        let _ = writeln!(
            std::io::stderr(),
            "skipped: {why} ({SKIP_EXTERNAL}=1 declares the external tools absent)"
        );
        return;
    }
    panic!(
        "{why}. This test needs external tools: {INSTALL}. \
         Or set {SKIP_EXTERNAL}=1 to skip the tests that need them."
    );
}

/// Whether a command is on PATH (`tool_missing` when not).
pub fn have(tool: &str) -> bool {
    let found = std::process::Command::new("sh")
        .args(["-c", &format!("command -v {tool}")])
        .output()
        .is_ok_and(|o| o.status.success());
    if !found {
        tool_missing(&format!("{tool} is not installed"));
    }
    found
}

/// The port of a `gutta-sim: WHAT on HOST:PORT` listener line.
pub fn listener_port(line: &str, what: &str) -> u16 {
    assert!(line.contains(what), "{line}");
    line.rsplit(':')
        .next()
        .and_then(|p| p.parse().ok())
        .unwrap_or_else(|| panic!("no port in `{line}`"))
}
