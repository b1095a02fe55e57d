//! The studio online (docs/studio.md, "Online"): gutta.toml's `[connection]` read as
//! `gutta-cc download`/`monitor` read it (the link flags' defaults, then the project's
//! values), the PLC session and its updates `gutta-cc monitor`'s (`monitor/session.rs`:
//! the program check, one batched read per update, power flow by
//! `gutta_ladder::live`), the download `gutta-cc download`'s (`client::send_image`).
//!
//! The link's transports are not `Send`: one worker thread owns the connection and does
//! every PLC exchange, in order; the server talks to it through a channel and reads the
//! latest state from memory, so no request ever holds the session's mutex (or any
//! other) across PLC I/O. The worker updates while a page asks for `/api/live` (within
//! `DEMAND`), every `INTERVAL`, and every `RECHECK` compares what the PLC holds with
//! the session's current program (compiled again when the buffers changed): a PLC that
//! runs another program, or none, is said so in the state (`program`), and the state
//! recovers by itself once the programs match again.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use axum::extract::State;
use axum::http::StatusCode;
use axum::response::Response;
use axum::routing::{get, post};
use gutta_cli::fatal::Fatal;
use gutta_cli::studio::Session;
use gutta_cli::vars;
use gutta_compiler::{compile_program, ExplicitTarget, ProgramSources};
use gutta_link::{Client, Credentials, LinkError, LoginError, PasswordPrompt, PASSWORD_ENV};
use serde_json::{json, Value};

use super::api::{json_answer, Studio};
use super::live::{LiveError, LiveSource, WatchRequest, WatchValue};
use crate::args::LinkArgs;
use crate::monitor::session::{Program, Session as Monitor};

/// Between two updates while a page watches.
const INTERVAL: Duration = Duration::from_millis(100);
/// Between two checks of the PLC's program against the session's.
const RECHECK: Duration = Duration::from_secs(3);
/// A page that has not asked for the state this long is gone: updates pause.
const DEMAND: Duration = Duration::from_secs(2);
/// How long a request waits for the worker's answer (RUN, STOP, a write, a read).
const ANSWER: Duration = Duration::from_secs(30);
/// How long a download may take.
const DOWNLOAD: Duration = Duration::from_secs(600);

/// The session's program as the buffers hold it, and the project's target: what the
/// PLC's program is compared with and what a download sends.
pub(crate) struct Current {
    pub name: String,
    pub sources: ProgramSources,
    pub target: Option<ExplicitTarget>,
}

/// Gives the session's current program (None: the studio is gone).
pub(crate) type CurrentFn = Box<dyn Fn() -> Option<Current> + Send>;

/// What two compilations compare: every source's and table's name and text.
type Fingerprint = Vec<(String, String)>;

fn fingerprint(sources: &ProgramSources) -> Fingerprint {
    sources
        .sources
        .iter()
        .chain(&sources.symbol_tables)
        .map(|f| (f.name.clone(), f.text.clone()))
        .collect()
}

/// `current` compiled for the PLC: refused (`code`: the compiler's, `E0101`) when it
/// has errors, nothing sent.
pub(crate) fn compile(current: &Current) -> Result<(Program, Fingerprint), LiveError> {
    let compiled = compile_program(current.sources.clone(), current.target.as_ref());
    let checked = &compiled.checked;
    if let Some(d) = checked.diagnostics().iter().find(|d| d.is_error()) {
        let at = checked
            .file
            .locate(&checked.index, d.primary.span.start as usize);
        return Err(LiveError {
            code: d.code.as_str(),
            message: format!(
                "{}:{}: {} ({}): the program must compile to go online or to download",
                at.file,
                at.line,
                d.message,
                d.code.as_str()
            ),
        });
    }
    let Some(image) = compiled.image.clone() else {
        return Err(LiveError {
            code: "no-image",
            message: "the program compiled to no image".into(),
        });
    };
    gutta_format::verify(&image, &checked.target).map_err(|e| LiveError {
        code: "verify",
        message: format!("the compiled image does not verify (a compiler defect): {e}"),
    })?;
    let program = crate::monitor::program_of(
        current.name.clone(),
        gutta_ladder::build(checked),
        checked.target.clone(),
        checked.symbols(),
        image,
    );
    Ok((program, fingerprint(&current.sources)))
}

/// The link to gutta.toml's `[connection]` of the project at `root`: the link flags'
/// defaults with the project's values, as `gutta-cc download` takes them when no flag
/// is given.
pub(crate) fn link_of(root: &std::path::Path) -> Result<LinkArgs, LiveError> {
    use clap::{Args, FromArgMatches};
    let no_project = || {
        LiveError {
        code: "no-connection",
        message: format!(
            "{} is not a project: going online needs gutta.toml's [connection] (tcp = \"HOST:PORT\")",
            root.display()
        ),
    }
    };
    let project = gutta_io::Project::find(root)
        .map_err(|e| LiveError {
            code: "project",
            message: e.to_string(),
        })?
        .ok_or_else(no_project)?;
    let matches = LinkArgs::augment_args(clap::Command::new("studio"))
        .try_get_matches_from(["studio"])
        .map_err(|e| LiveError {
            code: "project",
            message: e.to_string(),
        })?;
    let mut link = LinkArgs::from_arg_matches(&matches).map_err(|e| LiveError {
        code: "project",
        message: e.to_string(),
    })?;
    crate::project::apply_connection(&mut link, &matches, &project.connection);
    if link.tcp.is_none() && link.rtu_tcp.is_none() && link.serial.is_none() {
        return Err(LiveError {
            code: "no-connection",
            message: format!(
                "{} has no [connection]: add `tcp = \"HOST:PORT\"` (or rtu-tcp, serial) under [connection]",
                project.manifest.display()
            ),
        });
    }
    Ok(link)
}

/// Nobody to ask for a password: the studio's terminal is not its user's page.
struct NoPrompt;

impl PasswordPrompt for NoPrompt {
    fn ask(&mut self, _endpoint: &str) -> Result<Option<String>, String> {
        Ok(None)
    }
}

/// Log in with `--password`'s lookup (GUTTA_PASSWORD, then the factory password), never
/// a prompt.
fn log_in(client: Client, at: &str) -> Result<gutta_link::Session, Fatal> {
    let environment = std::env::var(PASSWORD_ENV).ok();
    let credentials = Credentials::lookup(None, environment.as_deref());
    gutta_link::Session::log_in(client, at, &credentials, &mut NoPrompt).map_err(|e| match e {
        LoginError::Link(e) => crate::login::failure(e),
        LoginError::PasswordNeeded(_) => Fatal::link(format!(
            "refused: the PLC has a password (the factory password was refused); \
             start the studio with {PASSWORD_ENV} set"
        )),
        LoginError::Prompt(e) => Fatal::io(e),
    })
}

fn fatal(code: &'static str, e: Fatal) -> LiveError {
    LiveError {
        code,
        message: match e.hint {
            Some(hint) => format!("{}: {hint}", e.message),
            None => e.message,
        },
    }
}

fn plc_error(e: LinkError) -> LiveError {
    LiveError {
        code: "plc-error",
        message: format!("the PLC did not answer as expected: {e}"),
    }
}

fn now_ms() -> u64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_millis() as u64)
}

/// What the worker asks to do.
enum Job {
    Run(bool, Sender<Result<(), LiveError>>),
    Write(String, String, Sender<Result<(), LiveError>>),
    Force(String, Option<String>, Sender<Result<(), LiveError>>),
    Read(Vec<WatchRequest>, Sender<Vec<WatchValue>>),
    Download(
        Box<(Program, Fingerprint)>,
        Sender<Result<Value, LiveError>>,
    ),
}

/// What the worker and the server share.
struct Shared {
    latest: Mutex<Latest>,
    /// The download's progress (`/api/online/progress`).
    progress: Mutex<Value>,
}

struct Latest {
    state: Option<Value>,
    /// When a page last asked for the state.
    wanted: Instant,
}

impl Shared {
    fn latest(&self) -> MutexGuard<'_, Latest> {
        self.latest.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn progress(&self) -> MutexGuard<'_, Value> {
        self.progress.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// The one online connection of this process: the download route reaches it here
/// (the live holder keeps it as a `dyn LiveSource`).
static ONLINE: Mutex<Option<Handle>> = Mutex::new(None);
static NEXT_ID: AtomicU64 = AtomicU64::new(1);

/// A way to the worker.
#[derive(Clone)]
pub(crate) struct Handle {
    id: u64,
    jobs: Sender<Job>,
    shared: Arc<Shared>,
    pub address: String,
}

impl Handle {
    /// The connection now, if the studio is online.
    pub(crate) fn current() -> Option<Handle> {
        ONLINE.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }

    /// `job` sent, its answer awaited at most `wait`.
    fn ask<T>(&self, job: impl FnOnce(Sender<T>) -> Job, wait: Duration) -> Result<T, LiveError> {
        let (answer, answered) = mpsc::channel();
        let gone = || LiveError {
            code: "not-online",
            message: "the connection to the PLC has ended: go online again".into(),
        };
        self.jobs.send(job(answer)).map_err(|_| gone())?;
        answered.recv_timeout(wait).map_err(|e| match e {
            RecvTimeoutError::Timeout => LiveError {
                code: "plc-timeout",
                message: format!("the PLC did not finish within {} s", wait.as_secs()),
            },
            RecvTimeoutError::Disconnected => gone(),
        })
    }

    /// The latest state (the `/api/live` object); marks that a page watches.
    pub(crate) fn state(&self) -> Value {
        let mut latest = self.shared.latest();
        latest.wanted = Instant::now();
        latest.state.clone().unwrap_or_else(|| {
            json!({
                "mode": "ONLINE", "live": false, "run": null, "scans": null,
                "address": self.address, "updated": now_ms(),
                "message": "connecting to the PLC", "program": null,
                "networks": [], "values": {}, "forced": [],
            })
        })
    }

    /// The download's progress: `{"active", "done", "total", "message", "result",
    /// "error"}`.
    pub(crate) fn progress(&self) -> Value {
        self.shared.progress().clone()
    }

    /// Download `program` (compiled from the session), then RUN if the PLC ran.
    pub(crate) fn download(&self, program: (Program, Fingerprint)) -> Result<Value, LiveError> {
        {
            let mut progress = self.shared.progress();
            if progress["active"] == json!(true) {
                return Err(LiveError {
                    code: "busy",
                    message: "a download is already running".into(),
                });
            }
            let total = 2 * program.0.image.pages.values().map(Vec::len).sum::<usize>();
            *progress = json!({"active": true, "done": 0, "total": total,
                               "message": "downloading", "result": null, "error": null});
        }
        let result = self
            .ask(|a| Job::Download(Box::new(program), a), DOWNLOAD)
            .and_then(|r| r);
        let mut progress = self.shared.progress();
        progress["active"] = json!(false);
        match &result {
            Ok(summary) => {
                progress["message"] = json!("downloaded");
                progress["result"] = summary.clone();
            }
            Err(e) => {
                progress["message"] = json!("download failed");
                progress["error"] = json!(e);
            }
        }
        result
    }
}

/// The connected PLC, as the live holder keeps it: dropping it ends the connection.
pub(crate) struct Online {
    handle: Handle,
}

impl Drop for Online {
    fn drop(&mut self) {
        let mut online = ONLINE.lock().unwrap_or_else(|e| e.into_inner());
        if online.as_ref().is_some_and(|h| h.id == self.handle.id) {
            *online = None;
        }
        // The worker ends when its last sender is gone (this handle's; a download in
        // flight keeps a clone until it answers).
    }
}

impl Online {
    /// Connect to `link` (logged in, the program checked) with the worker that owns the
    /// connection from now on; a PLC that does not answer is `plc-unreachable`.
    pub(crate) fn connect(link: LinkArgs, current: CurrentFn) -> Result<Online, LiveError> {
        let now = current().ok_or_else(|| LiveError {
            code: "not-online",
            message: "the studio is closing".into(),
        })?;
        let (program, print) = compile(&now)?;
        let address = crate::client::link_config(&link)
            .map_err(|e| fatal("no-connection", e))?
            .address()
            .to_string();
        let shared = Arc::new(Shared {
            latest: Mutex::new(Latest {
                state: None,
                wanted: Instant::now(),
            }),
            progress: Mutex::new(json!({"active": false, "done": 0, "total": 0,
                                        "message": "", "result": null, "error": null})),
        });
        let (jobs, inbox) = mpsc::channel();
        let (ready, connected) = mpsc::channel();
        let (worker_shared, worker_address) = (shared.clone(), address.clone());
        std::thread::Builder::new()
            .name("studio-online".into())
            .spawn(move || {
                let worker = Worker {
                    monitor: None,
                    program,
                    print,
                    broken: None,
                    status: None,
                    current,
                    shared: worker_shared,
                    address: worker_address,
                    session_forces: Default::default(),
                };
                worker.run(&link, &inbox, &ready);
            })
            .map_err(|e| LiveError {
                code: "io",
                message: format!("cannot start the online worker: {e}"),
            })?;
        connected.recv().map_err(|_| LiveError {
            code: "plc-unreachable",
            message: "the online worker ended before it connected".into(),
        })??;
        let handle = Handle {
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
            jobs,
            shared,
            address,
        };
        *ONLINE.lock().unwrap_or_else(|e| e.into_inner()) = Some(handle.clone());
        Ok(Online { handle })
    }

    pub(crate) fn handle(&self) -> &Handle {
        &self.handle
    }
}

impl LiveSource for Online {
    fn mode(&self) -> &'static str {
        "ONLINE"
    }

    fn state(&mut self) -> Value {
        self.handle.state()
    }

    fn run(&mut self) -> Result<(), LiveError> {
        self.handle.ask(|a| Job::Run(true, a), ANSWER)?
    }

    fn stop(&mut self) -> Result<(), LiveError> {
        self.handle.ask(|a| Job::Run(false, a), ANSWER)?
    }

    fn write(&mut self, operand: &str, value: &str) -> Result<(), LiveError> {
        let (operand, value) = (operand.to_string(), value.to_string());
        self.handle.ask(|a| Job::Write(operand, value, a), ANSWER)?
    }

    fn force(&mut self, operand: &str, value: Option<&str>) -> Result<(), LiveError> {
        let (operand, value) = (operand.to_string(), value.map(str::to_string));
        self.handle.ask(|a| Job::Force(operand, value, a), ANSWER)?
    }

    fn read(&mut self, rows: &[WatchRequest]) -> Vec<WatchValue> {
        let asked = rows.to_vec();
        self.handle
            .ask(|a| Job::Read(asked, a), ANSWER)
            .unwrap_or_else(|e| {
                rows.iter()
                    .map(|r| WatchValue {
                        operand: r.operand.clone(),
                        address: None,
                        value: None,
                        forced: false,
                        error: Some(e.clone()),
                    })
                    .collect()
            })
    }
}

/// The thread that owns the connection.
struct Worker {
    monitor: Option<Monitor>,
    /// What the PLC is compared with and read for: the session's program when last
    /// compiled without errors.
    program: Program,
    print: Fingerprint,
    /// The session's program has errors now (its message): the PLC is compared with the
    /// last one that compiled.
    broken: Option<String>,
    /// The RUN state of the last program check (shown while the programs differ).
    status: Option<bool>,
    current: CurrentFn,
    shared: Arc<Shared>,
    address: String,
    /// What this session forced and has not released (canonical addresses): UM4001 reads
    /// force values, not the mask, so a bit forced to 0 is marked from this set only.
    session_forces: std::collections::BTreeSet<String>,
}

impl Worker {
    fn run(
        mut self,
        link: &LinkArgs,
        inbox: &Receiver<Job>,
        ready: &Sender<Result<(), LiveError>>,
    ) {
        match Monitor::connect(&self.program, link, log_in) {
            Ok(monitor) => self.monitor = Some(monitor),
            Err(e) => {
                let _ = ready.send(Err(fatal("plc-unreachable", e)));
                return;
            }
        }
        let program = &self.program;
        let monitor = self.monitor.as_mut().expect("connected above");
        self.status = monitor
            .plc(program)
            .and_then(|plc| plc.client().status())
            .ok()
            .map(|s| s & 1 != 0);
        self.publish();
        let _ = ready.send(Ok(()));
        let mut checked = Instant::now();
        loop {
            match inbox.recv_timeout(INTERVAL) {
                Ok(job) => {
                    self.job(job);
                    continue;
                }
                Err(RecvTimeoutError::Disconnected) => return,
                Err(RecvTimeoutError::Timeout) => {}
            }
            if checked.elapsed() >= RECHECK {
                checked = Instant::now();
                self.recheck();
            }
            if self.shared.latest().wanted.elapsed() < DEMAND {
                self.publish();
            }
        }
    }

    /// The session's program compiled again if its buffers changed, and what the PLC
    /// holds compared with it.
    fn recheck(&mut self) {
        if let Some(now) = (self.current)() {
            if fingerprint(&now.sources) != self.print {
                match compile(&now) {
                    Ok((program, print)) => {
                        self.program = program;
                        self.print = print;
                        self.broken = None;
                    }
                    Err(e) => self.broken = Some(e.message),
                }
            }
        }
        let program = &self.program;
        let monitor = self.monitor.as_mut().expect("connected");
        // A failure dropped the connection: the next update says so and connects again.
        if monitor.recheck(program).is_ok() {
            self.status = monitor
                .plc(program)
                .and_then(|plc| plc.client().status())
                .ok()
                .map(|s| s & 1 != 0);
        }
    }

    /// One update, in the live state's shape, for the page.
    fn publish(&mut self) {
        let program = &self.program;
        let monitor = self.monitor.as_mut().expect("connected");
        let mut state = monitor.update(program);
        if state["run"].is_null() {
            // Another program, or none: the monitor reads no values, the RUN state is
            // the last check's.
            state["run"] = json!(self.status);
        }
        state["mode"] = json!("ONLINE");
        state["address"] = json!(self.address);
        state["scans"] = Value::Null;
        state["updated"] = json!(now_ms());
        if state["run"] == json!(false) {
            // In STOP the PLC solves no rung: no power flow is shown.
            state["networks"] = json!([]);
            if state["live"] == json!(true) {
                state["message"] = json!("the PLC is in STOP");
            }
        }
        if state["live"] == json!(true) {
            // The forces this session made count too (a bit forced to 0 reads as unforced).
            let mut forced: std::collections::BTreeSet<String> = state["forced"]
                .as_array()
                .map(|a| {
                    a.iter()
                        .filter_map(|v| v.as_str().map(String::from))
                        .collect()
                })
                .unwrap_or_default();
            forced.extend(self.session_forces.iter().cloned());
            state["forced"] = json!(forced);
            state["forced_note"] = json!(
                "a bit forced to 0 is marked only when this studio session forced it: the PLC's protocol reports force values, not which bits are forced"
            );
        }
        if state["program"] != json!("same") {
            state["message"] = json!(match state["program"].as_str() {
                Some("none") => "the PLC holds no program: download this one".to_string(),
                _ => format!(
                    "the PLC runs another program than {}: download this one",
                    program.name
                ),
            });
        }
        if let Some(broken) = &self.broken {
            state["message"] = json!(format!(
                "{broken}; the PLC is compared with the last version that compiled"
            ));
        }
        self.shared.latest().state = Some(state);
    }

    /// One job done, and the state published before the answer: a request's answer
    /// and the state it then asks for agree (STOP answered: the state says STOP).
    fn job(&mut self, job: Job) {
        match job {
            Job::Run(run, answer) => {
                let done = self.run_stop(run);
                self.publish();
                let _ = answer.send(done);
            }
            Job::Write(operand, value, answer) => {
                let done = self.write(&operand, Some(&value), false);
                self.publish();
                let _ = answer.send(done);
            }
            Job::Force(operand, value, answer) => {
                let done = self.write(&operand, value.as_deref(), true);
                self.publish();
                let _ = answer.send(done);
            }
            Job::Read(rows, answer) => {
                let _ = answer.send(self.read(&rows));
            }
            Job::Download(program, answer) => {
                let done = self.download(*program);
                self.publish();
                let _ = answer.send(done);
            }
        }
    }

    /// RUN or STOP, as `gutta-cc run`/`stop`: the status read back must agree.
    fn run_stop(&mut self, run: bool) -> Result<(), LiveError> {
        let program = &self.program;
        let monitor = self.monitor.as_mut().expect("connected");
        let plc = monitor.plc(program).map_err(plc_error)?;
        let client = plc.client();
        let done = client
            .set_running(run)
            .and_then(|()| client.status().map(|s| s & 1 != 0));
        monitor.refresh();
        let now = done.map_err(|e| {
            monitor.disconnect();
            plc_error(e)
        })?;
        if now != run {
            return Err(LiveError {
                code: "plc-refused",
                message: format!(
                    "the PLC accepted `{}` but its status says it {}",
                    if run { "run" } else { "stop" },
                    if now { "runs" } else { "is stopped" }
                ),
            });
        }
        Ok(())
    }

    /// A write or a force (`value`), or a release (a force of None), as `gutta-cc
    /// write`/`force`/`unforce`.
    fn write(&mut self, operand: &str, value: Option<&str>, force: bool) -> Result<(), LiveError> {
        let program = &self.program;
        let bad = |message: String| LiveError {
            code: "no-operand",
            message,
        };
        let monitor = self.monitor.as_mut().expect("connected");
        let done = match value {
            Some(value) => {
                let pair = vars::resolve_assignment(
                    &format!("{operand}={value}"),
                    &program.symbols,
                    &program.target,
                )
                .map_err(bad)?;
                let canonical = pair.0.canonical.clone();
                let plc = monitor.plc(program).map_err(plc_error)?;
                if force {
                    let done = plc.force(&[pair]);
                    if done.is_ok() {
                        self.session_forces.insert(canonical);
                    }
                    done
                } else {
                    plc.write(&[pair])
                }
            }
            None => {
                let var = vars::resolve(operand, &program.symbols, &program.target).map_err(bad)?;
                let canonical = var.canonical.clone();
                let plc = monitor.plc(program).map_err(plc_error)?;
                let done = plc.unforce(&[var]).map(drop);
                if done.is_ok() {
                    self.session_forces.remove(&canonical);
                }
                done
            }
        };
        monitor.refresh();
        done.map_err(|e| {
            monitor.disconnect();
            plc_error(e)
        })
    }

    /// The watch table's rows, read in one request.
    fn read(&mut self, rows: &[WatchRequest]) -> Vec<WatchValue> {
        let program = &self.program;
        let forced: Vec<String> = self
            .shared
            .latest()
            .state
            .as_ref()
            .and_then(|s| s["forced"].as_array().cloned())
            .unwrap_or_default()
            .iter()
            .filter_map(|v| v.as_str().map(str::to_string))
            .collect();
        let resolved: Vec<Result<vars::Var, String>> = rows
            .iter()
            .map(|r| {
                let text = match &r.format {
                    Some(f) => format!("{}:{f}", r.operand),
                    None => r.operand.clone(),
                };
                vars::resolve(&text, &program.symbols, &program.target)
            })
            .collect();
        let good: Vec<vars::Var> = resolved.iter().filter_map(|r| r.clone().ok()).collect();
        let monitor = self.monitor.as_mut().expect("connected");
        let values = monitor.plc(program).and_then(|plc| plc.read(&good));
        let mut values = match values {
            Ok(values) => Ok(values.into_iter()),
            Err(e) => {
                monitor.disconnect();
                Err(plc_error(e))
            }
        };
        rows.iter()
            .zip(resolved)
            .map(|(row, var)| {
                let mut answer = WatchValue {
                    operand: row.operand.clone(),
                    address: None,
                    value: None,
                    forced: false,
                    error: None,
                };
                match var {
                    Err(message) => {
                        answer.error = Some(LiveError {
                            code: "no-operand",
                            message,
                        });
                    }
                    Ok(var) => {
                        answer.forced = forced.contains(&var.canonical);
                        answer.address = Some(var.canonical.clone());
                        match &mut values {
                            Ok(values) => answer.value = values.next().map(|raw| var.show(raw)),
                            Err(e) => answer.error = Some(e.clone()),
                        }
                    }
                }
                answer
            })
            .collect()
    }

    /// `gutta-cc download`'s download of `program` over this connection (its password,
    /// its PLC type check, PLC_CLEAR ... STATUS_RESET), the progress shared, then RUN if
    /// the PLC ran before; the program is the one compared with from now on.
    fn download(&mut self, (program, print): (Program, Fingerprint)) -> Result<Value, LiveError> {
        let started = Instant::now();
        let shared = self.shared.clone();
        let old = &self.program;
        let monitor = self.monitor.as_mut().expect("connected");
        let password = monitor.password();
        let plc = monitor.plc(old).map_err(plc_error)?;
        let ran = plc
            .client()
            .status()
            .map(|s| s & 1 != 0)
            .map_err(plc_error)?;
        let mut transferred = 0usize;
        let mut progress = |n: usize| {
            transferred += n;
            shared.progress()["done"] = json!(transferred);
        };
        let sent = crate::client::send_image(
            plc.client(),
            &program.image,
            &program.target,
            &password,
            &mut progress,
        );
        // The reset ended the login: log in again, and compare with the new program.
        monitor.disconnect();
        let report = sent.map_err(|e| fatal("download-failed", e))?;
        self.program = program;
        self.print = print;
        self.broken = None;
        let program = &self.program;
        let monitor = self.monitor.as_mut().expect("connected");
        monitor.recheck(program).map_err(plc_error)?;
        let plc = monitor.plc(program).map_err(plc_error)?;
        let mut runs = plc
            .client()
            .status()
            .map(|s| s & 1 != 0)
            .map_err(plc_error)?;
        if ran && !runs {
            plc.client().set_running(true).map_err(plc_error)?;
            runs = true;
        }
        monitor.refresh();
        Ok(json!({
            "plc": program.image.plc_type,
            "pages": report.pages,
            "bytes": report.bytes,
            "transferred": transferred,
            "requests": report.requests,
            "seconds": started.elapsed().as_secs_f64(),
            "run": runs,
        }))
    }
}

// ---- the routes ----------------------------------------------------------------------

/// The online routes and `/api/tests` (merged into `api::router`, behind its guard):
/// `POST /api/online` connects, `GET /api/online` is the connection's state
/// (`{"mode":"EDIT"}` without one), `POST /api/online/download` compiles the session's
/// program and downloads it, `GET /api/online/progress` follows it, `POST /api/tests`
/// runs the project's tests on the session's program.
pub(crate) fn routes() -> axum::Router<Arc<Studio>> {
    axum::Router::new()
        .route("/api/online", get(state).post(connect))
        .route("/api/online/download", post(download))
        .route("/api/online/progress", get(progress))
        .route("/api/tests", post(tests))
}

/// A refusal `{"code", "message"}`: a program with errors or a busy PLC 409, a PLC that
/// does not answer or fails 502, a project without a connection 409.
fn refused(e: &LiveError) -> Response {
    let status = match e.code {
        "plc-unreachable" | "plc-error" | "plc-timeout" | "plc-refused" | "download-failed" => {
            StatusCode::BAD_GATEWAY
        }
        "io" => StatusCode::INTERNAL_SERVER_ERROR,
        _ => StatusCode::CONFLICT,
    };
    json_answer(status, &json!({"code": e.code, "message": e.message}))
}

/// `f` off the server's threads: PLC I/O and compiling take their time.
async fn blocking(f: impl FnOnce() -> Response + Send + 'static) -> Response {
    tokio::task::spawn_blocking(f).await.unwrap_or_else(|e| {
        refused(&LiveError {
            code: "io",
            message: e.to_string(),
        })
    })
}

/// The session's program now (the session's mutex held only to copy the buffers).
fn current_of(session: &Mutex<Session>) -> Current {
    let session = session.lock().unwrap_or_else(|e| e.into_inner());
    Current {
        name: session.project().name,
        sources: session.sources_now(),
        target: session.explicit_target().cloned(),
    }
}

/// Connect to gutta.toml's `[connection]` and make the PLC the live source (the
/// simulator, or an older connection, ends first); the mode stays EDIT when it fails.
fn go_online(studio: &Studio) -> Result<Handle, LiveError> {
    let root = {
        let session = studio.session.lock().unwrap_or_else(|e| e.into_inner());
        session.root().to_path_buf()
    };
    let link = link_of(&root)?;
    let old = studio.live.lock().unwrap_or_else(|e| e.into_inner()).take();
    drop(old);
    // The worker holds the session weakly: it never keeps a closed studio's alive.
    let session = Arc::downgrade(&studio.session);
    let current: CurrentFn = Box::new(move || session.upgrade().map(|s| current_of(&s)));
    let online = Online::connect(link, current)?;
    let handle = online.handle().clone();
    *studio.live.lock().unwrap_or_else(|e| e.into_inner()) = Some(Box::new(online));
    Ok(handle)
}

/// `POST /api/online`: connected, the first state.
async fn connect(State(studio): State<Arc<Studio>>) -> Response {
    blocking(move || match go_online(&studio) {
        Ok(handle) => {
            // The worker published its first update before it answered.
            json_answer(StatusCode::OK, &handle.state())
        }
        Err(e) => refused(&e),
    })
    .await
}

/// `GET /api/online`: the connection's latest state.
async fn state() -> Response {
    blocking(|| match Handle::current() {
        Some(handle) => json_answer(StatusCode::OK, &handle.state()),
        None => json_answer(StatusCode::OK, &json!({"mode": "EDIT"})),
    })
    .await
}

/// `GET /api/online/progress`: the download's progress.
async fn progress() -> Response {
    blocking(|| match Handle::current() {
        Some(handle) => json_answer(StatusCode::OK, &handle.progress()),
        None => json_answer(StatusCode::OK, &json!({"active": false})),
    })
    .await
}

/// `POST /api/online/download`: the session's program compiled (refused with its first
/// error's code, nothing sent), online first if need be, then downloaded: `{"download":
/// summary, "state": the state after it}`.
async fn download(State(studio): State<Arc<Studio>>) -> Response {
    blocking(move || {
        let result = (|| {
            let program = compile(&current_of(&studio.session))?;
            let handle = match Handle::current() {
                Some(handle) => handle,
                None => go_online(&studio)?,
            };
            let summary = handle.download(program)?;
            Ok::<_, LiveError>(json!({"download": summary, "state": handle.state()}))
        })();
        match result {
            Ok(value) => json_answer(StatusCode::OK, &value),
            Err(e) => refused(&e),
        }
    })
    .await
}

/// `POST /api/tests`: the project's tests on the session's program (`Session::
/// run_tests`), run without holding the session; a program with errors runs none:
/// `{"refused": {code, message, file, line}}`, its first error.
async fn tests(State(studio): State<Arc<Studio>>) -> Response {
    blocking(move || {
        let now = studio
            .session
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .tests_now();
        match now.run() {
            Ok(run) => json_answer(StatusCode::OK, &json!(run)),
            // Not a bad request: the answer of a run whose program does not compile.
            Err(e) => json_answer(
                StatusCode::OK,
                &json!({"refused": {"code": e.code, "message": e.to_string(),
                                    "file": e.file, "line": e.line}}),
            ),
        }
    })
    .await
}
