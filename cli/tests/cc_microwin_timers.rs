//! S7-200 timer resolutions through the real binary (docs/microwin.md, "Timer
//! resolutions"): a Micro/WIN export whose T33 counts 10 ms on an S7-200 and 100 ms on
//! the target warns (W0207) and keeps its preset; `--scale-timer-presets` and a
//! project's `[build] scale-timer-presets = true` scale it (the image says `TON T33, 5`).

mod common;

use common::{cc, cc_in, stderr, stdout};

use std::path::{Path, PathBuf};

/// A fresh directory for this test.
fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "gutta-cc-microwin-timers-{tag}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("creates the scratch directory");
    dir
}

const EXPORT: &str = "ORGANIZATION_BLOCK MAIN:OB1\r\nTITLE=PROGRAM COMMENTS\r\nBEGIN\r\n\
Network 1\r\nLD     I0.0\r\nTON    T33, +50\r\nNetwork 2\r\nLD     T33\r\n=      Q0.0\r\n\
END_ORGANIZATION_BLOCK\r\n";

/// The TON line of an image's disassembly.
fn ton_line(image: &Path) -> String {
    let o = cc(&["dis", image.to_str().expect("path")]);
    assert!(o.status.success(), "{}", stderr(&o));
    stdout(&o)
        .lines()
        .find(|l| l.starts_with("TON"))
        .map(|l| l.split("//").next().unwrap_or("").trim().to_string())
        .expect("the image has a TON")
}

#[test]
fn a_differing_resolution_warns_and_the_option_scales_the_preset() {
    let dir = scratch("flag");
    let source = dir.join("main.awl");
    std::fs::write(&source, EXPORT).expect("writes the export");
    let source = source.to_str().expect("path");

    let plain = dir.join("plain");
    let o = cc(&[
        source,
        "--plc",
        "CPU-EC20-M3",
        "-o",
        plain.to_str().expect("path"),
    ]);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("[W0207]")
            && err.contains("`T33` counts 10 ms on an S7-200 (TON/TOF) and 100 ms on CPU-EC20-M3")
            && err.contains("its preset 50 means 500 ms on an S7-200 and 5 s here")
            && err.contains("--scale-timer-presets keeps the S7-200 timing (50 becomes 5)"),
        "{err}"
    );
    assert_eq!(ton_line(&plain), "TON    T33, 50");

    let scaled = dir.join("scaled");
    let o = cc(&[
        source,
        "--plc",
        "CPU-EC20-M3",
        "--scale-timer-presets",
        "-o",
        scaled.to_str().expect("path"),
    ]);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        !err.contains("W0207"),
        "an exact scaling says nothing: {err}"
    );
    assert_eq!(ton_line(&scaled), "TON    T33, 5");
    // The bit reads the scaled preset too.
    let o = cc(&["dis", scaled.to_str().expect("path")]);
    assert!(stdout(&o).contains("LDW>=  T33, 5"), "{}", stdout(&o));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_project_scales_presets_from_its_manifest() {
    let dir = scratch("project");
    std::fs::create_dir_all(dir.join("src")).expect("creates src");
    std::fs::write(dir.join("src/main.awl"), EXPORT).expect("writes the export");
    std::fs::write(
        dir.join("gutta.toml"),
        "[program]\nplc = \"CPU-EC20-M3\"\nsources = [\"src/main.awl\"]\n\n\
         [build]\nscale-timer-presets = true\n",
    )
    .expect("writes the manifest");
    let o = cc_in(&dir, &["build"]);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(!err.contains("W0207"), "{err}");
    assert_eq!(ton_line(&dir.join("target/image")), "TON    T33, 5");

    // A misspelt key is refused with the keys [build] knows.
    std::fs::write(
        dir.join("gutta.toml"),
        "[program]\nsources = [\"src/main.awl\"]\n\n[build]\nscale-timer-preset = true\n",
    )
    .expect("writes the manifest");
    let o = cc_in(&dir, &["build"]);
    let err = stderr(&o);
    assert!(!o.status.success());
    assert!(err.contains("scale-timer-presets"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
