//! The flash across power cycles: the commits that make a state durable (PLC_CLEAR,
//! STATUS_RESET, STATUS_WRITE) through the PLC's [`FlashStore`], power-on from what a
//! store held, and the states a status tells apart (a download interrupted, a flash
//! that failed its check). No I/O: the store is the caller's (docs/simulator.md,
//! "Flash and power-on").

use std::collections::BTreeMap;
use std::sync::Arc;

use gutta_catalog::Target;
use gutta_format::PageId;
use gutta_vm::VmConfig;

use super::{Plc, Refusal};
use crate::persist::{FlashImage, FlashState, FlashStore};

/// Byte 15 of STATUS_DEBUG_INFOR_READ (ERROR) when the PLC has no program because a
/// download was cut short: a PLC_CLEAR with no STATUS_RESET after it (the power went,
/// the owner's connection closed or timed out). The VM's own fault codes are 1..4.
pub const ERROR_DOWNLOAD_INTERRUPTED: u8 = 0x10;
/// Byte 15 when the flash found at power-on failed its check (CRC, truncated,
/// malformed, another PLC type's): the PLC came up with no program.
pub const ERROR_FLASH_CHECK: u8 = 0x11;
/// Byte 15 when the pages in flash do not verify as an image (STATUS_READ's ERROR
/// after a STATUS_RESET or a power-on): the PLC is stopped.
pub const ERROR_IMAGE_INVALID: u8 = 0x12;

/// Why a PLC has no program to run, as its status shows (ERROR and a code).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FlashFault {
    /// PLC_CLEAR erased the flash and no STATUS_RESET followed.
    DownloadInterrupted,
    /// The flash found at power-on is unusable; the text says why.
    CheckFailed(String),
}

impl FlashFault {
    /// The code in byte 15 of STATUS_DEBUG_INFOR_READ.
    pub fn code(&self) -> u8 {
        match self {
            FlashFault::DownloadInterrupted => ERROR_DOWNLOAD_INTERRUPTED,
            FlashFault::CheckFailed(_) => ERROR_FLASH_CHECK,
        }
    }
}

/// What a power-on finds in the flash.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PowerOn {
    /// No flash yet: the PLC starts with these pages (an image, or none), as today.
    Fresh(BTreeMap<PageId, Vec<u8>>),
    /// The flash as the last commit left it.
    Flash(FlashImage),
    /// A flash that failed its check (the decoder's or the caller's words).
    Unreadable(String),
}

impl Plc {
    /// A PLC powered on from `found` (UM4001 is silent on most of this; our rules,
    /// docs/simulator.md): the pages loaded as STATUS_RESET loads them, the login,
    /// forces, memory, the debugger and the lockout count not retained (they are RAM);
    /// station and lines from the system page. It runs if the flash was in RUN and the
    /// image verifies. A cleared flash or one that fails its check (another PLC type's
    /// included) gives a PLC with no program, stopped, with ERROR and the reason.
    pub fn power_on(target: Arc<Target>, found: PowerOn, config: VmConfig) -> Result<Plc, String> {
        let fault = match &found {
            PowerOn::Flash(f) if f.plc_type != target.name() => {
                Some(FlashFault::CheckFailed(format!(
                    "it holds a {} program, this PLC is a {}",
                    f.plc_type,
                    target.name()
                )))
            }
            PowerOn::Flash(f) if f.state == FlashState::Cleared => {
                Some(FlashFault::DownloadInterrupted)
            }
            PowerOn::Unreadable(why) => Some(FlashFault::CheckFailed(why.clone())),
            _ => None,
        };
        let (pages, running) = match found {
            PowerOn::Fresh(pages) => (pages, true),
            PowerOn::Flash(f) if fault.is_none() => (f.pages, f.running),
            _ => (BTreeMap::new(), false),
        };
        let mut plc = Plc::new(target, pages, config)?;
        if !running {
            plc.vm.set_running(false);
        }
        plc.flash_fault = fault;
        Ok(plc)
    }

    /// Make every later PLC_CLEAR, STATUS_RESET and STATUS_WRITE durable in `store`
    /// before it is answered.
    pub fn set_flash_store(&mut self, store: Box<dyn FlashStore>) {
        self.store = Some(store);
    }

    /// Commit the PLC's present state to its store (e.g. an image that seeds an empty
    /// flash at start); without a store, nothing.
    pub fn commit_now(&mut self) -> Result<(), String> {
        let running = self.vm.is_running();
        let pages = self.pages.clone();
        self.commit(FlashState::Committed, running, &pages)
            .map_err(|r| match r {
                Refusal::FlashFailed(why) => why,
                other => format!("{other:?}"),
            })
    }

    /// Why the PLC has no program, when the flash says so.
    pub fn flash_fault(&self) -> Option<&FlashFault> {
        self.flash_fault.as_ref()
    }

    /// The code of byte 15 of STATUS_DEBUG_INFOR_READ: a flash fault's, else
    /// [`ERROR_IMAGE_INVALID`] for pages that do not verify, else the VM's.
    pub(super) fn error_code(&self, vm_code: u8) -> u8 {
        match (&self.flash_fault, self.image_error) {
            (Some(fault), _) => fault.code(),
            (None, true) => ERROR_IMAGE_INVALID,
            (None, false) => vm_code,
        }
    }

    /// Make `state` durable; refused (and nothing changed) when the store fails.
    pub(super) fn commit(
        &mut self,
        state: FlashState,
        running: bool,
        pages: &BTreeMap<PageId, Vec<u8>>,
    ) -> Result<(), Refusal> {
        let Some(store) = self.store.as_mut() else {
            return Ok(());
        };
        store
            .commit(&FlashImage {
                plc_type: self.target.name().to_string(),
                state,
                running,
                pages: pages.clone(),
            })
            .map_err(Refusal::FlashFailed)
    }
}
