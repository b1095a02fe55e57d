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
//! `VmSlave` is an in-process Modbus RTU slave answering from a second VM's memory,
//! for tests and simulation.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};

use gutta_catalog::{AreaKind, ModbusTable, Width};

use crate::{Fault, Location, Vm};

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

/// Queued exchanges and attached ports.
#[derive(Debug, Default)]
pub struct ExchState {
    pub queue: Vec<Queued>,
    pub ports: BTreeMap<u8, Box<dyn SerialPort>>,
}

impl ExchState {
    /// Whether the table at `slot`/`table` is queued.
    pub fn is_queued(&self, slot: u8, table: u32) -> bool {
        self.queue
            .iter()
            .any(|q| q.slot == slot && q.table == table)
    }
}

impl crate::Vm {
    /// Connect a device to serial port `port` (replacing any previous one).
    pub fn attach_port(&mut self, port: u8, p: Box<dyn SerialPort>) {
        self.exch.ports.insert(port, p);
    }

    /// Disconnect serial port `port`; its exchanges then time out.
    pub fn detach_port(&mut self, port: u8) -> Option<Box<dyn SerialPort>> {
        self.exch.ports.remove(&port)
    }

    /// Exchanges waiting in the EXCH queue.
    pub fn exch_queue(&self) -> &[Queued] {
        &self.exch.queue
    }
}

fn byte_at(slot: u8, offset: u32) -> Location {
    Location {
        slot,
        offset,
        width: Width::Byte,
        bit: 0,
    }
}

fn word_at(slot: u8, offset: u32) -> Location {
    Location {
        slot,
        offset,
        width: Width::Word,
        bit: 0,
    }
}

/// The M area's slot.
pub(crate) fn m_slot(vm: &Vm) -> Option<u8> {
    vm.target
        .memory
        .area_of_kind(AreaKind::Memory)
        .map(|a| a.slot)
}

/// Write byte 0 (A/D/E, keeping bits 3..7) and byte 1 of a table.
pub(crate) fn write_status(vm: &mut Vm, slot: u8, table: u32, a: bool, d: bool, err: u8) {
    let old = vm.memory.read(byte_at(slot, table)).unwrap_or(0);
    let e = err != 0;
    let b0 = (old & !0x07) | u32::from(a) | (u32::from(d) << 1) | (u32::from(e) << 2);
    let _ = vm.memory.write(byte_at(slot, table), b0);
    let _ = vm.memory.write(byte_at(slot, table + 1), u32::from(err));
}

/// End-of-scan communication: carry out queued exchanges in order.
pub(crate) fn service(vm: &mut Vm) -> Result<(), Fault> {
    let queue = std::mem::take(&mut vm.exch.queue);
    for q in queue {
        if q.scan != vm.scans {
            continue; // left over from a faulted scan before a reset
        }
        let err = exchange(vm, q);
        write_status(vm, q.slot, q.table, false, true, err);
    }
    Ok(())
}

/// One exchange; returns the error number (0 = none).
fn exchange(vm: &mut Vm, q: Queued) -> u8 {
    let area_len = vm.memory.area(q.slot).map_or(0, <[u8]>::len) as u64;
    let word = |vm: &Vm, k: u32| vm.memory.read(word_at(q.slot, q.table + k)).ok();
    let (Some(send_len), Some(send_at), Some(recv_len), Some(recv_at)) =
        (word(vm, 2), word(vm, 4), word(vm, 6), word(vm, 8))
    else {
        return ERR_TABLE;
    };
    if send_len == 0
        || u64::from(send_at) + u64::from(send_len) > area_len
        || u64::from(recv_at) + u64::from(recv_len) > area_len
    {
        return ERR_TABLE;
    }
    let area = vm.memory.area(q.slot).unwrap_or(&[]);
    let mut request = area[send_at as usize..(send_at + send_len) as usize].to_vec();
    let crc = gutta_format::crc16(&request);
    request.extend(crc.to_le_bytes());
    let timeout_ms = vm
        .image
        .system()
        .and_then(|s| s.ports.get(q.port as usize))
        .map_or(DEFAULT_TIMEOUT_MS, |p| u32::from(p.timeout) * 100);
    let broadcast = request[0] == 0;
    let answer = match vm.exch.ports.get_mut(&q.port) {
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
    if let Some(m) = vm.memory.area_mut(q.slot) {
        m[recv_at as usize..recv_at as usize + body.len()].copy_from_slice(body);
    }
    0
}

// ---- an in-process slave ------------------------------------------------------------

/// A Modbus RTU slave answering from another VM's memory (functions 01, 02, 03, 04,
/// 05, 06, 15, 16), as the PLC's own slave protocol does (GUTTA.md section 5): wire
/// addresses are 0-based and mapped by the target's Modbus table; registers are the
/// little-endian word at their offset, sent high byte first; reading or writing past
/// an area answers exception 02, a bad quantity or value exception 03, an unknown
/// function exception 01. A request with a bad CRC or for another station gets no
/// answer; a broadcast (station 0) is carried out without an answer.
#[derive(Debug, Clone)]
pub struct VmSlave {
    vm: Arc<Mutex<Vm>>,
    station: u8,
}

impl VmSlave {
    pub fn new(vm: Arc<Mutex<Vm>>, station: u8) -> VmSlave {
        VmSlave { vm, station }
    }

    /// The slave's VM (shared: the host scans it too).
    pub fn vm(&self) -> &Arc<Mutex<Vm>> {
        &self.vm
    }

    /// The answer to a request without CRC (`None`: no answer).
    pub fn answer(&self, pdu: &[u8]) -> Option<Vec<u8>> {
        let (&station, rest) = pdu.split_first()?;
        if station != 0 && station != self.station {
            return None;
        }
        let mut vm = self.vm.lock().unwrap_or_else(|e| e.into_inner());
        let body = match serve(&mut vm, rest) {
            Ok(b) => b,
            Err(code) => vec![rest.first().copied().unwrap_or(0) | 0x80, code],
        };
        if station == 0 {
            return None;
        }
        let mut out = vec![station];
        out.extend(body);
        Some(out)
    }
}

impl SerialPort for VmSlave {
    fn transact(&mut self, request: &[u8], _timeout_ms: u32) -> Result<Vec<u8>, PortError> {
        if request.len() < 4 {
            return Err(PortError::Timeout);
        }
        let (pdu, crc) = request.split_at(request.len() - 2);
        if gutta_format::crc16(pdu).to_le_bytes() != [crc[0], crc[1]] {
            return Err(PortError::Timeout);
        }
        let mut out = self.answer(pdu).ok_or(PortError::Timeout)?;
        let crc = gutta_format::crc16(&out);
        out.extend(crc.to_le_bytes());
        Ok(out)
    }
}

const ILLEGAL_FUNCTION: u8 = 1;
const ILLEGAL_ADDRESS: u8 = 2;
const ILLEGAL_VALUE: u8 = 3;

fn be16(b: &[u8], at: usize) -> Result<u16, u8> {
    match (b.get(at), b.get(at + 1)) {
        (Some(h), Some(l)) => Ok(u16::from_be_bytes([*h, *l])),
        _ => Err(ILLEGAL_VALUE),
    }
}

/// The location of object `start + i` of `table`.
fn cell(vm: &Vm, table: ModbusTable, start: u16, i: u16) -> Result<Location, u8> {
    let wire = start.checked_add(i).ok_or(ILLEGAL_ADDRESS)?;
    let c = vm
        .target
        .memory
        .modbus_cell(table, wire)
        .ok_or(ILLEGAL_ADDRESS)?;
    Ok(match c.bit {
        Some(bit) => Location {
            slot: c.slot,
            offset: c.offset,
            width: Width::Bit,
            bit,
        },
        None => word_at(c.slot, c.offset),
    })
}

/// Function code and data -> answer without station (Err: exception code).
fn serve(vm: &mut Vm, pdu: &[u8]) -> Result<Vec<u8>, u8> {
    let function = *pdu.first().ok_or(ILLEGAL_FUNCTION)?;
    let start = be16(pdu, 1)?;
    let mut out = vec![function];
    match function {
        1 | 2 => {
            let table = if function == 1 {
                ModbusTable::Coil
            } else {
                ModbusTable::DiscreteInput
            };
            let n = be16(pdu, 3)?;
            if !(1..=2000).contains(&n) {
                return Err(ILLEGAL_VALUE);
            }
            let mut data = vec![0u8; n.div_ceil(8) as usize];
            for i in 0..n {
                let loc = cell(vm, table, start, i)?;
                if vm.memory.read(loc).map_err(|_| ILLEGAL_ADDRESS)? & 1 == 1 {
                    data[(i / 8) as usize] |= 1 << (i % 8);
                }
            }
            out.push(data.len() as u8);
            out.extend(data);
        }
        3 | 4 => {
            let table = if function == 3 {
                ModbusTable::HoldingRegister
            } else {
                ModbusTable::InputRegister
            };
            let n = be16(pdu, 3)?;
            if !(1..=125).contains(&n) {
                return Err(ILLEGAL_VALUE);
            }
            out.push((n * 2) as u8);
            for i in 0..n {
                let loc = cell(vm, table, start, i)?;
                let v = vm.memory.read(loc).map_err(|_| ILLEGAL_ADDRESS)? as u16;
                out.extend(v.to_be_bytes());
            }
        }
        5 => {
            let v = match be16(pdu, 3)? {
                0xFF00 => 1,
                0x0000 => 0,
                _ => return Err(ILLEGAL_VALUE),
            };
            let loc = cell(vm, ModbusTable::Coil, start, 0)?;
            vm.memory.write(loc, v).map_err(|_| ILLEGAL_ADDRESS)?;
            out.extend(&pdu[1..5]);
        }
        6 => {
            let v = be16(pdu, 3)?;
            let loc = cell(vm, ModbusTable::HoldingRegister, start, 0)?;
            vm.memory
                .write(loc, u32::from(v))
                .map_err(|_| ILLEGAL_ADDRESS)?;
            out.extend(&pdu[1..5]);
        }
        15 | 16 => {
            let n = be16(pdu, 3)?;
            let count = *pdu.get(5).ok_or(ILLEGAL_VALUE)? as usize;
            let data = pdu.get(6..6 + count).ok_or(ILLEGAL_VALUE)?;
            let (table, max, need) = if function == 15 {
                (ModbusTable::Coil, 1968, n.div_ceil(8) as usize)
            } else {
                (ModbusTable::HoldingRegister, 123, n as usize * 2)
            };
            if !(1..=max).contains(&n) || count != need {
                return Err(ILLEGAL_VALUE);
            }
            // Check every address before writing any.
            let cells = (0..n)
                .map(|i| cell(vm, table, start, i))
                .collect::<Result<Vec<_>, u8>>()?;
            for (i, loc) in cells.into_iter().enumerate() {
                let v = if function == 15 {
                    u32::from((data[i / 8] >> (i % 8)) & 1)
                } else {
                    u32::from(be16(data, 2 * i)?)
                };
                vm.memory.write(loc, v).map_err(|_| ILLEGAL_ADDRESS)?;
            }
            out.extend(&pdu[1..5]);
        }
        _ => return Err(ILLEGAL_FUNCTION),
    }
    Ok(out)
}
