//! `gutta-cc download|upload|status|run|stop|read|write|force|unforce`: the client
//! commands, over gutta-link's `Session`, with their human and JSON output (one object
//! per line on stdout); `debug.rs`, `watch.rs` and the monitor build on the connection
//! helpers here (the flags made into a `LinkConfig`, the connect errors' hints).
//! Variables and values go through `gutta_cli::vars`; this file does not parse them, and
//! the session batches and masks the reads.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;

use gutta_catalog::Target;
use gutta_cli::fatal::Fatal;
use gutta_cli::plural::count;
use gutta_cli::target::TargetArgs;
use gutta_cli::vars::{self, Var, VarJson};
use gutta_format::SymbolTable;
use gutta_io::Endpoint;
use gutta_link::session::{line_parity, serial_line};
use gutta_link::{Client, ConnectFailure, LinkConfig, LinkError, Session};
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::json;

use crate::args::LinkArgs;

/// What every client command needs besides the link: the target options, where symbols
/// come from, and whether to print JSON. A project passes its own sources here.
pub(crate) struct Online<'a> {
    pub targets: &'a TargetArgs,
    /// `--symbols` files: program sources and symbol tables.
    pub symbol_files: &'a [PathBuf],
    /// One JSON object per line on stdout instead of text.
    pub json: bool,
}

impl Online<'_> {
    /// The symbols of `symbol_files` and of `tables` (an image's source map).
    pub fn symbols(&self, tables: Vec<SymbolTable>) -> Result<SymbolTable, Fatal> {
        let explicit = self.targets.explicit()?;
        vars::symbol_context(self.symbol_files, tables, explicit.as_ref()).map_err(Fatal::usage)
    }

    /// Print one result: `object` as a JSON line, or `human` as text.
    pub fn print(&self, object: serde_json::Value, human: impl FnOnce() -> String) {
        if self.json {
            println!("{object}");
        } else {
            let text = human();
            if !text.is_empty() {
                println!("{text}");
            }
        }
    }
}

pub(crate) fn link_error(e: LinkError) -> Fatal {
    Fatal::link(e.to_string())
}

/// The link the options ask for (a project's `[connection]` is in them already).
pub(crate) fn link_config(args: &LinkArgs) -> Result<LinkConfig, Fatal> {
    let endpoint = if let Some(a) = &args.tcp {
        Endpoint::Tcp(a.clone())
    } else if let Some(a) = &args.rtu_tcp {
        Endpoint::RtuTcp(a.clone())
    } else if let Some(d) = &args.serial {
        Endpoint::Serial(d.clone())
    } else {
        return Err(Fatal::usage(
            "no PLC given: use --tcp HOST:PORT, --rtu-tcp HOST:PORT or --serial DEVICE",
        ));
    };
    let parity = args.parity;
    Ok(LinkConfig {
        endpoint,
        station: args.station,
        timeout_ms: args.timeout,
        retries: args.retries,
        line: serial_line(Some(args.baud), Some(parity)),
    })
}

/// A transport that could not be opened, with what to try: a refused address names
/// the simulator that could listen there, a missing serial device says so.
pub(crate) fn connect_error(e: LinkError, flag: &str, at: &str) -> Fatal {
    let hint = match &e {
        LinkError::Connect {
            failure: ConnectFailure::Refused,
            ..
        } => Some(format!(
            "is a PLC or gutta-sim listening at {at}? Check the address, or start a simulated PLC there: `gutta-sim {flag} {at}`"
        )),
        LinkError::Connect {
            failure: ConnectFailure::NoDevice,
            ..
        } => Some(format!(
            "{at} does not exist: check the device name and that the adapter is plugged in (`ls /dev/ttyUSB* /dev/ttyACM*`)"
        )),
        _ => None,
    };
    let fatal = link_error(e);
    match hint {
        Some(hint) => fatal.with_hint(hint),
        None => fatal,
    }
}

/// The transport `config` names, with what to try when it cannot be opened
/// (`monitor.rs` counts the requests through it).
pub(crate) fn transport(config: &LinkConfig) -> Result<Box<dyn gutta_link::Transport>, Fatal> {
    config.transport().map_err(|e| {
        let flag = match config.endpoint {
            Endpoint::Tcp(_) => "--tcp",
            Endpoint::RtuTcp(_) => "--rtu-tcp",
            Endpoint::Serial(_) => "--serial",
        };
        connect_error(e, flag, config.address())
    })
}

/// Connect and log in.
pub(crate) fn login(args: &LinkArgs) -> Result<Session, Fatal> {
    let config = link_config(args)?;
    let client = Client::new(transport(&config)?, config.station);
    crate::login::log_in(client, config.address(), args)
}

/// The PLC's target: --plc/--target, else its GET_PLC_NAME from the stdlib.
pub(crate) fn plc_target(targets: &TargetArgs, client: &mut Client) -> Result<Arc<Target>, Fatal> {
    targets.for_plc(|| client.plc_name().map_err(link_error))
}

/// Check the variables named on the command line before connecting, so a misspelt
/// name gets its did-you-mean with no PLC at the address: with --plc/--target (or a
/// project's) every variable resolves now, and an assignment's value parses; without,
/// the names and formats that fit no target are refused, the rest waits for the PLC's
/// type.
pub(crate) fn check_early(
    online: &Online,
    texts: &[String],
    symbols: &SymbolTable,
    assignments: bool,
) -> Result<(), Fatal> {
    match online.targets.explicit()? {
        Some(e) if assignments => texts
            .iter()
            .try_for_each(|t| vars::resolve_assignment(t, symbols, &e.target).map(drop)),
        Some(e) => texts
            .iter()
            .try_for_each(|t| vars::resolve(t, symbols, &e.target).map(drop)),
        None => texts
            .iter()
            .try_for_each(|t| vars::check_without_target(t, symbols)),
    }
    .map_err(Fatal::usage)
}

/// Check the variables, connect, log in, find the target and resolve the variables.
pub(crate) fn login_with_vars(
    online: &Online,
    vars: &[String],
    args: &LinkArgs,
) -> Result<(Session, Vec<Var>), Fatal> {
    let symbols = online.symbols(vec![])?;
    check_early(online, vars, &symbols, false)?;
    let (session, target) = login_with_target(online, args)?;
    let vars = resolve_all(vars, &symbols, &target)?;
    Ok((session, vars))
}

/// Connect, log in and find the target; the session batches by its ExchPackSize.
pub(crate) fn login_with_target(
    online: &Online,
    args: &LinkArgs,
) -> Result<(Session, Arc<Target>), Fatal> {
    let mut session = login(args)?;
    let target = plc_target(online.targets, session.client())?;
    session.set_target(&target);
    Ok((session, target))
}

pub(crate) fn resolve_all(
    texts: &[String],
    symbols: &SymbolTable,
    target: &Target,
) -> Result<Vec<Var>, Fatal> {
    texts
        .iter()
        .map(|v| vars::resolve(v, symbols, target).map_err(Fatal::usage))
        .collect()
}

/// `NAME (ADDR) = VALUE` lines, or `{"command", "values": [...]}`.
fn print_values(online: &Online, command: &str, vars: &[Var], raw: &[u32]) {
    online.print(
        json!({
            "command": command,
            "values": vars.iter().zip(raw).map(|(v, r)| v.json(*r)).collect::<Vec<_>>(),
        }),
        || {
            vars.iter()
                .zip(raw)
                .map(|(v, r)| format!("{} = {}", v.label(), v.show(*r)))
                .collect::<Vec<_>>()
                .join("\n")
        },
    );
}

pub(crate) fn download(online: &Online, dir: &Path, args: &LinkArgs) -> Result<ExitCode, Fatal> {
    let (image, target) = online.targets.read_image(dir)?;
    gutta_format::verify(&image, &target)
        .map_err(|e| Fatal::program(format!("{}: {e}", dir.display())))?;
    // Every byte is written, then read back and compared: the bar and the summary both
    // count the bytes transferred, the image's bytes twice.
    let total: usize = 2 * image.pages.values().map(Vec::len).sum::<usize>();
    // Log in first: the password (perhaps typed at a prompt) the download logs in with.
    let mut session = login(args)?;
    let password = session.password();
    // A progress bar on a terminal; nothing when stderr is a file or a pipe (CI logs).
    let bar = if std::io::stderr().is_terminal() && !online.json {
        let style = ProgressStyle::with_template(
            "{prefix} [{bar:32}] {pos}/{len} bytes {binary_bytes_per_sec}",
        )
        .map_err(|e| Fatal::io(format!("progress bar: {e}")))?
        .progress_chars("=> ");
        ProgressBar::new(total as u64)
            .with_style(style)
            .with_prefix("downloading")
    } else {
        ProgressBar::hidden()
    };
    let start = std::time::Instant::now();
    let mut progress = |n: usize| bar.inc(n as u64);
    let result = send_image(session.client(), &image, &target, &password, &mut progress);
    if result.is_ok() {
        bar.finish_and_clear();
    } else {
        bar.abandon();
    }
    let report = result?;
    // The bar's own count (a hidden bar counts too), so the two cannot disagree.
    let seconds = start.elapsed().as_secs_f64();
    let summary = json!({
        "command": "download",
        "plc": image.plc_type,
        "pages": report.pages,
        "bytes": report.bytes,
        "transferred": bar.position(),
        "requests": report.requests,
        "seconds": seconds,
    });
    online.print(summary, || {
        format!(
            "downloaded {} of {}: {} written and read back in {} ({seconds:.2} s); the PLC verified and runs the image",
            count(report.pages, "page"),
            count(report.bytes, "byte"),
            count(bar.position(), "byte"),
            count(report.requests, "request"),
        )
    });
    // The reset applied the image's system block: say where the PLC answers now, when
    // that differs from how this download reached it.
    let port0 = image
        .page(gutta_format::PageKind::System, 0)
        .and_then(|b| gutta_format::SystemPage::decode(b).ok())
        .and_then(|s| s.ports.first().copied());
    if let Some(port) = port0 {
        let line = port.line();
        let moved = port.address != args.station && args.station != 0;
        let serial = args.serial.is_some() && line != link_config(args)?.line;
        if (moved || serial) && online.json {
            println!(
                "{}",
                json!({
                    "command": "download",
                    "note": "station moved",
                    "station": port.address,
                    "baud": line.baud,
                    "parity": line_parity(&line).name(),
                })
            );
        } else if moved || serial {
            println!(
                "the PLC now answers as station {}{} (its system block): use --station {}{}",
                port.address,
                if args.serial.is_some() {
                    format!(" on a {line} line")
                } else {
                    String::new()
                },
                port.address,
                if serial {
                    format!(
                        " --baud {} --parity {}",
                        line.baud,
                        line_parity(&line).name()
                    )
                } else {
                    String::new()
                }
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// The download itself (`gutta-cc download` and the studio's): the PLC type checked,
/// PLC_CLEAR, every page written and read back, STATUS_RESET (gutta_link::download),
/// `progress` told of every byte; its failures as the user reads them.
pub(crate) fn send_image(
    client: &mut Client,
    image: &gutta_format::Image,
    target: &Target,
    password: &[u8; 16],
    progress: &mut dyn FnMut(usize),
) -> Result<gutta_link::DownloadReport, Fatal> {
    gutta_link::download(
        client,
        image,
        password,
        target.plc.exch_pack_size as usize,
        progress,
    )
    .map_err(|e| match e {
        // Refused before anything changed: the other client's download goes on.
        LinkError::Busy { .. } => link_error(e),
        LinkError::LockedOut => crate::login::failure(e),
        e => Fatal::link(format!(
            "download failed: {e}. The PLC was not reset: it does not run a partial image"
        )),
    })
}

pub(crate) fn upload(online: &Online, dir: &Path, args: &LinkArgs) -> Result<ExitCode, Fatal> {
    // The PLC type decides the packet size; log in first to ask it.
    let (mut session, target) = login_with_target(online, args)?;
    let password = session.password();
    let client = session.client();
    // A fresh or cleared PLC has no program pages (and then no const page to read):
    // say so, exit 1, and write nothing.
    let program = client
        .page_list(gutta_protocol::function::PageArea::Program)
        .map_err(link_error)?;
    if program.is_empty() {
        if online.json {
            println!(
                "{}",
                json!({"command": "upload", "program": false, "message": "the PLC holds no program to upload"})
            );
        }
        eprintln!("gutta-cc: no program: the PLC holds no program to upload");
        return Ok(ExitCode::from(1));
    }
    let image = gutta_link::upload(client, &password, target.plc.exch_pack_size as usize)
        .map_err(link_error)?;
    if let Err(e) = gutta_format::verify(&image, &target) {
        eprintln!("gutta-cc: warning: the uploaded program does not verify: {e}");
    }
    gutta_io::write_image(dir, &image).map_err(|e| Fatal::io(e.0))?;
    let bytes = image.pages.values().map(Vec::len).sum::<usize>();
    online.print(
        json!({
            "command": "upload",
            "program": true,
            "plc": image.plc_type,
            "pages": image.pages.len(),
            "bytes": bytes,
            "output": dir.display().to_string(),
        }),
        || {
            format!(
                "uploaded {} ({}) of a {} into {}",
                count(image.pages.len(), "page"),
                count(bytes, "byte"),
                image.plc_type,
                dir.display()
            )
        },
    );
    Ok(ExitCode::SUCCESS)
}

/// What a PLC's status byte, program list and (with ERROR) debug error code say, one
/// `state` of `gutta-cc status` (docs/online.md): the codes 0x10.. are the simulator's
/// flash states (docs/simulator.md, "Flash and power-on"), 1..4 the VM's faults.
fn plc_state(
    status: u8,
    has_program: bool,
    error_code: Option<u8>,
) -> (&'static str, &'static str) {
    use gutta_sim::plc::{ERROR_DOWNLOAD_INTERRUPTED, ERROR_FLASH_CHECK, ERROR_IMAGE_INVALID};
    if status & 1 != 0 {
        return ("running", "RUN");
    }
    match error_code.filter(|_| status & 8 != 0) {
        Some(ERROR_DOWNLOAD_INTERRUPTED) => (
            "download-interrupted",
            "STOP, no program: a download was interrupted (PLC_CLEAR without STATUS_RESET)",
        ),
        Some(ERROR_FLASH_CHECK) => (
            "flash-check-failed",
            "STOP, no program: the flash failed its check at power-on",
        ),
        Some(ERROR_IMAGE_INVALID) => (
            "image-invalid",
            "STOP: the program in flash does not verify",
        ),
        Some(_) => ("faulted", "STOP: the program faulted"),
        None if status & 8 != 0 => ("error", "STOP: ERROR"),
        None if !has_program => ("empty", "STOP, no program"),
        None => ("stopped", "STOP"),
    }
}

pub(crate) fn status(online: &Online, args: &LinkArgs) -> Result<ExitCode, Fatal> {
    let mut session = login(args)?;
    let client = session.client();
    let name = client.plc_name().map_err(link_error)?;
    let s = client.status().map_err(link_error)?;
    let has_program = !client
        .page_list(gutta_protocol::function::PageArea::Program)
        .map_err(link_error)?
        .is_empty();
    // The debug block's error code says why when ERROR is set (a PLC without the
    // debug functions: none).
    let error_code = if s & 8 != 0 {
        client.debug_info().ok().map(|(_, info)| info.error)
    } else {
        None
    };
    let (state, said) = plc_state(s, has_program, error_code);
    let flags = [(1, "RUN"), (2, "RESET"), (4, "ATTACH"), (8, "ERROR")];
    let on: Vec<&str> = flags
        .iter()
        .filter(|(bit, _)| s & bit != 0)
        .map(|(_, n)| *n)
        .collect();
    online.print(
        json!({
            "command": "status",
            "plc": name,
            "run": s & 1 != 0,
            "status_byte": s,
            "flags": on,
            "state": state,
            "error_code": error_code,
        }),
        || {
            let code = error_code.map_or(String::new(), |c| format!(", error code {c:#04X}"));
            format!(
                "{name}: {said} (status byte {s:#04X}: {}{code})",
                if on.is_empty() {
                    "none".to_string()
                } else {
                    on.join(" ")
                }
            )
        },
    );
    Ok(ExitCode::SUCCESS)
}

pub(crate) fn run_stop(online: &Online, args: &LinkArgs, run: bool) -> Result<ExitCode, Fatal> {
    let mut session = login(args)?;
    let client = session.client();
    let running = |client: &mut Client| client.status().map(|s| s & 1 != 0);
    let before = running(client).map_err(link_error)?;
    client.set_running(run).map_err(link_error)?;
    let after = running(client).map_err(link_error)?;
    if after != run {
        return Err(Fatal::link(format!(
            "the PLC accepted `{}` but its status says it {}",
            if run { "run" } else { "stop" },
            if after { "runs" } else { "is stopped" }
        ))
        .with_hint("`gutta-cc status` shows its status byte (ERROR: the program stopped it)"));
    }
    let command = if run { "run" } else { "stop" };
    online.print(
        json!({"command": command, "ok": true, "run": after, "changed": before != after}),
        || run_stop_message(run, before),
    );
    Ok(ExitCode::SUCCESS)
}

/// What `run` or `stop` did, given whether the PLC ran before.
fn run_stop_message(run: bool, before: bool) -> String {
    match (run, before) {
        (true, true) => "the PLC already runs",
        (true, false) => "the PLC runs (it was stopped)",
        (false, false) => "the PLC was already stopped",
        (false, true) => "the PLC is stopped (it was running)",
    }
    .to_string()
}

pub(crate) fn read(online: &Online, vars: &[String], args: &LinkArgs) -> Result<ExitCode, Fatal> {
    let (mut session, vars) = login_with_vars(online, vars, args)?;
    let values = session.read(&vars).map_err(link_error)?;
    print_values(online, "read", &vars, &values);
    Ok(ExitCode::SUCCESS)
}

/// `write` or `force` `VAR=VALUE...`: each value parsed in its variable's format; prints
/// what was written as `read` prints it.
pub(crate) fn write(
    online: &Online,
    assignments: &[String],
    args: &LinkArgs,
    force: bool,
) -> Result<ExitCode, Fatal> {
    let symbols = online.symbols(vec![])?;
    check_early(online, assignments, &symbols, true)?;
    let (mut session, target) = login_with_target(online, args)?;
    let pairs = assignments
        .iter()
        .map(|item| vars::resolve_assignment(item, &symbols, &target).map_err(Fatal::usage))
        .collect::<Result<Vec<_>, Fatal>>()?;
    if force {
        session.force(&pairs)
    } else {
        session.write(&pairs)
    }
    .map_err(link_error)?;
    let (vars, values): (Vec<Var>, Vec<u32>) = pairs.into_iter().unzip();
    print_values(
        online,
        if force { "force" } else { "write" },
        &vars,
        &values,
    );
    Ok(ExitCode::SUCCESS)
}

/// `gutta-cc unforce VAR...`: `Session::unforce` (STATUS_VAR_FORCE_WRITE with USE = 15,
/// the current value sent with it).
pub(crate) fn unforce(
    online: &Online,
    vars: &[String],
    args: &LinkArgs,
) -> Result<ExitCode, Fatal> {
    let (mut session, vars) = login_with_vars(online, vars, args)?;
    let current = session.unforce(&vars).map_err(link_error)?;
    online.print(
        json!({
            "command": "unforce",
            "values": vars.iter().zip(&current).map(|(v, r)| v.json(*r)).collect::<Vec<_>>(),
        }),
        || {
            vars.iter()
                .map(|v| format!("{} released", v.label()))
                .collect::<Vec<_>>()
                .join("\n")
        },
    );
    Ok(ExitCode::SUCCESS)
}
