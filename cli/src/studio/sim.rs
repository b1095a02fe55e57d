//! The studio's simulator (docs/studio.md, "Simulate"): the session's program
//! (`Session::run_program`) on the reference VM, in real time, on a thread of its own.
//! It scans every `SCAN_MS` milliseconds of wall time and each scan advances the VM's
//! clock by as much, as `gutta-sim` runs its PLC (`VmConfig::scan_ms`), so timers count
//! in real time. Unlike gutta-sim, scans that a busy machine delayed are caught up
//! (up to one second), so the VM's clock stays the wall clock.
//!
//! RUN and STOP are the VM's (`Vm::set_running`, what STATUS_WRITE does in gutta-sim):
//! in STOP nothing scans and memory, outputs included, keeps the values of the last
//! scan (the GUTTA manuals say nothing of outputs in STOP; gutta-sim keeps them too); the
//! page shows no power flow in STOP. RUN after a fault resets the VM first (power-on).
//!
//! `state()` is the `/api/live` object (docs/studio.md, "Live state"). The scan thread
//! copies the drawn operands' values into a snapshot after every scan (and every write,
//! force, RUN or STOP does too), so `state()` never waits for a scan: it takes the
//! snapshot and computes power flow per drawn network through
//! `gutta_ladder::live::rung_power`. No HTTP here.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use gutta_catalog::{Address, Target, ValueFormat, Width};
use gutta_format::SymbolTable;
use gutta_ladder::live::{operands, rung_power, stl_status, Snapshot};
use gutta_ladder::model::{Body, Ladder};
use gutta_vm::{Vm, VmConfig};
use serde_json::{json, Value};

use super::run::RunProgram;
use crate::vars::{resolve, Var};

/// Wall time between two scans, and the VM's virtual time per scan (gutta-sim's
/// default `--scan-ms`).
pub const SCAN_MS: u32 = 10;

/// A refusal of the simulator: a stable code and a message that says what to do.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SimError {
    /// `no-operand` (not a symbol or address of the program's target), `bad-value`,
    /// `bad-format`, `not-forceable` (only I and Q force), `not-an-input`, `load`.
    pub code: &'static str,
    pub message: String,
}

impl std::fmt::Display for SimError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "[{}] {}", self.code, self.message)
    }
}

impl std::error::Error for SimError {}

fn refuse(code: &'static str, message: impl Into<String>) -> SimError {
    SimError {
        code,
        message: message.into(),
    }
}

/// One watch-table row read: the canonical address, the value in the row's format,
/// whether it is forced.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Watched {
    pub address: String,
    /// The format the value is shown in (`bool`, `int`, `uint`, `hex`, `real`).
    pub format: String,
    pub value: String,
    pub forced: bool,
}

/// What the simulator paints: fixed when it starts.
struct Drawn {
    target: Arc<Target>,
    symbols: SymbolTable,
    ladder: Ladder,
    /// Every drawn operand, resolved (read at every `state()`).
    vars: Vec<Var>,
}

/// What the scan thread and the callers share. Locks are taken in this order: `vm`,
/// then `snapshot`.
struct Shared {
    vm: Mutex<Vm>,
    quit: AtomicBool,
    /// The drawn operands: canonical address and address.
    drawn: Vec<(String, Address)>,
    snapshot: Mutex<Snap>,
}

/// The VM as of its last scan (or change): what `state()` shows.
#[derive(Debug, Clone, Default)]
struct Snap {
    raws: BTreeMap<String, u32>,
    running: bool,
    scans: u64,
    fault: Option<String>,
}

impl Shared {
    /// The snapshot taken again from `vm` (whose lock the caller holds).
    fn refresh(&self, vm: &Vm) {
        let mut raws = BTreeMap::new();
        for (canonical, address) in &self.drawn {
            if let Ok(raw) = vm.read(*address) {
                raws.insert(canonical.clone(), raw);
            }
        }
        let snap = Snap {
            raws,
            running: vm.is_running(),
            scans: vm.scans(),
            fault: vm.fault().map(ToString::to_string),
        };
        *self
            .snapshot
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner) = snap;
    }
}

/// The program running on the VM, on its own thread, until dropped.
pub struct Simulator {
    shared: Arc<Shared>,
    drawn: Drawn,
    /// Forced variables by canonical address (the page marks them).
    forced: Mutex<BTreeMap<String, Var>>,
    thread: Option<JoinHandle<()>>,
}

impl std::fmt::Debug for Simulator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Simulator")
            .field("scans", &self.scans())
            .field("running", &self.is_running())
            .finish_non_exhaustive()
    }
}

impl Simulator {
    /// `program` loaded on the VM and started in RUN, scanning every `SCAN_MS` ms.
    pub fn start(program: RunProgram) -> Result<Simulator, SimError> {
        Simulator::start_with(program, SCAN_MS)
    }

    /// As `start`, scanning every `scan_ms` milliseconds (at least 1).
    pub fn start_with(program: RunProgram, scan_ms: u32) -> Result<Simulator, SimError> {
        let scan_ms = scan_ms.max(1);
        let RunProgram {
            image,
            target,
            symbols,
            ladder,
        } = program;
        let verified = gutta_format::verify(&image, &target)
            .map_err(|e| refuse("load", format!("the image does not verify: {e}")))?;
        let config = VmConfig {
            scan_ms,
            ..VmConfig::default()
        };
        let vm = Vm::new(verified, Arc::clone(&target), config)
            .map_err(|e| refuse("load", format!("the image does not load: {e}")))?;
        let vars: Vec<Var> = operands(&ladder, &target, &symbols)
            .into_iter()
            .filter_map(|canonical| resolve(&canonical, &symbols, &target).ok())
            .collect();
        let shared = Arc::new(Shared {
            quit: AtomicBool::new(false),
            drawn: vars
                .iter()
                .map(|v| (v.canonical.clone(), v.address))
                .collect(),
            snapshot: Mutex::new(Snap::default()),
            vm: Mutex::new(vm),
        });
        shared.refresh(
            &shared
                .vm
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner),
        );
        let thread = {
            let shared = Arc::clone(&shared);
            std::thread::Builder::new()
                .name("gutta-studio-sim".into())
                .spawn(move || scan_forever(&shared, scan_ms))
                .map_err(|e| refuse("load", format!("cannot start the scan thread: {e}")))?
        };
        Ok(Simulator {
            shared,
            drawn: Drawn {
                target,
                symbols,
                ladder,
                vars,
            },
            forced: Mutex::new(BTreeMap::new()),
            thread: Some(thread),
        })
    }

    fn vm(&self) -> MutexGuard<'_, Vm> {
        // A panic inside a scan poisons the lock; the VM itself is still whole.
        self.shared
            .vm
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    fn forced_vars(&self) -> MutexGuard<'_, BTreeMap<String, Var>> {
        self.forced
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// Completed scans since the program was loaded (or last reset).
    pub fn scans(&self) -> u64 {
        self.vm().scans()
    }

    /// Whether the program runs (RUN).
    pub fn is_running(&self) -> bool {
        self.vm().is_running()
    }

    /// The VM's clock: virtual milliseconds since load (`SCAN_MS` per scan).
    pub fn clock_ms(&self) -> u64 {
        self.vm().clock_ms()
    }

    /// RUN. After a fault the VM is reset first (memory cleared, as at power-on).
    pub fn run(&self) {
        let mut vm = self.vm();
        if vm.fault().is_some() {
            vm.reset();
        }
        vm.set_running(true);
        self.shared.refresh(&vm);
    }

    /// STOP: nothing scans; memory keeps the last scan's values.
    pub fn stop(&self) {
        let mut vm = self.vm();
        vm.set_running(false);
        self.shared.refresh(&vm);
    }

    /// `operand` (a symbol or an address) resolved on the program's target.
    fn var(&self, operand: &str) -> Result<Var, SimError> {
        let operand = operand.trim();
        if operand.is_empty() {
            return Err(refuse("no-operand", "name a symbol or an address"));
        }
        resolve(operand, &self.drawn.symbols, &self.drawn.target)
            .map_err(|e| refuse("no-operand", e))
    }

    /// `operand`'s value in its format (its symbol's type, else its width's).
    pub fn value(&self, operand: &str) -> Result<String, SimError> {
        let var = self.var(operand)?;
        let raw = self.raw(&var)?;
        Ok(var.show(raw))
    }

    fn raw(&self, var: &Var) -> Result<u32, SimError> {
        self.vm()
            .read(var.address)
            .map_err(|e| refuse("no-operand", format!("{}: {}", var.label(), e.0)))
    }

    /// `value` (as `gutta-cc write` takes it: `1`, `-5`, `16#FF`, `2.5`) written into
    /// `operand`. An input holds it across scans (its terminal); a forced variable's
    /// force value changes with it.
    pub fn write(&self, operand: &str, value: &str) -> Result<(), SimError> {
        let var = self.var(operand)?;
        let raw = var
            .parse(value.trim())
            .map_err(|e| refuse("bad-value", e))?;
        let mut vm = self.vm();
        vm.write_through_forces(var.address, raw)
            .map_err(|e| refuse("no-operand", format!("{}: {}", var.label(), e.0)))?;
        self.shared.refresh(&vm);
        Ok(())
    }

    /// `operand` (an I or Q variable) forced to `value`: it reads (inputs) and is
    /// written (outputs) with it at every scan until released.
    pub fn force(&self, operand: &str, value: &str) -> Result<(), SimError> {
        let var = self.var(operand)?;
        let raw = var
            .parse(value.trim())
            .map_err(|e| refuse("bad-value", e))?;
        let mut vm = self.vm();
        vm.force(var.address, raw)
            .map_err(|e| refuse("not-forceable", format!("{}: {e}", var.label())))?;
        self.shared.refresh(&vm);
        drop(vm);
        self.forced_vars().insert(var.canonical.clone(), var);
        Ok(())
    }

    /// `operand`'s force removed: an input reads its terminal again (what was last
    /// written to it, else 0), an output what the program writes.
    pub fn release(&self, operand: &str) -> Result<(), SimError> {
        let var = self.var(operand)?;
        let mut vm = self.vm();
        vm.unforce(var.address);
        self.shared.refresh(&vm);
        drop(vm);
        self.forced_vars().remove(&var.canonical);
        Ok(())
    }

    /// What a click on an input contact does: an input bit that is not forced is
    /// forced to the opposite of its value now; one that is forced is released (back
    /// to its terminal, 0 unless written). So a first click presses a button, a second
    /// lets it go. Refused for anything but a bit of an input area.
    pub fn toggle(&self, operand: &str) -> Result<(), SimError> {
        let var = self.var(operand)?;
        let input = self
            .drawn
            .target
            .memory
            .area_by_slot(var.address.slot)
            .is_some_and(|a| a.name == "I");
        if !input || var.address.width != Width::Bit {
            return Err(refuse(
                "not-an-input",
                format!(
                    "{} is not an input bit: only an I contact toggles; write or force other variables in the watch table",
                    var.label()
                ),
            ));
        }
        if self.forced_vars().contains_key(&var.canonical) {
            return self.release(&var.canonical);
        }
        let now = self.raw(&var)? & 1;
        self.force(&var.canonical, if now == 1 { "0" } else { "1" })
    }

    /// The forced variables' canonical addresses, in address order.
    pub fn forced(&self) -> Vec<String> {
        self.forced_vars().keys().cloned().collect()
    }

    /// One watch-table row: `operand` read now, shown in `format` (`bool`/`bit`,
    /// `int`/`signed`, `uint`/`unsigned`, `hex`, `real`/`float`, or a type such as
    /// `DINT`; None or empty: the operand's own).
    pub fn read(&self, operand: &str, format: Option<&str>) -> Result<Watched, SimError> {
        let mut var = self.var(operand)?;
        if let Some(name) = format.map(str::trim).filter(|f| !f.is_empty()) {
            let alias = match name.to_ascii_lowercase().as_str() {
                "bit" => "bool".to_string(),
                "float" => "real".to_string(),
                other => other.to_string(),
            };
            let f = ValueFormat::from_suffix(&alias).ok_or_else(|| {
                refuse(
                    "bad-format",
                    format!("unknown format `{name}` (bool, int, uint, hex, real, or a type such as DINT)"),
                )
            })?;
            if !f.fits(var.address.width) {
                return Err(refuse(
                    "bad-format",
                    format!("{}: {}", var.label(), f.misfit(var.address.width)),
                ));
            }
            var.format = f;
        }
        let raw = self.raw(&var)?;
        let forced = self.forced_vars().contains_key(&var.canonical);
        Ok(Watched {
            address: var.canonical.clone(),
            format: var.format.name().to_string(),
            value: var.show(raw),
            forced,
        })
    }

    /// The `/api/live` object (docs/studio.md, "Live state"), mode `SIMULATE`: RUN or
    /// STOP, the scan count, every drawn operand's value, the forced ones, and in RUN
    /// the energized elements of every drawn network (none in STOP).
    pub fn state(&self) -> Value {
        let Snap {
            raws,
            running,
            scans,
            fault,
        } = self
            .shared
            .snapshot
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .clone();
        let forced = self.forced();
        let mut networks = Vec::new();
        let mut stl = Vec::new();
        let snapshot = Snapshot {
            target: &self.drawn.target,
            symbols: &self.drawn.symbols,
            values: &raws,
        };
        for block in &self.drawn.ladder.blocks {
            for network in &block.networks {
                match &network.body {
                    Body::Rung(rung) if running => {
                        let power = rung_power(rung, &snapshot);
                        networks.push(json!({
                            "block": block.name,
                            "network": network.number,
                            "on": power.energized,
                        }));
                    }
                    Body::Rung(_) => {}
                    // A network shown as STL: each line's RLO (in RUN), as the monitor's.
                    Body::Stl { .. } => {
                        let lines: Vec<Value> = stl_status(&network.stl_code, &snapshot)
                            .into_iter()
                            .map(|line| {
                                json!({
                                    "index": line.index,
                                    "rlo": line.rlo.filter(|_| running).map(u8::from),
                                })
                            })
                            .collect();
                        stl.push(json!({
                            "block": block.name,
                            "network": network.number,
                            "lines": lines,
                        }));
                    }
                }
            }
        }
        // Every bit's value, for `data-value` on contacts and coils.
        let bits: serde_json::Map<String, Value> = self
            .drawn
            .vars
            .iter()
            .filter(|v| v.address.width == gutta_catalog::Width::Bit)
            .filter_map(|v| Some((v.canonical.clone(), json!(raws.get(&v.canonical)? & 1))))
            .collect();
        let values: serde_json::Map<String, Value> = self
            .drawn
            .vars
            .iter()
            .filter_map(|v| Some((v.canonical.clone(), json!(v.show(*raws.get(&v.canonical)?)))))
            .collect();
        let message = match (&fault, running) {
            (Some(f), _) => format!("the program faulted: {f}; RUN resets it"),
            (None, true) => String::new(),
            (None, false) => "STOP: the program does not scan; outputs keep their values".into(),
        };
        let updated = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.as_millis() as u64);
        json!({
            "mode": "SIMULATE",
            "live": true,
            "run": running && fault.is_none(),
            "scans": scans,
            "address": null,
            "updated": updated,
            "message": message,
            "program": "same",
            "networks": networks,
            "stl": stl,
            "values": values,
            "bits": bits,
            "forced": forced,
        })
    }
}

impl Drop for Simulator {
    fn drop(&mut self) {
        self.shared.quit.store(true, Ordering::Relaxed);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// The scan cycle: one scan every `scan_ms` ms of wall time (when in RUN), the lock held
/// only for the scan. A thread that was kept from running catches up (scans back to
/// back until the VM's clock is the wall clock again), so timers keep counting in real
/// time on a busy machine; more than `MAX_LAG` behind, the missed time is dropped.
fn scan_forever(shared: &Shared, scan_ms: u32) {
    let period = Duration::from_millis(u64::from(scan_ms));
    let mut next = Instant::now() + period;
    while !shared.quit.load(Ordering::Relaxed) {
        let now = Instant::now();
        if next > now {
            std::thread::sleep(next - now);
            continue;
        }
        {
            let mut vm = shared
                .vm
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            if vm.is_running() {
                // A fault stops the VM (ERROR); `state()` reports it.
                let _ = vm.run_scan();
                shared.refresh(&vm);
            }
        }
        next += period;
        let now = Instant::now();
        if now > next + MAX_LAG {
            next = now + period;
        }
    }
}

/// How far the scan cycle may fall behind the wall clock and still catch up.
const MAX_LAG: Duration = Duration::from_secs(1);
