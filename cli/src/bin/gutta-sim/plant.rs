//! `gutta-sim --plant PLANT.toml`: every device of a plant in this one process
//! (docs/simulator.md, "Plants"). The plant file is gutta-io's (`Plant`); here each
//! device is made (a PLC by `device::load_plc`, a `project` compiled first as
//! `gutta-cc build` compiles it), its `device:NAME` ports wired in process
//! (`plant_ports.rs`), its listeners opened and said on one line, and every PLC scanned
//! by `scan::Scans` with its own period, until Ctrl-C. Serving a connection is the
//! same code as the single device's (`serve`, `relay::Board`, `fx::accept`).

use std::future::Future;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use gutta_cli::fatal::Fatal;
use gutta_cli::target::TargetArgs;
use gutta_compiler::compile_program;
use gutta_io::{DeviceKind, Plant, PlantDevice, PlcProgram, PortLead, Project};
use gutta_sim::fx::FxDevice;
use gutta_sim::plc::Plc;
use gutta_sim::session::Framing;

use crate::plant_ports::InProcessLine;
use crate::ports::{PortSpec, PortWiring};
use crate::{device, fx, listen, relay, say, scan};

/// A device of the plant, made.
enum Made {
    Plc(Arc<Mutex<Plc>>),
    Board(relay::Board),
    Fx(Arc<Mutex<FxDevice>>),
}

/// Runs the plant in `file` until `ctrl_c`; `stats_every` as `--stats-every`, per PLC.
pub async fn run(
    file: &Path,
    stats_every: Option<f64>,
    ctrl_c: impl Future<Output = listen::StoppedBy>,
) -> Result<(), Fatal> {
    let plant = Plant::load(file).map_err(|e| Fatal::usage(e.to_string()))?;
    let start = Instant::now();
    let mut made = Vec::new();
    for device in &plant.devices {
        made.push(make(device).map_err(|e| in_device(device, e))?);
    }
    for (device, this) in plant.devices.iter().zip(&made) {
        if let Made::Plc(plc) = this {
            let wiring = wiring(&plant, &made, device, start)?;
            lock(plc)?.set_port_factory(Box::new(wiring));
        }
    }
    for (device, this) in plant.devices.iter().zip(&made) {
        open_listeners(device, this, start)
            .await
            .map_err(|e| in_device(device, e))?;
    }
    let plcs = plant
        .devices
        .iter()
        .zip(&made)
        .filter_map(|(device, this)| match this {
            Made::Plc(plc) => Some(scan::ScanDevice {
                name: Some(device.name.clone()),
                plc: Arc::clone(plc),
                scan_ms: device.scan_ms,
            }),
            _ => None,
        })
        .collect();
    let scans = scan::Scans::start(plcs, stats_every)
        .map_err(|e| Fatal::io(format!("cannot start the scan threads: {e}")))?;
    let by = ctrl_c.await;
    scans.stop();
    listen::stopped(by)
}

/// An error of one device, said with its name and place in the plant file.
fn in_device(device: &PlantDevice, mut e: Fatal) -> Fatal {
    e.message = format!("device `{}` ({}): {}", device.name, device.place, e.message);
    e
}

fn lock(plc: &Mutex<Plc>) -> Result<std::sync::MutexGuard<'_, Plc>, Fatal> {
    plc.lock()
        .map_err(|_| Fatal("the PLC state was poisoned by a panic".into()))
}

/// The device itself: a PLC loaded (its project compiled first), a board, an fx port.
fn make(device: &PlantDevice) -> Result<Made, Fatal> {
    match device.kind {
        DeviceKind::RelayBoard => return Ok(Made::Board(relay::Board::new())),
        DeviceKind::Fx => return Ok(Made::Fx(Arc::new(Mutex::new(FxDevice::new())))),
        DeviceKind::Plc => {}
    }
    let flags = TargetArgs {
        plc: device.plc.clone(),
        target: device.target.clone(),
        project: None,
    };
    let (image, target) = match &device.program {
        PlcProgram::Empty => (None, flags),
        PlcProgram::Image(dir) => (Some(dir.clone()), flags),
        PlcProgram::Project(folder) => {
            let (dir, target) = build_project(folder, flags)?;
            (Some(dir), target)
        }
    };
    let ports = device.ports.clone().map(|lead| match lead {
        Some(PortLead::Spec(spec)) => Some(spec),
        _ => None,
    });
    let plc = device::load_plc(&device::PlcSpec {
        name: Some(device.name.clone()),
        image,
        target,
        flash: device.flash.clone(),
        scan_ms: device.scan_ms,
        ports,
    })?;
    Ok(Made::Plc(Arc::new(Mutex::new(plc))))
}

/// `project`: the project (a folder holding gutta.toml, or the file) compiled as
/// `gutta-cc build` compiles it, its image written to its output folder; that folder
/// and the target flags with the project's PLC type. A program with errors stops the
/// start with its first error.
fn build_project(folder: &Path, flags: TargetArgs) -> Result<(PathBuf, TargetArgs), Fatal> {
    let manifest = if folder.is_file() {
        folder.to_path_buf()
    } else {
        folder.join(gutta_io::MANIFEST)
    };
    let project = Project::load(&manifest).map_err(|e| Fatal::usage(format!("project: {e}")))?;
    let in_project = |p: &PathBuf| {
        p.strip_prefix(&project.root)
            .map(Path::to_path_buf)
            .unwrap_or_else(|_| p.clone())
    };
    let files: Vec<PathBuf> = project.sources.iter().map(in_project).collect();
    let tables: Vec<PathBuf> = project.symbols.iter().map(in_project).collect();
    let mut program =
        gutta_cli::sources::read_program_in(&project.root, &files, &tables, &mut Vec::new())?;
    program.options.scale_timer_presets = project.scale_timer_presets;
    if let Some(area) = &project.s_area {
        program.options.s_area = Some(area.parse().map_err(|e: String| {
            Fatal::usage(format!("{}: [microwin] s_area: {e}", manifest.display()))
        })?);
    }
    let target = TargetArgs {
        project: project.plc.spec(),
        ..flags
    };
    let compiled = compile_program(program, target.explicit()?.as_ref());
    let checked = &compiled.checked;
    let map = compiled.source_map();
    let first_error = checked.diagnostics().iter().find(|d| d.is_error());
    let (Some(image), Some(map), None) = (&compiled.image, map, first_error) else {
        let place = first_error.map_or_else(
            || "the program has no image".to_string(),
            |d| {
                let at = checked
                    .file
                    .locate(&checked.index, d.primary.span.start as usize);
                format!(
                    "{}:{}:{}: [{}] {}",
                    project.root.join(at.file).display(),
                    at.line,
                    at.column,
                    d.code.as_str(),
                    d.message
                )
            },
        );
        return Err(Fatal::program(format!(
            "the project {} does not compile: {place}",
            project.root.display()
        ))
        .with_hint(format!(
            "run `gutta-cc build` in {} to see every diagnostic",
            project.root.display()
        )));
    };
    gutta_io::write_image_with_map(&project.output, image, &map).map_err(|e| Fatal::io(e.0))?;
    Ok((project.output, target))
}

/// Where the PLC `device`'s ports lead: `device:NAME` to that device in process,
/// anything else as `--port0` leads; its trace lines carry its name.
fn wiring(
    plant: &Plant,
    made: &[Made],
    device: &PlantDevice,
    start: Instant,
) -> Result<PortWiring, Fatal> {
    let mut wiring = PortWiring::default();
    wiring.name = Some(device.name.clone());
    for (n, lead) in (0u8..).zip(&device.ports) {
        match lead {
            None => {}
            Some(PortLead::Spec(spec)) => wiring.lead(
                n,
                PortSpec::parse(spec).map_err(|e| in_device(device, Fatal::usage(e)))?,
            ),
            Some(PortLead::Device(name)) => {
                // The plant file names only devices it has, of a kind that answers.
                let far = plant.devices.iter().position(|d| &d.name == name);
                let line = match far.map(|i| &made[i]) {
                    Some(Made::Plc(plc)) => InProcessLine::Plc {
                        plc: Arc::clone(plc),
                        start,
                    },
                    Some(Made::Board(board)) => InProcessLine::Board(board.clone()),
                    _ => {
                        return Err(in_device(
                            device,
                            Fatal::usage(format!("port{n}: no device `{name}` answers on a line")),
                        ))
                    }
                };
                wiring.lead_in_process(n, line);
            }
        }
    }
    Ok(wiring)
}

/// The device's listeners, bound, accepting, and said on one line:
/// `gutta-sim: NAME: modbus-tcp on A, rtu-over-tcp on B` (`no listener` without one).
async fn open_listeners(device: &PlantDevice, this: &Made, start: Instant) -> Result<(), Fatal> {
    let mut said = Vec::new();
    match this {
        Made::Plc(plc) => {
            for (framing, kind, addresses) in [
                (Framing::Tcp, "modbus-tcp", &device.tcp),
                (Framing::Rtu, "rtu-over-tcp", &device.rtu_tcp),
            ] {
                for address in addresses {
                    let (listener, local) = listen::bind_silently(address).await?;
                    said.push(format!("{kind} on {local}"));
                    let plc = Arc::clone(plc);
                    listen::accept_forever(listener, move |stream| {
                        crate::serve(stream, framing, Arc::clone(&plc), start, None)
                    });
                }
            }
        }
        Made::Board(board) => {
            for address in &device.tcp {
                let (listener, local) = listen::bind_silently(address).await?;
                said.push(format!("relay-board on {local}"));
                board.accept(listener);
            }
        }
        Made::Fx(fx_device) => {
            for address in &device.tcp {
                let (listener, local) = listen::bind_silently(address).await?;
                said.push(format!("fx-tcp on {local}"));
                fx::accept(listener, fx_device);
            }
        }
    }
    let listeners = if said.is_empty() {
        "no listener".to_string()
    } else {
        said.join(", ")
    };
    say(&format!("gutta-sim: {}: {listeners}", device.name));
    Ok(())
}
