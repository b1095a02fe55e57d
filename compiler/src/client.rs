//! `gutta-cc download|status|run|stop|read|write|force`: the client commands, over
//! gutta-link. All printing and exit codes are here.

use std::io::IsTerminal;
use std::path::Path;
use std::process::ExitCode;
use std::sync::Arc;

use gutta_catalog::{stdlib, Address, Target, Width};
use gutta_format::{PackedOperand, Use};
use gutta_link::transport::{rtu_over_tcp, serial, TcpTransport};
use gutta_link::{Client, LinkError};

use crate::{explicit_target, Fatal, LinkArgs, TargetArgs};

fn link_error(e: LinkError) -> Fatal {
    Fatal(e.to_string())
}

/// Connect as the options say.
fn connect(args: &LinkArgs) -> Result<Client, Fatal> {
    let transport: Box<dyn gutta_link::Transport> = if let Some(a) = &args.tcp {
        Box::new(TcpTransport::connect(a, args.timeout, args.retries).map_err(link_error)?)
    } else if let Some(a) = &args.rtu_tcp {
        Box::new(rtu_over_tcp(a, args.timeout, args.retries).map_err(link_error)?)
    } else if let Some(d) = &args.serial {
        Box::new(serial(d, args.baud, args.timeout, args.retries).map_err(link_error)?)
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
    client
        .attach(&gutta_format::password_bytes(args.password.as_deref()))
        .map_err(link_error)?;
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
    PackedOperand::memory(a, Use::Value, a.width).0
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
    let image = gutta_io::read_image_dir(dir).map_err(Fatal)?;
    let target = match explicit_target(targets)? {
        Some(e) => e.target,
        None => stdlib::shared(&image.plc_type).map_err(|e| {
            Fatal(format!(
                "the image is for {}: {e} (pass --target DIR for a vendor PLC type)",
                image.plc_type
            ))
        })?,
    };
    gutta_format::verify(&image, &target).map_err(|e| Fatal(format!("{}: {e}", dir.display())))?;
    let total: usize = image.pages.values().map(Vec::len).sum();
    let mut client = connect(args)?;
    let terminal = std::io::stderr().is_terminal();
    let mut sent = 0usize;
    let start = std::time::Instant::now();
    let mut progress = |n: usize| {
        sent += n;
        if terminal {
            eprint!("\rgutta-cc: downloading {sent}/{total} bytes");
        }
    };
    let password = gutta_format::password_bytes(args.password.as_deref());
    let result = gutta_link::download(
        &mut client,
        &image,
        &password,
        target.plc.exch_pack_size as usize,
        &mut progress,
    );
    if terminal {
        eprintln!();
    }
    let report = result.map_err(|e| {
        Fatal(format!(
            "download failed: {e}. The PLC was not reset: it does not run a partial image"
        ))
    })?;
    println!(
        "downloaded {} pages, {} bytes in {} requests ({:.2} s); the PLC verified and runs the image",
        report.pages,
        report.bytes,
        report.requests,
        start.elapsed().as_secs_f64()
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
    let mut client = login(args)?;
    let target = plc_target(targets, &mut client)?;
    let addresses: Vec<Address> = vars
        .iter()
        .map(|v| parse_var(&target, v))
        .collect::<Result<_, _>>()?;
    let packed: Vec<u32> = addresses.iter().map(|a| packed(*a)).collect();
    let values = client.read_vars(&packed).map_err(link_error)?;
    for (a, bytes) in addresses.iter().zip(values) {
        let raw = u32::from_le_bytes(bytes);
        let value = match a.width {
            Width::Bit => (raw >> a.bit) & 1,
            Width::Byte => raw & 0xFF,
            Width::Word => raw & 0xFFFF,
            Width::Dword => raw,
        };
        println!("{} = {value}", target.memory.format_address(a));
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
