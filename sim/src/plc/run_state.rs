//! The run state through the protocol: STATUS_WRITE (run or stop) and STATUS_SCAN
//! (scans of a stopped PLC). STATUS_READ's byte and STATUS_RESET are the PLC's own
//! (`Plc::status_byte`, `Plc::reset`); this module adds no rule of its own beyond
//! "a PLC without a verified program cannot run".

use super::{Plc, Refusal};

impl Plc {
    /// STATUS_WRITE: run (only a program that verified) or stop.
    pub(super) fn set_running(&mut self, run: bool) -> Result<(), Refusal> {
        if run && (self.image_error || !self.has_program()) {
            return Err(Refusal::NoProgram);
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
