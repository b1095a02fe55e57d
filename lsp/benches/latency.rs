//! Latency benchmark of the language server, in process over `Connection::memory` (the
//! session driver of lsp/tests/session/): a generated 10,000-line program (the
//! compiler's scale generator, bench target GUTTA-BENCH, as a gutta.toml project):
//! open, then edits timed until their publishDiagnostics arrives (bar 20 ms); hover,
//! definition and completion over many positions (bar p99 5 ms); peak memory of the
//! process (VmHWM, bar 50 MB); then a 1 MB program: open, edit and hover. Prints
//! median and p99 of each and whether it meets its bar; a request the server does not
//! serve is listed as such. `cargo bench -p gutta-lsp --bench latency`; without
//! `--bench` (cargo test --benches) a quick run on a small program that checks only
//! that it works. Numbers from a shared, noisy 2-core machine are indicative.

#![allow(
    clippy::disallowed_methods,
    reason = "a benchmark writes its project files"
)]

#[allow(dead_code)]
#[path = "../../compiler/benches/scale_program/mod.rs"]
mod scale_program;
#[path = "../tests/session/mod.rs"]
mod session;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use lsp_server::{Message, Response};
use serde_json::{json, Value};
use session::Session;

/// Bars from the issue.
const DIAGNOSTICS_BAR: Duration = Duration::from_millis(20);
const REQUEST_BAR: Duration = Duration::from_millis(5);
const MEMORY_BAR_MB: f64 = 50.0;

struct Sizes {
    /// Whether the bars apply (the 10,000-line program; the 1 MB one must only
    /// answer in bounded time).
    bars: bool,
    lines: usize,
    edits: usize,
    positions: usize,
    megabyte: bool,
}

/// A project folder holding `text` as main.lad, on the bench target; the document's URI.
fn project(tag: &str, text: &str) -> (PathBuf, String) {
    let dir = std::env::temp_dir().join(format!("gutta-lsp-bench-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a scratch folder");
    let target = Path::new(env!("CARGO_MANIFEST_DIR")).join("../compiler/benches/target");
    let target = target.canonicalize().expect("the bench target folder");
    std::fs::write(
        dir.join("gutta.toml"),
        format!(
            "[program]\ntarget = {:?}\nsources = [\"main.lad\"]\n",
            target.display().to_string()
        ),
    )
    .expect("writes gutta.toml");
    let main = dir.join("main.lad");
    std::fs::write(&main, text).expect("writes main.lad");
    let uri = gutta_lsp::documents::path_to_uri(&main)
        .expect("a file URI")
        .as_str()
        .to_string();
    (dir, uri)
}

/// Wait for the diagnostics of `uri`; their count.
fn diagnostics(s: &mut Session, uri: &str) -> usize {
    loop {
        match s.client.receiver.recv_timeout(session::ANSWER_WITHIN) {
            Ok(Message::Notification(n))
                if n.method == "textDocument/publishDiagnostics" && n.params["uri"] == uri =>
            {
                return n.params["diagnostics"].as_array().map_or(0, Vec::len);
            }
            Ok(Message::Request(r)) => {
                let ok = Response::new_ok(r.id, Value::Null);
                let _ = s.client.sender.send(Message::Response(ok));
            }
            Ok(_) => {}
            Err(e) => panic!("no diagnostics for {uri}: {e}"),
        }
    }
}

/// Median and p99 of `times`.
fn stats(mut times: Vec<Duration>) -> (Duration, Duration) {
    times.sort();
    let at = |q: f64| times[((times.len() - 1) as f64 * q).round() as usize];
    (at(0.5), at(0.99))
}

fn row(what: &str, times: Vec<Duration>, bar: Option<Duration>) {
    let n = times.len();
    let (median, p99) = stats(times);
    let verdict = match bar {
        Some(b) if p99 <= b => format!("ok (bar {} ms)", b.as_millis()),
        Some(b) => format!("OVER the bar of {} ms", b.as_millis()),
        None => String::new(),
    };
    println!(
        "{what:<34} {n:>5} {:>10.3} {:>10.3}  {verdict}",
        median.as_secs_f64() * 1e3,
        p99.as_secs_f64() * 1e3
    );
}

/// Open `text` and time until its diagnostics arrive.
fn open(s: &mut Session, uri: &str, text: &str) -> (Duration, usize) {
    let start = Instant::now();
    s.open_at(uri, text);
    let count = diagnostics(s, uri);
    (start.elapsed(), count)
}

/// `n` edits, alternately typing a comment character at the end of a line and taking
/// it away again, each timed until the diagnostics arrive.
fn edits(s: &mut Session, uri: &str, lines: &[&str], n: usize) -> Vec<Duration> {
    let mut version = 100;
    (0..n)
        .map(|i| {
            let line = (i / 2 * 7919) % lines.len();
            let end = lines[line].encode_utf16().count();
            let (range, text) = if i % 2 == 0 {
                ([line, end, line, end], " //x")
            } else {
                ([line, end, line, end + 4], "")
            };
            version += 1;
            let start = Instant::now();
            s.notify(
                "textDocument/didChange",
                json!({"textDocument": {"uri": uri, "version": version},
                       "contentChanges": [{"range": {"start": {"line": range[0], "character": range[1]},
                                                     "end": {"line": range[2], "character": range[3]}},
                                           "text": text}]}),
            );
            diagnostics(s, uri);
            start.elapsed()
        })
        .collect()
}

/// `method` at `positions`: the times, or `None` when the server does not serve it.
fn requests(
    s: &mut Session,
    uri: &str,
    method: &str,
    positions: &[(usize, usize)],
) -> Option<Vec<Duration>> {
    let mut times = Vec::with_capacity(positions.len());
    for &(line, character) in positions {
        let start = Instant::now();
        let answer = s.request(
            method,
            json!({"textDocument": {"uri": uri}, "position": {"line": line, "character": character}}),
        );
        times.push(start.elapsed());
        if answer.error.as_ref().is_some_and(|e| e.code == -32601) {
            return None;
        }
    }
    Some(times)
}

/// Positions spread over the text: on mnemonics, operands and symbols.
fn positions(lines: &[&str], n: usize) -> Vec<(usize, usize)> {
    (0..n)
        .map(|i| {
            let line = (i * 104_729 + 13) % lines.len();
            let len = lines[line].encode_utf16().count();
            let character = [1, 4, 8, 10, 14][i % 5].min(len);
            (line, character)
        })
        .collect()
}

/// VmHWM of this process (client and server), in MB.
fn peak_memory_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

fn program(tag: &str, s: &mut Session, text: &str, sizes: &Sizes) {
    let (dir, uri) = project(tag, text);
    let lines: Vec<&str> = text.lines().collect();
    let (time, count) = open(s, &uri, text);
    assert_eq!(
        count, 0,
        "the generated program checks clean on the bench target"
    );
    println!(
        "{tag}: {} lines, {} bytes, {count} diagnostics after open",
        lines.len(),
        text.len()
    );
    row("open -> publishDiagnostics", vec![time], None);
    row(
        "edit -> publishDiagnostics",
        edits(s, &uri, &lines, sizes.edits),
        sizes.bars.then_some(DIAGNOSTICS_BAR),
    );
    let at = positions(&lines, sizes.positions);
    for method in [
        "textDocument/hover",
        "textDocument/definition",
        "textDocument/completion",
    ] {
        match requests(s, &uri, method, &at) {
            Some(times) => row(method, times, sizes.bars.then_some(REQUEST_BAR)),
            None => println!("{method:<34} not served by this build"),
        }
    }
    let _ = std::fs::remove_dir_all(dir);
}

fn main() {
    let bench = std::env::args().any(|a| a == "--bench");
    let sizes = if bench {
        Sizes {
            bars: true,
            lines: 10_000,
            edits: 200,
            positions: 1_000,
            megabyte: true,
        }
    } else {
        Sizes {
            bars: true,
            lines: 500,
            edits: 4,
            positions: 10,
            megabyte: false,
        }
    };
    println!(
        "gutta-lsp latency (in process; a shared 2-core machine is noisy: indicative figures)"
    );
    println!(
        "{:<34} {:>5} {:>10} {:>10}",
        "what", "n", "median ms", "p99 ms"
    );
    let mut s = Session::start(json!({}));
    let text = scale_program::generate(sizes.lines);
    program(&format!("{}-lines", sizes.lines), &mut s, &text, &sizes);
    match peak_memory_mb() {
        Some(mb) if mb <= MEMORY_BAR_MB => {
            println!("peak memory (VmHWM, whole process)  {mb:.1} MB  ok (bar {MEMORY_BAR_MB} MB)")
        }
        Some(mb) => println!(
            "peak memory (VmHWM, whole process)  {mb:.1} MB  OVER the bar of {MEMORY_BAR_MB} MB"
        ),
        None => println!("peak memory: /proc/self/status unreadable"),
    }
    if sizes.megabyte {
        let mut lines = 10_000;
        let mut big = scale_program::generate(lines);
        while big.len() < 1 << 20 {
            lines = lines * 11 / 10;
            big = scale_program::generate(lines);
        }
        let small = Sizes {
            bars: false,
            edits: 20,
            positions: 100,
            ..sizes
        };
        program("1MB", &mut s, &big, &small);
    }
    s.finish();
}
