//! The virtual clock and the scan counters, and the system bits derived from them
//! (SM0.0 always on, SM0.1 first scan, SM0.4 60 s, SM0.5 1 s, SM0.6 scan clock). Time
//! advances only at the end of a scan; nothing here reads a real clock.

/// Half a second: SM0.5 changes every half second, SM0.4 every 60 of them.
const HALF_MS: u64 = 500;

/// Virtual time and counts.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Clock {
    /// Virtual milliseconds since reset.
    pub ms: u64,
    /// Completed scans since reset.
    pub scans: u64,
    /// Instructions executed in the current scan (the watchdog's count; WDR clears it).
    pub executed: u64,
    /// SM0.4 and SM0.5 at `ms`, in place in SMB0: they change only at a half-second
    /// step, so a scan's start does not divide (0 at reset: time 0).
    time_bits: u8,
    /// The time of the next half-second step, when `time_bits` is found again (0 at
    /// reset: the first end of scan finds them).
    next_step_ms: u64,
}

impl Clock {
    /// A scan ended (completed or faulted): count it and advance the time.
    #[inline]
    pub fn end_scan(&mut self, scan_ms: u32) {
        self.scans += 1;
        self.ms += u64::from(scan_ms);
        if self.ms >= self.next_step_ms {
            // Half seconds since reset: SM0.5 is its parity, SM0.4 that of its 60ths.
            let halves = self.ms / HALF_MS;
            self.time_bits = u8::from((halves / 60) % 2 == 1) << 4 | u8::from(halves % 2 == 1) << 5;
            self.next_step_ms = (halves + 1) * HALF_MS;
        }
    }

    /// Write the system bits of SMB0 (at `smb0`, the flat index; None on a target
    /// without SM) for the scan about to start: one read-modify-write of the byte (bits
    /// 2, 3 and 7 keep their values).
    #[inline]
    pub fn set_system_bits(&self, bytes: &mut [u8], smb0: Option<usize>) {
        let Some(smb0) = smb0.and_then(|at| bytes.get_mut(at)) else {
            return;
        };
        let bits =
            1 | u8::from(self.scans == 0) << 1 | self.time_bits | ((self.scans & 1) as u8) << 6;
        *smb0 = (*smb0 & !0b0111_0011) | bits;
    }
}
