//! Issue 5's download figure: the largest program that fits CPU-EC20 (instruction
//! bytes at ProgramBlockInstructionBinarySize, found by compiling ever larger generated
//! programs) downloaded over loopback Modbus TCP into a `gutta-sim` process with
//! gutta-link, as `gutta-cc download` does: wall time (median of runs) and requests.
//! `cargo bench -p gutta-sim --bench download`; without `--bench`, one run.

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::Instant;

use gutta_catalog::stdlib;
use gutta_compiler::encode::ImageMeta;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_format::Image;
use gutta_link::transport::TcpTransport;
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
        &ImageMeta {
            source: "max.lad".into(),
            tool: "bench".into(),
        },
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
        .args(["--plc", "CPU-EC20", "--tcp", "127.0.0.1:0"])
        .stdout(Stdio::piped())
        .spawn()
        .expect("starts gutta-sim");
    let line = BufReader::new(child.stdout.take().expect("stdout"))
        .lines()
        .next()
        .expect("listener")
        .expect("text");
    let address = line.rsplit(' ').next().expect("address").to_string();
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
    let _ = child.kill();
    let _ = child.wait();
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
}
