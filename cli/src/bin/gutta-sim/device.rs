//! One simulated PLC made from what the command line (or a plant's `[[device]]`) says of
//! it: its image or none, its PLC type, its flash, its scan time and where its serial
//! ports lead. The command line's PLC and every PLC of a plant are made here, so they
//! are the same PLC.

use std::path::PathBuf;

use gutta_catalog::{choose_target, OwnName, Target, TargetInputs, TargetSpec};
use gutta_cli::fatal::Fatal;
use gutta_cli::target::TargetArgs;
use gutta_sim::plc::Plc;
use gutta_vm::VmConfig;
use std::sync::Arc;

use crate::ports::{PortSpec, PortWiring};

/// What a PLC is made from.
#[derive(Debug, Clone, Default)]
#[allow(dead_code)] // `name` and `flash`: the plant and the flash (issue 30) read them
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

/// --plc/--target, else the image's PLC type, else the stdlib default; a load error says
/// which folder or PLC type failed.
fn target_for(spec: &PlcSpec, image: Option<&gutta_format::Image>) -> Result<Arc<Target>, Fatal> {
    let chosen = choose_target(&TargetInputs {
        own: image
            .zip(spec.image.as_deref())
            .map(|(i, dir)| OwnName::Image {
                plc: &i.plc_type,
                dir,
            }),
        ..spec.target.inputs()
    });
    gutta_io::load_target(&chosen.spec).map_err(|e| {
        Fatal::target(match &chosen.spec {
            TargetSpec::Folder(dir) => format!("--target {}: {e}", dir.display()),
            TargetSpec::Stdlib(name) => format!("PLC type {name}: {e}"),
        })
    })
}

/// The simulated PLC: the image (verified on its target) or none, its scan time and
/// its EXCH port wiring (--port0/--port1).
pub fn load_plc(spec: &PlcSpec) -> Result<Plc, Fatal> {
    let image = match &spec.image {
        Some(dir) => Some(gutta_io::read_image_dir(dir).map_err(Fatal::io)?),
        None => None,
    };
    let target = target_for(spec, image.as_ref())?;
    if let Some(image) = &image {
        gutta_format::verify(image, &target)
            .map_err(|e| Fatal::program(format!("the image does not verify: {e}")))?;
    }
    let config = VmConfig {
        scan_ms: spec.scan_ms,
        ..VmConfig::default()
    };
    let pages = image.map(|i| i.pages).unwrap_or_default();
    let mut plc = Plc::new(target, pages, config).map_err(Fatal::program)?;
    let mut wiring = PortWiring::default();
    for (n, port) in (0u8..).zip(&spec.ports) {
        if let Some(port) = port {
            wiring.lead(n, PortSpec::parse(port).map_err(Fatal::usage)?);
        }
    }
    plc.set_port_factory(Box::new(wiring));
    Ok(plc)
}
