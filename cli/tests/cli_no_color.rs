//! NO_COLOR as no-color.org says, with the real `gutta-cc` printing a diagnostic on a
//! terminal (a pseudo-terminal from util-linux `script`): set and non-empty it turns
//! colour off, an empty value is ignored, and `--color always` still wins.

mod common;

use std::process::Command;

const PROGRAM: &str = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLD SM0.0\nMOVB 1, VB100\nEND_ORGANIZATION_BLOCK\n";

/// What `gutta-cc --check vb.lad EXTRA` prints on a terminal with NO_COLOR as given
/// (`None`: unset).
fn on_a_terminal(no_color: Option<&str>, extra: &str) -> String {
    let dir = std::env::temp_dir().join(format!("gutta-cli-no-color-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let file = dir.join("vb.lad");
    std::fs::write(&file, PROGRAM).expect("write");
    let line = format!(
        "{} --check {extra} {}",
        env!("CARGO_BIN_EXE_gutta-cc"),
        file.display()
    );
    let mut command = Command::new("script");
    command
        .args(["-qec", &line, "/dev/null"])
        .env_remove("NO_COLOR");
    if let Some(value) = no_color {
        command.env("NO_COLOR", value);
    }
    let out = command.output().expect("script runs");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(text.contains("error"), "no diagnostic: {text}");
    text
}

fn coloured(text: &str) -> bool {
    text.contains("\u{1b}[")
}

#[test]
fn no_color_follows_no_color_org() {
    if !common::have("script") {
        return;
    }
    assert!(coloured(&on_a_terminal(None, "")), "a terminal gets colour");
    assert!(
        !coloured(&on_a_terminal(Some("1"), "")),
        "NO_COLOR=1 turns it off"
    );
    assert!(
        coloured(&on_a_terminal(Some(""), "")),
        "an empty NO_COLOR is ignored"
    );
    assert!(
        coloured(&on_a_terminal(Some("1"), "--color always")),
        "--color always wins"
    );
    assert!(!coloured(&on_a_terminal(None, "--color never")));
}
