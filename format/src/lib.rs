//! The GUTTA download image (docs/image-format.md): packed operands, the five page
//! kinds, their encoders and decoders, and the manifest. The compiler writes it, the
//! VM and simulator read it. No I/O here: an image is pages in memory; decoders never
//! panic on any input.

mod crc;
pub mod disasm;
mod manifest;
mod operand;
mod pages;
mod position;
mod read;
mod sourcemap;
pub mod symbols;
mod verify;

pub use crc::crc16;
pub use gutta_catalog::{Address, BlockKind, Width};
pub use manifest::{Manifest, ManifestError, ManifestPage, FORMAT_VERSION};
pub use operand::{Operand, OperandError, PackedOperand, Pointer, UnitRef, Use, RELEASE_USE};
pub use pages::*;
pub use position::{function_name, parse_breakpoint, parse_position, Breakpoint};
pub use read::{ImageError, MANIFEST_FILE};
pub use sourcemap::{LineMatch, MappedInstruction, SourceMap, SOURCE_MAP_FORMAT};
pub use symbols::{Symbol, SymbolTable};
pub use verify::{
    verify, Location, UnitRecord, VerifiedImage, VerifiedUnit, VerifyCode, VerifyError,
};

use std::collections::BTreeMap;

/// The five kinds of page.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum PageKind {
    Const,
    Argument,
    Instruction,
    Data,
    System,
}

impl PageKind {
    pub const ALL: [PageKind; 5] = [
        PageKind::Const,
        PageKind::Argument,
        PageKind::Instruction,
        PageKind::Data,
        PageKind::System,
    ];

    pub fn keyword(self) -> &'static str {
        match self {
            PageKind::Const => "const",
            PageKind::Argument => "argument",
            PageKind::Instruction => "instruction",
            PageKind::Data => "data",
            PageKind::System => "system",
        }
    }

    pub fn from_keyword(s: &str) -> Option<PageKind> {
        PageKind::ALL.into_iter().find(|k| k.keyword() == s)
    }

    /// Highest page number of the kind (protocol limits: 256 program pages, 16 data
    /// and system pages, one const page).
    pub fn max_number(self) -> u8 {
        match self {
            PageKind::Const => 0,
            PageKind::Argument | PageKind::Instruction => 255,
            PageKind::Data | PageKind::System => 15,
        }
    }
}

/// A page's identity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct PageId {
    pub kind: PageKind,
    pub number: u8,
}

impl PageId {
    pub fn new(kind: PageKind, number: u8) -> PageId {
        PageId { kind, number }
    }

    /// File name inside the image directory: `const.bin`, `argument/08.bin`, `data/0.bin`.
    pub fn file_name(self) -> String {
        match self.kind {
            PageKind::Const => "const.bin".to_string(),
            PageKind::Argument | PageKind::Instruction => {
                format!("{}/{:02X}.bin", self.kind.keyword(), self.number)
            }
            PageKind::Data | PageKind::System => {
                format!("{}/{:X}.bin", self.kind.keyword(), self.number)
            }
        }
    }
}

/// A whole image: PLC type plus page bytes, ordered as the manifest lists them. Nothing
/// else: an image is a function of source and target, and the PLC holds all of it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Image {
    pub plc_type: String,
    pub pages: BTreeMap<PageId, Vec<u8>>,
}

impl Image {
    /// The manifest describing this image's pages.
    pub fn manifest(&self) -> Manifest {
        Manifest {
            format: FORMAT_VERSION,
            plc_type: self.plc_type.clone(),
            pages: self
                .pages
                .iter()
                .map(|(id, bytes)| ManifestPage {
                    kind: id.kind,
                    number: id.number,
                    file: id.file_name(),
                    length: bytes.len() as u32,
                    crc: crc16(bytes),
                })
                .collect(),
        }
    }

    pub fn page(&self, kind: PageKind, number: u8) -> Option<&[u8]> {
        self.pages
            .get(&PageId::new(kind, number))
            .map(Vec::as_slice)
    }

    /// Total bytes of all pages of a kind.
    pub fn total(&self, kind: PageKind) -> usize {
        self.pages
            .iter()
            .filter(|(id, _)| id.kind == kind)
            .map(|(_, b)| b.len())
            .sum()
    }
}
