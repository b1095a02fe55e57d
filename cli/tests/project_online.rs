//! A project online, through the real binaries: `gutta-cc download` in a new project
//! builds it and downloads into a `gutta-sim` at gutta.toml's `[connection]`; client
//! commands reach the PLC from there (`debug` with the project's source map), flags
//! override it, and a build error stops before connecting. Under tmux, the download's progress bar and its summary agree on the
//! byte count.

mod common;
mod projects;

use std::time::{Duration, Instant};

use common::{cc_in, stderr, stdout, text};
use projects::{connect_to, edit_manifest, new_project, read, write};

/// An address where no PLC answers (nothing listens on port 1 of the loopback).
const NOBODY: &str = "127.0.0.1:1";

#[test]
fn download_builds_the_project_and_reaches_the_plc_of_gutta_toml() {
    let sim = common::sim("CPU-EC20", None);
    let dir = new_project("online", "online");
    connect_to(&dir, &sim.1);
    let o = cc_in(&dir, &["download"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        stderr(&o).contains("src/main.lad: wrote target/image for CPU-EC20"),
        "the build's summary: {}",
        stderr(&o)
    );
    assert!(
        stdout(&o).contains("the PLC verified and runs the image"),
        "{}",
        stdout(&o)
    );
    let o = cc_in(&dir, &["status"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(stdout(&o).contains("CPU-EC20: RUN"), "{}", stdout(&o));

    // The program runs: pressing Start (forcing I0.0) latches M0.0.
    let o = cc_in(&dir, &["force", "I0.0=1"]);
    assert!(o.status.success(), "{}", text(&o));
    let deadline = Instant::now() + Duration::from_secs(5);
    loop {
        let o = cc_in(&dir, &["read", "M0.0"]);
        assert!(o.status.success(), "{}", text(&o));
        let latched = stdout(&o)
            .lines()
            .any(|l| l.contains("M0.0") && l.trim_end().ends_with("= 1"));
        if latched {
            break;
        }
        assert!(
            Instant::now() < deadline,
            "M0.0 never latched: {}",
            stdout(&o)
        );
        std::thread::sleep(Duration::from_millis(50));
    }

    // `debug` finds the project's image and its source map: breakpoints by the file
    // names of gutta.toml, from anywhere in the project.
    let line = read(&dir.join("src/main.lad"))
        .lines()
        .position(|l| l.starts_with("AN     Stop"))
        .expect("the latch's AN")
        + 1;
    let at = format!("src/main.lad:{line}");
    let o = cc_in(&dir.join("src"), &["debug", "break", &at]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        stdout(&o).contains(&format!("{at}:1 (MAIN:1:2)")),
        "{}",
        stdout(&o)
    );
    let o = cc_in(&dir, &["debug", "clear"]);
    assert!(o.status.success(), "{}", text(&o));

    // From a subfolder, with an image given: no build, the same PLC.
    let o = cc_in(&dir.join("src"), &["download", "../target/image"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(!stderr(&o).contains("wrote"), "{}", stderr(&o));
}

#[test]
fn flags_on_the_command_line_override_gutta_toml() {
    let sim = common::sim("CPU-EC20", None);
    let dir = new_project("override", "override");
    connect_to(&dir, NOBODY);
    // gutta.toml's endpoint is used...
    let o = cc_in(&dir, &["status"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(stderr(&o).contains(NOBODY), "{}", stderr(&o));
    // ...unless a flag names another one.
    let o = cc_in(&dir, &["status", "--tcp", &sim.1]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(stdout(&o).contains("CPU-EC20"), "{}", stdout(&o));
    // A serial line in gutta.toml gives way to --tcp too, its settings with it.
    edit_manifest(&dir, |t| {
        t.replace(
            &format!("tcp = \"{NOBODY}\""),
            "serial = \"/dev/gutta-no-such-line\"\nbaud = 9600\nparity = \"odd\"",
        )
    });
    let o = cc_in(&dir, &["status"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        stderr(&o).contains("/dev/gutta-no-such-line"),
        "{}",
        stderr(&o)
    );
    let o = cc_in(&dir, &["status", "--tcp", &sim.1]);
    assert!(o.status.success(), "{}", text(&o));
    // --timeout on the command line wins over gutta.toml's.
    edit_manifest(&dir, |t| format!("{t}timeout = 5\n"));
    let o = cc_in(&dir, &["status", "--tcp", &sim.1, "--timeout", "2000"]);
    assert!(o.status.success(), "{}", text(&o));
}

#[test]
fn a_build_error_stops_download_before_it_connects() {
    let dir = new_project("download-error", "broken");
    connect_to(&dir, NOBODY);
    let main = dir.join("src/main.lad");
    write(&main, &read(&main).replace("=      Lamp", "=      Lamb"));
    let o = cc_in(&dir, &["download"]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(
        stderr(&o).contains("undefined symbol `Lamb`"),
        "{}",
        stderr(&o)
    );
    assert!(!stderr(&o).contains(NOBODY), "it connected: {}", stderr(&o));
    assert!(!dir.join("target/image").exists());
}

/// The contents of `path` once they contain `what` (or after 20 s, whatever they are).
fn file_with(path: &std::path::Path, what: &str) -> String {
    let start = Instant::now();
    loop {
        let text = std::fs::read_to_string(path).unwrap_or_default();
        if text.contains(what) || start.elapsed() > Duration::from_secs(20) {
            return text;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

#[test]
fn on_a_terminal_download_shows_a_progress_bar_that_agrees_with_its_summary() {
    if !common::have("tmux") {
        return;
    }
    let sim = common::sim("CPU-EC20", None);
    let dir = new_project("progress", "progress");
    connect_to(&dir, &sim.1);
    // Everything the terminal receives, bar redraws included: the bar is cleared when
    // the download ends, so the final screen alone cannot show it. The program is small:
    // its few bar updates stay within indicatif's burst of redraws, the last one (the
    // full bar) included.
    let log = dir.join("terminal.log");
    let go = dir.join("go");
    let shell = format!(
        "while [ ! -e {go} ]; do sleep 0.05; done; {} download; echo exit=$?; sleep 60",
        env!("CARGO_BIN_EXE_gutta-cc"),
        go = go.display()
    );
    let tmux = common::Tmux::new("gutta-project");
    tmux.run(&[
        "new-session",
        "-d",
        "-s",
        "dl",
        "-x",
        "160",
        "-y",
        "20",
        "-c",
        &dir.display().to_string(),
        &shell,
    ]);
    tmux.run(&[
        "pipe-pane",
        "-t",
        "dl",
        "-o",
        &format!("cat > {}", log.display()),
    ]);
    write(&go, "");
    let output = file_with(&log, "exit=");
    assert!(output.contains("exit=0"), "{output}");
    assert!(
        output.contains("src/main.lad: wrote target/image"),
        "{output}"
    );
    let summary = output
        .split(['\r', '\n'])
        .find_map(|l| l.find("downloaded ").map(|at| &l[at..]))
        .unwrap_or_else(|| panic!("no summary in {output}"));
    let bytes: usize = summary
        .split(": ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no byte count in `{summary}`"));
    assert!(bytes > 0, "{summary}");
    let full_bar = format!("] {bytes}/{bytes} bytes");
    assert!(
        output.contains("downloading [") && output.contains(&full_bar),
        "no full bar `{full_bar}` before the summary `{summary}`:\n{output}"
    );
    let screen = tmux.screen("dl");
    assert!(screen.contains(summary.trim_end()), "{screen}");
}
