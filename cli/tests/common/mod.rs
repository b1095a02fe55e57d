//! Shared by the tests that run the binaries: compile a program for CPU-EC20, write it
//! as an image directory, start a `gutta-sim` process and run `gutta-cc` against it,
//! read its listener lines, and check for the external tools (Modbus clients) some
//! tests drive.

#![allow(dead_code)]

pub mod docs;
mod external;
pub mod studio;

use std::path::PathBuf;

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_format::Image;

/// Every file of a directory tree (an image directory, an upload) with its bytes, by
/// path relative to `dir`, sorted: two trees are the same when these are equal.
pub fn tree_files(dir: &std::path::Path) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).expect("reads the directory") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                stack.push(path);
            } else {
                let name = path.strip_prefix(dir).expect("under").display().to_string();
                out.push((name, std::fs::read(&path).expect("reads the file")));
            }
        }
    }
    out.sort();
    out
}

/// Channels 1..4 of a relay board (`gutta-sim --device relay-board` or a plant's) at
/// `board` (HOST:PORT) as bits 0..3, read by mbpoll as an independent Modbus TCP
/// client: channel n is coil 16#0200 + n - 1, mbpoll's reference 513 + n - 1.
pub fn relay_channels(board: &str) -> u32 {
    let port = board.rsplit(':').next().expect("port").to_string();
    let out = std::process::Command::new("mbpoll")
        .args(["-m", "tcp", "-p", &port, "-a", "1", "-1"])
        .args(["-t", "0", "-r", "513", "-c", "4", "127.0.0.1"])
        .output()
        .expect("runs mbpoll");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(out.status.success(), "{text}");
    (0..4u32)
        .filter(|n| text.contains(&format!("[{}]: \t1", 513 + n)))
        .fold(0, |bits, n| bits | 1 << n)
}

/// The repository's root.
pub fn root() -> PathBuf {
    docs::repo()
}

/// A fresh, empty scratch directory for one test of this process:
/// `gutta-cc-TAG-PID` in the temporary directory.
pub fn scratch(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gutta-cc-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("creates the scratch directory");
    dir
}

/// The example programs, `examples/*.lad`, sorted.
pub fn examples() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(root().join("examples"))
        .expect("examples/")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "lad"))
        .collect();
    files.sort();
    files
}

/// How to get every external tool these tests use.
pub const INSTALL: &str = "run `bash .ci/run`, or: apt-get install mbpoll socat \
     tmux libmodbus-dev pkg-config zsh fish neovim chromium; python3 -m venv .ci/venv && .ci/venv/bin/pip install \
     pymodbus==3.6.9 pytest==9.2.0 pytest-lsp==1.0.1; export GUTTA_PYTHON=$PWD/.ci/venv/bin/python";

/// `text` compiled for CPU-EC20 (it must compile).
pub fn image(name: &str, text: &str) -> Image {
    let target = stdlib::shared("CPU-EC20").expect("target");
    let c = compile(
        SourceFile::new(name, text),
        Some(&ExplicitTarget {
            target,
            origin: "test".into(),
        }),
    );
    c.image
        .unwrap_or_else(|| panic!("{name} does not compile: {:?}", c.checked.diagnostics()))
}

/// An example of examples/ compiled for CPU-EC20.
pub fn example(name: &str) -> Image {
    let path = format!("{}/../examples/{name}", env!("CARGO_MANIFEST_DIR"));
    image(name, &std::fs::read_to_string(path).expect("example"))
}

/// `image` written to a fresh directory named after `tag` and this process.
pub fn image_dir(tag: &str, image: &Image) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gutta-sim-test-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    gutta_io::write_image(&dir, image).expect("writes");
    dir
}

/// A tool the test needs is missing: fail with the install hint (or skip, see
/// `external.rs`).
pub fn tool_missing(why: &str) {
    external::tool_missing(INSTALL, why);
}

/// Whether a command is on PATH (`tool_missing` when not).
pub fn have(tool: &str) -> bool {
    external::have(INSTALL, tool)
}

/// The Python that has pymodbus (`GUTTA_PYTHON`, else `python3`), or None after
/// `tool_missing` said it has not.
pub fn pymodbus_python() -> Option<String> {
    let python = std::env::var("GUTTA_PYTHON").unwrap_or_else(|_| "python3".into());
    let has_pymodbus = std::process::Command::new(&python)
        .args(["-c", "import pymodbus"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !has_pymodbus {
        tool_missing(&format!("{python} cannot import pymodbus"));
        return None;
    }
    Some(python)
}

/// Run the client script `tests/clients/SCRIPT` with `python` and `args`; it must exit
/// 0 and print `PASSED` (its own summary line). Returns its output.
pub fn run_python_client(python: &str, script: &str, args: &[String], passed: &str) -> String {
    let path = format!("{}/tests/clients/{script}", env!("CARGO_MANIFEST_DIR"));
    let out = std::process::Command::new(python)
        .arg(path)
        .args(args)
        .output()
        .expect("runs python");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(text.contains(passed), "{text}");
    text
}

/// The port of a `gutta-sim: WHAT on HOST:PORT` listener line.
pub fn listener_port(line: &str, what: &str) -> u16 {
    assert!(line.contains(what), "{line}");
    line.rsplit(':')
        .next()
        .and_then(|p| p.parse().ok())
        .unwrap_or_else(|| panic!("no port in `{line}`"))
}

/// A `gutta-sim` process, killed when dropped: the child and its Modbus TCP address (or,
/// for a serial one, its listener line).
pub struct Sim(pub std::process::Child, pub String);

impl Drop for Sim {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// `gutta-sim [IMAGE] --plc PLC --tcp 127.0.0.1:0` on a free loopback port; its address
/// comes from the first listener line.
pub fn sim(plc: &str, image: Option<&std::path::Path>) -> Sim {
    let image = image.map(|dir| dir.display().to_string());
    let mut args: Vec<&str> = image.iter().map(String::as_str).collect();
    args.extend(["--plc", plc]);
    sim_on_free_port(&args)
}

/// `gutta-sim ARGS --tcp 127.0.0.1:0` (a PLC or another `--device`), with its TCP
/// address from its first listener line.
pub fn sim_on_free_port(args: &[&str]) -> Sim {
    use std::io::BufRead;
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
        .args(args)
        .args(["--tcp", "127.0.0.1:0"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("starts gutta-sim");
    let line = std::io::BufReader::new(child.stdout.take().expect("stdout"))
        .lines()
        .next()
        .expect("listener")
        .expect("text");
    let address = line.rsplit(' ').next().expect("address").to_string();
    Sim(child, address)
}

/// `gutta-cc read --tcp ADDRESS VAR` as a number.
pub fn read_number(address: &str, var: &str) -> u32 {
    let out = cc(&["read", "--tcp", address, var]);
    assert!(out.status.success(), "{}", text(&out));
    let shown = stdout(&out);
    shown
        .trim()
        .rsplit(' ')
        .next()
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("`{shown}` is not `{var} = N`"))
}

/// `gutta-cc ARGS`. The simulators of these tests keep their own passwords: a
/// developer's GUTTA_PASSWORD is never passed on.
pub fn cc(args: &[&str]) -> std::process::Output {
    cc_command(args).output().expect("gutta-cc runs")
}

/// `gutta-cc ARGS` run in `dir`.
pub fn cc_in(dir: &std::path::Path, args: &[&str]) -> std::process::Output {
    cc_command(args)
        .current_dir(dir)
        .output()
        .expect("gutta-cc runs")
}

fn cc_command(args: &[&str]) -> std::process::Command {
    let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_gutta-cc"));
    command.args(args).env_remove("GUTTA_PASSWORD");
    command
}

pub fn stdout(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

pub fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Standard output then standard error.
pub fn text(o: &std::process::Output) -> String {
    stdout(o) + &stderr(o)
}

/// A tmux server of its own (its socket named after the test and this process), killed
/// when dropped: the terminal the terminal-facing tests type into and read.
pub struct Tmux(String);

impl Tmux {
    pub fn new(tag: &str) -> Tmux {
        Tmux(format!("{tag}-{}", std::process::id()))
    }

    /// `tmux -L SOCKET ARGS`; its standard output.
    pub fn run(&self, args: &[&str]) -> String {
        let o = std::process::Command::new("tmux")
            .args(["-L", &self.0])
            .args(args)
            .output()
            .expect("tmux runs");
        String::from_utf8_lossy(&o.stdout).into_owned()
    }

    /// What the pane of session `target` shows now.
    pub fn screen(&self, target: &str) -> String {
        self.run(&["capture-pane", "-p", "-t", target])
    }

    /// The pane's text once `ok` holds for it (or after 10 s, whatever it shows).
    pub fn screen_when(&self, target: &str, ok: impl Fn(&str) -> bool) -> String {
        let start = std::time::Instant::now();
        loop {
            let screen = self.screen(target);
            if ok(&screen) || start.elapsed() > std::time::Duration::from_secs(10) {
                return screen;
            }
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
    }
}

impl Drop for Tmux {
    fn drop(&mut self) {
        self.run(&["kill-server"]);
    }
}
