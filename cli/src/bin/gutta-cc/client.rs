//! `gutta-cc download|upload|status|run|stop|read|write|force|unforce`: the client
//! commands, over gutta-link, with their human and JSON output (one object per line on
//! stdout); `debug.rs` and `watch.rs` build on the connection helpers here. Variables and
//! values go through `vars.rs`; this file does not parse them.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;

use gutta_catalog::{Address, Target, Width};
use gutta_cli::fatal::Fatal;
use gutta_cli::plural::count;
use gutta_cli::target::TargetArgs;
use gutta_format::{Operand, PackedOperand, SymbolTable};
use gutta_link::transport::{rtu_over_tcp, serial, TcpTransport};
use gutta_link::{Client, ConnectFailure, LinkError};
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::json;

use crate::args::LinkArgs;
use crate::vars::{self, Var};

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

/// The serial line the options ask for.
pub(crate) fn client_line(args: &LinkArgs) -> gutta_format::LineSettings {
    gutta_format::LineSettings {
        baud: args.baud,
        parity: match args.parity {
            crate::args::Parity::None => 0,
            crate::args::Parity::Even => 1,
            crate::args::Parity::Odd => 2,
        },
        ..gutta_format::LineSettings::DEFAULT
    }
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

/// Connect as the options say.
fn connect(args: &LinkArgs) -> Result<Client, Fatal> {
    Ok(Client::new(transport(args)?, args.station))
}

/// The transport the options ask for (`monitor.rs` counts the requests through it).
pub(crate) fn transport(args: &LinkArgs) -> Result<Box<dyn gutta_link::Transport>, Fatal> {
    Ok(if let Some(a) = &args.tcp {
        Box::new(
            TcpTransport::connect(a, args.timeout, args.retries)
                .map_err(|e| connect_error(e, "--tcp", a))?,
        )
    } else if let Some(a) = &args.rtu_tcp {
        Box::new(
            rtu_over_tcp(a, args.timeout, args.retries)
                .map_err(|e| connect_error(e, "--rtu-tcp", a))?,
        )
    } else if let Some(d) = &args.serial {
        Box::new(
            serial(d, client_line(args), args.timeout, args.retries)
                .map_err(|e| connect_error(e, "--serial", d))?,
        )
    } else {
        return Err(Fatal::usage(
            "no PLC given: use --tcp HOST:PORT, --rtu-tcp HOST:PORT or --serial DEVICE",
        ));
    })
}

/// Connect and log in.
pub(crate) fn login(args: &LinkArgs) -> Result<Client, Fatal> {
    let mut client = connect(args)?;
    crate::login::log_in(&mut client, args)?;
    Ok(client)
}

/// The PLC's target: --plc/--target, else its GET_PLC_NAME from the stdlib.
pub(crate) fn plc_target(targets: &TargetArgs, client: &mut Client) -> Result<Arc<Target>, Fatal> {
    targets.for_plc(|| client.plc_name().map_err(link_error))
}

pub(crate) fn packed(a: Address) -> u32 {
    PackedOperand::encode(Operand::Value(a)).0
}

/// A variable's value from the 4 bytes STATUS_VAR_READ returns from its first byte.
pub(crate) fn value_of(a: &Address, bytes: [u8; 4]) -> u32 {
    let raw = u32::from_le_bytes(bytes);
    match a.width {
        Width::Bit => (raw >> a.bit) & 1,
        Width::Byte => raw & 0xFF,
        Width::Word => raw & 0xFFFF,
        Width::Dword => raw,
    }
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
) -> Result<(Client, Arc<Target>, Vec<Var>), Fatal> {
    let symbols = online.symbols(vec![])?;
    check_early(online, vars, &symbols, false)?;
    let mut client = login(args)?;
    let target = plc_target(online.targets, &mut client)?;
    let vars = resolve_all(vars, &symbols, &target)?;
    Ok((client, target, vars))
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

/// The raw values of `vars`, in as few STATUS_VAR_READ requests as the PLC's packet
/// size allows.
pub(crate) fn read_values(
    client: &mut Client,
    target: &Target,
    vars: &[Var],
) -> Result<Vec<u32>, LinkError> {
    let per_request = (target.plc.exch_pack_size as usize / 4).max(1);
    let mut values = Vec::with_capacity(vars.len());
    for chunk in vars.chunks(per_request) {
        let packed: Vec<u32> = chunk.iter().map(|v| packed(v.address)).collect();
        let bytes = client.read_vars(&packed)?;
        values.extend(
            chunk
                .iter()
                .zip(bytes)
                .map(|(v, b)| value_of(&v.address, b)),
        );
    }
    Ok(values)
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
    let mut client = connect(args)?;
    // Log in first: the password (perhaps typed at a prompt) the download logs in with.
    let password = crate::login::log_in(&mut client, args)?;
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
    let result = gutta_link::download(
        &mut client,
        &image,
        &password,
        target.plc.exch_pack_size as usize,
        &mut progress,
    );
    if result.is_ok() {
        bar.finish_and_clear();
    } else {
        bar.abandon();
    }
    let report = result.map_err(|e| match e {
        // Refused before anything changed: the other client's download goes on.
        LinkError::Busy { .. } => link_error(e),
        LinkError::LockedOut => crate::login::failure(e),
        e => Fatal::link(format!(
            "download failed: {e}. The PLC was not reset: it does not run a partial image"
        )),
    })?;
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
        let serial = args.serial.is_some() && line != client_line(args);
        if (moved || serial) && online.json {
            println!(
                "{}",
                json!({
                    "command": "download",
                    "note": "station moved",
                    "station": port.address,
                    "baud": line.baud,
                    "parity": parity_name(line.parity),
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
                        parity_name(line.parity)
                    )
                } else {
                    String::new()
                }
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}

fn parity_name(parity: u8) -> &'static str {
    match parity {
        0 => "none",
        2 => "odd",
        _ => "even",
    }
}

pub(crate) fn upload(online: &Online, dir: &Path, args: &LinkArgs) -> Result<ExitCode, Fatal> {
    let mut client = connect(args)?;
    // The PLC type decides the packet size; log in first to ask it.
    let password = crate::login::log_in(&mut client, args)?;
    let target = plc_target(online.targets, &mut client)?;
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
    let image = gutta_link::upload(&mut client, &password, target.plc.exch_pack_size as usize)
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

pub(crate) fn status(online: &Online, args: &LinkArgs) -> Result<ExitCode, Fatal> {
    let mut client = login(args)?;
    let name = client.plc_name().map_err(link_error)?;
    let s = client.status().map_err(link_error)?;
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
        }),
        || {
            format!(
                "{name}: {} (status byte {s:#04X}: {})",
                if s & 1 != 0 { "RUN" } else { "STOP" },
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
    let mut client = login(args)?;
    let running = |client: &mut Client| client.status().map(|s| s & 1 != 0);
    let before = running(&mut client).map_err(link_error)?;
    client.set_running(run).map_err(link_error)?;
    let after = running(&mut client).map_err(link_error)?;
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
    let (mut client, target, vars) = login_with_vars(online, vars, args)?;
    let values = read_values(&mut client, &target, &vars).map_err(link_error)?;
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
    let mut client = login(args)?;
    let target = plc_target(online.targets, &mut client)?;
    let (vars, values): (Vec<Var>, Vec<u32>) = assignments
        .iter()
        .map(|item| vars::resolve_assignment(item, &symbols, &target).map_err(Fatal::usage))
        .collect::<Result<Vec<_>, Fatal>>()?
        .into_iter()
        .unzip();
    let pairs: Vec<(u32, u32)> = vars
        .iter()
        .zip(&values)
        .map(|(v, raw)| (packed(v.address), *raw))
        .collect();
    client.write_vars(&pairs, force).map_err(link_error)?;
    print_values(
        online,
        if force { "force" } else { "write" },
        &vars,
        &values,
    );
    Ok(ExitCode::SUCCESS)
}

/// `gutta-cc unforce VAR...`: STATUS_VAR_FORCE_WRITE with USE = 15, which gutta-sim
/// reads as "release" (UM4001 has no unforce). The value sent is the variable's current
/// value, so a PLC that ignores USE keeps it where it is rather than jumping.
pub(crate) fn unforce(
    online: &Online,
    vars: &[String],
    args: &LinkArgs,
) -> Result<ExitCode, Fatal> {
    let (mut client, target, vars) = login_with_vars(online, vars, args)?;
    let current = read_values(&mut client, &target, &vars).map_err(link_error)?;
    let pairs: Vec<(u32, u32)> = vars
        .iter()
        .zip(&current)
        .map(|(v, raw)| (PackedOperand::force_release(v.address).0, *raw))
        .collect();
    client.write_vars(&pairs, true).map_err(link_error)?;
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
