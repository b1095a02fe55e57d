//! Shell completions and man pages from the real binaries: gutta-cc's `completions` and
//! `man` commands, gutta-vm's and gutta-sim's `--completions` and `--man` flags. The
//! scripts are loaded by the real shells (bash always; zsh and fish when installed, see
//! common::INSTALL) and the pages rendered by groff and man without warnings. Every
//! script offers the stdlib PLC types for --plc.

mod common;

use std::process::{Command, Output, Stdio};

use common::{cc, have, stderr, stdout};

const CC: &str = env!("CARGO_BIN_EXE_gutta-cc");
const VM: &str = env!("CARGO_BIN_EXE_gutta-vm");
const SIM: &str = env!("CARGO_BIN_EXE_gutta-sim");

/// Commands every completion script and the man pages must name.
const SOME_COMMANDS: &[&str] = &["download", "read", "dis", "explain", "completions", "man"];

fn ok(out: Output) -> String {
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    stdout(&out)
}

fn tool(bin: &str, args: &[&str]) -> Output {
    Command::new(bin)
        .args(args)
        .output()
        .expect("the tool runs")
}

fn sh(shell: &str, script: &str) -> Output {
    Command::new(shell)
        .args(["-c", script])
        .env("CC_BIN", CC)
        .env("VM_BIN", VM)
        .env("SIM_BIN", SIM)
        .output()
        .expect("the shell runs")
}

#[test]
fn gutta_cc_scripts_name_the_commands() {
    for shell in ["bash", "zsh", "fish"] {
        let script = ok(cc(&["completions", shell]));
        for command in SOME_COMMANDS {
            assert!(script.contains(command), "{shell} script lacks {command}");
        }
        assert!(script.contains("rtu-tcp"), "{shell} script lacks --rtu-tcp");
    }
}

#[test]
fn every_script_offers_the_plc_types() {
    for shell in ["bash", "zsh", "fish"] {
        let scripts = [
            ("gutta-cc", ok(cc(&["completions", shell]))),
            ("gutta-vm", ok(tool(VM, &["--completions", shell]))),
            ("gutta-sim", ok(tool(SIM, &["--completions", shell]))),
        ];
        for (tool, script) in scripts {
            for plc in gutta_catalog::stdlib::names() {
                assert!(script.contains(plc), "{tool}'s {shell} script lacks {plc}");
            }
        }
    }
}

#[test]
fn bash_completes_a_plc_type() {
    // What bash offers after `gutta-cc status --plc EC30-EKS<TAB>`.
    let out = sh(
        "bash",
        r#"source <("$CC_BIN" completions bash)
COMP_WORDS=(gutta-cc status --plc EC30-EKS); COMP_CWORD=3; COMP_LINE="${COMP_WORDS[*]}"; COMP_POINT=${#COMP_LINE}
$(complete -p gutta-cc | sed -E 's/.* -F ([^ ]+) .*/\1/') gutta-cc EC30-EKS --plc
printf '%s\n' "${COMPREPLY[@]}""#,
    );
    let offered: Vec<String> = ok(out).lines().map(str::to_string).collect();
    assert_eq!(offered, ["EC30-EKSTM32", "EC30-EKSTM32-XC"], "{offered:?}");
}

#[test]
fn bash_loads_the_scripts() {
    let out = sh(
        "bash",
        r#"set -e
source <("$CC_BIN" completions bash); complete -p gutta-cc
source <("$VM_BIN" --completions bash); complete -p gutta-vm
source <("$SIM_BIN" --completions bash); complete -p gutta-sim"#,
    );
    let text = ok(out);
    for tool in ["gutta-cc", "gutta-vm", "gutta-sim"] {
        assert!(text.contains(&format!(" {tool}\n")), "{text}");
    }
}

#[test]
fn bash_completes_a_command() {
    // What bash offers after `gutta-cc dow<TAB>`.
    let out = sh(
        "bash",
        r#"source <("$CC_BIN" completions bash)
COMP_WORDS=(gutta-cc dow); COMP_CWORD=1; COMP_LINE="gutta-cc dow"; COMP_POINT=${#COMP_LINE}
$(complete -p gutta-cc | sed -E 's/.* -F ([^ ]+) .*/\1/') gutta-cc dow gutta-cc
printf '%s\n' "${COMPREPLY[@]}""#,
    );
    assert!(ok(out).lines().any(|l| l == "download"));
}

#[test]
fn zsh_loads_the_script() {
    if !have("zsh") {
        return;
    }
    let out = sh(
        "zsh",
        r#"autoload -U compinit && compinit -u -D
source <("$CC_BIN" completions zsh) && whence -w _gutta-cc
source <("$VM_BIN" --completions zsh) && whence -w _gutta-vm"#,
    );
    let text = ok(out);
    assert!(text.contains("_gutta-cc: function"), "{text}");
    assert!(text.contains("_gutta-vm: function"), "{text}");
}

#[test]
fn fish_loads_the_script() {
    if !have("fish") {
        return;
    }
    let out = sh(
        "fish",
        r#""$CC_BIN" completions fish | source; complete -C 'gutta-cc dow'
"$SIM_BIN" --completions fish | source; complete -C 'gutta-sim --scan'"#,
    );
    let text = ok(out);
    assert!(text.lines().any(|l| l.starts_with("download")), "{text}");
    assert!(text.contains("--scan-ms"), "{text}");
}

/// groff's warnings (-ww) on a page, which must render.
fn groff_warnings(page: &[u8]) -> String {
    use std::io::Write;
    let mut child = Command::new("groff")
        .args(["-man", "-Tutf8", "-ww", "-z"])
        .stdin(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("groff runs");
    child
        .stdin
        .take()
        .expect("stdin")
        .write_all(page)
        .expect("groff reads");
    let out = child.wait_with_output().expect("groff ends");
    assert!(out.status.success());
    stderr(&out)
}

#[test]
fn man_pages_are_written_one_per_command_and_render() {
    if !have("groff") || !have("man") {
        return;
    }
    let dir = std::env::temp_dir().join(format!("gutta-cli-man-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    ok(cc(&["man", "--output", dir.to_str().expect("utf-8")]));
    let mut pages: Vec<String> = std::fs::read_dir(&dir)
        .expect("written")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    pages.sort();
    assert!(pages.contains(&"gutta-cc.1".to_string()), "{pages:?}");
    for command in SOME_COMMANDS {
        assert!(
            pages.contains(&format!("gutta-cc-{command}.1")),
            "{pages:?}"
        );
    }
    for page in &pages {
        let text = std::fs::read(dir.join(page)).expect("page");
        assert_eq!(groff_warnings(&text), "", "{page}");
    }
    // man itself renders a page file, naming the command and its examples.
    let out = Command::new("man")
        .arg("-l")
        .arg(dir.join("gutta-cc-download.1"))
        .env("MANPAGER", "cat")
        .env("MANWIDTH", "100")
        .output()
        .expect("man runs");
    let text = ok(out);
    assert!(text.contains("gutta-cc-download"), "{text}");
    assert!(text.contains("--tcp"), "{text}");
    assert!(text.contains("Examples:"), "{text}");
}

#[test]
fn man_prints_one_page_on_stdout() {
    if !have("groff") {
        return;
    }
    let page = ok(cc(&["man"]));
    assert!(page.contains(".TH gutta-cc 1"), "{page}");
    assert_eq!(groff_warnings(page.as_bytes()), "");
    let page = ok(cc(&["man", "read"]));
    assert!(page.contains(".TH gutta-cc-read 1"), "{page}");
    for tool in [VM, SIM] {
        let page = ok(Command::new(tool).arg("--man").output().expect("runs"));
        assert!(page.contains(".TH gutta-"), "{page}");
        assert_eq!(groff_warnings(page.as_bytes()), "", "{tool}");
    }
}

#[test]
fn the_shell_flags_stand_alone() {
    // gutta-vm needs an image to run, but not to print its completions.
    let script = ok(Command::new(VM)
        .args(["--completions", "fish"])
        .output()
        .expect("runs"));
    assert!(script.contains("scan-ms"), "{script}");
    let out = Command::new(VM)
        .args(["--completions", "bash", "image/"])
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2), "--completions is used alone");
}

#[test]
fn an_unknown_plc_type_is_still_the_tools_error() {
    // The completion values do not make clap judge --plc: the tools' own error, with
    // the known names, stays.
    let wanted = "no stdlib PLC type `CPU-EC2` (known: CPU-EC20, ";
    let out = cc(&["modbus", "MW0", "--plc", "CPU-EC2"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains(wanted), "{}", stderr(&out));
    let out = tool(SIM, &["--plc", "CPU-EC2", "--tcp", "127.0.0.1:0"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains(wanted), "{}", stderr(&out));
}
