//! The commands that look something up and print it, without a PLC or a program to
//! compile: `modbus VAR` (a variable's Modbus address), `dis IMAGE` (an image as STL or
//! a Micro/WIN export), `list-targets` (the stdlib PLC types). The tables they read are
//! the catalog's and the image format's.

use std::io::Write;
use std::path::Path;
use std::process::ExitCode;

use gutta_catalog::{choose_target, stdlib};
use gutta_cli::fatal::Fatal;
use gutta_cli::target::TargetArgs;

use crate::args::DisFormat;

/// `modbus VAR`: the Modbus address of a direct address on the chosen target.
pub(crate) fn modbus(args: &TargetArgs, variable: &str) -> Result<ExitCode, Fatal> {
    let target = gutta_cli::target::load(&choose_target(&args.inputs()))?;
    let address = target
        .memory
        .parse_address(variable.trim())
        .map_err(|e| Fatal::usage(format!("`{variable}` on {}: {e}", target.name())))?;
    match target.memory.modbus_location(&address) {
        Some(loc) => {
            println!("{loc}");
            Ok(ExitCode::SUCCESS)
        }
        None => {
            let area = target
                .memory
                .area_by_slot(address.slot)
                .map(|a| a.name.clone())
                .unwrap_or_default();
            Err(Fatal::usage(format!(
                "`{variable}`: area {area} has no Modbus address on {}",
                target.name()
            )))
        }
    }
}

/// `dis IMAGE [--format stl|awl]`: the image as text that compiles back to its pages;
/// exit 1 when part of it cannot be disassembled.
pub(crate) fn dis(args: &TargetArgs, dir: &Path, format: DisFormat) -> Result<ExitCode, Fatal> {
    let (image, target) = args.read_image(dir)?;
    let format = match format {
        DisFormat::Stl => gutta_format::disasm::Format::Stl,
        DisFormat::Awl => gutta_format::disasm::Format::Awl,
    };
    let d = gutta_format::disasm::disassemble_as(&image, &target, format);
    let _ = std::io::stdout().lock().write_all(d.text.as_bytes());
    for e in &d.errors {
        eprintln!("gutta-cc dis: {e}");
    }
    Ok(if d.errors.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

/// `list-targets`: each stdlib PLC type with its description.
pub(crate) fn list_targets() -> Result<ExitCode, Fatal> {
    for name in stdlib::names() {
        let t = stdlib::load(name).map_err(|e| Fatal::target(e.to_string()))?;
        // A closed pipe (`| head`) ends the listing quietly.
        if writeln!(std::io::stdout(), "{:<16} {}", name, t.plc.information).is_err() {
            break;
        }
    }
    Ok(ExitCode::SUCCESS)
}
