//! `gutta-vm` in source terms: a program compiled by the `gutta-cc` binary (which writes
//! DIR.map.json beside DIR), then run with `--break FILE:LINE` / `LINE`, and a fault
//! that names its instruction and source line.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Two networks whose lines the tests name (main.lad:6 is `LD I0.0`, :10 `LD SM0.0`).
const PROGRAM: &str = include_str!("data/two_networks.lad");

/// `PROGRAM` written as `main.lad` in a fresh directory and compiled to `image/` there.
fn compiled(tag: &str) -> PathBuf {
    let root = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("gutta-vm-map-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).expect("temp dir");
    std::fs::write(root.join("main.lad"), PROGRAM).expect("source");
    let o = Command::new(env!("CARGO_BIN_EXE_gutta-cc"))
        .current_dir(&root)
        .args(["main.lad", "-o", "image"])
        .output()
        .expect("runs gutta-cc");
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(root.join("image.map.json").is_file());
    root.join("image")
}

fn gutta_vm(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gutta-vm"))
        .arg(dir)
        .args(args)
        .output()
        .expect("runs gutta-vm")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn break_by_file_and_line_shows_the_source() {
    let image = compiled("break");
    let o = gutta_vm(
        &image,
        &[
            "--break",
            "main.lad:11",
            "--set",
            "I0.0=1",
            "--read",
            "MW10",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(String::from_utf8_lossy(&o.stdout), "MW10 = 0\n");
    let err = stderr(&o);
    assert!(
        err.contains(
            "paused at main.lad:11:1 (MAIN network 2 step 1): MOVW   16#BEEF, MW10 in scan 1"
        ),
        "{err}"
    );
    // LD SM0.0 pushed 1 on a cleared stack.
    assert!(err.contains("logic stack (top first): 100000000"), "{err}");
    // The same place by position, and by line alone.
    let o = gutta_vm(&image, &["--break", "MAIN:2:1", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(v["break"]["source"]["line"], 11);
    assert_eq!(v["break"]["source"]["text"], "MOVW   16#BEEF, MW10");
    assert_eq!(v["break"]["logic_stack"], "100000000");
    let o = gutta_vm(&image, &["--break", "6", "--set", "I0.0=1"]);
    assert!(
        stderr(&o).contains("paused at main.lad:6:1 (MAIN network 1 step 0): LD     I0.0"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_line_without_an_instruction_takes_the_next_or_is_refused() {
    let image = compiled("lines");
    let o = gutta_vm(&image, &["--break", "main.lad:8"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("line 8 has no instruction; breaking at line 10"),
        "{err}"
    );
    assert!(err.contains("paused at main.lad:10:1"), "{err}");
    for (arg, why) in [
        ("main.lad:12", "no instruction on line 12 or after it"),
        ("other.lad:6", "not other.lad"),
    ] {
        let o = gutta_vm(&image, &["--break", arg]);
        assert_eq!(o.status.code(), Some(2), "{arg}");
        assert!(stderr(&o).contains(why), "{arg}: {}", stderr(&o));
    }
}

#[test]
fn without_the_map_a_line_is_refused_and_positions_still_work() {
    let image = compiled("nomap");
    std::fs::remove_file(image.with_file_name("image.map.json")).expect("map");
    let o = gutta_vm(&image, &["--break", "main.lad:6"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("image.map.json"), "{}", stderr(&o));
    let o = gutta_vm(&image, &["--break", "MAIN:2:1"]);
    assert!(
        stderr(&o).contains("paused at breakpoint MAIN (function 0) network 2 step 1"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_fault_names_its_instruction_and_source_line() {
    let image = compiled("fault");
    // Three instructions allowed: the fourth, MOVW, trips the watchdog.
    let o = gutta_vm(&image, &["--watchdog", "3"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("fault in scan 1"), "{err}");
    assert!(
        err.contains("the fault is in main.lad:11:1 (MAIN network 2 step 1): MOVW   16#BEEF, MW10"),
        "{err}"
    );
    let o = gutta_vm(&image, &["--watchdog", "3", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(v["error"]["source"]["line"], 11);
    assert_eq!(v["error"]["position"], "0:2:1");
}

#[test]
fn a_stale_map_is_ignored_with_a_warning() {
    let image = compiled("stale");
    let map = image.with_file_name("image.map.json");
    let text = std::fs::read_to_string(&map).expect("map");
    let mut json: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    let crc = json["manifest_crc"].as_u64().expect("a CRC");
    json["manifest_crc"] = (crc ^ 1).into();
    std::fs::write(&map, json.to_string()).expect("map");
    let o = gutta_vm(&image, &["--break", "MAIN:2:1"]);
    let err = stderr(&o);
    assert!(err.contains("was written for another image"), "{err}");
    assert!(err.contains("paused at breakpoint MAIN"), "{err}");
}
