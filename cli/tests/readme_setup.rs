//! The README's set-up as a newcomer meets it: the first command's output is what the
//! README says it prints, every install line pins Cargo.lock (`--locked`), and the
//! release profile ships lean binaries. Reads README.md, docs/ and Cargo.toml; runs the
//! binaries the first command names (never cargo itself).

mod common;

use std::process::Command;

use common::docs::{read, repo};

/// The body of the first fenced block of `lang` after `heading` in `text`.
fn block_after<'a>(text: &'a str, heading: &str, lang: &str) -> &'a str {
    let from = text
        .find(heading)
        .unwrap_or_else(|| panic!("README has no `{heading}`"));
    let fence = format!("```{lang}\n");
    let start = text[from..]
        .find(&fence)
        .map(|i| from + i + fence.len())
        .unwrap_or_else(|| panic!("no ```{lang} block after `{heading}`"));
    let end = text[start..].find("```").expect("the block ends") + start;
    &text[start..end]
}

/// `cargo run [-q] -p gutta-cli --bin NAME -- ARGS` as (NAME, ARGS).
fn cargo_run(command: &str) -> (String, Vec<String>) {
    let words: Vec<&str> = command.split_whitespace().collect();
    assert_eq!(&words[..2], ["cargo", "run"], "{command}");
    let bin = words
        .iter()
        .position(|w| *w == "--bin")
        .map(|i| words[i + 1])
        .unwrap_or_else(|| panic!("no --bin in `{command}`"));
    let dashes = words
        .iter()
        .position(|w| *w == "--")
        .unwrap_or_else(|| panic!("no -- in `{command}`"));
    (
        bin.to_string(),
        words[dashes + 1..].iter().map(|w| w.to_string()).collect(),
    )
}

fn binary(name: &str) -> &'static str {
    match name {
        "gutta-cc" => env!("CARGO_BIN_EXE_gutta-cc"),
        "gutta-vm" => env!("CARGO_BIN_EXE_gutta-vm"),
        "gutta-sim" => env!("CARGO_BIN_EXE_gutta-sim"),
        other => panic!("the README runs an unknown binary {other}"),
    }
}

#[test]
fn the_first_command_prints_what_the_readme_says() {
    let readme = read(&repo().join("README.md"));
    let commands = block_after(&readme, "## Two commands", "sh");
    let first = commands
        .lines()
        .find(|l| l.starts_with("cargo run"))
        .expect("the first command");
    // It shows the build's progress: not quiet until its binary runs.
    let (build, _) = first.split_once("&&").expect("compile && run");
    assert!(
        !build.contains(" -q"),
        "the first cargo run must show the build's progress: {first}"
    );

    let shown = block_after(&readme, "it prints:", "console");
    let (prompt, expected) = shown.split_once('\n').expect("a command and its output");
    let prompt = prompt.strip_prefix("$ ").expect("a `$ ` command line");
    assert_eq!(
        prompt.replace(" -q", ""),
        first.replace(" -q", ""),
        "the console block shows the first command"
    );

    let work = std::env::temp_dir().join(format!("gutta-readme-first-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(work.join("examples")).expect("work dir");
    let example = "in1001_pointers.lad";
    std::fs::copy(
        repo().join("examples").join(example),
        work.join("examples").join(example),
    )
    .expect("copy the example");

    let mut actual = String::new();
    for step in first.split("&&") {
        let (bin, args) = cargo_run(step.trim());
        let out = Command::new(binary(&bin))
            .args(&args)
            .current_dir(&work)
            .env("NO_COLOR", "1")
            .output()
            .expect("runs");
        assert!(out.status.success(), "{bin} {args:?}: {out:?}");
        actual.push_str(&String::from_utf8_lossy(&out.stderr));
        actual.push_str(&String::from_utf8_lossy(&out.stdout));
    }
    let _ = std::fs::remove_dir_all(&work);
    assert_eq!(actual, expected, "README.md's first command output");
    assert!(
        expected.contains("MW24 = 3585"),
        "the README explains 3585: {expected}"
    );
}

/// Every `cargo install` of our packages the docs show pins the lockfile, as CI builds.
#[test]
fn every_install_line_is_locked() {
    let root = repo();
    let mut files = vec![root.join("README.md"), root.join("ARCHITECTURE.md")];
    for dir in ["docs", "editors/vscode", "editors/vscode/src"] {
        for entry in std::fs::read_dir(root.join(dir)).expect("dir") {
            let path = entry.expect("entry").path();
            if path.is_file() {
                files.push(path);
            }
        }
    }
    let mut unlocked = Vec::new();
    for file in &files {
        for (n, line) in read(file).lines().enumerate() {
            let ours = line.contains("cargo install") && line.contains("--path");
            if ours && !line.contains("--locked") {
                unlocked.push(format!("{}:{}: {line}", file.display(), n + 1));
            }
        }
    }
    assert!(
        unlocked.is_empty(),
        "install with --locked:\n{}",
        unlocked.join("\n")
    );
}

/// The `key = value` lines of one `[section]` of a TOML file.
fn section<'a>(toml: &'a str, name: &str) -> Vec<(&'a str, &'a str)> {
    let header = format!("[{name}]");
    let mut inside = false;
    let mut keys = Vec::new();
    for line in toml.lines().map(str::trim) {
        if line.starts_with('[') {
            inside = line == header;
        } else if inside {
            if let Some((k, v)) = line.split_once('=') {
                keys.push((k.trim(), v.trim()));
            }
        }
    }
    keys
}

#[test]
fn release_binaries_are_lean_and_a_profile_keeps_symbols() {
    let manifest = read(&repo().join("Cargo.toml"));
    let release = section(&manifest, "profile.release");
    assert!(
        release.contains(&("debug", "false")) && release.contains(&("strip", "\"debuginfo\"")),
        "[profile.release] ships no debug info: {release:?}"
    );
    let profiling = section(&manifest, "profile.profiling");
    assert!(
        profiling.contains(&("inherits", "\"release\"")) && profiling.contains(&("debug", "1")),
        "[profile.profiling] is release with symbols: {profiling:?}"
    );
    let bench = section(&manifest, "profile.bench");
    assert!(
        bench.contains(&("strip", "\"none\"")),
        "benches keep their symbols for profilers: {bench:?}"
    );
}
