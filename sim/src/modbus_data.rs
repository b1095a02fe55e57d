//! Standard Modbus data functions on a simulated PLC's memory: 01 read coils (Q), 02
//! read discrete inputs (I), 03 read holding registers (AQ, M, V, T, C, HC, SM, J), 04
//! read input registers (AI), 05 write single coil, 06 write single register, 15 write
//! multiple coils, 16 write multiple registers. The mapping is the target's
//! (ManagerVar.xml `Modbus`/`ModbusStart`, via `MemoryMap::modbus_cell`): a register is
//! the little-endian word at its byte offset, sent high byte first.
//!
//! This is the toolchain's one Modbus slave. `serve` takes a request PDU (function code
//! and data, no station, no CRC or MBAP) and returns the response PDU or the exception
//! PDU; `answer_frame` and `answer_rtu` are a slave at a station on an RTU line (station
//! filter, broadcast, CRC), for EXCH peers and tests. Requests are decoded and answers
//! encoded by gutta-protocol (which checks the Modbus limits); this module does no I/O.
//! Exceptions (Modbus application protocol 1.1b3, 7): 01 an unknown function, 02 an address range not wholly served by the table, 03 a bad
//! quantity, byte count or coil value, or a request of the wrong length.

use gutta_catalog::{Address, ModbusTable};
use gutta_protocol::modbus::{pack_bits, ExceptionCode, ModbusRequest, ModbusResponse};
use gutta_protocol::rtu::{decode_rtu, RtuFrame};
use gutta_vm::Vm;

/// Whether `function` is one `serve` handles.
pub fn is_data_function(function: u8) -> bool {
    matches!(function, 1..=6 | 15 | 16)
}

/// The exception response to `function`.
pub fn exception(function: u8, code: ExceptionCode) -> Vec<u8> {
    gutta_protocol::modbus::exception(function, code)
}

/// Serve one request PDU on `vm`'s memory.
pub fn serve(vm: &mut Vm, pdu: &[u8]) -> Vec<u8> {
    let function = pdu.first().copied().unwrap_or(0);
    let answer = ModbusRequest::decode(pdu)
        .map_err(|e| e.exception_code())
        .and_then(|request| answer(vm, request));
    match answer.and_then(|r| r.encode().map_err(|e| e.exception_code())) {
        Ok(bytes) => bytes,
        Err(code) => exception(function, code),
    }
}

/// A Modbus RTU slave at `station` answering one request frame (station, function
/// code, data; no CRC) from `vm`'s memory. `None` when a slave stays silent: the request
/// is for another station, or it is a broadcast (station 0), which is carried out.
/// The answer carries the slave's station and is the response or the exception PDU.
pub fn answer_frame(vm: &mut Vm, station: u8, request: &RtuFrame) -> Option<RtuFrame> {
    if request.station != station && request.station != 0 {
        return None;
    }
    let pdu = serve(vm, &request.pdu);
    (request.station != 0).then_some(RtuFrame { station, pdu })
}

/// `answer_frame` for the bytes on the line: a request frame with its CRC in, the answer
/// frame with its CRC out. A frame whose CRC does not check gets no answer either.
pub fn answer_rtu(vm: &mut Vm, station: u8, frame: &[u8]) -> Option<Vec<u8>> {
    let request = decode_rtu(frame).ok()?;
    answer_frame(vm, station, &request).map(|answer| answer.encode())
}

fn answer(vm: &mut Vm, request: ModbusRequest) -> Result<ModbusResponse, ExceptionCode> {
    use ModbusRequest as Q;
    use ModbusResponse as A;
    Ok(match request {
        Q::ReadCoils { address, quantity } => {
            A::ReadCoils(read_bits(vm, ModbusTable::Coil, address, quantity)?)
        }
        Q::ReadDiscreteInputs { address, quantity } => A::ReadDiscreteInputs(read_bits(
            vm,
            ModbusTable::DiscreteInput,
            address,
            quantity,
        )?),
        Q::ReadHoldingRegisters { address, quantity } => A::ReadHoldingRegisters(read_registers(
            vm,
            ModbusTable::HoldingRegister,
            address,
            quantity,
        )?),
        Q::ReadInputRegisters { address, quantity } => A::ReadInputRegisters(read_registers(
            vm,
            ModbusTable::InputRegister,
            address,
            quantity,
        )?),
        Q::WriteSingleCoil { address, value } => {
            let a = cells(vm, ModbusTable::Coil, address, 1)?[0];
            write_value(vm, a, u32::from(value))?;
            A::WriteSingleCoil { address, value }
        }
        Q::WriteSingleRegister { address, value } => {
            let a = cells(vm, ModbusTable::HoldingRegister, address, 1)?[0];
            write_value(vm, a, u32::from(value))?;
            A::WriteSingleRegister { address, value }
        }
        // Multiple writes write nothing unless every object is served.
        Q::WriteMultipleCoils { address, values } => {
            let quantity = values.len() as u16;
            let addresses = cells(vm, ModbusTable::Coil, address, quantity)?;
            for (a, v) in addresses.into_iter().zip(values) {
                write_value(vm, a, u32::from(v))?;
            }
            A::WriteMultipleCoils { address, quantity }
        }
        Q::WriteMultipleRegisters { address, values } => {
            let quantity = values.len() as u16;
            let addresses = cells(vm, ModbusTable::HoldingRegister, address, quantity)?;
            for (a, v) in addresses.into_iter().zip(values) {
                write_value(vm, a, u32::from(v))?;
            }
            A::WriteMultipleRegisters { address, quantity }
        }
    })
}

/// The addresses behind `count` objects from `first`, or exception 02.
fn cells(
    vm: &Vm,
    table: ModbusTable,
    first: u16,
    count: u16,
) -> Result<Vec<Address>, ExceptionCode> {
    (0..count)
        .map(|k| {
            first
                .checked_add(k)
                .and_then(|wire| vm.target().memory.modbus_cell(table, wire))
                .map(|c| c.address())
                .ok_or(ExceptionCode::IllegalDataAddress)
        })
        .collect()
}

fn read_value(vm: &Vm, a: Address) -> Result<u32, ExceptionCode> {
    vm.read(a).map_err(|_| ExceptionCode::IllegalDataAddress)
}

fn write_value(vm: &mut Vm, a: Address, v: u32) -> Result<(), ExceptionCode> {
    vm.write(a, v)
        .map_err(|_| ExceptionCode::IllegalDataAddress)
}

/// 01 / 02: the bits, packed LSB first.
fn read_bits(
    vm: &Vm,
    table: ModbusTable,
    first: u16,
    count: u16,
) -> Result<Vec<u8>, ExceptionCode> {
    let bits = cells(vm, table, first, count)?
        .into_iter()
        .map(|a| read_value(vm, a).map(|v| v == 1))
        .collect::<Result<Vec<bool>, _>>()?;
    Ok(pack_bits(&bits))
}

/// 03 / 04: each register is the little-endian word at its offset.
fn read_registers(
    vm: &Vm,
    table: ModbusTable,
    first: u16,
    count: u16,
) -> Result<Vec<u16>, ExceptionCode> {
    cells(vm, table, first, count)?
        .into_iter()
        .map(|a| read_value(vm, a).map(|v| v as u16))
        .collect()
}
