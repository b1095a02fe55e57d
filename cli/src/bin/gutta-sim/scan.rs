//! The real-time scan loops of every simulated PLC in the process (one for the command
//! line's PLC, one per PLC of a plant). Each PLC scans every `scan_ms` on absolute
//! deadlines: a late scan does not shift the ones after it, and a scan more than a
//! period late skips the scans it missed instead of running them back to back. The
//! period is the time between scan starts. `--stats-every` lines and the fault line
//! carry the device's name in a plant. No protocol and no listener here: connections
//! lock the same `Plc` from their tasks.
//!
//! The scheduling rule (docs/simulator.md, "Scale"):
//! - a PLC whose serial port is wired (EXCH may wait on the line for up to its
//!   timeout) scans on a thread of its own, so its waits hold up no other PLC;
//! - every other PLC is served by one of a few scan threads (one per core), dealt in
//!   turn; each thread keeps a queue of its PLCs ordered by deadline, sleeps until the
//!   earliest and scans every PLC then due, back to back, before it sleeps again;
//! - the PLCs of one thread start together (thread j of n at j/n of the period), so
//!   those with the same period fall due together: one wake-up per period scans them
//!   all, always in the same order, so each keeps its place and its period.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use gutta_sim::plc::Plc;

use crate::say;

/// A PLC whose program the loops scan.
#[derive(Debug)]
pub struct ScanDevice {
    /// The device's name in a plant (`None` for the command line's PLC): the prefix of
    /// its stats and fault lines (`gutta-sim: NAME: stats: ...`).
    pub name: Option<String>,
    pub plc: Arc<Mutex<Plc>>,
    /// Real time per scan, in milliseconds (also the VM's virtual time per scan).
    pub scan_ms: u32,
}

/// The running scan loops; [`Scans::stop`] ends them.
#[derive(Debug)]
pub struct Scans {
    stop: Arc<AtomicBool>,
    threads: Vec<JoinHandle<()>>,
}

impl Scans {
    /// Starts scanning every device; every `stats_every` seconds each prints
    /// `gutta-sim: [NAME: ]stats: 100 scans in 1.00 s, period max 10.4 ms`.
    pub fn start(devices: Vec<ScanDevice>, stats_every: Option<f64>) -> std::io::Result<Scans> {
        let stop = Arc::new(AtomicBool::new(false));
        let cores = std::thread::available_parallelism().map_or(1, usize::from);
        let mut threads = Vec::new();
        for lane in plan_lanes(devices, cores, Instant::now()) {
            let lane_stop = Arc::clone(&stop);
            let name = match lane.as_slice() {
                [only] => format!("scan {}", only.device.name.as_deref().unwrap_or("plc")),
                many => format!("scan {} plcs", many.len()),
            };
            let spawned = std::thread::Builder::new()
                .name(name)
                .spawn(move || run_lane(lane, stats_every, &lane_stop));
            match spawned {
                Ok(thread) => threads.push(thread),
                Err(e) => {
                    Scans { stop, threads }.stop();
                    return Err(e);
                }
            }
        }
        Ok(Scans { stop, threads })
    }

    /// Ends every loop after its current scan and waits for them.
    pub fn stop(self) {
        self.stop.store(true, Ordering::SeqCst);
        for thread in self.threads {
            let _ = thread.join();
        }
    }
}

/// The line prefix of a device: `gutta-sim: ` or `gutta-sim: NAME: `.
pub fn prefix(name: Option<&str>) -> String {
    match name {
        Some(name) => format!("gutta-sim: {name}: "),
        None => "gutta-sim: ".to_string(),
    }
}

/// Whether EXCH on this PLC may wait on a line: one of its serial ports leads
/// somewhere (its port factory made a port for it).
fn has_wired_port(plc: &Mutex<Plc>) -> bool {
    let Ok(plc) = plc.lock() else {
        return false;
    };
    (0..plc.target().memory.serial_ports).any(|n| plc.vm().has_port(n))
}

/// Which thread scans which PLC (the module's scheduling rule): a lane of its own for
/// each PLC with a wired port, the others dealt in turn over at most `cores` shared
/// lanes. The PLCs of a shared lane all start at the same instant (lane j of n at j/n
/// of the period after `start`), so those with the same period fall due together and
/// are scanned back to back after one wake-up.
fn plan_lanes(devices: Vec<ScanDevice>, cores: usize, start: Instant) -> Vec<Vec<Scanned>> {
    let (own, shared): (Vec<_>, Vec<_>) = devices
        .into_iter()
        .partition(|device| has_wired_port(&device.plc));
    let mut lanes: Vec<Vec<Scanned>> = own
        .into_iter()
        .map(|device| vec![Scanned::new(device, start)])
        .collect();
    let shared_lanes = cores.clamp(1, shared.len().max(1));
    let first = lanes.len();
    lanes.extend((0..shared_lanes.min(shared.len())).map(|_| Vec::new()));
    for (k, device) in shared.into_iter().enumerate() {
        let lane = k % shared_lanes;
        let phase = device.period().mul_f64(lane as f64 / shared_lanes as f64);
        lanes[first + lane].push(Scanned::new(device, start + phase));
    }
    lanes
}

impl ScanDevice {
    fn period(&self) -> Duration {
        Duration::from_millis(u64::from(self.scan_ms.max(1)))
    }
}

/// A PLC in a lane: its next deadline and its statistics window.
#[derive(Debug)]
struct Scanned {
    device: ScanDevice,
    prefix: String,
    period: Duration,
    deadline: Instant,
    reported_fault: bool,
    last_scan: Option<Instant>,
    window_start: Instant,
    window_scans: u64,
    window_max: Duration,
}

/// What a lane does after a scan.
#[derive(Debug, PartialEq, Eq)]
enum Next {
    Again,
    /// The PLC's state was poisoned by a panic: its scans stop (the lane goes on).
    Retire,
}

impl Scanned {
    fn new(device: ScanDevice, first: Instant) -> Scanned {
        Scanned {
            prefix: prefix(device.name.as_deref()),
            period: device.period(),
            device,
            deadline: first,
            reported_fault: false,
            last_scan: None,
            window_start: first,
            window_scans: 0,
            window_max: Duration::ZERO,
        }
    }

    /// The scan due at `self.deadline`, started at `now` (the missed scans of a late
    /// one are not run back to back: [`next_deadline`]).
    /// A stats line falling due is added to `said`, which the lane prints once the
    /// PLCs then due are scanned (one write for them all, never between two scans).
    fn scan(&mut self, now: Instant, stats_every: Option<f64>, said: &mut Vec<String>) -> Next {
        self.deadline = next_deadline(self.deadline, now, self.period);
        if let Some(last) = self.last_scan {
            self.window_max = self.window_max.max(now - last);
        }
        self.last_scan = Some(now);
        self.window_scans += 1;
        if let Some(every) = stats_every {
            let elapsed = now.saturating_duration_since(self.window_start);
            if elapsed.as_secs_f64() >= every {
                said.push(stats_line(
                    &self.prefix,
                    self.window_scans,
                    elapsed,
                    self.window_max,
                ));
                (self.window_start, self.window_scans, self.window_max) = (now, 0, Duration::ZERO);
            }
        }
        let result = match self.device.plc.lock() {
            Ok(mut plc) => plc.scan(),
            Err(_) => {
                eprintln!(
                    "{}the PLC state was poisoned by a panic; its scans stop",
                    self.prefix
                );
                return Next::Retire;
            }
        };
        match result {
            Err(f) if !self.reported_fault => {
                eprintln!(
                    "{}the program faulted: {f} (error code {})",
                    self.prefix,
                    f.code()
                );
                self.reported_fault = true;
            }
            Ok(_) => self.reported_fault = false,
            Err(_) => {}
        }
        Next::Again
    }
}

/// The deadline after a scan due at `deadline` that started at `now`: a period later;
/// when the scan is more than a period late, the first deadline of the same grid after
/// `now` (the missed scans are skipped, not run back to back, and the PLC stays in
/// step with the others of its lane).
fn next_deadline(deadline: Instant, now: Instant, period: Duration) -> Instant {
    let late = now.saturating_duration_since(deadline);
    if late > period {
        let missed = late.as_nanos() / period.as_nanos().max(1);
        deadline + period * u32::try_from(missed + 1).unwrap_or(u32::MAX)
    } else {
        deadline + period
    }
}

/// `gutta-sim: [NAME: ]stats: 100 scans in 1.00 s, period max 10.4 ms`.
fn stats_line(prefix: &str, scans: u64, elapsed: Duration, period_max: Duration) -> String {
    format!(
        "{prefix}stats: {} in {:.2} s, period max {:.1} ms",
        gutta_cli::plural::count(scans, "scan"),
        elapsed.as_secs_f64(),
        period_max.as_secs_f64() * 1e3
    )
}

/// The longest a lane sleeps before it looks at `stop` again.
const STOP_CHECK: Duration = Duration::from_millis(50);

/// Scans the lane's PLCs, earliest deadline first, until `stop`; the stats lines of
/// the PLCs scanned since the last sleep are printed before the next sleep.
fn run_lane(lane: Vec<Scanned>, stats_every: Option<f64>, stop: &AtomicBool) {
    let mut plcs = lane;
    // (deadline, index): the earliest deadline on top; equal deadlines by index.
    let mut due: BinaryHeap<Reverse<(Instant, usize)>> = plcs
        .iter()
        .enumerate()
        .map(|(i, p)| Reverse((p.deadline, i)))
        .collect();
    let mut said = Vec::new();
    while !stop.load(Ordering::Relaxed) {
        let Some(&Reverse((deadline, i))) = due.peek() else {
            return;
        };
        let now = Instant::now();
        if now < deadline {
            if !said.is_empty() {
                say(&said.join("\n"));
                said.clear();
                continue;
            }
            std::thread::sleep((deadline - now).min(STOP_CHECK));
            continue;
        }
        due.pop();
        if plcs[i].scan(now, stats_every, &mut said) == Next::Again {
            due.push(Reverse((plcs[i].deadline, i)));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use gutta_catalog::stdlib;
    use gutta_compiler::source::SourceFile;
    use gutta_compiler::{compile, ExplicitTarget};
    use gutta_sim::ports::PortFactory;
    use gutta_vm::exch::{PortError, SerialPort};
    use gutta_vm::VmConfig;

    /// A PLC running a one-rung program (it counts its scans in the VM).
    fn running_plc(scan_ms: u32) -> Arc<Mutex<Plc>> {
        let target = stdlib::shared("CPU-EC20").expect("target");
        let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLD SM0.0\n= Q0.0\n\
                    END_ORGANIZATION_BLOCK\n";
        let c = compile(
            SourceFile::new("t.lad", text),
            Some(&ExplicitTarget {
                target: Arc::clone(&target),
                origin: "test".into(),
            }),
        );
        let image = c.image.expect("compiles");
        let config = VmConfig {
            scan_ms,
            ..VmConfig::default()
        };
        let plc = Plc::new(target, image.pages, config).expect("a PLC");
        assert!(plc.vm().is_running(), "the program runs");
        Arc::new(Mutex::new(plc))
    }

    fn device(name: &str, plc: Arc<Mutex<Plc>>) -> ScanDevice {
        ScanDevice {
            name: Some(name.into()),
            plc,
            scan_ms: 10,
        }
    }

    fn scans(plc: &Mutex<Plc>) -> u64 {
        plc.lock().expect("not poisoned").vm().scans()
    }

    /// A port that never answers, wired to port 0 only.
    #[derive(Debug)]
    struct Silent;
    impl SerialPort for Silent {
        fn transact(&mut self, _: &[u8], _: u32) -> Result<Vec<u8>, PortError> {
            Err(PortError::Timeout)
        }
    }
    impl PortFactory for Silent {
        fn port(&mut self, port: u8, _: gutta_format::LineSettings) -> Option<Box<dyn SerialPort>> {
            (port == 0).then(|| Box::new(Silent) as Box<dyn SerialPort>)
        }
    }

    #[test]
    fn a_late_scan_keeps_the_grid_and_one_more_than_a_period_late_skips_its_missed_scans() {
        let t0 = Instant::now();
        let p = Duration::from_millis(10);
        let ms = Duration::from_millis;
        assert_eq!(next_deadline(t0, t0, p), t0 + p);
        assert_eq!(
            next_deadline(t0, t0 + ms(7), p),
            t0 + p,
            "7 ms late: same grid"
        );
        assert_eq!(
            next_deadline(t0, t0 + ms(10), p),
            t0 + p,
            "a period late: same grid"
        );
        assert_eq!(
            next_deadline(t0, t0 + ms(25), p),
            t0 + ms(30),
            "more than a period late: the grid's first deadline after now"
        );
        assert_eq!(next_deadline(t0, t0 + ms(20), p), t0 + ms(30));
        assert_eq!(
            next_deadline(t0 + ms(5), t0, p),
            t0 + ms(15),
            "early: the grid"
        );
    }

    #[test]
    fn a_plc_with_a_wired_port_scans_alone_and_the_others_share_a_lane_per_core() {
        let wired = running_plc(10);
        wired
            .lock()
            .expect("lock")
            .set_port_factory(Box::new(Silent));
        assert!(has_wired_port(&wired));
        let mut devices: Vec<ScanDevice> = (0..5)
            .map(|k| device(&format!("p{k}"), running_plc(10)))
            .collect();
        devices.insert(2, device("wired", wired));
        let start = Instant::now();
        let lanes = plan_lanes(devices, 2, start);
        let names: Vec<Vec<&str>> = lanes
            .iter()
            .map(|l| {
                l.iter()
                    .map(|s| s.device.name.as_deref().unwrap_or(""))
                    .collect()
            })
            .collect();
        assert_eq!(
            names,
            [vec!["wired"], vec!["p0", "p2", "p4"], vec!["p1", "p3"]]
        );
        // Each shared lane starts together: lane 1 at the start, lane 2 half a period on.
        let firsts: Vec<Vec<Duration>> = lanes[1..]
            .iter()
            .map(|l| l.iter().map(|s| s.deadline - start).collect())
            .collect();
        let ms = |x: u64| Duration::from_millis(x);
        assert_eq!(firsts, [vec![ms(0); 3], vec![ms(5); 2]]);
        // One core, one device: one lane each way.
        assert_eq!(
            plan_lanes(vec![device("a", running_plc(10))], 2, start).len(),
            1
        );
        assert!(plan_lanes(Vec::new(), 2, start).is_empty());
    }

    #[test]
    fn every_plc_of_a_shared_lane_scans_and_a_poisoned_one_stops_alone() {
        let plcs: Vec<Arc<Mutex<Plc>>> = (0..4).map(|_| running_plc(10)).collect();
        // PLC 1's state is poisoned by a panic before the scans start.
        let poisoned = Arc::clone(&plcs[1]);
        let _ = std::thread::spawn(move || {
            let _guard = poisoned.lock();
            panic!("poisons the PLC's mutex on purpose");
        })
        .join();
        assert!(plcs[1].is_poisoned());
        let devices = plcs
            .iter()
            .enumerate()
            .map(|(k, p)| device(&format!("p{k}"), Arc::clone(p)))
            .collect();
        // One lane for all four (a single-core plan), as on a busy machine.
        let stop = Arc::new(AtomicBool::new(false));
        let lane = plan_lanes(devices, 1, Instant::now())
            .pop()
            .expect("one lane");
        let runner = {
            let stop = Arc::clone(&stop);
            std::thread::spawn(move || run_lane(lane, None, &stop))
        };
        std::thread::sleep(Duration::from_millis(300));
        stop.store(true, Ordering::SeqCst);
        runner.join().expect("the lane ends when told");
        for k in [0, 2, 3] {
            let n = scans(&plcs[k]);
            assert!(n >= 5, "PLC {k} scanned {n} times in 300 ms at 10 ms");
            assert!(
                n <= 32,
                "PLC {k} scanned {n} times in 300 ms at 10 ms: a burst"
            );
        }
    }

    #[test]
    fn a_wired_plc_that_blocks_holds_up_no_other_plc() {
        let wired = running_plc(10);
        wired
            .lock()
            .expect("lock")
            .set_port_factory(Box::new(Silent));
        let others: Vec<Arc<Mutex<Plc>>> = (0..3).map(|_| running_plc(10)).collect();
        let mut devices = vec![device("wired", Arc::clone(&wired))];
        devices.extend(
            others
                .iter()
                .enumerate()
                .map(|(k, p)| device(&format!("p{k}"), Arc::clone(p))),
        );
        let running = Scans::start(devices, None).expect("starts");
        std::thread::sleep(Duration::from_millis(50));
        // The wired PLC's scan blocks for 300 ms (as an EXCH waiting on its line would):
        // its state is held here meanwhile, so its scan thread waits.
        {
            let _held = wired.lock().expect("lock");
            let before: Vec<u64> = others.iter().map(|p| scans(p)).collect();
            std::thread::sleep(Duration::from_millis(300));
            let during: Vec<u64> = others.iter().map(|p| scans(p)).collect();
            for (k, (b, d)) in before.iter().zip(&during).enumerate() {
                assert!(d - b >= 10, "PLC p{k} scanned {} times in 300 ms", d - b);
            }
        }
        running.stop();
    }

    #[test]
    fn stop_ends_every_loop_and_the_scans_with_it() {
        let plcs: Vec<Arc<Mutex<Plc>>> = (0..3).map(|_| running_plc(10)).collect();
        let devices = plcs
            .iter()
            .enumerate()
            .map(|(k, p)| device(&format!("p{k}"), Arc::clone(p)))
            .collect();
        let scans_running = Scans::start(devices, Some(0.05)).expect("starts");
        std::thread::sleep(Duration::from_millis(150));
        scans_running.stop();
        let after: Vec<u64> = plcs.iter().map(|p| scans(p)).collect();
        assert!(after.iter().all(|&n| n > 0), "every PLC scanned: {after:?}");
        std::thread::sleep(Duration::from_millis(50));
        let later: Vec<u64> = plcs.iter().map(|p| scans(p)).collect();
        assert_eq!(after, later, "no scan after stop");
    }
}
