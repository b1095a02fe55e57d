//! `gutta-cc debug` in source terms against a `gutta-sim` process: with the source map
//! beside the image directory (`--image DIR`, or `image/` in the working directory),
//! `break FILE:LINE` works and breakpoints and pauses show file:line and the instruction.

mod common;

use common::{cc_in, text};
use std::path::{Path, PathBuf};

/// Two networks whose lines the tests name (main.lad:6 is `LD I0.0`, :10 `LD SM0.0`).
const PROGRAM: &str = include_str!("data/two_networks.lad");

/// A fresh directory holding main.lad, compiled to image/ (and image.map.json).
fn project() -> PathBuf {
    let root = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("gutta-cc-debug-source-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).expect("temp dir");
    std::fs::write(root.join("main.lad"), PROGRAM).expect("source");
    let o = cc_in(&root, &["main.lad", "-o", "image"]);
    assert!(o.status.success(), "{}", text(&o));
    root
}

#[test]
fn debug_shows_file_line_and_instruction() {
    let sim = common::sim("CPU-EC20", None);
    let root = project();
    let at = ["--tcp", sim.1.as_str()];
    let run = |args: &[&str]| {
        let mut all = args.to_vec();
        all.extend_from_slice(&at);
        cc_in(&root, &all)
    };
    let o = run(&["download", "image"]);
    assert!(o.status.success(), "{}", text(&o));
    // By line, with the map named; line 8 has no instruction: the next one (10) is taken.
    let o = run(&["debug", "break", "main.lad:8", "--image", "image"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("line 8 has no instruction; breaking at line 10"),
        "{}",
        text(&o)
    );
    assert!(
        text(&o).contains("breakpoint: main.lad:10:1 (MAIN:2:0): LD     SM0.0"),
        "{}",
        text(&o)
    );
    // The default map: image/ in the working directory.
    assert!(run(&["debug", "break", "11"]).status.success());
    assert!(run(&["debug", "reset"]).status.success());
    assert!(run(&["debug", "run"]).status.success());
    std::thread::sleep(std::time::Duration::from_millis(100));
    let o = run(&["debug", "info"]);
    assert!(
        text(&o).contains("paused at:  main.lad:11:1 (MAIN:2:1): MOVW   16#BEEF, MW10"),
        "{}",
        text(&o)
    );
    // A line past the last instruction is refused before anything is sent.
    let o = run(&["debug", "break", "main.lad:40"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        text(&o).contains("no instruction on line 40"),
        "{}",
        text(&o)
    );
    // Without a map: positions as today, and a line is refused.
    std::fs::remove_file(root.join("image.map.json")).expect("map");
    let o = run(&["debug", "info"]);
    assert!(text(&o).contains("paused at:  MAIN:2:1\n"), "{}", text(&o));
    let o = run(&["debug", "break", "main.lad:11"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("image.map.json"), "{}", text(&o));
    let o = run(&["debug", "info", "--image", "image"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(run(&["debug", "clear"]).status.success());
    assert!(run(&["debug", "run"]).status.success());
    let _ = std::fs::remove_dir_all(&root);
}
