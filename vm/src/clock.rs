//! The virtual clock and the scan counters, and the system bits derived from them
//! (SM0.0 always on, SM0.1 first scan, SM0.4 60 s, SM0.5 1 s, SM0.6 scan clock). Time
//! advances only at the end of a scan; nothing here reads a real clock.

use crate::memory::Memory;

/// Virtual time and counts.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Clock {
    /// Virtual milliseconds since reset.
    pub ms: u64,
    /// Completed scans since reset.
    pub scans: u64,
    /// Instructions executed in the current scan (the watchdog's count; WDR clears it).
    pub executed: u64,
}

impl Clock {
    /// A scan ended (completed or faulted): count it and advance the time.
    pub fn end_scan(&mut self, scan_ms: u32) {
        self.scans += 1;
        self.ms += u64::from(scan_ms);
    }

    /// Write the system bits of SMB0 (slot `sm`) for the scan about to start: one
    /// read-modify-write of the byte (bits 2, 3 and 7 keep their values).
    pub fn set_system_bits(&self, memory: &mut Memory, sm: u8) {
        let Some(smb0) = memory.area_mut(sm).and_then(|a| a.first_mut()) else {
            return;
        };
        // Half seconds since reset: SM0.5 is its parity, SM0.4 that of its 60ths.
        let halves = self.ms / 500;
        let bits = 1
            | u8::from(self.scans == 0) << 1
            | u8::from((halves / 60) % 2 == 1) << 4
            | u8::from(halves % 2 == 1) << 5
            | u8::from(self.scans % 2 == 1) << 6;
        *smb0 = (*smb0 & !0b0111_0011) | bits;
    }
}
