//! The PLC side of `gutta-cc monitor`: the connection (logged in once, re-made after a
//! failure with back-off), the program check (the uploaded pages against the compiled
//! image, again every `RECHECK` while the PLC holds another program or none), and one
//! update: a single batched STATUS_VAR_READ of every drawn operand, with the RUN state
//! and the force values now and then, turned into the `/state` JSON (power flow only in
//! RUN, bit values always, per-line status of networks shown as STL). It knows no HTTP;
//! `monitor.rs` decides when an update is wanted.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use gutta_catalog::Target;
use gutta_catalog::Width;
use gutta_format::{Image, SymbolTable};
use gutta_ladder::live::{rung_power, stl_status, Snapshot};
use gutta_ladder::model::{Body, Ladder};
use gutta_link::plan::ReadPlan;
use gutta_link::{Client, LinkConfig, LinkError, Transport};
use serde_json::json;

use crate::args::LinkArgs;
use crate::client;
use gutta_cli::vars::Var;

/// Every update reads the RUN state and the force values again after this many updates
/// (and on the first): at 20 updates a second, twice a second.
const SLOW_EVERY: u64 = 10;

/// While the PLC holds another program or none, what it holds is checked again this
/// often (the page list, then a full upload when it lists pages: UM4001 gives no page
/// CRC to compare), so the view resumes by itself once the right program is there.
pub(crate) const RECHECK: Duration = Duration::from_secs(2);

/// After a failed connection the next attempt waits this long, doubled after each
/// further failure up to `BACKOFF_MAX`.
const BACKOFF_FIRST: Duration = Duration::from_millis(250);
const BACKOFF_MAX: Duration = Duration::from_secs(4);

/// Counts every request sent to the PLC (the figure `/state` and the bench report).
#[derive(Debug)]
struct Counted {
    inner: Box<dyn Transport>,
    requests: Arc<AtomicU64>,
}

impl Transport for Counted {
    fn exchange(&mut self, station: u8, pdu: &[u8]) -> Result<gutta_link::Answer, LinkError> {
        self.requests.fetch_add(1, Ordering::Relaxed);
        self.inner.exchange(station, pdu)
    }

    fn set_line(&mut self, line: gutta_format::LineSettings) -> Result<(), LinkError> {
        self.inner.set_line(line)
    }
}

/// What the monitor shows, fixed at start: the program and its operands.
pub(crate) struct Program {
    /// The source as named on the command line (or the project's name).
    pub name: String,
    pub ladder: Ladder,
    pub target: Arc<Target>,
    pub symbols: SymbolTable,
    pub image: Image,
    /// Every drawn operand.
    pub vars: Vec<Var>,
    /// How one STATUS_VAR_READ reads them all.
    pub plan: ReadPlan,
}

/// Counters reported in `/state` (and read by the tests and the bench).
#[derive(Debug, Default)]
pub(crate) struct Counters {
    /// Every request sent to the PLC, login and upload included.
    pub requests: Arc<AtomicU64>,
    /// STATUS_VAR_READ requests.
    pub var_reads: AtomicU64,
    /// Updates made (each one batched read).
    pub updates: AtomicU64,
}

/// What the PLC holds, against the compiled image.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Held {
    /// Exactly the compiled image.
    Same,
    /// Another program.
    Other,
    /// No program at all (a fresh or cleared PLC).
    Nothing,
}

/// The PLC connection and what the last slow read found.
pub(crate) struct Session {
    config: LinkConfig,
    password: [u8; 16],
    plc: Option<gutta_link::Session>,
    /// What the PLC holds against the compiled image (checked on every connection).
    held: Held,
    run: Option<bool>,
    forced: Vec<String>,
    /// Read the RUN state and the forces at the next update, whatever the count.
    slow_now: bool,
    /// When what the PLC holds was last checked.
    checked_at: Instant,
    /// Check what the PLC holds at the next update (a page was opened or reloaded).
    check_now: bool,
    /// Connection attempts failed in a row, and when the next one may be made.
    failures: u32,
    retry_at: Option<Instant>,
    pub counters: Arc<Counters>,
}

impl Session {
    /// Log in now (the prompt, if any, comes before the server starts) and check the
    /// program.
    pub fn start(program: &Program, link: &LinkArgs) -> Result<Session, crate::Fatal> {
        Session::connect(program, link, |client, at| {
            crate::login::log_in(client, at, link)
        })
    }

    /// Connect, log in with `log_in` (the monitor's prompt, or the studio's none) and
    /// check the program.
    pub(crate) fn connect(
        program: &Program,
        link: &LinkArgs,
        log_in: impl FnOnce(Client, &str) -> Result<gutta_link::Session, crate::Fatal>,
    ) -> Result<Session, crate::Fatal> {
        let counters = Arc::new(Counters::default());
        let config = client::link_config(link)?;
        let client = Client::new(
            Box::new(Counted {
                inner: client::transport(&config)?,
                requests: counters.requests.clone(),
            }),
            config.station,
        );
        let address = config.address().to_string();
        let mut plc = log_in(client, &address)?;
        plc.set_target(&program.target);
        let mut session = Session {
            password: plc.password(),
            config,
            plc: None,
            held: Held::Nothing,
            run: None,
            forced: Vec::new(),
            slow_now: false,
            checked_at: Instant::now(),
            check_now: false,
            failures: 0,
            retry_at: None,
            counters,
        };
        session.held = session
            .check(&mut plc, program)
            .map_err(client::link_error)?;
        session.plc = Some(plc);
        Ok(session)
    }

    /// The logged-in PLC session (connected again if a failure dropped it), for what
    /// the studio sends besides the updates: RUN/STOP, writes, forces, a download.
    pub(crate) fn plc(&mut self, program: &Program) -> Result<&mut gutta_link::Session, LinkError> {
        if self.plc.is_none() {
            self.reconnect(program)?;
        }
        Ok(self.plc.as_mut().expect("connected above"))
    }

    /// Check again what the PLC holds against `program` (it may have been downloaded,
    /// or `program` changed); a failure drops the connection.
    pub(crate) fn recheck(&mut self, program: &Program) -> Result<(), LinkError> {
        let checked = match self.plc.take() {
            None => return self.reconnect(program),
            Some(mut plc) => {
                plc.set_target(&program.target);
                let held = self.check(&mut plc, program);
                self.plc = Some(plc);
                held
            }
        };
        match checked {
            Ok(held) => {
                self.held = held;
                self.slow_now = true;
                Ok(())
            }
            Err(e) => {
                self.plc = None;
                Err(e)
            }
        }
    }

    /// The next update reads the RUN state and the forces again (after a RUN, STOP or
    /// force).
    pub(crate) fn refresh(&mut self) {
        self.slow_now = true;
    }

    /// A page was opened or reloaded: read the RUN state now, check again what the PLC
    /// holds if it was not the program, and try a lost connection at once.
    pub(crate) fn page_opened(&mut self) {
        self.slow_now = true;
        self.check_now = self.held != Held::Same;
        self.retry_at = None;
    }

    /// The password the login used (a download logs in with it).
    pub(crate) fn password(&self) -> [u8; 16] {
        self.password
    }

    /// Forget the connection: the next request connects again.
    pub(crate) fn disconnect(&mut self) {
        self.plc = None;
    }

    /// How the user named the PLC.
    pub fn address(&self) -> &str {
        self.config.address()
    }

    /// Whether the PLC holds exactly the compiled image, another program, or none.
    fn check(
        &mut self,
        plc: &mut gutta_link::Session,
        program: &Program,
    ) -> Result<Held, LinkError> {
        self.checked_at = Instant::now();
        self.check_now = false;
        let pack = plc.pack_size();
        let client = plc.client();
        // RUN or STOP, for the status bar also while the program differs.
        self.run = Some(client.status()? & 1 != 0);
        if client
            .page_list(gutta_protocol::function::PageArea::Program)?
            .is_empty()
        {
            return Ok(Held::Nothing);
        }
        let uploaded = gutta_link::upload(client, &self.password, pack)?;
        Ok(if uploaded == program.image {
            Held::Same
        } else {
            Held::Other
        })
    }

    /// A new connection after a failure: log in with the password that worked, check
    /// the program again (it may have been downloaded meanwhile).
    fn reconnect(&mut self, program: &Program) -> Result<(), LinkError> {
        let transport = client::transport(&self.config).map_err(|e| LinkError::Io(e.message))?;
        let client = Client::new(
            Box::new(Counted {
                inner: transport,
                requests: self.counters.requests.clone(),
            }),
            self.config.station,
        );
        let mut plc = gutta_link::Session::reattach(client, self.password)?;
        plc.set_target(&program.target);
        self.held = self.check(&mut plc, program)?;
        self.plc = Some(plc);
        self.slow_now = true;
        Ok(())
    }

    /// One update: the `/state` object. A failure drops the connection (the next update
    /// connects again) and is the state's error.
    pub fn update(&mut self, program: &Program) -> serde_json::Value {
        let started = Instant::now();
        if let Some(at) = self.retry_at.filter(|at| *at > started) {
            let wait = at - started;
            let mut state = self.state(
                program,
                format!(
                    "the PLC at {} does not answer: trying again in {:.1} s",
                    self.address(),
                    wait.as_secs_f64()
                ),
            );
            state["connection"] = json!("reconnecting");
            return state;
        }
        match self.read(program) {
            Ok(Some(values)) => {
                self.failures = 0;
                self.retry_at = None;
                self.live_state(program, &values, started)
            }
            Ok(None) if self.held == Held::Nothing => self.state(
                program,
                format!(
                    "the PLC holds no program: download {} with `gutta-cc download`; the view resumes by itself (checked every {} s)",
                    program.name,
                    RECHECK.as_secs()
                ),
            ),
            Ok(None) => self.state(
                program,
                format!(
                    "the PLC runs another program than {}: download it; the view resumes by itself (checked every {} s)",
                    program.name,
                    RECHECK.as_secs()
                ),
            ),
            Err(e) => {
                self.plc = None;
                self.run = None;
                self.failures += 1;
                let wait = BACKOFF_FIRST
                    .saturating_mul(1 << self.failures.saturating_sub(1).min(5))
                    .min(BACKOFF_MAX);
                self.retry_at = Some(Instant::now() + wait);
                let mut state = self.state(
                    program,
                    format!(
                        "the PLC at {} does not answer: {e}; trying again in {:.1} s",
                        self.address(),
                        wait.as_secs_f64()
                    ),
                );
                state["connection"] = json!("not answering");
                state
            }
        }
    }

    /// The values by canonical address, or None when the PLC runs another program or
    /// none.
    fn read(&mut self, program: &Program) -> Result<Option<BTreeMap<String, u32>>, LinkError> {
        if self.plc.is_none() {
            self.reconnect(program)?;
        } else if self.held != Held::Same
            && (self.check_now || self.checked_at.elapsed() >= RECHECK)
        {
            self.recheck(program)?;
        }
        if self.held != Held::Same {
            return Ok(None);
        }
        let plc = self.plc.as_mut().expect("connected above");
        let n = self.counters.updates.load(Ordering::Relaxed);
        if n.is_multiple_of(SLOW_EVERY) || self.slow_now {
            self.slow_now = false;
            self.run = Some(plc.client().status()? & 1 != 0);
            self.forced = forced(plc, program)?;
        }
        let sent = plc.var_reads();
        let raw = plc.read_plan(&program.plan);
        self.counters
            .var_reads
            .fetch_add(plc.var_reads() - sent, Ordering::Relaxed);
        let raw = raw?;
        self.counters.updates.fetch_add(1, Ordering::Relaxed);
        Ok(Some(
            program
                .vars
                .iter()
                .zip(raw)
                .map(|(v, r)| (v.canonical.clone(), r))
                .collect(),
        ))
    }

    /// The state with values: every drawn network's energized elements, every operand's
    /// value in its format, the forced operands.
    fn live_state(
        &self,
        program: &Program,
        values: &BTreeMap<String, u32>,
        started: Instant,
    ) -> serde_json::Value {
        let snapshot = Snapshot {
            target: &program.target,
            symbols: &program.symbols,
            values,
        };
        let shown: BTreeMap<&str, String> = program
            .vars
            .iter()
            .map(|v| (v.canonical.as_str(), v.show(values[&v.canonical])))
            .collect();
        // In STOP the PLC does not scan: no power flows, whatever the bits say.
        let running = self.run == Some(true);
        let mut networks = Vec::new();
        let mut stl = Vec::new();
        for block in &program.ladder.blocks {
            for network in &block.networks {
                match &network.body {
                    Body::Rung(rung) => {
                        let on = if running {
                            rung_power(rung, &snapshot).energized
                        } else {
                            Default::default()
                        };
                        networks.push(json!({
                            "block": block.name,
                            "network": network.number,
                            "on": on,
                        }));
                    }
                    Body::Stl { .. } => {
                        let lines: Vec<serde_json::Value> = stl_status(&network.stl_code, &snapshot)
                            .into_iter()
                            .map(|line| {
                                let value: Vec<String> = line
                                    .operands
                                    .iter()
                                    .filter_map(|a| Some(format!("{a} = {}", shown.get(a.as_str())?)))
                                    .collect();
                                json!({
                                    "index": line.index,
                                    "rlo": if running { line.rlo.map(u8::from) } else { None },
                                    "value": if value.is_empty() { None } else { Some(value.join(", ")) },
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
        let bits: BTreeMap<&str, u32> = program
            .vars
            .iter()
            .filter(|v| v.address.width == Width::Bit)
            .map(|v| (v.canonical.as_str(), values[&v.canonical] & 1))
            .collect();
        let mut state = self.state(program, String::new());
        state["live"] = json!(true);
        state["networks"] = json!(networks);
        state["stl"] = json!(stl);
        state["values"] = json!(shown);
        state["bits"] = json!(bits);
        state["forced"] = json!(self.forced);
        state["read_ms"] = json!(started.elapsed().as_secs_f64() * 1000.0);
        state
    }

    /// The state without values: `message` says why.
    fn state(&self, program: &Program, message: String) -> serde_json::Value {
        let now = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.as_millis() as u64);
        json!({
            "source": program.name,
            "live": false,
            "message": message,
            "plc": self.address(),
            "station": self.config.station,
            "connection": if self.plc.is_some() { "connected" } else { "not answering" },
            "time_ms": now,
            "program_matches": self.held == Held::Same,
            "program": match self.held {
                Held::Same => "same",
                Held::Other => "other",
                Held::Nothing => "none",
            },
            "run": self.run,
            "networks": [],
            "stl": [],
            "values": {},
            "bits": {},
            "forced": [],
            // UM4001 reads the force values, not the force mask: a bit forced to 0
            // looks unforced (docs/ladder.md, "Live view").
            "forced_note": "a bit forced to 0 is not marked: the PLC's protocol reports force values, not which bits are forced",
            "read_addresses": program.plan.windows().len(),
            "updates": self.counters.updates.load(Ordering::Relaxed),
            "var_reads": self.counters.var_reads.load(Ordering::Relaxed),
            "plc_requests": self.counters.requests.load(Ordering::Relaxed),
        })
    }
}

/// The I and Q operands whose force value is set (STATUS_VAR_FORCE_READ returns the force
/// value image, not the mask: a bit forced to 0 does not show; docs/ladder.md).
fn forced(plc: &mut gutta_link::Session, program: &Program) -> Result<Vec<String>, LinkError> {
    let memory = &program.target.memory;
    let forceable: Vec<&Var> = program
        .vars
        .iter()
        .filter(|v| {
            memory
                .area_by_slot(v.address.slot)
                .is_some_and(|a| matches!(a.name.as_str(), "I" | "Q"))
        })
        .collect();
    let addresses: Vec<_> = forceable.iter().map(|v| v.address).collect();
    let values = plc.read_forces(&addresses)?;
    Ok(forceable
        .iter()
        .zip(values)
        .filter(|(_, value)| *value != 0)
        .map(|(v, _)| v.canonical.clone())
        .collect())
}
