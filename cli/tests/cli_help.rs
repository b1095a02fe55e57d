//! The help of the three tools as users read it: `gutta-cc --help` lists every command
//! under a task group, every command's `--help` ends with 2-4 examples, and the examples
//! are run for real so they stay true: the offline ones (compile, dis, explain, man,
//! gutta-vm...) in a scratch directory, the online ones against a `gutta-sim`. No help
//! text names a vendor or seed document or a source file.

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

use common::{cc, stderr, stdout};

const CC: &str = env!("CARGO_BIN_EXE_gutta-cc");
const VM: &str = env!("CARGO_BIN_EXE_gutta-vm");
const SIM: &str = env!("CARGO_BIN_EXE_gutta-sim");

/// The program the examples name `main.lad`: line 12 holds an instruction (the debug
/// example breaks there) and it uses every address the examples read or write.
const MAIN_LAD: &str = "// main.lad: the program of the examples in gutta-cc's help.
ORGANIZATION_BLOCK MAIN:OB1
BEGIN
Network 1 // Q0.0 follows I0.0
LD     I0.0
=      Q0.0
Network 2 // MW24 counts scans
LD     SM0.0
INCW   MW24
MOVW   AIW0, MW26
MOVB   IB0, MB30
MOVD   MD4, MD8
END_ORGANIZATION_BLOCK
";

/// The group headings of `gutta-cc --help`, in order.
const GROUPS: &[&str] = &["Build:", "Online", "Inspect:", "Shell:"];

fn ok(out: &Output) -> String {
    assert_eq!(out.status.code(), Some(0), "{}{}", stdout(out), stderr(out));
    stdout(out)
}

/// The commands `gutta-cc --help` lists under its groups (the pseudo-entry of source
/// files and `help` aside), and whether a group other than ours appeared.
fn listed_commands(help: &str) -> Vec<String> {
    let mut commands = Vec::new();
    let mut in_group = false;
    for line in help.lines() {
        if !line.starts_with(' ') && !line.is_empty() {
            assert!(
                !line.starts_with("Other:"),
                "a command is in no group:\n{help}"
            );
            in_group = GROUPS.iter().any(|g| line.starts_with(g));
        } else if in_group && line.starts_with("  ") {
            let name = line.split_whitespace().next().unwrap_or("");
            if !name.ends_with("...") && name != "help" {
                commands.push(name.to_string());
            }
        }
    }
    commands
}

/// The example lines of a help text: the indented lines after `Examples:`, without
/// their `# comment`.
fn examples(help: &str) -> Vec<String> {
    help.lines()
        .skip_while(|l| !l.starts_with("Examples:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .map(|l| l.split(" # ").next().unwrap_or(l).trim().to_string())
        .collect()
}

#[test]
fn the_help_groups_commands_by_task() {
    let help = ok(&cc(&["--help"]));
    let mut at = 0;
    for group in GROUPS {
        let found = help[at..].find(group).map(|i| i + at);
        at = found.unwrap_or_else(|| panic!("{group} missing or out of order:\n{help}"));
    }
    let commands = listed_commands(&help);
    for command in [
        "download",
        "read",
        "force",
        "debug",
        "dis",
        "explain",
        "completions",
        "man",
    ] {
        assert!(
            commands.iter().any(|c| c == command),
            "{command} not listed:\n{help}"
        );
    }
}

#[test]
fn every_command_ends_its_help_with_examples() {
    let help = ok(&cc(&["--help"]));
    for command in listed_commands(&help) {
        let text = ok(&cc(&[&command, "--help"]));
        let lines = examples(&text);
        assert!(
            (2..=4).contains(&lines.len()),
            "`gutta-cc {command} --help` has {} examples:\n{text}",
            lines.len()
        );
        let tail = text.trim_end().lines().last().unwrap_or("");
        assert!(
            lines.iter().any(|l| tail.contains(l.as_str())),
            "{command}: examples are not last:\n{text}"
        );
    }
    for tool in [VM, SIM] {
        let text = ok(&std::process::Command::new(tool)
            .arg("--help")
            .output()
            .expect("runs"));
        assert!((2..=4).contains(&examples(&text).len()), "{text}");
    }
}

#[test]
fn gutta_sim_help_says_ctrl_c_exits_0() {
    let text = ok(&std::process::Command::new(SIM)
        .arg("--help")
        .output()
        .expect("runs"));
    assert!(
        text.contains("Ctrl-C") && text.contains("exits 0"),
        "{text}"
    );
}

/// A scratch directory holding `main.lad`.
fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gutta-cli-examples-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    std::fs::write(dir.join("main.lad"), MAIN_LAD).expect("main.lad");
    dir
}

/// Run one example line with bash in `dir`, the tools first on PATH; each line is its
/// own shell (`gutta-cc new demo && cd demo && gutta-cc build` for a project).
fn run_example(dir: &Path, line: &str) -> Output {
    let bin = Path::new(CC).parent().expect("bin dir");
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    // An example must end by itself (a `watch` example takes --once): a minute at most.
    std::process::Command::new("timeout")
        .args(["60", "bash", "-c", &format!("set -o pipefail; {line}")])
        .current_dir(dir)
        .env("PATH", path)
        .env("MANPAGER", "cat")
        .env_remove("GUTTA_PASSWORD")
        .output()
        .expect("bash runs")
}

/// Whether an example talks to a PLC.
fn online(line: &str) -> bool {
    ["--tcp", "--rtu-tcp", "--serial"]
        .iter()
        .any(|f| line.contains(f))
}

/// The examples of gutta-cc (its own first, then each command's in help order) and of
/// gutta-vm.
fn all_examples() -> Vec<String> {
    let help = ok(&cc(&["--help"]));
    let mut lines = examples(&help);
    for command in listed_commands(&help) {
        lines.extend(examples(&ok(&cc(&[&command, "--help"]))));
    }
    let vm = ok(&std::process::Command::new(VM)
        .arg("--help")
        .output()
        .expect("runs"));
    lines.extend(examples(&vm));
    lines
}

#[test]
fn the_offline_examples_run() {
    let dir = scratch("offline");
    let mut ran = 0;
    for line in all_examples().iter().filter(|l| !online(l)) {
        let out = run_example(&dir, line);
        assert_eq!(
            out.status.code(),
            Some(0),
            "`{line}`:\n{}{}",
            stdout(&out),
            stderr(&out)
        );
        ran += 1;
    }
    assert!(ran >= 15, "only {ran} offline examples");
    assert!(dir.join("image/manifest.json").exists());
    assert!(dir.join("man/gutta-cc-download.1").exists());
}

#[test]
fn the_online_examples_run_against_the_simulator() {
    let dir = scratch("online");
    assert!(run_example(&dir, "gutta-cc main.lad -o image/")
        .status
        .success());
    let sim = common::sim("CPU-EC20", None);
    let mut ran = 0;
    for line in all_examples()
        .iter()
        .filter(|l| l.contains("--tcp 127.0.0.1:5020"))
    {
        let line = line.replace("127.0.0.1:5020", &sim.1);
        let out = run_example(&dir, &line);
        assert_eq!(
            out.status.code(),
            Some(0),
            "`{line}`:\n{}{}",
            stdout(&out),
            stderr(&out)
        );
        ran += 1;
    }
    assert!(ran >= 15, "only {ran} online examples");
}

/// What help texts must not name: the vendor documents, the project's seed documents,
/// source files and their folders. Users get docs/*.md pages and words instead.
const INTERNAL_REFERENCES: &[&str] = &["UM4001", "IN1001", "AN2002", "seed", ".rs", "../shared"];

/// The subcommands a `Commands:` section lists (clap's own layout), `help` aside.
fn clap_commands(help: &str) -> Vec<String> {
    help.lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|name| *name != "help")
        .map(str::to_string)
        .collect()
}

#[test]
fn help_texts_name_no_internal_documents_or_source_files() {
    let run = |tool: &str, args: &[&str]| {
        ok(&std::process::Command::new(tool)
            .args(args)
            .output()
            .expect("runs"))
    };
    let mut helps: Vec<(String, String)> = Vec::new();
    for tool in [CC, VM, SIM] {
        for flag in ["-h", "--help"] {
            helps.push((format!("{tool} {flag}"), run(tool, &[flag])));
        }
    }
    let commands = listed_commands(&ok(&cc(&["--help"])));
    assert!(commands.iter().any(|c| c == "fx"), "{commands:?}");
    for command in &commands {
        for flag in ["-h", "--help"] {
            let text = run(CC, &[command, flag]);
            for sub in clap_commands(&text) {
                let name = format!("gutta-cc {command} {sub} {flag}");
                helps.push((name, run(CC, &[command, &sub, flag])));
            }
            helps.push((format!("gutta-cc {command} {flag}"), text));
        }
    }
    assert!(
        helps.iter().any(|(n, _)| n.contains("fx download-program")),
        "fx's subcommands were not found"
    );
    for (name, text) in &helps {
        for pattern in INTERNAL_REFERENCES {
            assert!(
                !text.to_lowercase().contains(&pattern.to_lowercase()),
                "`{name}` names `{pattern}`:\n{text}"
            );
        }
    }
}
