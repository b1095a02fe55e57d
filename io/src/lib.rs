//! File I/O shared by the command-line tools (gutta-cc, gutta-vm, and the simulator to
//! come): reading a target folder, reading an image directory, writing one atomically.
//! The libraries (catalog, format, compiler, vm) do no I/O; only binaries use this.

mod image_dir;

use std::path::Path;

use gutta_catalog::{stdlib, CatalogErrorCode, Target, TargetSources};
use gutta_format::Image;

pub use image_dir::{write_image, WriteError};

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
