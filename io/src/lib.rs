//! File I/O shared by the command-line tools (gutta-cc, gutta-vm and gutta-sim, in
//! cli/): reading a target folder, reading an image directory, writing one atomically,
//! the source map beside it, writing one file atomically (reports, drawings), and
//! projects (gutta.toml).
//! The libraries do no I/O (their clippy.toml forbids it); only the binaries use this.

mod image_dir;
mod plant;
mod project;
mod source_map;
mod target;

use std::path::Path;

use gutta_catalog::{stdlib, CatalogErrorCode, Target, TargetSources};
use gutta_format::Image;

pub use image_dir::{write_image, WriteError};
pub use plant::{
    DeviceKind, Plant, PlantDevice, PlantError, PlantErrorCode, PlcProgram, PortLead,
    DEFAULT_SCAN_MS,
};
pub use project::{
    find_manifest, Connection, Endpoint, Parity, Project, ProjectTarget, DEFAULT_OUTPUT, MANIFEST,
};
pub use source_map::{read_source_map, source_map_path, write_image_with_map};
pub use target::load_target;

/// Read a target folder: PlcType.xml and ManagerVar.xml, and ManagerFun.xml if present
/// (else the stdlib instruction set). Errors carry the catalog's T codes.
pub fn load_target_dir(dir: &Path) -> Result<Target, String> {
    let read = |name: &str| std::fs::read(dir.join(name));
    let missing = |name: &str, e: std::io::Error| {
        format!(
            "[{}] cannot read {}: {e}",
            CatalogErrorCode::NotFound.as_str(),
            dir.join(name).display()
        )
    };
    let plc = read("PlcType.xml").map_err(|e| missing("PlcType.xml", e))?;
    let var = read("ManagerVar.xml").map_err(|e| missing("ManagerVar.xml", e))?;
    let fun = match read("ManagerFun.xml") {
        Ok(b) => b,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => stdlib::MANAGER_FUN.to_vec(),
        Err(e) => return Err(missing("ManagerFun.xml", e)),
    };
    Target::load(TargetSources {
        plc_type: &plc,
        manager_var: &var,
        manager_fun: &fun,
    })
    .map_err(|e| format!("target {}: {e}", dir.display()))
}

/// Read an image directory: the manifest, then every page it lists (names, lengths and
/// CRCs checked by `Image::read`).
pub fn read_image_dir(dir: &Path) -> Result<Image, String> {
    let manifest_path = dir.join(gutta_format::MANIFEST_FILE);
    let manifest = std::fs::read_to_string(&manifest_path)
        .map_err(|e| format!("cannot read {}: {e}", manifest_path.display()))?;
    Image::read(&manifest, |file| {
        std::fs::read(dir.join(file))
            .map_err(|e| format!("cannot read {}: {e}", dir.join(file).display()))
    })
    .map_err(|e| format!("{}: {e}", dir.display()))
}

/// Every file under `dir` (recursively), by its path relative to `dir` with `/`
/// separators, and its bytes: for comparing image directories whole (an upload with
/// the download it came from).
pub fn directory_files(dir: &Path) -> std::io::Result<std::collections::BTreeMap<String, Vec<u8>>> {
    let mut files = std::collections::BTreeMap::new();
    let mut dirs = vec![dir.to_path_buf()];
    while let Some(d) = dirs.pop() {
        for entry in std::fs::read_dir(&d)? {
            let path = entry?.path();
            if path.is_dir() {
                dirs.push(path);
            } else {
                let name: Vec<String> = path
                    .strip_prefix(dir)
                    .unwrap_or(&path)
                    .components()
                    .map(|c| c.as_os_str().to_string_lossy().into_owned())
                    .collect();
                files.insert(name.join("/"), std::fs::read(&path)?);
            }
        }
    }
    Ok(files)
}

/// Write `bytes` into the file `path` through a synced temporary sibling renamed into
/// place, so no reader ever sees half of it and a failure leaves the old file as it was.
pub fn write_file_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write as _;
    let name = path
        .file_name()
        .map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
    let temporary = path.with_file_name(format!(".{name}.tmp{}", std::process::id()));
    let write = || -> std::io::Result<()> {
        let mut file = std::fs::File::create(&temporary)?;
        file.write_all(bytes)?;
        file.sync_all()?;
        std::fs::rename(&temporary, path)
    };
    write().inspect_err(|_| {
        let _ = std::fs::remove_file(&temporary);
    })
}
