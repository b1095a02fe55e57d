//! The real-time scan loops of every simulated PLC in the process (one for the command
//! line's PLC, one per PLC of a plant): each PLC scans every `scan_ms` on absolute
//! deadlines (a late scan does not shift the ones after it; a scan more than a period
//! late resynchronises instead of bursting), on a thread of its own, so one PLC's EXCH
//! waiting on its port holds up no other PLC and no connection. `--stats-every` lines
//! and the fault line carry the device's name in a plant.

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
        let mut threads = Vec::new();
        for device in devices {
            let stop = Arc::clone(&stop);
            let name = device.name.clone().unwrap_or_else(|| "plc".into());
            threads.push(
                std::thread::Builder::new()
                    .name(format!("scan {name}"))
                    .spawn(move || scan_loop(&device, stats_every, &stop))?,
            );
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

fn scan_loop(device: &ScanDevice, stats_every: Option<f64>, stop: &AtomicBool) {
    let prefix = prefix(device.name.as_deref());
    let period = Duration::from_millis(u64::from(device.scan_ms.max(1)));
    let mut deadline = Instant::now();
    let mut reported_fault = false;
    let (mut window_start, mut last_scan) = (Instant::now(), None::<Instant>);
    let (mut window_scans, mut window_max) = (0u64, Duration::ZERO);
    while !stop.load(Ordering::Relaxed) {
        let now = Instant::now();
        if now < deadline {
            std::thread::sleep(deadline - now);
        }
        let now = Instant::now();
        // The next deadline is a period after this one; a scan more than a period late
        // starts the count again from now rather than running the missed scans back to
        // back.
        deadline = if now.duration_since(deadline) > period {
            now + period
        } else {
            deadline + period
        };
        if let Some(last) = last_scan {
            window_max = window_max.max(now - last);
        }
        last_scan = Some(now);
        window_scans += 1;
        if let Some(every) = stats_every {
            let elapsed = now - window_start;
            if elapsed.as_secs_f64() >= every {
                say(&format!(
                    "{prefix}stats: {} in {:.2} s, period max {:.1} ms",
                    gutta_cli::plural::count(window_scans, "scan"),
                    elapsed.as_secs_f64(),
                    window_max.as_secs_f64() * 1e3
                ));
                (window_start, window_scans, window_max) = (now, 0, Duration::ZERO);
            }
        }
        let result = match device.plc.lock() {
            Ok(mut plc) => plc.scan(),
            Err(_) => {
                eprintln!("{prefix}the PLC state was poisoned by a panic; its scans stop");
                return;
            }
        };
        match result {
            Err(f) if !reported_fault => {
                eprintln!("{prefix}the program faulted: {f} (error code {})", f.code());
                reported_fault = true;
            }
            Ok(_) => reported_fault = false,
            Err(_) => {}
        }
    }
}
