//! The source map file beside an image directory: `DIR.map.json` for `DIR`
//! (docs/image-format.md, "The source map"). Outside the directory, so the directory
//! stays exactly what the PLC holds and an upload reproduces it byte for byte. Written
//! atomically after the image; read only when it describes the image in `DIR`.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use gutta_format::{Image, SourceMap};

use crate::image_dir::{write_image, WriteError};

/// `out/image` -> `out/image.map.json`; `image/` -> `image.map.json`.
pub fn source_map_path(dir: &Path) -> PathBuf {
    let name = dir
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .or_else(|| {
            let full = dir.canonicalize().ok()?;
            full.file_name().map(|n| n.to_string_lossy().into_owned())
        })
        .unwrap_or_else(|| "image".into());
    dir.with_file_name(format!("{name}.map.json"))
}

/// Write `image` to `dir` (atomically, `write_image`), then its source map beside it
/// (atomically: a temporary file renamed over the old map).
pub fn write_image_with_map(dir: &Path, image: &Image, map: &SourceMap) -> Result<(), WriteError> {
    write_image(dir, image)?;
    let path = source_map_path(dir);
    let tmp = path.with_extension(format!("json.tmp-{}", std::process::id()));
    let written = (|| {
        let mut f = fs::File::create(&tmp)?;
        f.write_all(map.to_json().as_bytes())?;
        f.sync_all()?;
        fs::rename(&tmp, &path)
    })();
    written.map_err(|e| {
        let _ = fs::remove_file(&tmp);
        WriteError(format!(
            "wrote the image {} but not its source map {}: {e}",
            dir.display(),
            path.display()
        ))
    })
}

/// The source map beside `dir`, if there is one: `Ok(None)` when there is no map file;
/// an error when it cannot be read or parsed, or was written for another image than
/// `image` (a stale map: recompile).
pub fn read_source_map(dir: &Path, image: &Image) -> Result<Option<SourceMap>, String> {
    let path = source_map_path(dir);
    let text = match fs::read_to_string(&path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(format!("cannot read {}: {e}", path.display())),
    };
    let map = SourceMap::from_json(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    if !map.describes(&image.manifest()) {
        return Err(format!(
            "{} was written for another image than {} (recompile to refresh it)",
            path.display(),
            dir.display()
        ));
    }
    Ok(Some(map))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn map_path_is_beside_the_directory() {
        assert_eq!(
            source_map_path(Path::new("out/image")),
            Path::new("out/image.map.json")
        );
        assert_eq!(
            source_map_path(Path::new("image/")),
            Path::new("image.map.json")
        );
    }

    #[test]
    fn written_read_and_refused_when_stale() {
        let base = std::env::temp_dir().join(format!("gutta-io-map-{}", std::process::id()));
        let dir = base.join("img");
        let image = Image {
            plc_type: "CPU-EC20".into(),
            pages: [(
                gutta_format::PageId::new(gutta_format::PageKind::Const, 0),
                vec![1],
            )]
            .into(),
        };
        let map = SourceMap::new("main.lad", &image.manifest(), Vec::new());
        assert_eq!(read_source_map(&dir, &image), Ok(None));
        write_image_with_map(&dir, &image, &map).expect("writes");
        assert_eq!(read_source_map(&dir, &image), Ok(Some(map)));
        let other = Image {
            plc_type: "CPU-EC30".into(),
            ..image
        };
        let stale = read_source_map(&dir, &other);
        let _ = fs::remove_dir_all(&base);
        assert!(stale.is_err_and(|e| e.contains("another image")));
    }
}
