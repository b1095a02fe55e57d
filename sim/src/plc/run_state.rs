//! The run state through the protocol: STATUS_WRITE (run or stop) and STATUS_SCAN
//! (scans of a stopped PLC). STATUS_READ's byte and STATUS_RESET are the PLC's own
//! (`Plc::status_byte`, `Plc::reset`); this module adds no rule of its own beyond
//! "a PLC without a verified program cannot run".

use super::{Plc, Refusal};
use crate::persist::FlashState;

impl Plc {
    /// STATUS_WRITE: run (only a program that verified and was reset: not inside a
    /// download window, not with a flash fault) or stop. Outside a window the new run
    /// state is committed to the flash before it takes effect; inside one the flash
    /// stays cleared.
    pub(super) fn set_running(&mut self, run: bool) -> Result<(), Refusal> {
        let no_program = self.image_error
            || !self.has_program()
            || self.window.is_some()
            || self.flash_fault.is_some();
        if run && no_program {
            return Err(Refusal::NoProgram);
        }
        if self.window.is_none() {
            let pages = self.pages.clone();
            self.commit(FlashState::Committed, run, &pages)?;
        }
        self.vm.set_running(run);
        Ok(())
    }

    /// STATUS_SCAN: `count` scans of MAIN while stopped.
    pub(super) fn scan_stopped(&mut self, count: u8) -> Result<(), Refusal> {
        self.vm
            .scan_while_stopped(count)
            .map_err(|f| Refusal::Access(f.to_string()))
    }
}
