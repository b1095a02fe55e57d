//! Issue 30's restart figure: how long `gutta-sim` takes from process start to its
//! listener line with a full flash (the largest generated program CPU-EC20 holds,
//! seeded into `--flash DIR`), with an empty DIR, and without `--flash`. The three are
//! interleaved, ~20 runs each, and their medians printed with the ratio to no flash.
//! `cargo bench -p gutta-cli --bench sim_flash_restart`.

#![allow(clippy::disallowed_methods, clippy::disallowed_types)]

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use gutta_catalog::stdlib;
use gutta_compiler::source::SourceFile;
use gutta_compiler::{compile, ExplicitTarget};
use gutta_format::{Image, PageKind};

/// MAIN with `networks` networks of bit logic.
fn program(networks: usize) -> String {
    let body: String = (0..networks)
        .map(|n| {
            format!(
                "NETWORK {}\nLD I0.{}\nA M{}.{}\n= Q{}.{}\n",
                n + 1,
                n % 8,
                n % 64,
                (n / 64) % 8,
                n % 8,
                (n + 1) % 8
            )
        })
        .collect();
    format!("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n{body}END_ORGANIZATION_BLOCK\n")
}

fn image_of(networks: usize) -> Option<Image> {
    let target = stdlib::shared("CPU-EC20").expect("target");
    compile(
        SourceFile::new("full.lad", program(networks)),
        Some(&ExplicitTarget {
            target,
            origin: "bench".into(),
        }),
    )
    .image
}

/// The largest generated program that still fits (bisection on the network count).
fn full_image() -> Image {
    let (mut lo, mut hi) = (1usize, 8192usize);
    while lo + 1 < hi {
        let mid = (lo + hi) / 2;
        if image_of(mid).is_some() {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    image_of(lo).expect("fits")
}

/// Start gutta-sim with `args`, wait for its listener line, kill it: the time to the line.
fn start_time(args: &[&str]) -> Duration {
    let started = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
        .args(args)
        .args(["--tcp", "127.0.0.1:0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("starts gutta-sim");
    let lines = BufReader::new(child.stdout.take().expect("stdout")).lines();
    let listening = lines
        .map_while(Result::ok)
        .any(|l| l.contains("modbus-tcp on"));
    let took = started.elapsed();
    assert!(listening, "gutta-sim did not listen with {args:?}");
    let _ = child.kill();
    let _ = child.wait();
    took
}

fn median(mut v: Vec<Duration>) -> Duration {
    v.sort();
    v[v.len() / 2]
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gutta-flash-bench-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

fn main() {
    let bench = std::env::args().any(|a| a == "--bench");
    let runs = if bench { 21 } else { 1 };
    let image = full_image();
    let instruction_bytes: usize = image
        .pages
        .iter()
        .filter(|(id, _)| id.kind == PageKind::Instruction)
        .map(|(_, p)| p.len())
        .sum();
    let total: usize = image.pages.values().map(Vec::len).sum();
    let image_dir = scratch("image");
    gutta_io::write_image(&image_dir, &image).expect("writes the image");
    let full = scratch("full");
    let empty = scratch("empty");
    // Seed the full flash once (the image is committed at that start).
    start_time(&[s(&image_dir), "--flash", s(&full)]);
    let flash_bytes = std::fs::metadata(full.join("flash.bin"))
        .expect("flash.bin")
        .len();
    start_time(&["--flash", s(&empty)]);
    let (mut with_full, mut with_empty, mut without) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..runs {
        with_full.push(start_time(&["--flash", s(&full)]));
        with_empty.push(start_time(&["--flash", s(&empty)]));
        without.push(start_time(&["--plc", "CPU-EC20"]));
    }
    let (full_m, empty_m, none_m) = (median(with_full), median(with_empty), median(without));
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    println!(
        "full flash: {} pages, {total} bytes ({instruction_bytes} instruction bytes), flash.bin {flash_bytes} bytes",
        image.pages.len()
    );
    println!(
        "restart to the listener line, median of {runs}: full flash {:.1} ms ({:.2}x), empty DIR {:.1} ms ({:.2}x), no --flash {:.1} ms",
        ms(full_m),
        ms(full_m) / ms(none_m),
        ms(empty_m),
        ms(empty_m) / ms(none_m),
        ms(none_m)
    );
    for dir in [&image_dir, &full, &empty] {
        let _ = std::fs::remove_dir_all(dir);
    }
}
