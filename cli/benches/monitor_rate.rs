//! Issue 15's monitor figure: a generated 50-network program (contacts in series and in
//! parallel, compares, MOVW, TON and CTU boxes) in `gutta-sim` over TCP, `gutta-cc
//! monitor` on it, and a client holding `/events` open as the page does. Prints updates
//! per second, PLC requests per second and STATUS_VAR_READs per second over the run
//! (from the monitor's `/metrics`) and the events the client received per second, at the
//! default interval (50 ms) and as fast as the link allows (`--interval 1`); fails below
//! the bar of 10 updates (and events received) per second. An event carries the latest
//! update: a client slower than the updates gets fewer events, never old ones.
//! `cargo bench -p gutta-cli --bench monitor_rate`; without `--bench` (as under `cargo
//! test --benches`) each run lasts 1 s.

use std::io::{BufRead, BufReader, Read, Write};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};

const NETWORKS: usize = 50;

/// Network `n` of the generated program: one of five shapes.
fn network(n: usize) -> String {
    let i = |k: usize| format!("I{}.{}", (n + k) % 8, (n * 3 + k) % 8);
    let m = |k: usize| format!("M{}.{}", (n + k) % 64, k % 8);
    let body = match n % 5 {
        0 => format!(
            "LD     {}\nA      {}\nAN     {}\n=      Q{}.{}\n",
            i(0),
            i(1),
            m(0),
            n % 8,
            n % 8
        ),
        1 => format!(
            "LD     {}\nO      {}\nLD     {}\nO      {}\nALD\n=      {}\n",
            i(0),
            i(1),
            i(2),
            m(1),
            m(2)
        ),
        2 => format!(
            "LDW>=  MW{}, {}\nMOVW   MW{}, MW{}\n",
            2 * (n % 40),
            n,
            2 * (n % 40),
            2 * ((n + 7) % 40)
        ),
        3 => format!(
            "LD     {}\nTON    T{}, {}\n=      {}\n",
            i(0),
            n % 16,
            10 + n,
            m(3)
        ),
        _ => format!(
            "LD     {}\nLD     {}\nCTU    C{}, {}\n=      {}\n",
            i(0),
            i(1),
            n % 8,
            3 + n % 5,
            m(4)
        ),
    };
    format!("NETWORK {} // generated {n}\n{body}", n + 1)
}

fn program() -> String {
    let networks: String = (0..NETWORKS).map(network).collect();
    format!("PLC_TYPE CPU-EC20\n\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n{networks}END_ORGANIZATION_BLOCK\n")
}

struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn get(host: &str, path: &str) -> String {
    let mut s = std::net::TcpStream::connect(host).expect("connects");
    write!(
        s,
        "GET {path} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n"
    )
    .expect("sends");
    let mut r = String::new();
    s.read_to_string(&mut r).expect("reads");
    r.split_once("\r\n\r\n")
        .map(|(_, b)| b.to_string())
        .expect("body")
}

fn metrics(host: &str) -> (u64, u64, u64) {
    let m: serde_json::Value = serde_json::from_str(&get(host, "/metrics")).expect("JSON");
    let n = |k: &str| m[k].as_u64().expect("count");
    (n("updates"), n("plc_requests"), n("var_reads"))
}

/// Reads `/events` until `stop`: the first event's JSON through `first`, then counts
/// every event in `events`.
fn listen(
    host: &str,
    first: std::sync::mpsc::Sender<serde_json::Value>,
    events: Arc<AtomicU64>,
    stop: Arc<AtomicBool>,
) {
    let mut s = std::net::TcpStream::connect(host).expect("connects");
    s.set_read_timeout(Some(Duration::from_millis(200)))
        .expect("timeout");
    write!(s, "GET /events HTTP/1.1\r\nHost: {host}\r\n\r\n").expect("sends");
    let mut reader = BufReader::new(s);
    let mut line = String::new();
    let mut sent = false;
    while !stop.load(Ordering::SeqCst) {
        line.clear();
        match reader.read_line(&mut line) {
            Ok(0) => break,
            Ok(_) => {}
            Err(_) => continue,
        }
        if let Some(data) = line.strip_prefix("data:") {
            events.fetch_add(1, Ordering::SeqCst);
            if !sent {
                sent = true;
                let _ = first.send(serde_json::from_str(data.trim()).expect("JSON"));
            }
        }
    }
}

/// One run: the figures per second.
fn run(
    source: &std::path::Path,
    sim: &str,
    interval: &str,
    seconds: f64,
) -> (f64, f64, f64, f64, usize, u64) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-cc"))
        .args(["monitor", source.to_str().expect("path"), "--tcp", sim])
        .args(["--http", "127.0.0.1:0", "--interval", interval])
        .env_remove("GUTTA_PASSWORD")
        .stderr(Stdio::piped())
        .spawn()
        .expect("gutta-cc monitor starts");
    let line = BufReader::new(child.stderr.take().expect("stderr"))
        .lines()
        .next()
        .expect("line")
        .expect("text");
    let _monitor = Killed(child);
    let host = line
        .split_whitespace()
        .find_map(|w| w.strip_prefix("http://"))
        .expect("URL")
        .trim_end_matches('/')
        .to_string();
    // The open stream wakes the poller; count from its first event on.
    let (first_tx, first_rx) = std::sync::mpsc::channel();
    let events = Arc::new(AtomicU64::new(0));
    let stop = Arc::new(AtomicBool::new(false));
    let listener = {
        let (host, events, stop) = (host.clone(), events.clone(), stop.clone());
        std::thread::spawn(move || listen(&host, first_tx, events, stop))
    };
    let first = first_rx
        .recv_timeout(Duration::from_secs(10))
        .expect("a first event");
    assert_eq!(first["live"], true, "{first}");
    let operands = first["values"].as_object().map_or(0, |v| v.len());
    let addresses = first["read_addresses"].as_u64().expect("a count");
    let (u0, r0, v0) = metrics(&host);
    let e0 = events.load(Ordering::SeqCst);
    let start = Instant::now();
    std::thread::sleep(Duration::from_secs_f64(seconds));
    let (u1, r1, v1) = metrics(&host);
    let e1 = events.load(Ordering::SeqCst);
    let t = start.elapsed().as_secs_f64();
    stop.store(true, Ordering::SeqCst);
    listener.join().expect("the listener ends");
    (
        (u1 - u0) as f64 / t,
        (r1 - r0) as f64 / t,
        (v1 - v0) as f64 / t,
        (e1 - e0) as f64 / t,
        operands,
        addresses,
    )
}

fn main() {
    let bench = std::env::args().any(|a| a == "--bench");
    let seconds = if bench { 10.0 } else { 1.0 };
    let text = program();
    let target = stdlib::shared("CPU-EC20").expect("target");
    let image = compile(
        SourceFile::new("gen.lad", &text),
        Some(&ExplicitTarget {
            target,
            origin: "bench".into(),
        }),
    )
    .image
    .expect("the generated program compiles");
    let dir = std::env::temp_dir().join(format!("gutta-monitor-rate-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    gutta_io::write_image(&dir, &image).expect("writes");
    let source = dir.with_extension("lad");
    std::fs::write(&source, &text).expect("writes the source");
    let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
        .arg(&dir)
        .args(["--tcp", "127.0.0.1:0"])
        .stdout(Stdio::piped())
        .spawn()
        .expect("starts gutta-sim");
    let first = BufReader::new(child.stdout.take().expect("stdout"))
        .lines()
        .next()
        .expect("listener")
        .expect("text");
    let _sim = Killed(child);
    let sim = first.rsplit(' ').next().expect("address").to_string();
    for interval in ["50", "1"] {
        let (updates, requests, reads, events, operands, addresses) =
            run(&source, &sim, interval, seconds);
        println!(
            "monitor_rate: {NETWORKS} networks, {operands} operands in {addresses} read addresses, --interval {interval}: \
             {updates:.1} updates/s, {requests:.1} PLC requests/s, {reads:.1} STATUS_VAR_READ/s ({:.1} per update), \
             {events:.1} events/s received over {seconds} s",
            reads / updates
        );
        assert!(
            updates >= 10.0 && events >= 10.0,
            "{updates:.1} updates/s, {events:.1} events/s: below the bar of 10"
        );
    }
}
