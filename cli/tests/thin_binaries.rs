//! The binaries are thin (issue 25, point 2): gutta-cc's main.rs parses and dispatches
//! and holds no helper a command module could import back; no `run` of the three
//! binaries grows past 100 lines.

use std::path::{Path, PathBuf};

fn bin_dir(tool: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("src/bin")
        .join(tool)
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The functions defined at the top level of a file (`fn name` at column 0).
fn top_level_functions(text: &str) -> Vec<&str> {
    text.lines()
        .filter_map(|l| {
            l.strip_prefix("fn ")
                .or_else(|| l.strip_prefix("pub(crate) fn "))
                .or_else(|| l.strip_prefix("async fn "))
        })
        .map(|rest| rest.split(['(', '<']).next().unwrap_or(rest))
        .collect()
}

#[test]
fn gutta_cc_main_only_parses_and_dispatches() {
    let main = read(&bin_dir("gutta-cc").join("main.rs"));
    assert_eq!(top_level_functions(&main), ["main", "run"]);
    for entry in std::fs::read_dir(bin_dir("gutta-cc")).expect("gutta-cc's folder") {
        let path = entry.expect("entry").path();
        if path.extension().is_none_or(|x| x != "rs") || path.ends_with("main.rs") {
            continue;
        }
        let text = read(&path);
        for helper in ["crate::run", "crate::main", "crate::TOOL"] {
            assert!(
                !text.contains(helper),
                "{} imports `{helper}` from main.rs",
                path.display()
            );
        }
    }
}

#[test]
fn no_run_function_is_over_100_lines() {
    for (tool, file) in [
        ("gutta-cc", "main.rs"),
        ("gutta-vm", "main.rs"),
        ("gutta-sim", "main.rs"),
    ] {
        let path = bin_dir(tool).join(file);
        let text = read(&path);
        let lines: Vec<&str> = text.lines().collect();
        for (start, line) in lines.iter().enumerate() {
            let is_run = ["fn run", "async fn run"]
                .iter()
                .any(|p| line.starts_with(p));
            if !is_run {
                continue;
            }
            let length = lines[start..]
                .iter()
                .position(|l| *l == "}")
                .map(|end| end + 1)
                .expect("a function ends with `}` at column 0");
            assert!(
                length <= 100,
                "{tool}: `{}` is {length} lines",
                line.trim_end_matches(" {")
            );
        }
    }
}
