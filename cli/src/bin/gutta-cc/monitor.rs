//! `gutta-cc monitor [SOURCE_OR_PROJECT]`: the ladder page of a program, kept live from
//! the PLC running it (docs/ladder.md, "Live view"). An HTTP server (axum) serves `/`
//! (the page with `monitor.js` inline), `/events` (server-sent events: the latest
//! update at once, then one per update), `/state` (the latest update as JSON, for
//! `--once`-like tools) and `/metrics` (the request counters, without waking the
//! poller); a poller thread updates only while an event stream is open or a tool has
//! fetched `/state` within the last second. The power flow is `gutta_ladder::live`'s,
//! the PLC side `monitor/session.rs`'s; this file only wires them to HTTP and the
//! command line.

pub(crate) mod session;

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

use axum::http::header;
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::IntoResponse;
use axum::routing::get;
use gutta_catalog::ValueFormat;
use gutta_cli::fatal::Fatal;
use gutta_cli::plural::count;
use gutta_cli::sources::read_source;
use gutta_compiler::{compile_program, ProgramSources};
use gutta_ladder::html::{ladder_html, HtmlOptions};
use serde_json::json;

use crate::args::{Cli, LinkArgs};
use gutta_cli::vars::Var;
use session::{Program, Session};

/// The page's script: listen to `/events`, set the status, the classes and the values.
const SCRIPT: &str = include_str!("monitor.js");

/// A tool that has not fetched `/state` for this long is gone: updates stop (an event
/// stream counts while it is open).
const DEMAND: Duration = Duration::from_secs(1);

/// A `/state` older than this waits for a fresh update (the first fetch after an idle
/// spell), at most `FRESH_WAIT`.
const FRESH: Duration = Duration::from_millis(500);
const FRESH_WAIT: Duration = Duration::from_secs(3);

pub(crate) struct Options {
    pub program: Option<PathBuf>,
    pub http: String,
    pub interval_ms: u64,
    pub once: bool,
}

/// What the server and the poller share.
struct Shared {
    state: Mutex<Latest>,
    fresh: Condvar,
    /// Every update's JSON text, for the event streams.
    events: tokio::sync::watch::Sender<Option<Arc<str>>>,
    /// Event streams open now (the poller runs while there is one).
    streams: AtomicUsize,
    /// Event streams ever opened: a new one makes the poller check the PLC again.
    opened: AtomicU64,
}

/// Held by an open event stream: counts it, and uncounts it when the page goes.
struct StreamGuard(Arc<Shared>);

impl StreamGuard {
    fn new(shared: Arc<Shared>) -> StreamGuard {
        shared.streams.fetch_add(1, Ordering::SeqCst);
        shared.opened.fetch_add(1, Ordering::SeqCst);
        StreamGuard(shared)
    }
}

impl Drop for StreamGuard {
    fn drop(&mut self) {
        self.0.streams.fetch_sub(1, Ordering::SeqCst);
    }
}

struct Latest {
    /// The last update, and when it was made.
    json: Option<(Instant, serde_json::Value)>,
    /// When a page last fetched `/state`.
    wanted: Option<Instant>,
}

impl Shared {
    fn lock(&self) -> std::sync::MutexGuard<'_, Latest> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// `/state`: mark the demand, and answer an update younger than `FRESH` (waiting for
    /// one if need be).
    fn fetch(&self) -> serde_json::Value {
        let mut latest = self.lock();
        latest.wanted = Some(Instant::now());
        let deadline = Instant::now() + FRESH_WAIT;
        loop {
            if let Some((at, json)) = &latest.json {
                if at.elapsed() < FRESH || Instant::now() >= deadline {
                    return json.clone();
                }
            } else if Instant::now() >= deadline {
                return json!({"live": false, "message": "waiting for the PLC"});
            }
            let left = deadline.saturating_duration_since(Instant::now());
            latest = self
                .fresh
                .wait_timeout(latest, left)
                .unwrap_or_else(|e| e.into_inner())
                .0;
        }
    }

    fn wanted(&self) -> bool {
        self.streams.load(Ordering::SeqCst) > 0
            || self.lock().wanted.is_some_and(|t| t.elapsed() < DEMAND)
    }

    fn publish(&self, json: serde_json::Value) {
        self.events.send_replace(Some(Arc::from(json.to_string())));
        self.lock().json = Some((Instant::now(), json));
        self.fresh.notify_all();
    }
}

pub(crate) fn monitor(cli: &Cli, options: &Options, link: &LinkArgs) -> Result<ExitCode, Fatal> {
    let program = load(cli, options.program.as_deref())?;
    let mut session = Session::start(&program, link)?;
    if options.once {
        let state = session.update(&program);
        println!("{state}");
        return Ok(if state["live"] == json!(true) {
            ExitCode::SUCCESS
        } else {
            ExitCode::from(1)
        });
    }
    let page = ladder_html(
        &program.ladder,
        &HtmlOptions {
            title: format!("{}: live", program.name),
            live_script: Some(SCRIPT.to_string()),
            ..HtmlOptions::default()
        },
    );
    let shared = Arc::new(Shared {
        state: Mutex::new(Latest {
            json: None,
            wanted: None,
        }),
        fresh: Condvar::new(),
        events: tokio::sync::watch::Sender::new(None),
        streams: AtomicUsize::new(0),
        opened: AtomicU64::new(0),
    });
    let counters = session.counters.clone();
    let interval = Duration::from_millis(options.interval_ms.max(1));
    let plc = session.address().to_string();
    let name = program.name.clone();
    let http = options.http.clone();
    // The link's transports are not Send: the session stays on this thread, the
    // server gets its own, and its end (Ctrl-C, an error) ends the poller.
    let (done, ended) = std::sync::mpsc::channel();
    let server_shared = shared.clone();
    std::thread::spawn(move || {
        let _ = done.send(serve(&http, page, server_shared, counters, &name, &plc));
    });
    let mut opened = 0;
    loop {
        if let Ok(result) = ended.try_recv() {
            return result.map(|()| ExitCode::SUCCESS);
        }
        let now_opened = shared.opened.load(Ordering::SeqCst);
        if now_opened != opened {
            opened = now_opened;
            session.page_opened();
        }
        if !shared.wanted() {
            std::thread::sleep(Duration::from_millis(10));
            continue;
        }
        let next = Instant::now() + interval;
        let state = session.update(&program);
        shared.publish(state);
        std::thread::sleep(next.saturating_duration_since(Instant::now()));
    }
}

/// The HTTP server until Ctrl-C.
fn serve(
    http: &str,
    page: String,
    shared: Arc<Shared>,
    counters: Arc<session::Counters>,
    name: &str,
    plc: &str,
) -> Result<(), Fatal> {
    crate::serve::until_ctrl_c(http, |at| {
        eprintln!("gutta-cc monitor: http://{at}/ shows {name} live from {plc} (Ctrl-C ends)");
        let page = Arc::new(page);
        let state = shared.clone();
        let events = shared.clone();
        axum::Router::new()
            .route(
                "/",
                get(move || {
                    let page = page.clone();
                    async move {
                        (
                            [(header::CONTENT_TYPE, "text/html; charset=utf-8")],
                            page.to_string(),
                        )
                    }
                }),
            )
            .route(
                "/state",
                get(move || {
                    let state = state.clone();
                    async move {
                        let json = tokio::task::spawn_blocking(move || state.fetch())
                            .await
                            .unwrap_or_else(|e| json!({"live": false, "message": e.to_string()}));
                        json_response(&json)
                    }
                }),
            )
            // No icon: an empty answer rather than a 404 in the browser's console.
            .route(
                "/favicon.ico",
                get(|| async { axum::http::StatusCode::NO_CONTENT }),
            )
            .route(
                "/events",
                get(move || {
                    let events = events.clone();
                    async move { event_stream(events) }
                }),
            )
            .route(
                "/metrics",
                get(move || {
                    let c = counters.clone();
                    async move {
                        json_response(&json!({
                            "updates": c.updates.load(Ordering::Relaxed),
                            "var_reads": c.var_reads.load(Ordering::Relaxed),
                            "plc_requests": c.requests.load(Ordering::Relaxed),
                        }))
                    }
                }),
            )
    })
}

/// `/events`: the latest update at once (if there is one), then every update, until the
/// page goes or the server ends (Ctrl-C: an open stream must not hold the shutdown).
fn event_stream(shared: Arc<Shared>) -> impl IntoResponse {
    let mut receiver = shared.events.subscribe();
    receiver.mark_changed();
    let guard = StreamGuard::new(shared);
    let stream = futures_util::stream::unfold((receiver, guard), |(mut rx, guard)| async move {
        loop {
            tokio::select! {
                changed = rx.changed() => changed.ok()?,
                _ = tokio::signal::ctrl_c() => return None,
            }
            let latest = rx.borrow_and_update().clone();
            if let Some(json) = latest {
                let event = Event::default().data(json.as_ref());
                return Some((Ok::<_, std::convert::Infallible>(event), (rx, guard)));
            }
        }
    });
    (
        [(header::CACHE_CONTROL, "no-store")],
        Sse::new(stream).keep_alive(KeepAlive::default()),
    )
}

fn json_response(value: &serde_json::Value) -> impl IntoResponse {
    (
        [
            (header::CONTENT_TYPE, "application/json"),
            (header::CACHE_CONTROL, "no-store"),
        ],
        value.to_string(),
    )
}

/// The program to show: a source file (with the `--symbols` tables), a project folder,
/// or the project around the current directory; compiled, it must have no errors.
fn load(cli: &Cli, given: Option<&Path>) -> Result<Program, Fatal> {
    let (name, files, tables, scale) = match given {
        Some(path) if path.is_file() => {
            let tables: Vec<PathBuf> = cli
                .symbols
                .iter()
                .filter(|p| !p.extension().is_some_and(|x| x.eq_ignore_ascii_case("lad")))
                .cloned()
                .collect();
            (
                path.display().to_string(),
                vec![path.to_path_buf()],
                tables,
                cli.scale_timer_presets,
            )
        }
        Some(dir) => {
            let project = gutta_io::Project::find(dir)
                .map_err(Fatal::usage)?
                .ok_or_else(|| {
                    Fatal::usage(format!(
                        "{} is neither a source file nor inside a project ({})",
                        dir.display(),
                        gutta_io::MANIFEST
                    ))
                })?;
            project_program(&project, cli)
        }
        None => {
            let project = crate::project::required(cli.project.as_ref(), "monitor")?;
            project_program(&project, cli)
        }
    };
    let mut sources = ProgramSources::default();
    let mut notes = Vec::new();
    for f in &files {
        sources.sources.push(read_source(f, false, &mut notes)?);
    }
    for t in &tables {
        sources
            .symbol_tables
            .push(read_source(t, true, &mut notes)?);
    }
    gutta_cli::notes::print(&notes, cli.message_format, gutta_cli::notes::JsonTo::Stdout);
    sources.options.scale_timer_presets = scale;
    sources.options.s_area = cli.s_area.clone();
    let explicit = cli.target.explicit()?;
    let compiled = compile_program(sources, explicit.as_ref());
    let Some(image) = compiled.image.clone() else {
        let errors = compiled
            .checked
            .diagnostics()
            .iter()
            .filter(|d| d.is_error())
            .count();
        return Err(Fatal::program(format!(
            "{name} has {}: `gutta-cc --check {name}` shows {}; the monitor needs the compiled image",
            count(errors, "error"),
            if errors == 1 { "it" } else { "them" }
        )));
    };
    let checked = &compiled.checked;
    Ok(program_of(
        name,
        gutta_ladder::build(checked),
        checked.target.clone(),
        checked.symbols(),
        image,
    ))
}

/// What the monitor (or the studio online) shows of a compiled program: its ladder, its
/// symbols, its image and every drawn operand with how one read gets them all.
pub(crate) fn program_of(
    name: String,
    ladder: gutta_ladder::model::Ladder,
    target: std::sync::Arc<gutta_catalog::Target>,
    symbols: gutta_format::SymbolTable,
    image: gutta_format::Image,
) -> Program {
    let vars: Vec<Var> = gutta_ladder::live::operands(&ladder, &target, &symbols)
        .into_iter()
        .filter_map(|canonical| {
            let address = target.memory.parse_address(&canonical).ok()?;
            let format = symbols
                .for_address(&canonical)
                .map_or(ValueFormat::default_for(address.width), |s| {
                    s.format(address.width)
                });
            Some(Var {
                symbol: symbols.for_address(&canonical).map(|s| s.name.clone()),
                address,
                canonical,
                format,
            })
        })
        .collect();
    let addresses: Vec<_> = vars.iter().map(|v: &Var| v.address).collect();
    Program {
        plan: gutta_link::plan::ReadPlan::new(&addresses),
        name,
        ladder,
        target,
        symbols,
        image,
        vars,
    }
}

fn project_program(
    project: &gutta_io::Project,
    cli: &Cli,
) -> (String, Vec<PathBuf>, Vec<PathBuf>, bool) {
    let name = project.root.file_name().map_or_else(
        || project.root.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    (
        name,
        project.sources.clone(),
        project.symbols.clone(),
        project.scale_timer_presets || cli.scale_timer_presets,
    )
}
