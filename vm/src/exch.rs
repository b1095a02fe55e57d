//! EXCH: the PLC as a Modbus RTU master on its serial ports (AN2002). Exchanges queued
//! by the EXCH instruction (`ops/comm.rs`) are carried out at the end of the scan, in
//! queue order, through ports the host attaches (`Vm::attach_port`).
//!
//! The table (ManagerFun.xml, EXCH): byte 0 bits .0 A (queued), .1 D (done), .2 E
//! (error); byte 1 error number; word 2 send length; word 4 send buffer offset in M;
//! word 6 receive buffer length; word 8 receive buffer offset in M (native words).
//!
//! Errors: 1 bad table (a buffer outside M, or send length 0), 2 timeout (no answer,
//! or no device attached to the port), 3 CRC error in the answer (or an answer too
//! short to hold a CRC), 4 the answer (without CRC) is longer than the receive buffer;
//! on error 4 nothing is stored. Station 0 is a broadcast: sent, no answer awaited.
//!
//! The devices at the ports' other ends are the host's (`SerialPort`); the one Modbus
//! slave of the toolchain is the simulator's (`gutta_sim::modbus_data`).

use std::collections::BTreeMap;

use gutta_catalog::{Address, AreaKind, Target, Width};
use gutta_format::VerifiedImage;

use crate::memory::Memory;

/// At most this many exchanges are queued at once (for the whole PLC).
pub const QUEUE_LIMIT: usize = 8;

/// Response timeout when the image has no system block entry for the port (ms).
pub const DEFAULT_TIMEOUT_MS: u32 = 1000;

/// Error numbers in table byte 1.
pub const ERR_TABLE: u8 = 1;
pub const ERR_TIMEOUT: u8 = 2;
pub const ERR_CRC: u8 = 3;
pub const ERR_SHORT_BUFFER: u8 = 4;

/// Why a port gave no answer.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PortError {
    /// Nothing came back within the timeout.
    Timeout,
    /// An answer came back with a bad CRC (and no good one after it).
    Crc,
}

/// A serial line with a device (or devices) at its other end.
pub trait SerialPort: std::fmt::Debug + Send {
    /// Send `request` (a whole RTU frame, CRC included) and return the answer frame
    /// (CRC included), or a timeout. For a broadcast the answer is ignored.
    fn transact(&mut self, request: &[u8], timeout_ms: u32) -> Result<Vec<u8>, PortError>;
}

/// One queued exchange: the table (in M) and the port.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Queued {
    pub slot: u8,
    /// Byte offset of the table in M.
    pub table: u32,
    pub port: u8,
    /// The scan that queued it (entries left over from a faulted scan before a reset
    /// are dropped).
    pub scan: u64,
}

/// The exchanges EXCH queued, in order.
#[derive(Debug, Default)]
pub(crate) struct ExchQueue(pub Vec<Queued>);

impl ExchQueue {
    /// Whether the table at `slot`/`table` is queued.
    pub fn is_queued(&self, slot: u8, table: u32) -> bool {
        self.0.iter().any(|q| q.slot == slot && q.table == table)
    }

    pub fn is_full(&self) -> bool {
        self.0.len() >= QUEUE_LIMIT
    }
}

/// Queued exchanges and the serial ports the host attached.
#[derive(Debug, Default)]
pub(crate) struct Exch {
    pub queue: ExchQueue,
    pub ports: BTreeMap<u8, Box<dyn SerialPort>>,
}

fn byte_at(slot: u8, offset: u32) -> Address {
    Address {
        slot,
        offset,
        width: Width::Byte,
        bit: 0,
    }
}

fn word_at(slot: u8, offset: u32) -> Address {
    Address {
        slot,
        offset,
        width: Width::Word,
        bit: 0,
    }
}

/// The M area's slot.
pub(crate) fn m_slot(target: &Target) -> Option<u8> {
    target.memory.area_of_kind(AreaKind::Memory).map(|a| a.slot)
}

/// Write byte 0 (A/D/E, keeping bits 3..7) and byte 1 of a table.
pub(crate) fn write_status(memory: &mut Memory, slot: u8, table: u32, a: bool, d: bool, err: u8) {
    let old = memory.read(byte_at(slot, table)).unwrap_or(0);
    let e = err != 0;
    let b0 = (old & !0x07) | u32::from(a) | (u32::from(d) << 1) | (u32::from(e) << 2);
    let _ = memory.write(byte_at(slot, table), b0);
    let _ = memory.write(byte_at(slot, table + 1), u32::from(err));
}

impl Exch {
    /// End-of-scan communication: carry out the exchanges queued in scan `scan` in
    /// order (entries left over from a faulted scan before a reset are dropped).
    #[inline]
    pub fn service(&mut self, memory: &mut Memory, image: &VerifiedImage, scan: u64) {
        if !self.queue.0.is_empty() {
            // Most scans queue nothing: no call, no frame.
            self.serve(memory, image, scan);
        }
    }

    #[inline(never)]
    fn serve(&mut self, memory: &mut Memory, image: &VerifiedImage, scan: u64) {
        let queue = std::mem::take(&mut self.queue.0);
        for q in queue {
            if q.scan != scan {
                continue;
            }
            let err = self.exchange(memory, image, q);
            write_status(memory, q.slot, q.table, false, true, err);
        }
    }

    /// One exchange; returns the error number (0 = none).
    fn exchange(&mut self, memory: &mut Memory, image: &VerifiedImage, q: Queued) -> u8 {
        let area_len = memory.area(q.slot).map_or(0, <[u8]>::len) as u64;
        let word = |k: u32| memory.read(word_at(q.slot, q.table + k)).ok();
        let (Some(send_len), Some(send_at), Some(recv_len), Some(recv_at)) =
            (word(2), word(4), word(6), word(8))
        else {
            return ERR_TABLE;
        };
        if send_len == 0
            || u64::from(send_at) + u64::from(send_len) > area_len
            || u64::from(recv_at) + u64::from(recv_len) > area_len
        {
            return ERR_TABLE;
        }
        let area = memory.area(q.slot).unwrap_or(&[]);
        let mut request = area[send_at as usize..(send_at + send_len) as usize].to_vec();
        let crc = gutta_format::crc16(&request);
        request.extend(crc.to_le_bytes());
        let timeout_ms = image
            .system()
            .and_then(|s| s.ports.get(q.port as usize))
            .map_or(DEFAULT_TIMEOUT_MS, |p| u32::from(p.timeout) * 100);
        let broadcast = request[0] == 0;
        let answer = match self.ports.get_mut(&q.port) {
            Some(port) => port.transact(&request, timeout_ms),
            None => Err(PortError::Timeout),
        };
        if broadcast {
            return 0;
        }
        let answer = match answer {
            Ok(a) => a,
            Err(PortError::Crc) => return ERR_CRC,
            Err(PortError::Timeout) => return ERR_TIMEOUT,
        };
        if answer.len() < 3 {
            return ERR_CRC;
        }
        let (body, crc) = answer.split_at(answer.len() - 2);
        if gutta_format::crc16(body).to_le_bytes() != [crc[0], crc[1]] {
            return ERR_CRC;
        }
        if body.len() > recv_len as usize {
            return ERR_SHORT_BUFFER;
        }
        if let Some(m) = memory.area_mut(q.slot) {
            m[recv_at as usize..recv_at as usize + body.len()].copy_from_slice(body);
        }
        0
    }
}
