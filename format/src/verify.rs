//! The verifier: checks an [`Image`] against a [`Target`] (docs/image-format.md,
//! "Verifying an image") and returns the only thing the VM runs, a [`VerifiedImage`],
//! or the first [`VerifyError`]. Never panics, whatever the bytes; does no I/O.
//!
//! Order of the checks: identity (PLC type), which pages exist, size limits, argument
//! pages, instruction pages, the call graph, data pages, the system page.

mod code;
mod data;
mod error;
mod operand;
mod program;

use std::collections::BTreeMap;

use gutta_catalog::{AreaKind, BlockKind, InstrId, Target};

pub use error::{Location, VerifyCode, VerifyError};

use crate::{DataItem, Image, LocalEntry, PackedOperand, PageId, PageKind, SystemPage};
use program::kind_range;

/// An image that passed [`verify`] for one target, with its pages decoded for the VM.
/// Only `verify` makes one. Instruction ids index the instruction set of the target it
/// was verified against.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VerifiedImage {
    image: Image,
    target: String,
    units: BTreeMap<u8, VerifiedUnit>,
    data: BTreeMap<u8, Vec<DataItem>>,
    system: Option<SystemPage>,
}

/// One program unit (interrupt routine or subroutine): its locals and code.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VerifiedUnit {
    /// Function index: the argument and instruction page number.
    pub page: u8,
    pub kind: BlockKind,
    /// n of INTn / SBRn (MAIN is interrupt 0).
    pub number: u8,
    /// Locals in L order, as the argument page lists them.
    pub locals: Vec<LocalEntry>,
    /// The instruction page's records in order.
    pub records: Vec<UnitRecord>,
    /// Label number -> index in `records` of its `LBL`.
    pub labels: BTreeMap<u16, usize>,
    /// Index in `records` of each `FOR` -> index of the `NEXT` that closes it (every NEXT
    /// closes the innermost open FOR of its page; the verifier refuses an unmatched one).
    pub loops: BTreeMap<usize, usize>,
}

impl VerifiedUnit {
    /// The locals a CALL passes (VAR_INPUT, VAR_IN_OUT, VAR_OUTPUT), in order.
    pub fn parameters(&self) -> impl Iterator<Item = &LocalEntry> {
        self.locals
            .iter()
            .filter(|l| l.section != crate::LocalSection::Temp)
    }
}

/// A record of a verified instruction page.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum UnitRecord {
    Network {
        /// Byte offset in the instruction page.
        offset: usize,
        number: u16,
    },
    Instruction {
        /// Byte offset in the instruction page.
        offset: usize,
        /// The instruction, in the target's instruction set.
        id: InstrId,
        /// Declared operands, then CALL arguments.
        operands: Vec<PackedOperand>,
    },
}

impl VerifiedImage {
    /// The image as read.
    pub fn image(&self) -> &Image {
        &self.image
    }

    pub fn into_image(self) -> Image {
        self.image
    }

    /// Name of the PLC type it was verified for.
    pub fn target_name(&self) -> &str {
        &self.target
    }

    /// Program units by page number (function index).
    /// Move the units out, and drop the pages they were read from (a VM that decoded
    /// them keeps no second copy of the code): `units()` is empty afterwards and
    /// `image()` has no instruction or argument page left.
    pub fn take_units(&mut self) -> BTreeMap<u8, VerifiedUnit> {
        self.image
            .pages
            .retain(|id, _| !matches!(id.kind, PageKind::Instruction | PageKind::Argument));
        std::mem::take(&mut self.units)
    }

    pub fn units(&self) -> &BTreeMap<u8, VerifiedUnit> {
        &self.units
    }

    pub fn unit(&self, page: u8) -> Option<&VerifiedUnit> {
        self.units.get(&page)
    }

    /// MAIN (page 0); every verified image has it.
    pub fn main(&self) -> Option<&VerifiedUnit> {
        self.units.get(&0)
    }

    /// Initial contents of K (the const page; shorter than K, the rest is zero).
    pub fn constants(&self) -> &[u8] {
        self.image.page(PageKind::Const, 0).unwrap_or(&[])
    }

    /// Data items by data page number.
    pub fn data(&self) -> &BTreeMap<u8, Vec<DataItem>> {
        &self.data
    }

    /// System page 0, if the image has one.
    pub fn system(&self) -> Option<&SystemPage> {
        self.system.as_ref()
    }
}

/// Verify an image for a target. See docs/image-format.md "Verifying an image" for
/// every rule and its code.
pub fn verify(image: &Image, target: &Target) -> Result<VerifiedImage, VerifyError> {
    if image.plc_type != target.plc.name {
        return Err(VerifyError::PlcTypeMismatch {
            image: image.plc_type.clone(),
            target: target.plc.name.clone(),
        });
    }
    verify_page_set(image, target)?;
    verify_sizes(image, target)?;
    let units = program::verify_units(image, target)?;
    let data = data::verify_data_pages(image, target)?;
    let system = data::verify_system_page(image, target)?;
    Ok(VerifiedImage {
        image: image.clone(),
        target: target.plc.name.clone(),
        units,
        data,
        system,
    })
}

/// Every page number exists on the target; const and MAIN are there; program pages
/// come in pairs.
fn verify_page_set(image: &Image, target: &Target) -> Result<(), VerifyError> {
    let plc = &target.plc;
    for id in image.pages.keys() {
        let (count, limit) = match id.kind {
            PageKind::Const => (1, "one const page"),
            PageKind::Argument | PageKind::Instruction => (
                plc.program_block_page_int_size
                    .saturating_add(plc.program_block_page_sbr_size),
                "ProgramBlockPageIntSize + ProgramBlockPageSbrSize",
            ),
            PageKind::Data => (plc.data_block_page_size, "DataBlockPageSize"),
            PageKind::System => (1, "system page 0 only"),
        };
        let exists = match id.kind {
            PageKind::Argument | PageKind::Instruction => {
                crate::UnitRef::from_page(id.number, plc).is_some()
            }
            _ => u32::from(id.number) < count,
        };
        if !exists {
            return Err(VerifyError::PageNotOnTarget {
                page: *id,
                count,
                limit,
            });
        }
    }
    if !image.pages.contains_key(&PageId::new(PageKind::Const, 0)) {
        return Err(VerifyError::MissingConstPage);
    }
    for (kind, other) in [
        (PageKind::Argument, PageKind::Instruction),
        (PageKind::Instruction, PageKind::Argument),
    ] {
        for id in image.pages.range(kind_range(kind)).map(|(id, _)| *id) {
            let missing = PageId::new(other, id.number);
            if !image.pages.contains_key(&missing) {
                return Err(VerifyError::UnpairedPage { page: id, missing });
            }
        }
    }
    if image.page(PageKind::Argument, 0).is_none() {
        return Err(VerifyError::MissingMain);
    }
    Ok(())
}

/// The const page fits ProgramBlockConstBinarySize and K; all instruction pages
/// together fit ProgramBlockInstructionBinarySize.
fn verify_sizes(image: &Image, target: &Target) -> Result<(), VerifyError> {
    let plc = &target.plc;
    let const_id = PageId::new(PageKind::Const, 0);
    let const_len = image.page(PageKind::Const, 0).map_or(0, <[u8]>::len) as u64;
    let k = target.memory.area_of_kind(AreaKind::Constant);
    let limits = [
        (
            u64::from(plc.program_block_const_binary_size),
            "ProgramBlockConstBinarySize".to_string(),
        ),
        (
            k.map_or(0, |a| u64::from(a.size)),
            format!("the size of {}", k.map_or("K", |a| a.name.as_str())),
        ),
    ];
    for (max, limit) in limits {
        if const_len > max {
            return Err(VerifyError::SizeLimit {
                page: Some(const_id),
                what: "bytes",
                size: const_len,
                limit,
                max,
            });
        }
    }
    let total: u64 = image
        .pages
        .range(kind_range(PageKind::Instruction))
        .map(|(_, b)| b.len() as u64)
        .sum();
    let max = u64::from(plc.program_block_instruction_binary_size);
    if total > max {
        return Err(VerifyError::SizeLimit {
            page: None,
            what: "instruction bytes",
            size: total,
            limit: "ProgramBlockInstructionBinarySize".to_string(),
            max,
        });
    }
    Ok(())
}
