//! Reading an image from its manifest and page files, and listing the files to write.
//! No I/O here: the caller's callback reads a file by its name in the image directory.
//! Only file names of the form `PageId::file_name()` are ever asked for, so a manifest
//! cannot make a reader open `../secret` or `/etc/passwd`.

use std::collections::BTreeMap;
use std::fmt;

use crate::{crc16, Image, Manifest, ManifestError, PageId, PageKind};

/// Name of the manifest file in an image directory.
pub const MANIFEST_FILE: &str = "manifest.json";

/// Why an image directory does not read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ImageError {
    /// `manifest.json` is not valid JSON of the documented shape or format version.
    Manifest(ManifestError),
    /// A page's `file` is not the name its kind and number give (`argument/08.bin`).
    FileName {
        page: PageId,
        file: String,
        expected: String,
    },
    /// Two manifest entries name the same page.
    DuplicatePage { page: PageId },
    /// The manifest lists no const page (every image has `const.bin`).
    MissingConstPage,
    /// The callback could not read a page file.
    Read { file: String, message: String },
    /// A page file's length differs from the manifest's.
    Length {
        file: String,
        manifest: u32,
        actual: usize,
    },
    /// A page file's CRC-16/MODBUS differs from the manifest's.
    Crc {
        file: String,
        manifest: u16,
        actual: u16,
    },
}

impl fmt::Display for ImageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ImageError::Manifest(e) => write!(f, "{e}"),
            ImageError::FileName {
                page,
                file,
                expected,
            } => write!(
                f,
                "manifest.json: {} page {} must be in file `{expected}`, not `{file}`",
                page.kind.keyword(),
                page.number
            ),
            ImageError::DuplicatePage { page } => write!(
                f,
                "manifest.json: {} page {} is listed twice",
                page.kind.keyword(),
                page.number
            ),
            ImageError::MissingConstPage => {
                write!(
                    f,
                    "manifest.json: no const page (every image has const.bin)"
                )
            }
            ImageError::Read { file, message } => write!(f, "{file}: cannot read: {message}"),
            ImageError::Length {
                file,
                manifest,
                actual,
            } => write!(f, "{file}: {actual} bytes, the manifest says {manifest}"),
            ImageError::Crc {
                file,
                manifest,
                actual,
            } => write!(
                f,
                "{file}: CRC 0x{actual:04X}, the manifest says 0x{manifest:04X}"
            ),
        }
    }
}

impl std::error::Error for ImageError {}

impl From<ManifestError> for ImageError {
    fn from(e: ManifestError) -> ImageError {
        ImageError::Manifest(e)
    }
}

impl Image {
    /// Read an image: parse `manifest_json`, then fetch every page it lists through
    /// `read_file` (called with names such as `const.bin`, `instruction/08.bin`,
    /// relative to the image directory) and check each page's length and CRC.
    ///
    /// The manifest is checked before any page is read: file names must be exactly
    /// the documented names of their pages, no page may be listed twice, and the
    /// const page must be there. The order of the entries is not checked (writers
    /// list them in page order). Whether the pages fit a target is `verify`'s job.
    pub fn read(
        manifest_json: &str,
        mut read_file: impl FnMut(&str) -> Result<Vec<u8>, String>,
    ) -> Result<Image, ImageError> {
        let manifest = Manifest::parse(manifest_json)?;
        let mut seen = BTreeMap::new();
        for entry in &manifest.pages {
            let page = PageId::new(entry.kind, entry.number);
            let expected = page.file_name();
            if entry.file != expected {
                return Err(ImageError::FileName {
                    page,
                    file: entry.file.clone(),
                    expected,
                });
            }
            if seen.insert(page, entry).is_some() {
                return Err(ImageError::DuplicatePage { page });
            }
        }
        if !seen.contains_key(&PageId::new(PageKind::Const, 0)) {
            return Err(ImageError::MissingConstPage);
        }
        let mut pages = BTreeMap::new();
        for (page, entry) in seen {
            let bytes = read_file(&entry.file).map_err(|message| ImageError::Read {
                file: entry.file.clone(),
                message,
            })?;
            if u32::try_from(bytes.len()).ok() != Some(entry.length) {
                return Err(ImageError::Length {
                    file: entry.file.clone(),
                    manifest: entry.length,
                    actual: bytes.len(),
                });
            }
            let crc = crc16(&bytes);
            if crc != entry.crc {
                return Err(ImageError::Crc {
                    file: entry.file.clone(),
                    manifest: entry.crc,
                    actual: crc,
                });
            }
            pages.insert(page, bytes);
        }
        Ok(Image {
            plc_type: manifest.plc_type,
            pages,
        })
    }

    /// Every file of the image directory with its bytes, for writers: `manifest.json`
    /// first, then each page file in manifest order. Names use `/` as separator.
    pub fn files(&self) -> Vec<(String, Vec<u8>)> {
        let mut out = Vec::with_capacity(self.pages.len() + 1);
        out.push((
            MANIFEST_FILE.to_string(),
            self.manifest().to_json().into_bytes(),
        ));
        for (id, bytes) in &self.pages {
            out.push((id.file_name(), bytes.clone()));
        }
        out
    }
}
