//! `gutta-cc new` and `gutta-cc build` through the real binaries: a new project's files,
//! its build run on gutta-vm (the lamp blinks only after Start), discovery from a
//! subfolder, --output, [build] output, --plc over gutta.toml, build errors, `build`
//! outside a project, and `new` refusing names and folders it must not use.

mod common;
mod projects;

use common::{cc_in, stderr, stdout, text};
use projects::{edit_manifest, new_project, read, scratch, write};

/// `gutta-vm IMAGE --scans 120 --trace --read Q0.0` (10 ms scans: 1.2 s), Start as given.
fn lamp_trace(image: &std::path::Path, start: bool) -> String {
    let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_gutta-vm"));
    command
        .arg(image)
        .args(["--scans", "120", "--trace", "--read", "Q0.0"]);
    if start {
        command.args(["--set", "I0.0=1"]);
    }
    let o = command.output().expect("gutta-vm runs");
    assert!(o.status.success(), "{}", text(&o));
    stdout(&o)
}

#[test]
fn a_new_project_builds_and_its_lamp_blinks_after_start() {
    let dir = new_project("blinks", "blinky");
    for file in [
        "gutta.toml",
        "src/main.lad",
        "symbols.csv",
        "tests/main.gtest",
        ".gitignore",
        "README.md",
    ] {
        assert!(dir.join(file).is_file(), "{file} was not created");
    }
    assert_eq!(read(&dir.join(".gitignore")), "/target/\n");
    let manifest = read(&dir.join("gutta.toml"));
    assert!(manifest.contains("name = \"blinky\""), "{manifest}");
    assert!(manifest.contains("plc = \"CPU-EC20\""), "{manifest}");

    let o = cc_in(&dir, &["build"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        stderr(&o).contains("src/main.lad: wrote target/image for CPU-EC20"),
        "{}",
        stderr(&o)
    );
    let image = dir.join("target/image");
    assert!(image.join("manifest.json").is_file());
    assert!(
        dir.join("target/image.map.json").is_file(),
        "the source map"
    );

    // SM0.5 is off for 0.5 s, then on: with Start the lamp lights at scan 51 and goes
    // out at scan 101; without it, it never lights.
    let trace = lamp_trace(&image, true);
    assert!(trace.contains("scan 51: Q0.0 0 -> 1"), "{trace}");
    assert!(trace.contains("scan 101: Q0.0 1 -> 0"), "{trace}");
    let idle = lamp_trace(&image, false);
    assert!(!idle.contains("Q0.0 0 -> 1"), "{idle}");

    // Its tests pass as created, through `gutta-cc test` with no arguments.
    let o = cc_in(&dir, &["test"]);
    assert!(o.status.success(), "{}", text(&o));
    let out = stdout(&o);
    assert!(
        out.contains("PASS  tests/main.gtest::start_latches_and_stop_releases"),
        "{out}"
    );
    assert!(
        out.contains("PASS  tests/main.gtest::lamp_blinks_while_running"),
        "{out}"
    );
    assert!(
        out.contains("2 passed, 0 failed (2 tests in 1 file)"),
        "{out}"
    );
}

#[test]
fn new_prints_what_it_created_and_the_next_commands() {
    let parent = scratch("new-output");
    let o = cc_in(&parent, &["new", "pump", "--plc", "EC30-EKSTM32-XC"]);
    assert!(o.status.success(), "{}", text(&o));
    let out = stdout(&o);
    assert!(
        out.contains("created project `pump` for EC30-EKSTM32-XC"),
        "{out}"
    );
    assert!(out.contains("pump/src/main.lad"), "{out}");
    assert!(out.contains("gutta-cc build"), "{out}");
    assert!(out.contains("pump/tests/main.gtest"), "{out}");
    assert!(out.contains("gutta-cc test"), "{out}");
    assert!(out.contains("gutta-cc download"), "{out}");
    let manifest = read(&parent.join("pump/gutta.toml"));
    assert!(manifest.contains("plc = \"EC30-EKSTM32-XC\""), "{manifest}");
}

#[test]
fn new_refuses_a_non_empty_folder_an_invalid_name_and_an_unknown_plc() {
    let parent = scratch("new-refuses");
    std::fs::create_dir_all(parent.join("taken")).expect("mkdir");
    write(&parent.join("taken/notes.txt"), "mine");
    let o = cc_in(&parent, &["new", "taken"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        stderr(&o).contains("taken already exists and is not empty"),
        "{}",
        stderr(&o)
    );
    assert_eq!(read(&parent.join("taken/notes.txt")), "mine");
    assert!(!parent.join("taken/gutta.toml").exists());

    // An empty folder is fine.
    std::fs::create_dir_all(parent.join("empty")).expect("mkdir");
    assert!(cc_in(&parent, &["new", "empty"]).status.success());

    for bad in ["9lives", "my project", "a.b"] {
        let o = cc_in(&parent, &["new", bad]);
        assert_eq!(o.status.code(), Some(2), "{bad}: {}", text(&o));
        assert!(
            stderr(&o).contains(&format!("`{bad}` is not a project name")),
            "{}",
            stderr(&o)
        );
    }
    let o = cc_in(&parent.join("empty"), &["new", "."]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        stderr(&o).contains("takes the new project's folder"),
        "{}",
        stderr(&o)
    );
    let o = cc_in(&parent, &["new", "x", "--plc", "CPU-NOPE"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(stderr(&o).contains("--plc CPU-NOPE"), "{}", stderr(&o));
    assert!(!parent.join("x").exists());
}

#[test]
fn build_finds_the_project_from_a_subfolder() {
    let dir = new_project("subfolder", "deep");
    let sub = dir.join("src/more");
    std::fs::create_dir_all(&sub).expect("mkdir");
    let o = cc_in(&sub, &["build"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        stderr(&o).contains("src/main.lad: wrote target/image for CPU-EC20"),
        "{}",
        stderr(&o)
    );
    assert!(dir.join("target/image/manifest.json").is_file());
}

#[test]
fn build_writes_where_output_and_the_build_section_say() {
    let dir = new_project("output", "out");
    let o = cc_in(&dir, &["build", "--output", "elsewhere"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(dir.join("elsewhere/manifest.json").is_file());
    assert!(!dir.join("target/image").exists());

    edit_manifest(&dir, |t| {
        format!("{t}\n[build]\noutput = \"images/main\"\n")
    });
    let o = cc_in(&dir, &["build"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(dir.join("images/main/manifest.json").is_file());
    assert!(dir.join("images/main.map.json").is_file());
}

#[test]
fn a_plc_on_the_command_line_wins_over_gutta_toml() {
    let dir = new_project("plc-flag", "flag");
    let o = cc_in(&dir, &["build", "--plc", "EC30-EKSTM32-XC"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(stderr(&o).contains("for EC30-EKSTM32-XC"), "{}", stderr(&o));
    let manifest = read(&dir.join("target/image/manifest.json"));
    assert!(manifest.contains("EC30-EKSTM32-XC"), "{manifest}");
}

#[test]
fn a_plc_type_line_that_gutta_toml_overrides_is_a_warning_naming_it() {
    let dir = new_project("plc-line", "line");
    let main = dir.join("src/main.lad");
    write(&main, &format!("PLC_TYPE EC30-EKSTM32-XC\n{}", read(&main)));
    let o = cc_in(&dir, &["build", "--color", "never"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        stderr(&o).contains(
            "the file names EC30-EKSTM32-XC; [program] plc in gutta.toml selects CPU-EC20"
        ),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_build_error_exits_1_with_the_compilers_diagnostics() {
    let dir = new_project("broken", "broken");
    let main = dir.join("src/main.lad");
    write(
        &main,
        &read(&main).replace("INCW   Blinks", "INCW   Blonks"),
    );
    let o = cc_in(&dir, &["build"]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(
        stderr(&o).contains("undefined symbol `Blonks`"),
        "{}",
        stderr(&o)
    );
    assert!(
        stderr(&o).contains("src/main.lad: 1 error"),
        "{}",
        stderr(&o)
    );
    assert!(!dir.join("target/image").exists());

    let o = cc_in(&dir, &["build", "--message-format", "json"]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    let first = stdout(&o);
    let diagnostic: serde_json::Value =
        serde_json::from_str(first.lines().next().expect("a line")).expect("JSON");
    assert_eq!(diagnostic["code"], "E0202", "{first}");
}

#[test]
fn build_outside_a_project_says_how_to_make_one() {
    let dir = scratch("no-project");
    let o = cc_in(&dir, &["build"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let err = stderr(&o);
    assert!(err.contains("no gutta.toml was found in"), "{err}");
    assert!(err.contains("gutta-cc new NAME"), "{err}");
    let o = cc_in(&dir, &["download", "--tcp", "127.0.0.1:1"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        stderr(&o).contains("download needs an IMAGE"),
        "{}",
        stderr(&o)
    );
}
