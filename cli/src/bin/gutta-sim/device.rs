//! One simulated PLC made from what the command line (or a plant's `[[device]]`) says of
//! it: its image or none, its PLC type, its flash, its scan time and where its serial
//! ports lead. The command line's PLC and every PLC of a plant are made here, so they
//! are the same PLC.

use std::path::{Path, PathBuf};

use gutta_catalog::{choose_target, OwnName, Target, TargetInputs, TargetSpec};
use gutta_cli::fatal::Fatal;
use gutta_cli::target::TargetArgs;
use gutta_sim::plc::Plc;
use gutta_vm::VmConfig;
use std::sync::Arc;

use crate::flash;
use crate::ports::{PortSpec, PortWiring};

/// A start line on stdout (or stderr), flushed; a closed stream is not an error.
fn announce(to_stderr: bool, line: &str) {
    use std::io::Write;
    if to_stderr {
        let _ = writeln!(std::io::stderr().lock(), "{line}");
    } else {
        let mut out = std::io::stdout().lock();
        let _ = writeln!(out, "{line}");
        let _ = out.flush();
    }
}

/// What a PLC is made from.
#[derive(Debug, Clone, Default)]
#[allow(dead_code)] // `name`: the plant (issue 30) reads it
pub struct PlcSpec {
    /// The device's name in a plant (`None` on the command line).
    pub name: Option<String>,
    /// An image directory written by `gutta-cc -o` (the PLC starts empty without one).
    pub image: Option<PathBuf>,
    /// --plc/--target (else the image's PLC type, else the stdlib default).
    pub target: TargetArgs,
    /// `--flash DIR`: the user flash kept in DIR across restarts (volatile without).
    pub flash: Option<PathBuf>,
    /// Real time per scan, in milliseconds (also the VM's virtual time per scan).
    pub scan_ms: u32,
    /// Where serial ports 0 and 1 lead (`--port0`/`--port1` specs); a plant's
    /// `device:NAME` ports are wired by the plant, not here.
    pub ports: [Option<String>; 2],
}

/// --plc/--target, else the flash's PLC type (a flash that holds one), else the image's,
/// else the stdlib default; a load error says which folder or PLC type failed.
fn target_for(
    spec: &PlcSpec,
    image: Option<&gutta_format::Image>,
    flash: Option<&flash::Found>,
) -> Result<Arc<Target>, Fatal> {
    let from_image = image
        .zip(spec.image.as_deref())
        .map(|(i, dir)| OwnName::Image {
            plc: &i.plc_type,
            dir,
        });
    let chosen = choose_target(&TargetInputs {
        own: flash
            .and_then(flash::Found::plc_type)
            .map(OwnName::Plc)
            .or(from_image),
        ..spec.target.inputs()
    });
    gutta_io::load_target(&chosen.spec).map_err(|e| {
        Fatal::target(match &chosen.spec {
            TargetSpec::Folder(dir) => format!("--target {}: {e}", dir.display()),
            TargetSpec::Stdlib(name) => format!("PLC type {name}: {e}"),
        })
    })
}

/// The simulated PLC: the image (verified on its target) or none, or with `--flash`
/// what DIR's flash holds (the image only seeds a DIR without a flash file), its scan
/// time and its EXCH port wiring (--port0/--port1).
pub fn load_plc(spec: &PlcSpec) -> Result<Plc, Fatal> {
    let image = match &spec.image {
        Some(dir) => Some(gutta_io::read_image_dir(dir).map_err(Fatal::io)?),
        None => None,
    };
    let opened = spec.flash.as_deref().map(flash::open).transpose()?;
    let found = opened.as_ref().map(|(_, found)| found);
    let target = target_for(spec, image.as_ref(), found)?;
    if let Some(image) = &image {
        gutta_format::verify(image, &target)
            .map_err(|e| Fatal::program(format!("the image does not verify: {e}")))?;
    }
    let config = VmConfig {
        scan_ms: spec.scan_ms,
        ..VmConfig::default()
    };
    let mut plc = match opened {
        None => {
            let pages = image.map(|i| i.pages).unwrap_or_default();
            Plc::new(target, pages, config).map_err(Fatal::program)?
        }
        Some((store, found)) => {
            let dir = spec.flash.as_deref().unwrap_or(Path::new(""));
            let seed = image.as_ref().filter(|_| !flash::holds_a_flash(&found));
            let mut plc =
                Plc::power_on(target, found.power_on(seed), config).map_err(Fatal::program)?;
            plc.set_flash_store(Box::new(store));
            if seed.is_some() {
                plc.commit_now()
                    .map_err(|e| Fatal::io(format!("--flash {}: {e}", dir.display())))?;
            }
            let seeded = seed.and(spec.image.as_deref());
            let (to_stderr, text) = flash::describe(&found, &plc, seeded);
            let prefix = match &spec.name {
                Some(name) => format!("gutta-sim: {name}: flash {}", dir.display()),
                None => format!("gutta-sim: flash {}", dir.display()),
            };
            announce(to_stderr, &format!("{prefix}: {text}"));
            if let (Some(image_dir), true) = (&spec.image, flash::holds_a_flash(&found)) {
                announce(
                    false,
                    &format!(
                        "{prefix}: holds a flash already; the image in {} was not loaded",
                        image_dir.display()
                    ),
                );
            }
            plc
        }
    };
    let mut wiring = PortWiring::default();
    for (n, port) in (0u8..).zip(&spec.ports) {
        if let Some(port) = port {
            wiring.lead(n, PortSpec::parse(port).map_err(Fatal::usage)?);
        }
    }
    plc.set_port_factory(Box::new(wiring));
    Ok(plc)
}
