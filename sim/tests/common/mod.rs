//! Shared by the simulator's tests: compile a program for CPU-EC20, and write it as an
//! image directory for a `gutta-sim` process.

#![allow(dead_code)]

use std::path::PathBuf;

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_format::Image;

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

/// A tool the test needs is missing: fails when the CI requires the tools
/// (GUTTA_REQUIRE_TOOLS, set by `.ci/run`), else says the test skipped.
pub fn tool_missing(why: &str) {
    assert!(
        std::env::var("GUTTA_REQUIRE_TOOLS").is_err(),
        "{why} (GUTTA_REQUIRE_TOOLS is set, so the tools are required)"
    );
    eprintln!("skipped: {why} (bash .ci/run installs it)");
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
