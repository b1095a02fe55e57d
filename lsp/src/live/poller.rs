//! The poller: one thread per PLC (a project's `[connection]`) that logs in, reads the
//! addresses the editor last showed every 500 ms, and tells the client when a value
//! changed. It never blocks the server's loop: the loop only swaps the wanted list and
//! reads the last values under a mutex; connecting, logging in and waiting for answers
//! happen here. A PLC that does not answer: one warning per outage, every value `?`,
//! retries with a backoff that doubles up to 8 s.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread;
use std::time::{Duration, Instant};

use gutta_catalog::Address;
use gutta_io::Connection;
use gutta_link::plan::ReadPlan;
use gutta_link::{Credentials, LinkConfig, LoginError, NoPrompt, Session};

/// How often the wanted values are read.
pub const PERIOD: Duration = Duration::from_millis(500);
/// The longest wait between two attempts to reach a PLC that does not answer.
const MAX_BACKOFF: Duration = Duration::from_secs(8);
/// A poller nobody asked for this long stops reading (and lets go of the PLC) until
/// the next request: a closed editor does not keep polling.
const IDLE_AFTER: Duration = Duration::from_secs(30);
/// How often a sleeping poller looks at its stop flag.
const TICK: Duration = Duration::from_millis(25);

/// The environment variable holding the PLC's password (gutta-cc's too); unset or
/// empty: the factory password.
pub use gutta_link::PASSWORD_ENV;

/// What the poller tells the server: values changed (refresh the hints), or the PLC
/// stopped answering (warn the user once).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Event {
    Changed,
    Unreachable(String),
}

/// Where the poller's events go (the server turns them into LSP messages). Called on
/// the poller's thread.
pub type Notify = Arc<dyn Fn(Event) + Send + Sync>;

/// How to reach the PLC: a project's `[connection]` with gutta-cc's defaults filled in
/// (gutta-link's `LinkConfig`), and the packet size its reads are batched by.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LinkSettings {
    pub config: LinkConfig,
    /// The PLC's ExchPackSize.
    pub exch_pack_size: u32,
}

impl LinkSettings {
    /// `None` when the project names no PLC.
    pub fn from_connection(c: &Connection, exch_pack_size: u32) -> Option<LinkSettings> {
        Some(LinkSettings {
            config: LinkConfig::from_connection(c)?,
            exch_pack_size,
        })
    }

    /// Connect and log in: GUTTA_PASSWORD or the factory password (nobody to prompt).
    fn open(&self) -> Result<Session, LoginError> {
        let environment = std::env::var(PASSWORD_ENV).ok();
        let credentials = Credentials::lookup(None, environment.as_deref());
        let mut session = Session::open(&self.config, &credentials, &mut NoPrompt)?;
        session.set_exch_pack_size(self.exch_pack_size);
        Ok(session)
    }
}

/// The last value read of an address; `None` (shown `?`) until read or while the PLC
/// does not answer.
pub type Values = BTreeMap<Address, u32>;

#[derive(Debug)]
struct Shared {
    wanted: Vec<Address>,
    values: Values,
    /// When the editor last asked.
    asked: Instant,
}

/// A running poller; dropping it stops the thread (without waiting for it).
pub struct Poller {
    shared: Arc<Mutex<Shared>>,
    stop: Arc<AtomicBool>,
    pub settings: LinkSettings,
}

fn lock(shared: &Mutex<Shared>) -> MutexGuard<'_, Shared> {
    // A panic elsewhere cannot leave `Shared` half-written: its fields are swapped whole.
    shared
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

impl Poller {
    pub fn start(settings: LinkSettings, notify: Notify) -> Poller {
        let shared = Arc::new(Mutex::new(Shared {
            wanted: Vec::new(),
            values: Values::new(),
            asked: Instant::now(),
        }));
        let stop = Arc::new(AtomicBool::new(false));
        let worker = Worker {
            settings: settings.clone(),
            shared: Arc::clone(&shared),
            stop: Arc::clone(&stop),
            notify,
        };
        thread::Builder::new()
            .name("gutta-live".into())
            .spawn(move || worker.run())
            .map(|_| ())
            .unwrap_or_else(|_| stop.store(true, Ordering::Relaxed));
        Poller {
            shared,
            stop,
            settings,
        }
    }

    /// Read these addresses from now on (the operands the editor shows).
    pub fn want(&self, addresses: Vec<Address>) {
        let mut s = lock(&self.shared);
        s.asked = Instant::now();
        if s.wanted != addresses {
            s.wanted = addresses;
        }
    }

    /// The last values read.
    pub fn values(&self) -> Values {
        lock(&self.shared).values.clone()
    }
}

impl Drop for Poller {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
    }
}

struct Worker {
    settings: LinkSettings,
    shared: Arc<Mutex<Shared>>,
    stop: Arc<AtomicBool>,
    notify: Notify,
}

impl Worker {
    fn run(self) {
        let mut session: Option<Session> = None;
        let mut backoff = PERIOD;
        let mut next_attempt = Instant::now();
        let mut warned = false;
        while !self.stop.load(Ordering::Relaxed) {
            let started = Instant::now();
            let (wanted, asked) = {
                let s = lock(&self.shared);
                (s.wanted.clone(), s.asked)
            };
            if asked.elapsed() > IDLE_AFTER {
                session = None;
            } else if !wanted.is_empty() && started >= next_attempt {
                match self.poll(&mut session, &wanted) {
                    Ok(values) => {
                        backoff = PERIOD;
                        warned = false;
                        self.publish(values);
                    }
                    Err(e) => {
                        session = None;
                        self.publish(Values::new());
                        if !warned {
                            warned = true;
                            (self.notify)(Event::Unreachable(format!(
                                "live values: the PLC at {} does not answer ({e}); \
                                 showing `?` and retrying",
                                self.settings.config.describe()
                            )));
                        }
                        next_attempt = Instant::now() + backoff;
                        backoff = (backoff * 2).min(MAX_BACKOFF);
                    }
                }
            }
            self.sleep_until(started + PERIOD);
        }
    }

    /// Connect and log in if needed, then read every wanted address.
    fn poll(
        &self,
        session: &mut Option<Session>,
        wanted: &[Address],
    ) -> Result<Values, LoginError> {
        let plc = match session {
            Some(plc) => plc,
            None => session.insert(self.settings.open()?),
        };
        let values = plc.read_plan(&ReadPlan::new(wanted))?;
        Ok(wanted.iter().copied().zip(values).collect())
    }

    /// Keep `values` (those of addresses no longer wanted are dropped); tell the client
    /// when something it shows changed.
    fn publish(&self, values: Values) {
        let changed = {
            let mut s = lock(&self.shared);
            let changed = s.values != values;
            s.values = values;
            changed
        };
        if changed {
            (self.notify)(Event::Changed);
        }
    }

    fn sleep_until(&self, until: Instant) {
        while !self.stop.load(Ordering::Relaxed) {
            let left = until.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return;
            }
            thread::sleep(left.min(TICK));
        }
    }
}
