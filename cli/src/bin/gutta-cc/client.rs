//! `gutta-cc download|status|run|stop|read|write|force`: the client commands, over
//! gutta-link. All printing and exit codes are here.

use std::io::IsTerminal;
use std::path::Path;
use std::process::ExitCode;
use std::sync::Arc;

use gutta_catalog::{stdlib, Address, Target, Width};
use gutta_format::{Operand, PackedOperand, SourceMap};
use gutta_link::message::{debug_state, Breakpoint, DebugStep};
use gutta_link::transport::{rtu_over_tcp, serial, TcpTransport};
use gutta_link::{Client, LinkError};
use indicatif::{ProgressBar, ProgressStyle};

use crate::{explicit_target, Fatal, LinkArgs, TargetArgs};

fn link_error(e: LinkError) -> Fatal {
    Fatal::link(e.to_string())
}

/// The serial line the options ask for.
pub(crate) fn client_line(args: &LinkArgs) -> gutta_format::LineSettings {
    gutta_format::LineSettings {
        baud: args.baud,
        parity: match args.parity {
            crate::Parity::None => 0,
            crate::Parity::Even => 1,
            crate::Parity::Odd => 2,
        },
        ..gutta_format::LineSettings::DEFAULT
    }
}

/// Connect as the options say.
fn connect(args: &LinkArgs) -> Result<Client, Fatal> {
    let transport: Box<dyn gutta_link::Transport> = if let Some(a) = &args.tcp {
        Box::new(TcpTransport::connect(a, args.timeout, args.retries).map_err(link_error)?)
    } else if let Some(a) = &args.rtu_tcp {
        Box::new(rtu_over_tcp(a, args.timeout, args.retries).map_err(link_error)?)
    } else if let Some(d) = &args.serial {
        Box::new(serial(d, client_line(args), args.timeout, args.retries).map_err(link_error)?)
    } else {
        return Err(Fatal(
            "no PLC given: use --tcp HOST:PORT, --rtu-tcp HOST:PORT or --serial DEVICE".into(),
        ));
    };
    Ok(Client::new(transport, args.station))
}

/// Connect and log in.
fn login(args: &LinkArgs) -> Result<Client, Fatal> {
    let mut client = connect(args)?;
    crate::login::log_in(&mut client, args)?;
    Ok(client)
}

/// The PLC's target: --plc/--target, else its GET_PLC_NAME from the stdlib.
fn plc_target(targets: &TargetArgs, client: &mut Client) -> Result<Arc<Target>, Fatal> {
    if let Some(e) = explicit_target(targets)? {
        return Ok(e.target);
    }
    let name = client.plc_name().map_err(link_error)?;
    stdlib::shared(&name).map_err(|e| {
        Fatal(format!(
            "the PLC is a {name}: {e} (pass --target DIR for a vendor PLC type)"
        ))
    })
}

fn packed(a: Address) -> u32 {
    PackedOperand::encode(Operand::Value(a)).0
}

/// A variable's value from the 4 bytes STATUS_VAR_READ returns from its first byte.
fn value_of(a: &Address, bytes: [u8; 4]) -> u32 {
    let raw = u32::from_le_bytes(bytes);
    match a.width {
        Width::Bit => (raw >> a.bit) & 1,
        Width::Byte => raw & 0xFF,
        Width::Word => raw & 0xFFFF,
        Width::Dword => raw,
    }
}

/// Connect, log in, find the target and parse the variables.
fn login_with_vars(
    targets: &TargetArgs,
    vars: &[String],
    args: &LinkArgs,
) -> Result<(Client, Arc<Target>, Vec<Address>), Fatal> {
    let mut client = login(args)?;
    let target = plc_target(targets, &mut client)?;
    let addresses = vars
        .iter()
        .map(|v| parse_var(&target, v))
        .collect::<Result<_, _>>()?;
    Ok((client, target, addresses))
}

fn parse_var(target: &Target, text: &str) -> Result<Address, Fatal> {
    target
        .memory
        .parse_address(text.trim())
        .map_err(|e| Fatal(format!("`{text}` on {}: {e}", target.name())))
}

pub(crate) fn download(
    targets: &TargetArgs,
    dir: &Path,
    args: &LinkArgs,
) -> Result<ExitCode, Fatal> {
    let (image, target) = crate::image_and_target(targets, dir)?;
    gutta_format::verify(&image, &target).map_err(|e| Fatal(format!("{}: {e}", dir.display())))?;
    // Every byte is written, then read back and compared: the bar and the summary both
    // count the bytes transferred, the image's bytes twice.
    let total: usize = 2 * image.pages.values().map(Vec::len).sum::<usize>();
    let mut client = connect(args)?;
    // Log in first: the password (perhaps typed at a prompt) the download logs in with.
    let password = crate::login::log_in(&mut client, args)?;
    // A progress bar on a terminal; nothing when stderr is a file or a pipe (CI logs).
    let bar = if std::io::stderr().is_terminal() {
        let style = ProgressStyle::with_template(
            "{prefix} [{bar:32}] {pos}/{len} bytes {binary_bytes_per_sec}",
        )
        .map_err(|e| Fatal(format!("progress bar: {e}")))?
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
        e => Fatal(format!(
            "download failed: {e}. The PLC was not reset: it does not run a partial image"
        )),
    })?;
    // The bar's own count (a hidden bar counts too), so the two cannot disagree.
    println!(
        "downloaded {} pages of {} bytes: {} bytes written and read back in {} requests ({:.2} s); the PLC verified and runs the image",
        report.pages,
        report.bytes,
        bar.position(),
        report.requests,
        start.elapsed().as_secs_f64()
    );
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
        if moved || serial {
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

pub(crate) fn upload(targets: &TargetArgs, dir: &Path, args: &LinkArgs) -> Result<ExitCode, Fatal> {
    let mut client = connect(args)?;
    // The PLC type decides the packet size; log in first to ask it.
    let password = crate::login::log_in(&mut client, args)?;
    let target = plc_target(targets, &mut client)?;
    // A fresh or cleared PLC has no program pages (and then no const page to read):
    // say so, exit 1, and write nothing.
    let program = client
        .page_list(gutta_protocol::function::PageArea::Program)
        .map_err(link_error)?;
    if program.is_empty() {
        eprintln!("gutta-cc: no program: the PLC holds no program to upload");
        return Ok(ExitCode::from(1));
    }
    let image = gutta_link::upload(&mut client, &password, target.plc.exch_pack_size as usize)
        .map_err(link_error)?;
    if let Err(e) = gutta_format::verify(&image, &target) {
        eprintln!("gutta-cc: warning: the uploaded program does not verify: {e}");
    }
    gutta_io::write_image(dir, &image).map_err(|e| Fatal(e.0))?;
    println!(
        "uploaded {} pages ({} bytes) of a {} into {}",
        image.pages.len(),
        image.pages.values().map(Vec::len).sum::<usize>(),
        image.plc_type,
        dir.display()
    );
    Ok(ExitCode::SUCCESS)
}

pub(crate) fn status(args: &LinkArgs) -> Result<ExitCode, Fatal> {
    let mut client = login(args)?;
    let name = client.plc_name().map_err(link_error)?;
    let s = client.status().map_err(link_error)?;
    let flags = [(1, "RUN"), (2, "RESET"), (4, "ATTACH"), (8, "ERROR")];
    let on: Vec<&str> = flags
        .iter()
        .filter(|(bit, _)| s & bit != 0)
        .map(|(_, n)| *n)
        .collect();
    println!(
        "{name}: {} (status byte {s:#04X}: {})",
        if s & 1 != 0 { "RUN" } else { "STOP" },
        if on.is_empty() {
            "none".to_string()
        } else {
            on.join(" ")
        }
    );
    Ok(ExitCode::SUCCESS)
}

pub(crate) fn run_stop(args: &LinkArgs, run: bool) -> Result<ExitCode, Fatal> {
    let mut client = login(args)?;
    client.set_running(run).map_err(link_error)?;
    Ok(ExitCode::SUCCESS)
}

pub(crate) fn read(
    targets: &TargetArgs,
    vars: &[String],
    args: &LinkArgs,
) -> Result<ExitCode, Fatal> {
    let (mut client, target, addresses) = login_with_vars(targets, vars, args)?;
    let packed: Vec<u32> = addresses.iter().map(|a| packed(*a)).collect();
    let values = client.read_vars(&packed).map_err(link_error)?;
    for (a, bytes) in addresses.iter().zip(values) {
        println!(
            "{} = {}",
            target.memory.format_address(a),
            value_of(a, bytes)
        );
    }
    Ok(ExitCode::SUCCESS)
}

pub(crate) fn write(
    targets: &TargetArgs,
    assignments: &[String],
    args: &LinkArgs,
    force: bool,
) -> Result<ExitCode, Fatal> {
    let mut client = login(args)?;
    let target = plc_target(targets, &mut client)?;
    let pairs: Vec<(u32, u32)> = assignments
        .iter()
        .map(|item| {
            let (var, value) = item
                .split_once('=')
                .ok_or_else(|| Fatal(format!("`{item}`: expected VAR=VALUE")))?;
            let a = parse_var(&target, var)?;
            let v = gutta_catalog::parse_value(value.trim(), a.width)
                .map_err(|e| Fatal(format!("`{item}`: {e}")))?;
            Ok((packed(a), v))
        })
        .collect::<Result<_, Fatal>>()?;
    client.write_vars(&pairs, force).map_err(link_error)?;
    Ok(ExitCode::SUCCESS)
}

/// The image directory `debug` takes its source map from when `--image` is not given.
const DEFAULT_DEBUG_IMAGE: &str = "image";

/// The source map for `debug`: beside `--image DIR` (an error when it is missing or stale),
/// else beside `image/` when there is one (a warning when it cannot be used).
fn debug_source_map(image: Option<&Path>) -> Result<Option<SourceMap>, Fatal> {
    let (dir, explicit) = match image {
        Some(dir) => (dir, true),
        None => (Path::new(DEFAULT_DEBUG_IMAGE), false),
    };
    let map_path = gutta_io::source_map_path(dir);
    if !explicit && !map_path.is_file() {
        return Ok(None);
    }
    let map = gutta_io::read_image_dir(dir)
        .and_then(|image| gutta_io::read_source_map(dir, &image))
        .and_then(|map| map.ok_or_else(|| format!("no source map {}", map_path.display())));
    match map {
        Ok(map) => Ok(Some(map)),
        Err(e) if explicit => Err(Fatal(format!("--image {}: {e}", dir.display()))),
        Err(e) => {
            eprintln!("gutta-cc: warning: {e}; showing positions without source lines");
            Ok(None)
        }
    }
}

/// `gutta-cc debug ACTION [ARG]`: UM4001's DEBUG_* functions.
pub(crate) fn debug(
    targets: &TargetArgs,
    action: &[String],
    image: Option<&Path>,
    args: &LinkArgs,
) -> Result<ExitCode, Fatal> {
    let map = debug_source_map(image)?;
    let mut client = login(args)?;
    let target = plc_target(targets, &mut client)?;
    let plc = &target.plc;
    let arg = action.get(1).map(String::as_str);
    match (action[0].as_str(), arg) {
        ("break", Some(at)) => {
            let map_name =
                gutta_io::source_map_path(image.unwrap_or(Path::new(DEFAULT_DEBUG_IMAGE)));
            let at = gutta_format::parse_breakpoint(
                at,
                plc,
                map.as_ref(),
                &map_name.display().to_string(),
            )
            .map_err(Fatal)?;
            if let Some(note) = at.note {
                eprintln!("gutta-cc: note: {note}");
            }
            let (index, network, step) = at.position;
            client.set_breakpoint(Some(Breakpoint {
                index,
                network,
                step,
            }))
        }
        ("clear", None) => client.set_breakpoint(None),
        ("stop", None) => client.debug_run(false),
        ("run", None) => client.debug_run(true),
        ("reset", None) => client.debug_reset(),
        ("step", Some(kind)) => {
            let step = match kind {
                "in" => DebugStep::In,
                "over" => DebugStep::Over,
                "out" => DebugStep::Out,
                other => return Err(Fatal(format!("step `{other}`: in, over or out"))),
            };
            client.debug_step(step)
        }
        ("info", None) => Ok(()),
        (other, _) => {
            return Err(Fatal(format!(
                "debug `{other}`: break POSITION, clear, stop, run, step in|over|out, reset or info"
            )))
        }
    }
    .map_err(link_error)?;
    // Every action ends by showing where the program is.
    let (state, info) = client.debug_info().map_err(link_error)?;
    // `MAIN:2:1`, or with the map `main.lad:11:1 (MAIN:2:1): MOVW   16#BEEF, MW10`.
    let place = |f: u8, n: u16, s: u16| {
        if f == 0xFF {
            return "none".to_string();
        }
        let position = format!("{}:{n}:{s}", gutta_format::function_name(f, plc));
        match map
            .as_ref()
            .and_then(|m| Some((m, m.at_position(f, n, s)?)))
        {
            Some((m, i)) => format!(
                "{}:{}:{} ({position}): {}",
                m.file, i.line, i.column, i.text
            ),
            None => position,
        }
    };
    let b = info.breakpoint;
    println!("breakpoint: {}", place(b.index, b.network, b.step));
    println!(
        "paused at:  {}",
        place(info.state_index, info.state_network, info.state_step)
    );
    println!(
        "mode: {}; logic stack {:#06X}; call depth {}; saved L {} bytes; error {}",
        if state & debug_state::RUN != 0 {
            "run until a breakpoint"
        } else {
            "single-step stop"
        },
        info.stack_logic,
        info.sp,
        info.stack_data,
        info.error
    );
    Ok(ExitCode::SUCCESS)
}

/// `gutta-cc unforce VAR...`: STATUS_VAR_FORCE_WRITE with USE = 15, which gutta-sim
/// reads as "release" (UM4001 has no unforce). The value sent is the variable's current
/// value, so a PLC that ignores USE keeps it where it is rather than jumping.
pub(crate) fn unforce(
    targets: &TargetArgs,
    vars: &[String],
    args: &LinkArgs,
) -> Result<ExitCode, Fatal> {
    let (mut client, _, addresses) = login_with_vars(targets, vars, args)?;
    let current = client
        .read_vars(&addresses.iter().map(|a| packed(*a)).collect::<Vec<_>>())
        .map_err(link_error)?;
    let pairs: Vec<(u32, u32)> = addresses
        .iter()
        .zip(current)
        .map(|(a, bytes)| (PackedOperand::force_release(*a).0, value_of(a, bytes)))
        .collect();
    client.write_vars(&pairs, true).map_err(link_error)?;
    Ok(ExitCode::SUCCESS)
}
