//! Every way gutta.toml can be wrong, through the real `gutta-cc build`: each error
//! names the manifest's path, the line and column at fault and what to write instead
//! (exit 2). Commands that do not use a project are not stopped by a broken one.

mod common;
mod projects;

use common::{cc_in, stderr, text};
use projects::{scratch, write};

const MAIN: &str =
    "ORGANIZATION_BLOCK MAIN\nBEGIN\nNETWORK 1\nLD SM0.0\nINCW MW30\nEND_ORGANIZATION_BLOCK\n";

/// A folder with src/main.lad and `manifest` as gutta.toml.
fn project(tag: &str, manifest: &str) -> std::path::PathBuf {
    let dir = scratch(tag);
    std::fs::create_dir_all(dir.join("src")).expect("mkdir");
    write(&dir.join("src/main.lad"), MAIN);
    write(&dir.join("gutta.toml"), manifest);
    dir
}

/// `gutta-cc build` in a project with `manifest`: exit 2 and the error
/// `PATH/gutta.toml:LOCATION: MESSAGE`.
fn build_fails(tag: &str, manifest: &str, location: &str, message: &str) {
    let dir = project(tag, manifest);
    let o = cc_in(&dir, &["build"]);
    assert_eq!(o.status.code(), Some(2), "{tag}: {}", text(&o));
    let expected = format!(
        "gutta-cc: error: {}{location}: {message}",
        dir.join("gutta.toml").display()
    );
    assert!(
        stderr(&o).contains(&expected),
        "{tag}: expected\n{expected}\ngot\n{}",
        stderr(&o)
    );
}

const PROGRAM: &str = "[program]\nsources = [\"src/main.lad\"]\n";

#[test]
fn unknown_keys_name_the_key_its_place_and_the_key_meant() {
    build_fails(
        "plcc",
        "[program]\nplcc = \"CPU-EC20\"\nsources = [\"src/main.lad\"]\n",
        ":2:1",
        "unknown key `plcc` in [program]; did you mean `plc`?",
    );
    build_fails(
        "staton",
        &format!("{PROGRAM}\n[connection]\nstaton = 3\n"),
        ":5:1",
        "unknown key `staton` in [connection]; did you mean `station`?",
    );
    build_fails(
        "rtu_tcp",
        &format!("{PROGRAM}[connection]\nrtu_tcp = \"127.0.0.1:5021\"\n"),
        ":4:1",
        "unknown key `rtu_tcp` in [connection]; did you mean `rtu-tcp`?",
    );
    build_fails(
        "programm",
        "[programm]\nsources = [\"src/main.lad\"]\n",
        ":1:2",
        "unknown key `programm` at the top level; did you mean `program`?",
    );
    build_fails(
        "dotted",
        "program.sources = [\"src/main.lad\"]\nprogram.plcc = \"CPU-EC20\"\n",
        ":2:9",
        "unknown key `plcc` in [program]; did you mean `plc`?",
    );
    build_fails(
        "subtable",
        &format!("{PROGRAM}[connection.extra]\nx = 1\n"),
        ":3:13",
        "unknown key `extra` in [connection]; expected one of: tcp, rtu-tcp, serial, baud, parity, station, timeout, retries",
    );
    build_fails(
        "whatever",
        &format!("{PROGRAM}whatever = 1\n"),
        ":3:1",
        "unknown key `whatever` in [program]; expected one of: name, plc, target, sources, symbols",
    );
}

#[test]
fn the_program_section_needs_sources_that_exist_and_one_target() {
    build_fails(
        "no-program",
        "[connection]\ntcp = \"127.0.0.1:5020\"\n",
        ":1:1",
        "no [program] section",
    );
    build_fails(
        "no-sources",
        "[program]\nplc = \"CPU-EC20\"\n",
        ":1:1",
        "[program] needs sources = [\"src/main.lad\", ...]",
    );
    build_fails(
        "empty-sources",
        "[program]\nsources = []\n",
        ":2:11",
        "[program] sources is empty",
    );
    build_fails(
        "sources-string",
        "[program]\nsources = \"src/main.lad\"\n",
        ":2:11",
        "[program] sources: invalid type: string \"src/main.lad\", expected a sequence",
    );
    let dir = project(
        "missing-source",
        "[program]\nsources = [\"src/main.lad\", \"src/b.lad\"]\n",
    );
    let o = cc_in(&dir, &["build"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        stderr(&o).contains(&format!(
            "gutta.toml:2:28: [program] sources: {} does not exist (paths are relative to the project folder {})",
            dir.join("src/b.lad").display(),
            dir.display()
        )),
        "{}",
        stderr(&o)
    );
    build_fails(
        "missing-table",
        &format!("{PROGRAM}symbols = [\"io.csv\"]\n"),
        ":3:12",
        "[program] symbols: ",
    );
    build_fails(
        "plc-and-target",
        "[program]\nplc = \"CPU-EC20\"\ntarget = \"vendor\"\nsources = [\"src/main.lad\"]\n",
        ":3:10",
        "[program] has both plc = \"CPU-EC20\" and target: give one",
    );
    build_fails(
        "empty-plc",
        "[program]\nplc = \"\"\nsources = [\"src/main.lad\"]\n",
        ":2:7",
        "[program] plc is empty",
    );
    build_fails(
        "syntax",
        "[program\nsources = [\"src/main.lad\"]\n",
        ":1:9",
        "unclosed table, expected `]`",
    );
}

#[test]
fn the_connection_section_is_one_endpoint_with_settings_that_fit_it() {
    let with = |connection: &str| format!("{PROGRAM}[connection]\n{connection}");
    build_fails(
        "two-endpoints",
        &with("tcp = \"127.0.0.1:5020\"\nserial = \"/dev/ttyUSB0\"\n"),
        ":5:10",
        "[connection] has both tcp and serial: give one way to reach the PLC",
    );
    build_fails(
        "baud-tcp",
        &with("tcp = \"127.0.0.1:5020\"\nbaud = 9600\n"),
        ":5:8",
        "[connection] baud applies only to a serial line",
    );
    build_fails(
        "parity-alone",
        &with("parity = \"even\"\n"),
        ":4:10",
        "[connection] parity applies only to a serial line",
    );
    build_fails(
        "parity-mark",
        &with("serial = \"/dev/ttyUSB0\"\nparity = \"mark\"\n"),
        ":5:10",
        "[connection] parity = \"mark\": expected \"none\", \"even\" or \"odd\"",
    );
    for (tag, station) in [
        ("station-0", "0"),
        ("station-300", "300"),
        ("station-neg", "-1"),
    ] {
        build_fails(
            tag,
            &with(&format!("station = {station}\n")),
            ":4:11",
            &format!("[connection] station = {station}: a Modbus station is 1 to 247"),
        );
    }
    build_fails(
        "station-text",
        &with("station = \"one\"\n"),
        ":4:11",
        "[connection] station: invalid type: string \"one\"",
    );
}

#[test]
fn a_valid_serial_connection_builds() {
    let dir = project(
        "serial-ok",
        &format!("{PROGRAM}[connection]\nserial = \"/dev/ttyUSB0\"\nbaud = 38400\nparity = \"odd\"\nstation = 20\ntimeout = 500\nretries = 1\n"),
    );
    let o = cc_in(&dir, &["build"]);
    assert!(o.status.success(), "{}", text(&o));
}

#[test]
fn client_commands_stop_at_a_broken_manifest_and_others_do_not() {
    let dir = project("broken-client", "[program]\nplcc = \"CPU-EC20\"\n");
    let o = cc_in(&dir, &["status"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(stderr(&o).contains("unknown key `plcc`"), "{}", stderr(&o));
    // Compiling a named file, explain and list-targets do not read gutta.toml.
    let o = cc_in(&dir, &["--check", "src/main.lad"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(cc_in(&dir, &["explain", "E0202"]).status.success());
    assert!(cc_in(&dir, &["list-targets"]).status.success());
}
