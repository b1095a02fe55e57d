//! Issue 5's download figure: the largest program that fits CPU-EC20 (instruction
//! bytes at ProgramBlockInstructionBinarySize, found by compiling ever larger generated
//! programs) downloaded over loopback Modbus TCP into a `gutta-sim` process with
//! gutta-link, as `gutta-cc download` does: wall time (median of runs) and requests.
//! `cargo bench -p gutta-cli --bench sim_download`; without `--bench`, one run.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Bits per byte on an RTU line: start, 8 data, even parity, stop.
const BITS_PER_BYTE: f64 = 11.0;

/// A simulated serial line between a client and the simulator's RTU-over-TCP
/// listener: bytes pass in each direction no faster than `baud` allows (a byte takes
/// 11 bit times), so the link behaves like the wire. Counts the bytes it carried.
fn paced_link(to: String, baud: f64, carried: Arc<AtomicU64>) -> String {
    let listener = TcpListener::bind("127.0.0.1:0").expect("binds");
    let address = listener.local_addr().expect("address").to_string();
    std::thread::spawn(move || {
        for client in listener.incoming() {
            let Ok(client) = client else { continue };
            let Ok(server) = TcpStream::connect(&to) else {
                continue;
            };
            let _ = client.set_nodelay(true);
            let _ = server.set_nodelay(true);
            for (mut from, mut into) in [
                (
                    client.try_clone().expect("clone"),
                    server.try_clone().expect("clone"),
                ),
                (server, client),
            ] {
                let carried = Arc::clone(&carried);
                std::thread::spawn(move || {
                    let byte_time = Duration::from_secs_f64(BITS_PER_BYTE / baud);
                    let mut line_free = Instant::now();
                    let mut buf = [0u8; 1024];
                    while let Ok(n) = from.read(&mut buf) {
                        if n == 0 {
                            break;
                        }
                        // The bytes leave the line one byte time after another.
                        let start = line_free.max(Instant::now());
                        line_free = start + byte_time * n as u32;
                        let wait = line_free.saturating_duration_since(Instant::now());
                        std::thread::sleep(wait);
                        carried.fetch_add(n as u64, Ordering::Relaxed);
                        if into.write_all(&buf[..n]).is_err() {
                            break;
                        }
                    }
                });
            }
        }
    });
    address
}

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_format::Image;
use gutta_link::transport::{rtu_over_tcp, TcpTransport};
use gutta_link::{download, Client, FACTORY_PASSWORD};

fn program(networks: usize) -> String {
    let mut code = String::new();
    for n in 0..networks {
        code.push_str(&format!(
            "NETWORK {}\nLD I0.{}\nA M{}.{}\nAN I1.{}\n= Q{}.{}\n",
            n + 1,
            n % 8,
            n % 64,
            (n / 64) % 8,
            (n + 3) % 8,
            n % 8,
            (n + 1) % 8
        ));
    }
    format!("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n{code}END_ORGANIZATION_BLOCK\n")
}

fn try_image(networks: usize) -> Option<Image> {
    let target = stdlib::shared("CPU-EC20").expect("target");
    compile(
        SourceFile::new("max.lad", program(networks)),
        Some(&ExplicitTarget {
            target,
            origin: "bench".into(),
        }),
    )
    .image
}

/// The largest generated program that still fits.
fn maximal() -> Image {
    let (mut lo, mut hi) = (1usize, 4096usize);
    while lo + 1 < hi {
        let mid = (lo + hi) / 2;
        if try_image(mid).is_some() {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    try_image(lo).expect("fits")
}

fn main() {
    let bench = std::env::args().any(|a| a == "--bench");
    let runs = if bench { 9 } else { 1 };
    let image = maximal();
    let target = stdlib::shared("CPU-EC20").expect("target");
    let limit = target.plc.program_block_instruction_binary_size;
    let instruction_bytes: usize = image
        .pages
        .iter()
        .filter(|(id, _)| id.kind == gutta_format::PageKind::Instruction)
        .map(|(_, p)| p.len())
        .sum();
    let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
        .args([
            "--plc",
            "CPU-EC20",
            "--tcp",
            "127.0.0.1:0",
            "--rtu-tcp",
            "127.0.0.1:0",
        ])
        .stdout(Stdio::piped())
        .spawn()
        .expect("starts gutta-sim");
    let mut lines = BufReader::new(child.stdout.take().expect("stdout")).lines();
    let mut next_address = || {
        let line = lines.next().expect("listener").expect("text");
        line.rsplit(' ').next().expect("address").to_string()
    };
    let address = next_address();
    let rtu_address = next_address();
    let pack = target.plc.exch_pack_size as usize;
    let mut times = Vec::new();
    let mut report = None;
    for _ in 0..runs {
        let transport = TcpTransport::connect(&address, 2000, 2).expect("connects");
        let mut client = Client::new(Box::new(transport), 1);
        let start = Instant::now();
        let r =
            download(&mut client, &image, &FACTORY_PASSWORD, pack, &mut |_| {}).expect("downloads");
        times.push(start.elapsed().as_secs_f64());
        report = Some(r);
    }
    // The same download over a simulated 115200-baud RTU line.
    let baud = 115_200.0;
    let carried = Arc::new(AtomicU64::new(0));
    let line = paced_link(rtu_address, baud, Arc::clone(&carried));
    let transport = rtu_over_tcp(&line, 2000, 2).expect("connects");
    let mut client = Client::new(Box::new(transport), 1);
    let start = Instant::now();
    let rtu_report =
        download(&mut client, &image, &FACTORY_PASSWORD, pack, &mut |_| {}).expect("downloads");
    let rtu_seconds = start.elapsed().as_secs_f64();
    let _ = child.kill();
    let _ = child.wait();
    let bytes = carried.load(Ordering::Relaxed) as f64;
    let wire = bytes * BITS_PER_BYTE / baud;
    times.sort_by(f64::total_cmp);
    let report = report.expect("one run");
    println!(
        "maximal CPU-EC20 image: {} pages, {} bytes ({instruction_bytes} of {limit} instruction bytes), ExchPackSize {pack}",
        report.pages, report.bytes
    );
    println!(
        "download over loopback Modbus TCP: {} requests (write, read back, control), median {:.1} ms of {runs} runs (min {:.1}, max {:.1})",
        report.requests,
        times[times.len() / 2] * 1e3,
        times[0] * 1e3,
        times[times.len() - 1] * 1e3
    );
    println!(
        "download over a simulated 115200-baud RTU line (11 bits a byte): {} requests, {:.0} bytes on the wire (both ways) take {:.3} s; the download took {:.3} s = {:.1}% over the wire time",
        rtu_report.requests,
        bytes,
        wire,
        rtu_seconds,
        (rtu_seconds / wire - 1.0) * 100.0
    );
}
