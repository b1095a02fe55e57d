//! Issue 30's scale figures: a plant of N PLCs (examples/tank.lad compiled once with
//! gutta-cc, `scan-ms = 10`, each on its own Modbus TCP listener) run by one
//! `gutta-sim --plant PLANT.toml --stats-every 1`, every PLC polled meanwhile over
//! Modbus TCP as a SCADA would (one connection per PLC, function 03 for 10 holding
//! registers every 100 ms). For N = 100 it prints every PLC's worst scan period, the
//! worst of all, the median of the per-PLC worsts and the scans counted against the
//! scans expected; then it searches the largest N that holds (see [`Verdict::holds`])
//! by doubling, then bisecting. `cargo bench -p gutta-cli --bench sim_plant`; without
//! `--bench` (as under `cargo test --benches`) it checks its own parsers and runs a
//! plant of 4 PLCs for 2 s; `-- --bench 100 2000` runs only the sizes given. A gutta-sim without `--plant` is measured as N separate
//! processes instead (said in the output). It only measures: no figure is written here.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// The scan period every PLC of the plant asks for.
const SCAN_MS: u32 = 10;
/// How often each PLC is polled.
const POLL_EVERY: Duration = Duration::from_millis(100);
/// Holding registers read per poll (function 03 from address 0).
const POLL_REGISTERS: u16 = 10;
/// Threads of the SCADA side; each polls its share of the connections.
const POLL_THREADS: usize = 2;

/// How a run is timed: stats lines that arrive within `warmup..warmup + measure` count.
#[derive(Debug, Clone, Copy)]
struct Timing {
    warmup: Duration,
    measure: Duration,
}

fn main() {
    let bench = std::env::args().any(|a| a == "--bench");
    check_parsers();
    let work = std::env::temp_dir().join(format!("gutta-plant-bench-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(&work).expect("creates the work directory");
    let image = compile_tank(&work);
    let launch = if sim_has_plant() {
        Launch::Plant
    } else {
        println!("this gutta-sim has no --plant: each PLC runs in a gutta-sim process of its own");
        Launch::Processes
    };
    let sizes: Vec<usize> = std::env::args().filter_map(|a| a.parse().ok()).collect();
    if bench && !sizes.is_empty() {
        sizes_only(&work, &image, launch, &sizes);
    } else if bench {
        full(&work, &image, launch);
    } else {
        let timing = Timing {
            warmup: Duration::from_millis(500),
            measure: Duration::from_millis(1500),
        };
        let verdict = run_plant(&work, &image, launch, 4, timing).expect("a plant of 4 starts");
        verdict.print_per_plc();
        assert_eq!(verdict.plcs.len(), 4, "every PLC reported its stats");
        assert!(
            verdict.plcs.iter().all(|p| p.scans > 0),
            "every PLC scanned"
        );
        assert!(verdict.polls.answered > 0, "the PLCs answered their polls");
        assert_eq!(verdict.polls.failed, 0, "no poll failed");
    }
    let _ = std::fs::remove_dir_all(&work);
}

/// The benchmark: the 100-PLC plant in detail, then the search.
fn full(work: &Path, image: &Path, launch: Launch) {
    let timing = Timing {
        warmup: Duration::from_secs(2),
        measure: Duration::from_secs(10),
    };
    let began = Instant::now();
    println!(
        "machine: {} cores; every PLC scans every {SCAN_MS} ms and is polled every {} ms \
         (function 03, {POLL_REGISTERS} registers, one connection per PLC, {POLL_THREADS} \
         polling threads); {} s warm-up, then {} s measured",
        std::thread::available_parallelism().map_or(1, usize::from),
        POLL_EVERY.as_millis(),
        timing.warmup.as_secs(),
        timing.measure.as_secs()
    );
    println!("holds: {}", Verdict::RULE);
    // The machine's own noise: a plant of one PLC in the same conditions.
    match run_plant(work, image, launch, 1, timing) {
        Ok(one) => println!(
            "control, a plant of 1 PLC: worst period {:.1} ms, gutta-sim {} cores",
            one.worst(),
            one.sim_cores
                .map_or_else(|| "-".to_string(), |c| format!("{c:.3}"))
        ),
        Err(e) => println!("control, a plant of 1 PLC: did not start: {e}"),
    }
    let hundred = run_plant(work, image, launch, 100, timing).expect("a plant of 100 starts");
    println!("\nthe plant of 100 PLCs:");
    hundred.print_per_plc();
    hundred.print_summary();

    // Doubling from 100, then bisecting between the largest that held and the smallest
    // that did not, within about five minutes in all.
    let budget = Duration::from_secs(270);
    let mut rows = vec![(100, hundred.summary_row())];
    let (mut good, mut bad) = if hundred.holds() {
        (Some(100), None)
    } else {
        (None, Some(100))
    };
    // Separate processes cost far more than PLCs in one plant: fewer are tried.
    let largest = match launch {
        Launch::Plant => 6400,
        Launch::Processes => 800,
    };
    let mut n = 200;
    while bad.is_none() && n <= largest && began.elapsed() < budget {
        let held = try_size(work, image, launch, n, timing, &mut rows);
        if held {
            good = Some(n);
            n *= 2;
        } else {
            bad = Some(n);
        }
    }
    let mut low = good.unwrap_or(0);
    let mut high = bad.unwrap_or(100);
    if good.is_none() {
        // Not even 100 holds: bisect below it.
        low = 0;
    }
    while bad.is_some() && high - low > (low / 16).max(1) && began.elapsed() < budget {
        let mid = (low + high) / 2;
        if mid == 0 {
            break;
        }
        if try_size(work, image, launch, mid, timing, &mut rows) {
            low = mid;
        } else {
            high = mid;
        }
    }
    rows.sort_by_key(|(n, _)| *n);
    println!("\n{:>6}  {}", "PLCs", SummaryRow::HEADER);
    for (n, row) in &rows {
        println!("{n:>6}  {row}");
    }
    match bad {
        Some(_) => println!(
            "largest plant that holds {SCAN_MS} ms: {low} PLCs (the next tried, {high}, did not){}",
            if began.elapsed() >= budget {
                " (the time budget ended the search)"
            } else {
                ""
            }
        ),
        None => println!(
            "largest plant that holds {SCAN_MS} ms: at least {low} PLCs (the largest tried)"
        ),
    }
    println!("search took {:.0} s", began.elapsed().as_secs_f64());
}

/// `-- --bench N...`: only these plant sizes, one row each.
fn sizes_only(work: &Path, image: &Path, launch: Launch, sizes: &[usize]) {
    let timing = Timing {
        warmup: Duration::from_secs(2),
        measure: Duration::from_secs(10),
    };
    println!("holds: {}", Verdict::RULE);
    println!("{:>6}  {}", "PLCs", SummaryRow::HEADER);
    let mut rows = Vec::new();
    for &n in sizes {
        try_size(work, image, launch, n, timing, &mut rows);
    }
}

/// One size of the search: run it, add its row, say whether it held.
fn try_size(
    work: &Path,
    image: &Path,
    launch: Launch,
    n: usize,
    timing: Timing,
    rows: &mut Vec<(usize, SummaryRow)>,
) -> bool {
    match run_plant(work, image, launch, n, timing) {
        Ok(verdict) => {
            let row = verdict.summary_row();
            println!("{n:>6} PLCs: {row}");
            rows.push((n, row));
            verdict.holds()
        }
        Err(e) => {
            println!("{n:>6} PLCs: did not start: {e}");
            rows.push((n, SummaryRow::failed(&e)));
            false
        }
    }
}

/// `examples/tank.lad` compiled by gutta-cc into `work/tank/`.
fn compile_tank(work: &Path) -> PathBuf {
    let out = work.join("tank");
    let source = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/tank.lad");
    let status = Command::new(env!("CARGO_BIN_EXE_gutta-cc"))
        .arg(source)
        .arg("-o")
        .arg(&out)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .expect("runs gutta-cc");
    assert!(status.success(), "gutta-cc compiles examples/tank.lad");
    out
}

/// Whether this gutta-sim takes `--plant`.
fn sim_has_plant() -> bool {
    Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
        .arg("--help")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).contains("--plant"))
}

/// How the N PLCs are run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Launch {
    /// One `gutta-sim --plant` process.
    Plant,
    /// One `gutta-sim IMAGE --tcp` process per PLC (before `--plant` existed).
    Processes,
}

/// The name of the k-th PLC of a plant.
fn plc_name(k: usize) -> String {
    format!("plc{k:04}")
}

/// PLANT.toml for `n` PLCs running `image`, each on a free port of 127.0.0.1.
fn plant_toml(n: usize, image: &Path) -> String {
    let image = image.display().to_string().replace('\\', "\\\\");
    let mut text = format!("# {n} PLCs for the sim_plant benchmark\n");
    for k in 0..n {
        text.push_str(&format!(
            "\n[[device]]\nname = \"{}\"\nkind = \"plc\"\nimage = \"{image}\"\n\
             tcp = \"127.0.0.1:0\"\nscan-ms = {SCAN_MS}\n",
            plc_name(k)
        ));
    }
    text
}

/// A stdout line of gutta-sim, as far as the bench reads it.
#[derive(Debug, Clone, PartialEq)]
enum SimLine {
    /// `gutta-sim: [NAME: ]modbus-tcp on ADDRESS[, ...]`.
    Listens {
        name: Option<String>,
        address: SocketAddr,
    },
    /// `gutta-sim: [NAME: ]stats: 100 scans in 1.00 s, period max 10.4 ms`.
    Stats {
        name: Option<String>,
        stats: Window,
    },
    Other,
}

/// One stats line's window.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Window {
    scans: u64,
    seconds: f64,
    period_max_ms: f64,
}

/// Reads one line of gutta-sim's stdout.
fn parse_line(line: &str) -> SimLine {
    let Some(rest) = line.strip_prefix("gutta-sim: ") else {
        return SimLine::Other;
    };
    // A device's name comes first in a plant: `NAME: `, NAME without spaces.
    let (name, rest) = match rest.split_once(": ") {
        Some((name, after)) if !name.contains(' ') && name != "stats" => {
            (Some(name.to_string()), after)
        }
        _ => (None, rest),
    };
    if let Some(stats) = rest.strip_prefix("stats: ") {
        return match parse_window(stats) {
            Some(stats) => SimLine::Stats { name, stats },
            None => SimLine::Other,
        };
    }
    let first = rest.split(", ").next().unwrap_or("");
    match first
        .strip_prefix("modbus-tcp on ")
        .and_then(|a| a.parse().ok())
    {
        Some(address) => SimLine::Listens { name, address },
        None => SimLine::Other,
    }
}

/// `100 scans in 1.00 s, period max 10.4 ms`.
fn parse_window(text: &str) -> Option<Window> {
    let words: Vec<&str> = text.split_whitespace().collect();
    match words.as_slice() {
        [scans, "scans" | "scan", "in", seconds, "s,", "period", "max", max, "ms"] => {
            Some(Window {
                scans: scans.replace(',', "").parse().ok()?,
                seconds: seconds.parse().ok()?,
                period_max_ms: max.parse().ok()?,
            })
        }
        _ => None,
    }
}

/// The parsers and the plant writer on known text; a wrong parse stops the bench.
fn check_parsers() {
    assert_eq!(
        parse_line("gutta-sim: plc0007: stats: 100 scans in 1.00 s, period max 10.4 ms"),
        SimLine::Stats {
            name: Some("plc0007".into()),
            stats: Window {
                scans: 100,
                seconds: 1.0,
                period_max_ms: 10.4
            }
        }
    );
    assert_eq!(
        parse_line("gutta-sim: stats: 1 scan in 1.25 s, period max 0.0 ms"),
        SimLine::Stats {
            name: None,
            stats: Window {
                scans: 1,
                seconds: 1.25,
                period_max_ms: 0.0
            }
        }
    );
    assert_eq!(
        parse_line("gutta-sim: a: modbus-tcp on 127.0.0.1:5020, rtu-over-tcp on 127.0.0.1:5021"),
        SimLine::Listens {
            name: Some("a".into()),
            address: "127.0.0.1:5020".parse().expect("address")
        }
    );
    assert_eq!(
        parse_line("gutta-sim: modbus-tcp on 127.0.0.1:40001"),
        SimLine::Listens {
            name: None,
            address: "127.0.0.1:40001".parse().expect("address")
        }
    );
    assert_eq!(parse_line("gutta-sim: b: no listener"), SimLine::Other);
    assert_eq!(
        parse_line("gutta-sim: c: the program faulted: x (error code 3)"),
        SimLine::Other
    );
    let toml = plant_toml(3, Path::new("/tmp/x"));
    assert_eq!(toml.matches("[[device]]").count(), 3);
    assert!(toml.contains("name = \"plc0002\"\nkind = \"plc\"\nimage = \"/tmp/x\"\ntcp = \"127.0.0.1:0\"\nscan-ms = 10\n"));
}

/// What the SCADA side did.
#[derive(Debug, Clone, Copy, Default)]
struct PollCount {
    answered: u64,
    failed: u64,
    /// The longest round of a slice (its requests sent, then its answers read), in
    /// milliseconds.
    slowest_ms: f64,
    seconds: f64,
}

/// One PLC's measured window.
#[derive(Debug, Clone)]
struct PlcFigures {
    name: String,
    scans: u64,
    seconds: f64,
    worst_ms: f64,
}

impl PlcFigures {
    fn mean_ms(&self) -> f64 {
        if self.scans == 0 {
            f64::INFINITY
        } else {
            self.seconds * 1e3 / self.scans as f64
        }
    }
    fn expected_scans(&self) -> f64 {
        self.seconds * 1e3 / f64::from(SCAN_MS)
    }
}

/// A run's figures and whether it held.
#[derive(Debug)]
struct Verdict {
    plcs: Vec<PlcFigures>,
    /// PLCs of the plant that reported no stats within the measured window.
    silent: usize,
    polls: PollCount,
    plcs_polled: usize,
    /// CPU time of the gutta-sim process(es) over the measured window, in cores (Linux:
    /// /proc; `None` elsewhere).
    sim_cores: Option<f64>,
}

impl Verdict {
    const RULE: &'static str =
        "over the measured window (stats lines of gutta-sim, one a second), every \
         PLC's longest period is at most 2 x scan-ms, every PLC's mean period is within 2 % of \
         scan-ms (so no more than 2 % of its scans lost), every PLC reported, and every poll was \
         answered";

    fn worst(&self) -> f64 {
        self.plcs.iter().map(|p| p.worst_ms).fold(0.0, f64::max)
    }

    fn median_worst(&self) -> f64 {
        let mut w: Vec<f64> = self.plcs.iter().map(|p| p.worst_ms).collect();
        w.sort_by(f64::total_cmp);
        match w.len() {
            0 => f64::NAN,
            n if n % 2 == 1 => w[n / 2],
            n => (w[n / 2 - 1] + w[n / 2]) / 2.0,
        }
    }

    fn worst_mean_deviation(&self) -> f64 {
        let period = f64::from(SCAN_MS);
        self.plcs
            .iter()
            .map(|p| (p.mean_ms() - period).abs() / period)
            .fold(0.0, f64::max)
    }

    fn scans(&self) -> (u64, f64) {
        (
            self.plcs.iter().map(|p| p.scans).sum(),
            self.plcs.iter().map(PlcFigures::expected_scans).sum(),
        )
    }

    fn holds(&self) -> bool {
        self.silent == 0
            && !self.plcs.is_empty()
            && self.worst() <= 2.0 * f64::from(SCAN_MS)
            && self.worst_mean_deviation() <= 0.02
            && self.polls.failed == 0
    }

    fn poll_rate(&self) -> f64 {
        self.polls.answered as f64 / self.polls.seconds.max(1e-9) / self.plcs_polled.max(1) as f64
    }

    fn print_per_plc(&self) {
        println!("worst period of every PLC (ms):");
        for chunk in self.plcs.chunks(10) {
            let cells: Vec<String> = chunk
                .iter()
                .map(|p| format!("{} {:5.1}", p.name, p.worst_ms))
                .collect();
            println!("  {}", cells.join("  "));
        }
    }

    fn print_summary(&self) {
        let (scans, expected) = self.scans();
        println!(
            "worst period over all: {:.1} ms; median of the per-PLC worst: {:.1} ms; mean period \
             at most {:.2} % off {SCAN_MS} ms",
            self.worst(),
            self.median_worst(),
            self.worst_mean_deviation() * 100.0
        );
        println!(
            "scans: {scans} counted, {expected:.0} expected ({:+.2} %); {} PLCs silent",
            (scans as f64 / expected - 1.0) * 100.0,
            self.silent
        );
        println!(
            "polls: {} answered ({:.1} per PLC per second), {} failed, slowest round {:.1} ms",
            self.polls.answered,
            self.poll_rate(),
            self.polls.failed,
            self.polls.slowest_ms
        );
        if let Some(cores) = self.sim_cores {
            println!("gutta-sim used {cores:.2} cores over the measured window");
        }
        println!("holds: {}", if self.holds() { "yes" } else { "no" });
    }

    fn summary_row(&self) -> SummaryRow {
        let (scans, expected) = self.scans();
        SummaryRow(format!(
            "{:>8.1}  {:>9.1}  {:>7.2}  {:>8.2}  {:>11.1}  {:>6}  {:>9}  {}",
            self.worst(),
            self.median_worst(),
            self.worst_mean_deviation() * 100.0,
            (scans as f64 / expected - 1.0) * 100.0,
            self.poll_rate(),
            self.polls.failed,
            self.sim_cores
                .map_or_else(|| "-".to_string(), |c| format!("{c:.2}")),
            if self.holds() { "yes" } else { "no" }
        ))
    }
}

/// A row of the search's table.
#[derive(Debug)]
struct SummaryRow(String);

impl SummaryRow {
    const HEADER: &'static str =
        "worst ms  median ms  mean ±%  scans ±%  polls/s/PLC  failed  sim cores  holds";
    fn failed(reason: &str) -> SummaryRow {
        SummaryRow(format!("did not start: {reason}"))
    }
}

impl std::fmt::Display for SummaryRow {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// Stats lines received, with when they arrived.
type Received = Arc<Mutex<Vec<(Instant, String, Window)>>>;

/// Started gutta-sim processes, stopped on drop: Ctrl-C (SIGINT, through `kill`) and,
/// for any still running 5 s later, SIGKILL.
#[derive(Debug)]
struct Running(Vec<Child>);

impl Drop for Running {
    fn drop(&mut self) {
        if self.0.is_empty() {
            return;
        }
        let _ = Command::new("kill")
            .arg("-INT")
            .args(self.0.iter().map(|c| c.id().to_string()))
            .status();
        let until = Instant::now() + Duration::from_secs(5);
        for child in &mut self.0 {
            while Instant::now() < until && matches!(child.try_wait(), Ok(None)) {
                std::thread::sleep(Duration::from_millis(20));
            }
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

/// Starts `n` PLCs, polls them through warm-up and the measured window, and judges the
/// stats lines that arrived in that window.
fn run_plant(
    work: &Path,
    image: &Path,
    launch: Launch,
    n: usize,
    timing: Timing,
) -> Result<Verdict, String> {
    let received: Received = Arc::new(Mutex::new(Vec::new()));
    let (addresses_tx, addresses_rx) = mpsc::channel();
    let mut running = Running(Vec::new());
    let starting = Instant::now();
    match launch {
        Launch::Plant => {
            let file = work.join(format!("plant-{n}.toml"));
            std::fs::write(&file, plant_toml(n, image))
                .map_err(|e| format!("cannot write {}: {e}", file.display()))?;
            let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
                .arg("--plant")
                .arg(&file)
                .args(["--stats-every", "1"])
                .stdout(Stdio::piped())
                .spawn()
                .map_err(|e| format!("cannot start gutta-sim: {e}"))?;
            let stdout = child.stdout.take().ok_or("no stdout")?;
            running.0.push(child);
            read_lines(stdout, None, addresses_tx, Arc::clone(&received));
        }
        Launch::Processes => {
            for k in 0..n {
                let mut child = Command::new(env!("CARGO_BIN_EXE_gutta-sim"))
                    .arg(image)
                    .args(["--tcp", "127.0.0.1:0", "--scan-ms", &SCAN_MS.to_string()])
                    .args(["--stats-every", "1"])
                    .stdout(Stdio::piped())
                    .spawn()
                    .map_err(|e| format!("cannot start gutta-sim {k}: {e}"))?;
                let stdout = child.stdout.take().ok_or("no stdout")?;
                running.0.push(child);
                read_lines(
                    stdout,
                    Some(plc_name(k)),
                    addresses_tx.clone(),
                    Arc::clone(&received),
                );
            }
            drop(addresses_tx);
        }
    }
    let mut addresses = Vec::with_capacity(n);
    let start_limit = Duration::from_secs(60);
    while addresses.len() < n {
        let left = start_limit.saturating_sub(starting.elapsed());
        match addresses_rx.recv_timeout(left) {
            Ok(a) => addresses.push(a),
            Err(_) => {
                return Err(format!(
                    "{} of {n} listeners announced within {} s",
                    addresses.len(),
                    start_limit.as_secs()
                ))
            }
        }
    }
    let started_in = starting.elapsed();
    let polls = Poller::start(&addresses)?;
    let pids: Vec<u32> = running.0.iter().map(Child::id).collect();
    std::thread::sleep(timing.warmup);
    let measure_from = Instant::now();
    let cpu_from = cpu_seconds(&pids);
    std::thread::sleep(timing.measure);
    let measure_to = Instant::now();
    let sim_cores = cpu_seconds(&pids)
        .zip(cpu_from)
        .map(|(to, from)| (to - from) / (measure_to - measure_from).as_secs_f64());
    let polls = polls.stop();
    drop(running);
    if started_in > Duration::from_secs(5) {
        println!(
            "       ({n} PLCs took {:.1} s to start)",
            started_in.as_secs_f64()
        );
    }
    let lines = received.lock().map_err(|_| "poisoned")?.clone();
    let mut verdict = judge(n, &lines, measure_from, measure_to, polls, addresses.len());
    verdict.sim_cores = sim_cores;
    Ok(verdict)
}

/// User and system CPU seconds of these processes so far (Linux: /proc/PID/stat, at
/// 100 ticks a second, the kernel's USER_HZ); `None` where that cannot be read.
fn cpu_seconds(pids: &[u32]) -> Option<f64> {
    let mut ticks = 0u64;
    for pid in pids {
        let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
        // After the command name in parentheses: state is field 3, utime 14, stime 15.
        let fields: Vec<&str> = stat.rsplit_once(')')?.1.split_whitespace().collect();
        ticks += fields.get(11)?.parse::<u64>().ok()? + fields.get(12)?.parse::<u64>().ok()?;
    }
    Some(ticks as f64 / 100.0)
}

/// A reader of one gutta-sim's stdout: listener lines go to `addresses` (named as the
/// line names them, else `name`), stats lines into `received`.
fn read_lines(
    stdout: impl Read + Send + 'static,
    name: Option<String>,
    addresses: mpsc::Sender<SocketAddr>,
    received: Received,
) {
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            match parse_line(&line) {
                SimLine::Listens { address, .. } => {
                    let _ = addresses.send(address);
                }
                SimLine::Stats { name: own, stats } => {
                    let who = own.or_else(|| name.clone()).unwrap_or_default();
                    if let Ok(mut r) = received.lock() {
                        r.push((Instant::now(), who, stats));
                    }
                }
                SimLine::Other => {}
            }
        }
    });
}

/// The figures of every PLC from the stats lines that arrived after `from` and until
/// `to` (a line covers the second before it).
fn judge(
    n: usize,
    lines: &[(Instant, String, Window)],
    from: Instant,
    to: Instant,
    polls: PollCount,
    plcs_polled: usize,
) -> Verdict {
    let mut by_name: std::collections::BTreeMap<String, PlcFigures> = Default::default();
    for (at, name, w) in lines {
        if *at < from || *at > to {
            continue;
        }
        let p = by_name.entry(name.clone()).or_insert_with(|| PlcFigures {
            name: name.clone(),
            scans: 0,
            seconds: 0.0,
            worst_ms: 0.0,
        });
        p.scans += w.scans;
        p.seconds += w.seconds;
        p.worst_ms = p.worst_ms.max(w.period_max_ms);
    }
    let plcs: Vec<PlcFigures> = by_name.into_values().collect();
    Verdict {
        silent: n.saturating_sub(plcs.len()),
        plcs,
        polls,
        plcs_polled,
        sim_cores: None,
    }
}

/// The SCADA side: every PLC read every [`POLL_EVERY`] over a connection of its own.
#[derive(Debug)]
struct Poller {
    stop: Arc<AtomicBool>,
    threads: Vec<std::thread::JoinHandle<PollCount>>,
}

impl Poller {
    /// Connects to every address (one connection each) and starts polling; each thread
    /// spreads its connections over the poll period in ten slices.
    fn start(addresses: &[SocketAddr]) -> Result<Poller, String> {
        let mut streams = Vec::with_capacity(addresses.len());
        for a in addresses {
            let s = TcpStream::connect(a).map_err(|e| format!("cannot connect to {a}: {e}"))?;
            s.set_nodelay(true).map_err(|e| e.to_string())?;
            s.set_read_timeout(Some(Duration::from_secs(2)))
                .map_err(|e| e.to_string())?;
            streams.push(s);
        }
        let stop = Arc::new(AtomicBool::new(false));
        let per_thread = streams.len().div_ceil(POLL_THREADS).max(1);
        let mut threads = Vec::new();
        let mut rest = streams;
        while !rest.is_empty() {
            let mine: Vec<TcpStream> = rest.drain(..per_thread.min(rest.len())).collect();
            let stop = Arc::clone(&stop);
            threads.push(std::thread::spawn(move || poll_loop(mine, &stop)));
        }
        Ok(Poller { stop, threads })
    }

    fn stop(self) -> PollCount {
        self.stop.store(true, Ordering::Relaxed);
        let mut total = PollCount::default();
        for t in self.threads {
            if let Ok(c) = t.join() {
                total.answered += c.answered;
                total.failed += c.failed;
                total.slowest_ms = total.slowest_ms.max(c.slowest_ms);
                total.seconds = total.seconds.max(c.seconds);
            }
        }
        total
    }
}

/// Polls `streams` until `stop`: in each tenth of [`POLL_EVERY`], a tenth of them get a
/// request, then their answers are read. A connection that fails is counted and left.
fn poll_loop(mut streams: Vec<TcpStream>, stop: &AtomicBool) -> PollCount {
    const SLICES: usize = 10;
    let slice = POLL_EVERY / SLICES as u32;
    let began = Instant::now();
    let mut count = PollCount::default();
    let mut alive = vec![true; streams.len()];
    let mut tid: u16 = 0;
    let mut next = Instant::now();
    let per_slice = streams.len().div_ceil(SLICES).max(1);
    let mut k = 0usize;
    while !stop.load(Ordering::Relaxed) {
        let from = (k % SLICES) * per_slice;
        let to = (from + per_slice).min(streams.len());
        let sent_at = Instant::now();
        let mut asked = Vec::new();
        for i in from..to {
            if !alive[i] {
                continue;
            }
            tid = tid.wrapping_add(1);
            let t = tid;
            let mut request = t.to_be_bytes().to_vec();
            request.extend([0, 0, 0, 6, 1, 0x03, 0, 0]);
            request.extend(POLL_REGISTERS.to_be_bytes());
            if streams[i].write_all(&request).is_ok() {
                asked.push((i, t));
            } else {
                alive[i] = false;
                count.failed += 1;
            }
        }
        let mut answer = vec![0u8; 9 + 2 * usize::from(POLL_REGISTERS)];
        for (i, t) in asked {
            let ok = streams[i].read_exact(&mut answer).is_ok()
                && answer[..2] == t.to_be_bytes()
                && answer[7] == 0x03;
            if ok {
                count.answered += 1;
            } else {
                alive[i] = false;
                count.failed += 1;
            }
        }
        count.slowest_ms = count.slowest_ms.max(sent_at.elapsed().as_secs_f64() * 1e3);
        k += 1;
        next += slice;
        let now = Instant::now();
        if next > now {
            std::thread::sleep(next - now);
        } else if now - next > POLL_EVERY {
            next = now;
        }
    }
    count.seconds = began.elapsed().as_secs_f64();
    count
}
