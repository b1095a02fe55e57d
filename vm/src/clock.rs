//! The virtual clock and the scan counters, and the system bits derived from them
//! (SM0.0 always on, SM0.1 first scan, SM0.4 60 s, SM0.5 1 s, SM0.6 scan clock). Time
//! advances only at the end of a scan; nothing here reads a real clock.

use gutta_catalog::{Address, Width};

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

    /// Write the system bits of SMB0 (slot `sm`) for the scan about to start.
    pub fn set_system_bits(&self, memory: &mut Memory, sm: u8) {
        let bit = |b: u8| Address {
            slot: sm,
            offset: 0,
            width: Width::Bit,
            bit: b,
        };
        let t = self.ms;
        let _ = memory.write(bit(0), 1);
        let _ = memory.write(bit(1), u32::from(self.scans == 0));
        let _ = memory.write(bit(4), u32::from((t / 30_000) % 2 == 1));
        let _ = memory.write(bit(5), u32::from((t / 500) % 2 == 1));
        let _ = memory.write(bit(6), u32::from(self.scans % 2 == 1));
    }
}
