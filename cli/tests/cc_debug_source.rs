//! `gutta-cc debug` in source terms against a `gutta-sim` process: with the source map
//! beside the image directory (`--image DIR`, or `image/` in the working directory),
//! `break FILE:LINE` works and breakpoints and pauses show file:line and the instruction.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};

const PROGRAM: &str = "\
PLC_TYPE CPU-EC20

ORGANIZATION_BLOCK MAIN:OB1
BEGIN
NETWORK 1 // start
LD     I0.0
=      Q0.0   // lamp

NETWORK 2
LD     SM0.0
MOVW   16#BEEF, MW10
END_ORGANIZATION_BLOCK
";

struct Sim(Child, String);

impl Drop for Sim {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn sim() -> Sim {
    let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
        .args(["--plc", "CPU-EC20", "--tcp", "127.0.0.1:0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("gutta-sim starts");
    let line = BufReader::new(child.stdout.take().expect("stdout"))
        .lines()
        .next()
        .expect("listener")
        .expect("text");
    let address = line.rsplit(' ').next().expect("address").to_string();
    Sim(child, address)
}

/// `gutta-cc ARGS` run in `dir`.
fn cc(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gutta-cc"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("gutta-cc runs")
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// A fresh directory holding main.lad, compiled to image/ (and image.map.json).
fn project() -> PathBuf {
    let root = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("gutta-cc-debug-source-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).expect("temp dir");
    std::fs::write(root.join("main.lad"), PROGRAM).expect("source");
    let o = cc(&root, &["main.lad", "-o", "image"]);
    assert!(o.status.success(), "{}", text(&o));
    root
}

#[test]
fn debug_shows_file_line_and_instruction() {
    let sim = sim();
    let root = project();
    let at = ["--tcp", sim.1.as_str()];
    let run = |args: &[&str]| {
        let mut all = args.to_vec();
        all.extend_from_slice(&at);
        cc(&root, &all)
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
