//! Issue 17's command-line bar: what `gutta-vm IMAGE --scans N` adds to a scan. The
//! per-scan benchmark's program (vm/benches/awlsim/scan_cost.lad, 10 instructions, STOP
//! after 1,000,000 scans) is compiled to an image in a temporary folder; the real
//! gutta-vm process is timed from spawn to exit at N = 1,000,000 and at N = 1 (process
//! start, reading, verifying and loading the image); a run's time past the median start, over
//! the scans, is the command line's ns per scan. Next to it, the library's ns per scan of
//! the same image through `Vm::scan`, measured in the same run, and the ratio (bar:
//! the command line adds at most 10%). Medians (min..max) of the runs.
//! `cargo bench -p gutta-cli --bench vm_scans [-- --bench RUNS]`; without `--bench`
//! (as in `cargo test --benches`), one run of 1,000 scans.

use std::path::Path;
use std::process::Command;
use std::sync::Arc;
use std::time::Instant;

use gutta_compiler::compile;
use gutta_compiler::source::SourceFile;
use gutta_vm::{Vm, VmConfig};

const PROGRAM: &str = include_str!("../../vm/benches/awlsim/scan_cost.lad");

/// Median, min and max.
fn spread(mut values: Vec<f64>) -> (f64, f64, f64) {
    values.sort_by(f64::total_cmp);
    (
        values[values.len() / 2],
        values[0],
        values[values.len() - 1],
    )
}

/// Wall seconds of one `gutta-vm DIR --scans N EXTRA...` process; checks it ran.
fn cli_run(dir: &Path, scans: u64, extra: &[&str]) -> f64 {
    let started = Instant::now();
    let output = Command::new(env!("CARGO_BIN_EXE_gutta-vm"))
        .arg(dir)
        .arg("--scans")
        .arg(scans.to_string())
        .args(extra)
        .output()
        .expect("gutta-vm runs");
    let elapsed = started.elapsed().as_secs_f64();
    assert!(
        output.status.success(),
        "gutta-vm failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    if !extra.is_empty() {
        let stdout = String::from_utf8_lossy(&output.stdout);
        let expected = format!("MD0 = {}", scans.min(1_000_000));
        assert!(stdout.contains(&expected), "{expected} in {stdout}");
    }
    elapsed
}

/// Seconds per scan of the library over `scans` scans of a freshly reset VM.
fn library_run(vm: &mut Vm, scans: u64) -> f64 {
    vm.reset();
    let started = Instant::now();
    for _ in 0..scans {
        vm.scan().expect("scan");
    }
    let elapsed = started.elapsed().as_secs_f64();
    assert_eq!(vm.scans(), scans, "every scan ran");
    elapsed / scans as f64
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let bench_mode = args.iter().any(|a| a == "--bench");
    let runs: usize = args
        .iter()
        .find_map(|a| a.parse().ok())
        .unwrap_or(if bench_mode { 11 } else { 1 });
    let scans: u64 = if bench_mode { 1_000_000 } else { 1_000 };

    let compiled = compile(SourceFile::new("scan_cost.lad", PROGRAM), None);
    let image = compiled.image.expect("scan_cost.lad compiles");
    let target = Arc::clone(&compiled.checked.target);
    let dir = std::env::temp_dir().join(format!("gutta-vm-scans-bench-{}", std::process::id()));
    gutta_io::write_image(&dir, &image).expect("write the image");
    let verified = gutta_format::verify(&image, &target).expect("verifies");
    let mut vm = Vm::new(verified, target, VmConfig::default()).expect("loads");

    let reads = ["--read", "Q0.1", "--read", "MD0"];
    // Warm-up: the binary and the image in the page cache, the library's code hot.
    cli_run(&dir, 1, &[]);
    library_run(&mut vm, scans.min(1000));
    let (mut start, mut whole, mut whole_read, mut library) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for _ in 0..runs {
        start.push(cli_run(&dir, 1, &[]));
        whole.push(cli_run(&dir, scans, &[]));
        whole_read.push(cli_run(&dir, scans, &reads));
        library.push(library_run(&mut vm, scans) * 1e9);
    }
    // The process start varies from run to run by more than a few scans: its median is
    // what each run's scans are measured past.
    let (start_median, _, _) = spread(start.clone());
    let per_scan = |whole: &[f64]| -> Vec<f64> {
        whole
            .iter()
            .map(|t| (t - start_median).max(0.0) / (scans - 1) as f64 * 1e9)
            .collect()
    };
    let (plain, read) = (per_scan(&whole), per_scan(&whole_read));
    let start: Vec<f64> = start.iter().map(|t| t * 1e3).collect();
    let _ = std::fs::remove_dir_all(&dir);

    let ratio = |cli: &[f64]| spread(cli.iter().zip(&library).map(|(c, l)| c / l).collect()).0;
    let (plain_ratio, read_ratio) = (ratio(&plain), ratio(&read));
    println!(
        "\ngutta-vm --scans {scans} of scan_cost.lad (10 instructions per scan), \
         median (min..max) of {runs} runs:"
    );
    let row = |name: &str, unit: &str, values: Vec<f64>| {
        let (median, min, max) = spread(values);
        println!("{name:<42} {median:>8.1} {unit:<8} ({min:.1}..{max:.1})");
    };
    row("process start (--scans 1)", "ms", start);
    row("library, Vm::scan", "ns/scan", library);
    row("gutta-vm --scans N", "ns/scan", plain);
    row("gutta-vm --scans N --read Q0.1 --read MD0", "ns/scan", read);
    println!(
        "command line / library: {plain_ratio:.2}x, with --read {read_ratio:.2}x \
         (bar: at most 1.10x)"
    );
}
