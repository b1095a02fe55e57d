//! Issue 14's end-to-end bar for `gutta-cc test`: a file of 100 tests of a generated
//! 200-instruction program (`gtest/benches/bench_program/`, shared with the library's
//! `gtest_run` bench through `#[path]`) written to a temporary folder, and the real
//! `gutta-cc test FILE` process timed from spawn to exit (read, compile, plan, run,
//! print), after one warm-up run. Prints median, min and max wall time. Bar: < 100 ms.
//! `cargo bench -p gutta-cli --bench test_command [-- --bench RUNS]`; without
//! `--bench` (as in `cargo test --benches`), one run.

#[path = "../../gtest/benches/bench_program/mod.rs"]
#[allow(dead_code, reason = "the 1,000-scan test is the library bench's")]
mod bench_program;

use std::process::Command;
use std::time::{Duration, Instant};

/// Tests in the file.
const TESTS: u32 = 100;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let bench_mode = args.iter().any(|a| a == "--bench");
    let runs: usize = args
        .iter()
        .find_map(|a| a.parse().ok())
        .unwrap_or(if bench_mode { 31 } else { 1 });
    let dir = std::env::temp_dir().join(format!("gutta-test-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    std::fs::write(
        dir.join(bench_program::PROGRAM_FILE),
        bench_program::program(),
    )
    .expect("write the program");
    let tests = dir.join("tests.gtest");
    std::fs::write(&tests, bench_program::many_tests(TESTS)).expect("write the tests");

    let expected = format!("{TESTS} passed, 0 failed ({TESTS} tests in 1 file)");
    let mut times = Vec::with_capacity(runs);
    for run in 0..=runs {
        let started = Instant::now();
        let output = Command::new(env!("CARGO_BIN_EXE_gutta-cc"))
            .arg("test")
            .arg(&tests)
            .output()
            .expect("run gutta-cc test");
        let elapsed = started.elapsed();
        let stdout = String::from_utf8_lossy(&output.stdout);
        assert!(
            output.status.success() && stdout.contains(&expected),
            "gutta-cc test did not pass all {TESTS} tests ({}):\n{stdout}\n{}",
            output.status,
            String::from_utf8_lossy(&output.stderr)
        );
        // Run 0 warms the page cache and the binary; it is not counted.
        if run > 0 {
            times.push(elapsed);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);

    times.sort();
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    println!(
        "gutta-cc test, a file of {TESTS} tests of a {}-instruction program, process spawn to exit",
        bench_program::INSTRUCTIONS
    );
    println!(
        "runs {runs}: median {:.2} ms, min {:.2} ms, max {:.2} ms (bar: < 100 ms)",
        ms(times[times.len() / 2]),
        ms(times[0]),
        ms(times[times.len() - 1])
    );
}
