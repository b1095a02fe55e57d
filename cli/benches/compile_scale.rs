//! Full-compile benchmark: the generated programs of `compiler/benches/check_scale.rs`
//! (10k and 100k lines by default, or the sizes given) compiled in process (check,
//! lower, encode) and by the `gutta-cc FILE -o DIR` binary (read, check, lower, encode,
//! atomic write). Prints min/median wall time and lines/s. Bar: 400,000 lines/s at 100k
//! lines, whole pipeline. It lives with the binary it runs and shares the program
//! generator and the bench target with `check_scale` (`#[path]`).

#[path = "../../compiler/benches/scale_program/mod.rs"]
mod scale_program;

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

use gutta_compiler::compile;
use gutta_compiler::source::SourceFile;

fn median(mut v: Vec<Duration>) -> (Duration, Duration) {
    v.sort();
    (v[0], v[v.len() / 2])
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let bench_mode = args.iter().any(|a| a == "--bench");
    let mut sizes: Vec<usize> = args.iter().filter_map(|a| a.parse().ok()).collect();
    if sizes.is_empty() {
        sizes = if bench_mode {
            vec![10_000, 100_000]
        } else {
            vec![2_000]
        };
    }
    let runs = if bench_mode { 9 } else { 1 };
    let target = scale_program::bench_target();
    let dir = std::env::temp_dir().join(format!("gutta-compile-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let target_dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../compiler/benches/target");
    println!(
        "{:>9} {:>10} {:>10} {:>12}   {:>10} {:>10} {:>12}  image bytes  check-only",
        "lines", "lib min", "lib med", "lib lines/s", "cli min", "cli med", "cli lines/s"
    );
    println!("(lib: compile() in process; cli: gutta-cc FILE -o DIR, process start to exit; last column: gutta-cc --check FILE, median)");
    for lines in sizes {
        let text = scale_program::generate(lines);
        let n = text.lines().count();
        // In process: check, lower, encode.
        let mut lib = Vec::new();
        let mut image_bytes = 0;
        for _ in 0..runs + 1 {
            let file = SourceFile::new("bench.lad", text.clone());
            let t = Instant::now();
            let c = compile(file, Some(&target));
            lib.push(t.elapsed());
            let image = c.image.unwrap_or_else(|| {
                panic!(
                    "bench program does not compile: {:?}",
                    c.checked.diagnostics().first()
                )
            });
            image_bytes = image.pages.values().map(Vec::len).sum::<usize>();
        }
        lib.remove(0);
        // The binary: read, compile, write atomically.
        let src = dir.join(format!("bench{lines}.lad"));
        std::fs::write(&src, &text).expect("write source");
        let out = dir.join("image");
        let mut cli = Vec::new();
        for _ in 0..runs + 1 {
            let t = Instant::now();
            let status = Command::new(env!("CARGO_BIN_EXE_gutta-cc"))
                .arg(&src)
                .arg("-o")
                .arg(&out)
                .arg("--target")
                .arg(&target_dir)
                .output()
                .expect("run gutta-cc");
            cli.push(t.elapsed());
            assert!(
                status.status.success(),
                "{}",
                String::from_utf8_lossy(&status.stderr)
            );
        }
        cli.remove(0);
        // The same without writing: how much of the binary's time is the image write.
        let mut check_only = Vec::new();
        for _ in 0..runs + 1 {
            let t = Instant::now();
            let status = Command::new(env!("CARGO_BIN_EXE_gutta-cc"))
                .arg(&src)
                .arg("--check")
                .arg("--target")
                .arg(&target_dir)
                .output()
                .expect("run gutta-cc");
            check_only.push(t.elapsed());
            assert!(
                status.status.success(),
                "{}",
                String::from_utf8_lossy(&status.stderr)
            );
        }
        check_only.remove(0);
        let (_, check_med) = median(check_only);
        let ((lmin, lmed), (cmin, cmed)) = (median(lib), median(cli));
        let rate = |d: Duration| n as f64 / d.as_secs_f64();
        println!(
            "{n:>9} {:>8.2}ms {:>8.2}ms {:>12.0}   {:>8.2}ms {:>8.2}ms {:>12.0}  {image_bytes:>11}  {:>8.2}ms",
            lmin.as_secs_f64() * 1e3,
            lmed.as_secs_f64() * 1e3,
            rate(lmed),
            cmin.as_secs_f64() * 1e3,
            cmed.as_secs_f64() * 1e3,
            rate(cmed),
            check_med.as_secs_f64() * 1e3
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
