//! Issue 5's load figure: 32 Modbus TCP clients poll 100 holding registers of a running
//! `gutta-sim` (the pointer example on CPU-EC20, 10 ms scans) as fast as they can for
//! 10 s. Prints requests per second served and the simulator's own scan statistics
//! (scans per second and the longest scan period of each second), which say whether
//! the scan period held. `cargo bench -p gutta-cli --bench sim_poll`; without `--bench`
//! (as under `cargo test --benches`) 2 clients poll for 1 s.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};

fn main() {
    let bench = std::env::args().any(|a| a == "--bench");
    let (clients, seconds) = if bench { (32, 10.0) } else { (2, 1.0) };
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/in1001_pointers.lad"
    ))
    .expect("example");
    let target = stdlib::shared("CPU-EC20").expect("target");
    let image = compile(
        SourceFile::new("p.lad", &text),
        Some(&ExplicitTarget {
            target,
            origin: "bench".into(),
        }),
    )
    .image
    .expect("compiles");
    let dir = std::env::temp_dir().join(format!("gutta-poll-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    gutta_io::write_image(&dir, &image).expect("writes");

    let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
        .arg(&dir)
        .args([
            "--tcp",
            "127.0.0.1:0",
            "--scan-ms",
            "10",
            "--stats-every",
            "1",
        ])
        .stdout(Stdio::piped())
        .spawn()
        .expect("starts gutta-sim");
    let mut lines = BufReader::new(child.stdout.take().expect("stdout")).lines();
    let first = lines.next().expect("listener").expect("text");
    let port: u16 = first
        .rsplit(':')
        .next()
        .and_then(|p| p.parse().ok())
        .expect("port");
    let stats = std::thread::spawn(move || {
        lines
            .map_while(Result::ok)
            .filter(|l| l.contains("stats:"))
            .collect::<Vec<String>>()
    });

    let done = Arc::new(AtomicBool::new(false));
    let served = Arc::new(AtomicU64::new(0));
    let start = Instant::now();
    let workers: Vec<_> = (0..clients)
        .map(|k| {
            let (done, served) = (Arc::clone(&done), Arc::clone(&served));
            std::thread::spawn(move || {
                let mut s = TcpStream::connect(("127.0.0.1", port)).expect("connects");
                s.set_nodelay(true).expect("nodelay");
                let mut answer = vec![0u8; 9 + 200];
                let mut tid: u16 = k;
                while !done.load(Ordering::Relaxed) {
                    tid = tid.wrapping_add(1);
                    let mut req = tid.to_be_bytes().to_vec();
                    req.extend([0, 0, 0, 6, 1, 0x03, 0x00, 0x00, 0x00, 100]);
                    s.write_all(&req).expect("send");
                    s.read_exact(&mut answer).expect("answer");
                    assert_eq!(&answer[..2], &tid.to_be_bytes(), "transaction id");
                    assert_eq!(answer[7], 0x03, "not an exception");
                    served.fetch_add(1, Ordering::Relaxed);
                }
            })
        })
        .collect();
    std::thread::sleep(Duration::from_secs_f64(seconds));
    done.store(true, Ordering::Relaxed);
    for w in workers {
        w.join().expect("client");
    }
    let elapsed = start.elapsed().as_secs_f64();
    let _ = child.kill();
    let _ = child.wait();
    let stats = stats.join().unwrap_or_default();
    let _ = std::fs::remove_dir_all(&dir);
    let total = served.load(Ordering::Relaxed);
    println!(
        "{clients} clients x read 100 holding registers for {elapsed:.1} s: {total} requests, {:.0} requests/s",
        total as f64 / elapsed
    );
    println!("simulator scan statistics (10 ms scans), one line per second:");
    for line in stats {
        println!("  {line}");
    }
}
