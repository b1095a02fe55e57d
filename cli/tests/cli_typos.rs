//! `gutta-cc` with a word that is not a command: a near miss of a command is a usage
//! error with did-you-mean, a far one `no such file or command`, while source files (with
//! or without an extension, when they exist) still compile as before.

mod common;

use common::{cc, cc_in, stderr, stdout};

const PROGRAM: &str =
    "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLD SM0.0\n= Q0.0\nEND_ORGANIZATION_BLOCK\n";

fn temp_dir(tag: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("gutta-cli-typos-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

#[test]
fn a_mistyped_command_suggests_the_command() {
    let out = cc(&["donwload", "image/", "--tcp", "127.0.0.1:5020"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("unknown command 'donwload'; did you mean 'download'?"),
        "{}",
        stderr(&out)
    );
    let out = cc(&["--plc", "CPU-EC20", "stauts"]);
    assert!(
        stderr(&out).contains("did you mean 'status'?"),
        "{}",
        stderr(&out)
    );
    let out = cc(&["list-target"]);
    assert!(
        stderr(&out).contains("did you mean 'list-targets'?"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn a_word_far_from_every_command_lists_the_commands() {
    let out = cc(&["xyzzy"]);
    assert_eq!(out.status.code(), Some(2));
    let text = stderr(&out);
    assert!(text.contains("no such file or command 'xyzzy'"), "{text}");
    assert!(
        text.contains("commands: ") && text.contains("download"),
        "{text}"
    );
}

#[test]
fn source_files_still_compile_without_a_command() {
    let dir = temp_dir("files");
    std::fs::write(dir.join("main.lad"), PROGRAM).expect("write");
    let out = cc_in(&dir, &["main.lad", "-o", "image/"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(dir.join("image/manifest.json").exists());
    // A file without an extension whose name is close to a command: it exists, so it is
    // a file.
    std::fs::write(dir.join("stop"), PROGRAM).expect("write");
    let out = cc_in(&dir, &["--check", "stop"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    // A missing file with an extension is an I/O error, not a command.
    let out = cc_in(&dir, &["dwnload.lad"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("cannot read dwnload.lad"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn a_typo_is_a_json_usage_error_with_message_format_json() {
    let out = cc(&["--message-format", "json", "donwload", "image/"]);
    assert_eq!(out.status.code(), Some(2));
    let error: serde_json::Value = serde_json::from_str(stdout(&out).trim()).expect("JSON");
    assert_eq!(error["type"], "error");
    assert_eq!(error["kind"], "usage");
    assert_eq!(
        error["message"],
        "unknown command 'donwload'; did you mean 'download'?"
    );
    assert!(stderr(&out).is_empty(), "{}", stderr(&out));
}

#[test]
fn a_global_flag_before_a_command_keeps_the_command() {
    let out = cc(&["--plc", "CPU-EC20", "modbus", "MW20"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stdout(&out).contains("400019"), "{}", stdout(&out));
}

#[test]
fn help_of_a_mistyped_command_suggests_the_command() {
    let out = cc(&["help", "donwload"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let text = stderr(&out);
    assert!(
        text.contains("unknown command 'donwload'; did you mean 'download'?"),
        "{text}"
    );
    assert!(
        text.contains("hint: `gutta-cc help download` shows its usage"),
        "{text}"
    );
    let out = cc(&["help", "xyzzy"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("no such command 'xyzzy'"),
        "{}",
        stderr(&out)
    );
    // A real command's help is still help.
    let out = cc(&["help", "download"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stdout(&out).contains("Usage: gutta-cc download"));
}
