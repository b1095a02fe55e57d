//! Scaling benchmark of the front end (`check_source`): generated programs of 10k, 100k
//! and 1M lines on the bench target (benches/target/), each size in its own child
//! process. Prints wall time (min/median), lines/s, peak memory per source line and the
//! linearity ratio. Measures only; it asserts that the programs check without errors.
//!
//! `cargo bench -p gutta-compiler --bench check_scale [-- SIZE...]`. Without `--bench`
//! (as under `cargo test --benches`) it runs one small size once, as a smoke test.

#![allow(
    clippy::disallowed_methods,
    clippy::disallowed_types,
    clippy::disallowed_macros,
    reason = "a benchmark is a program: it reads its arguments, runs itself, times and prints"
)]

mod scale_program;

use std::process::{Command, ExitCode};
use std::time::{Duration, Instant};

use gutta_compiler::diagnostics::render::{render, RenderStyle};
use gutta_compiler::source::SourceFile;
use gutta_compiler::{check_source, CheckedFile};

const DEFAULT_SIZES: [usize; 3] = [10_000, 100_000, 1_000_000];
const SMOKE_SIZE: usize = 2_000;

/// Figures of one size, as the child prints them on one `RESULT` line.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Figures {
    lines: usize,
    text_bytes: usize,
    runs: usize,
    min_ms: f64,
    median_ms: f64,
    peak_bytes: u64,
    retained_bytes: u64,
    warnings: usize,
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let Some(i) = args.iter().position(|a| a == "--child") {
        let lines = args.get(i + 1).and_then(|s| s.parse().ok()).unwrap_or(0);
        let runs = args.get(i + 2).and_then(|s| s.parse().ok()).unwrap_or(1);
        return child(lines, runs);
    }
    let bench_mode = args.iter().any(|a| a == "--bench");
    let mut sizes: Vec<usize> = args.iter().filter_map(|a| a.parse().ok()).collect();
    if sizes.is_empty() {
        sizes = if bench_mode {
            DEFAULT_SIZES.to_vec()
        } else {
            vec![SMOKE_SIZE]
        };
    }
    let mut results = Vec::new();
    for &size in &sizes {
        let runs = if !bench_mode {
            1
        } else if size <= 20_000 {
            21
        } else if size <= 200_000 {
            11
        } else {
            5
        };
        match run_child(size, runs) {
            Ok(f) => results.push(f),
            Err(e) => {
                eprintln!("check_scale: size {size}: {e}");
                return ExitCode::FAILURE;
            }
        }
    }
    print_table(&results);
    ExitCode::SUCCESS
}

fn run_child(lines: usize, runs: usize) -> Result<Figures, String> {
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let out = Command::new(exe)
        .args(["--child", &lines.to_string(), &runs.to_string()])
        .output()
        .map_err(|e| e.to_string())?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    if !out.status.success() {
        return Err(format!(
            "child failed ({}):\n{stdout}\n{}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    stdout
        .lines()
        .find_map(|l| l.strip_prefix("RESULT "))
        .and_then(parse_result)
        .ok_or_else(|| format!("no RESULT line in child output:\n{stdout}"))
}

fn parse_result(line: &str) -> Option<Figures> {
    let field = |name: &str| -> Option<&str> {
        line.split_whitespace()
            .find_map(|kv| kv.strip_prefix(name)?.strip_prefix('='))
    };
    Some(Figures {
        lines: field("lines")?.parse().ok()?,
        text_bytes: field("text_bytes")?.parse().ok()?,
        runs: field("runs")?.parse().ok()?,
        min_ms: field("min_ms")?.parse().ok()?,
        median_ms: field("median_ms")?.parse().ok()?,
        peak_bytes: field("peak_bytes")?.parse().ok()?,
        retained_bytes: field("retained_bytes")?.parse().ok()?,
        warnings: field("warnings")?.parse().ok()?,
    })
}

fn print_table(results: &[Figures]) {
    println!(
        "{:>9} {:>5} {:>10} {:>10} {:>12} {:>11} {:>13} {:>11} {:>5}",
        "lines",
        "runs",
        "min ms",
        "median ms",
        "lines/s",
        "text B/line",
        "peak B/line",
        "kept B/line",
        "warn"
    );
    for f in results {
        let per_line = |b: u64| b as f64 / f.lines as f64;
        println!(
            "{:>9} {:>5} {:>10.2} {:>10.2} {:>12.0} {:>11.1} {:>13.1} {:>11.1} {:>5}",
            f.lines,
            f.runs,
            f.min_ms,
            f.median_ms,
            f.lines as f64 / (f.median_ms / 1000.0),
            f.text_bytes as f64 / f.lines as f64,
            per_line(f.peak_bytes),
            per_line(f.retained_bytes),
            f.warnings
        );
    }
    if let (Some(first), Some(last)) = (results.first(), results.last()) {
        if results.len() > 1 {
            let ns = |ms: f64, f: &Figures| ms * 1e6 / f.lines as f64;
            let (med_first, med_last) = (ns(first.median_ms, first), ns(last.median_ms, last));
            let (min_first, min_last) = (ns(first.min_ms, first), ns(last.min_ms, last));
            println!(
                "time per line, {} vs {} lines: median {med_first:.0} vs {med_last:.0} ns (ratio {:.2}), \
                 min {min_first:.0} vs {min_last:.0} ns (ratio {:.2}); 1.00 = linear",
                first.lines,
                last.lines,
                med_last / med_first,
                min_last / min_first
            );
        }
    }
    println!("peak B/line: VmHWM growth during the first check_source, source text excluded");
    println!("kept B/line: VmRSS growth while the CheckedFile is alive, source text excluded");
}

// ---- child: one size --------------------------------------------------------------

/// `VmHWM` and `VmRSS` of this process, in bytes.
fn memory() -> (u64, u64) {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let field = |name: &str| {
        status
            .lines()
            .find_map(|l| l.strip_prefix(name))
            .and_then(|rest| rest.split_whitespace().next())
            .and_then(|kb| kb.parse::<u64>().ok())
            .map_or(0, |kb| kb * 1024)
    };
    (field("VmHWM:"), field("VmRSS:"))
}

/// Reset the peak (VmHWM) to the current RSS; false where the kernel does not allow it.
fn reset_peak() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

fn child(lines: usize, runs: usize) -> ExitCode {
    let target = scale_program::bench_target();
    let text = scale_program::generate(lines);
    let text_bytes = text.len();
    let line_count = text.lines().count();
    let mut file = SourceFile::new("bench.lad", text);

    // Memory: the first check, from a baseline that holds the target and the text.
    let reset = reset_peak();
    let (hwm_before, rss_before) = memory();
    let checked = check_source(file, Some(&target));
    let (hwm_after, rss_after) = memory();
    let baseline = if reset {
        rss_before
    } else {
        hwm_before.max(rss_before)
    };
    let errors = checked
        .diagnostics()
        .iter()
        .filter(|d| d.is_error())
        .count();
    let warnings = checked.diagnostics().len() - errors;
    if errors > 0 {
        let shown = &checked.diagnostics()[..checked.diagnostics().len().min(10)];
        println!("{errors} errors in the generated program; the first ones:");
        println!("{}", render(&checked.file, shown, RenderStyle::PLAIN));
        return ExitCode::FAILURE;
    }
    file = take_file(checked);

    // Time: one warm-up, then `runs` timed runs.
    let mut times: Vec<Duration> = Vec::with_capacity(runs);
    for run in 0..=runs {
        let start = Instant::now();
        let checked = check_source(file, Some(&target));
        let elapsed = start.elapsed();
        file = take_file(checked);
        if run > 0 {
            times.push(elapsed);
        }
    }
    times.sort();
    // `RUNS` 0 (memory only, e.g. under valgrind) reports zero times.
    let ms = |d: Option<&Duration>| d.map_or(0.0, |d| d.as_secs_f64() * 1000.0);
    println!(
        "RESULT lines={line_count} text_bytes={text_bytes} runs={runs} min_ms={:.3} median_ms={:.3} peak_bytes={} retained_bytes={} warnings={warnings} peak_reset={reset}",
        ms(times.first()),
        ms(times.get(times.len() / 2)),
        hwm_after.saturating_sub(baseline),
        rss_after.saturating_sub(rss_before),
    );
    ExitCode::SUCCESS
}

/// Keep the source for the next run; drop everything else (outside the timed region).
fn take_file(checked: CheckedFile) -> SourceFile {
    let CheckedFile { file, .. } = checked;
    file
}
