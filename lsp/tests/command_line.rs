//! The binary's command line: `--help` and `--version` print and exit 0 without
//! serving, an unknown argument is a usage error with status 2, and `--stdio` (which
//! VS Code's language client passes) serves as without it.

use std::io::Write;
use std::process::{Command, Output, Stdio};

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gutta-lsp"))
        .args(args)
        .stdin(Stdio::null())
        .output()
        .expect("run gutta-lsp")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn help_says_what_it_is_and_exits_0() {
    for flag in ["--help", "-h"] {
        let out = run(&[flag]);
        let stdout = text(&out.stdout);
        assert_eq!(out.status.code(), Some(0), "{flag}: {}", text(&out.stderr));
        assert!(stdout.contains("language server"), "{stdout}");
        assert!(stdout.contains("standard\ninput and output"), "{stdout}");
        assert!(stdout.contains("docs/editors.md"), "{stdout}");
        assert!(stdout.contains("--version"), "{stdout}");
        assert!(out.stderr.is_empty(), "{}", text(&out.stderr));
    }
}

#[test]
fn version_prints_the_package_version_and_exits_0() {
    for flag in ["--version", "-V"] {
        let out = run(&[flag]);
        assert_eq!(out.status.code(), Some(0), "{flag}: {}", text(&out.stderr));
        assert_eq!(
            text(&out.stdout),
            format!("gutta-lsp {}\n", env!("CARGO_PKG_VERSION"))
        );
    }
}

#[test]
fn an_unknown_argument_is_a_usage_error() {
    let out = run(&["--bogus"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty(), "{}", text(&out.stdout));
    let stderr = text(&out.stderr);
    assert!(
        stderr.starts_with("gutta-lsp: unexpected argument `--bogus`"),
        "{stderr}"
    );
    assert!(stderr.contains("Usage: gutta-lsp"), "{stderr}");
    assert!(!stderr.contains("disconnected channel"), "{stderr}");
}

/// `gutta-lsp --stdio` serves: an initialize request gets its result, and
/// shutdown + exit end it with status 0.
#[test]
fn stdio_flag_serves() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-lsp"))
        .arg("--stdio")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start gutta-lsp");
    let messages = [
        r#"{"jsonrpc":"2.0","id":1,"method":"initialize","params":{"capabilities":{}}}"#,
        r#"{"jsonrpc":"2.0","method":"initialized","params":{}}"#,
        r#"{"jsonrpc":"2.0","id":2,"method":"shutdown"}"#,
        r#"{"jsonrpc":"2.0","method":"exit"}"#,
    ];
    let mut stdin = child.stdin.take().expect("stdin");
    for m in messages {
        write!(stdin, "Content-Length: {}\r\n\r\n{m}", m.len()).expect("write");
    }
    drop(stdin);
    let out = child.wait_with_output().expect("wait");
    let stdout = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(stdout.contains(r#""name":"gutta-lsp""#), "{stdout}");
}
