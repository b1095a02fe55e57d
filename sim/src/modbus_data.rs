//! Standard Modbus data functions on a simulated PLC's memory: 01 read coils (Q), 02
//! read discrete inputs (I), 03 read holding registers (AQ, M, V, T, C, HC, SM, J), 04
//! read input registers (AI), 05 write single coil, 06 write single register, 15 write
//! multiple coils, 16 write multiple registers. The mapping is the target's
//! (ManagerVar.xml `Modbus`/`ModbusStart`, via `MemoryMap::modbus_cell`): a register is
//! the little-endian word at its byte offset, sent high byte first.
//!
//! `serve` takes a request PDU (function code and data, no station, no CRC or MBAP) and
//! returns the response PDU. Exceptions (Modbus application protocol 1.1b3, 7): 01 an
//! unknown function, 02 an address range not wholly served by the table, 03 a bad
//! quantity, byte count or coil value, or a request of the wrong length.

use gutta_catalog::{Address, ModbusTable};
use gutta_vm::Vm;

/// Modbus exception codes.
pub const ILLEGAL_FUNCTION: u8 = 0x01;
pub const ILLEGAL_DATA_ADDRESS: u8 = 0x02;
pub const ILLEGAL_DATA_VALUE: u8 = 0x03;

/// The exception response to `function`.
pub fn exception(function: u8, code: u8) -> Vec<u8> {
    vec![function | 0x80, code]
}

/// Whether `function` is one `serve` handles.
pub fn is_data_function(function: u8) -> bool {
    matches!(function, 1..=6 | 15 | 16)
}

fn word(data: &[u8], at: usize) -> Option<u16> {
    Some(u16::from_be_bytes([*data.get(at)?, *data.get(at + 1)?]))
}

/// Serve one request PDU on `vm`'s memory.
pub fn serve(vm: &mut Vm, pdu: &[u8]) -> Vec<u8> {
    let Some((&function, data)) = pdu.split_first() else {
        return exception(0, ILLEGAL_FUNCTION);
    };
    let result = match function {
        1 => read_bits(vm, ModbusTable::Coil, data),
        2 => read_bits(vm, ModbusTable::DiscreteInput, data),
        3 => read_registers(vm, ModbusTable::HoldingRegister, data),
        4 => read_registers(vm, ModbusTable::InputRegister, data),
        5 => write_coil(vm, data),
        6 => write_register(vm, data),
        15 => write_coils(vm, data),
        16 => write_registers(vm, data),
        _ => Err(ILLEGAL_FUNCTION),
    };
    match result {
        Ok(body) => {
            let mut out = Vec::with_capacity(body.len() + 1);
            out.push(function);
            out.extend(body);
            out
        }
        Err(code) => exception(function, code),
    }
}

/// The addresses behind `count` objects from `first`, or exception 02.
fn cells(vm: &Vm, table: ModbusTable, first: u16, count: u16) -> Result<Vec<Address>, u8> {
    (0..count)
        .map(|k| {
            first
                .checked_add(k)
                .and_then(|wire| vm.target().memory.modbus_cell(table, wire))
                .map(|c| c.address())
                .ok_or(ILLEGAL_DATA_ADDRESS)
        })
        .collect()
}

fn read_value(vm: &Vm, a: Address) -> Result<u32, u8> {
    vm.read(a).map_err(|_| ILLEGAL_DATA_ADDRESS)
}

/// 01 / 02: start, quantity 1..2000; answer byte count and the bits, LSB first.
fn read_bits(vm: &Vm, table: ModbusTable, data: &[u8]) -> Result<Vec<u8>, u8> {
    let (Some(first), Some(count), 4) = (word(data, 0), word(data, 2), data.len()) else {
        return Err(ILLEGAL_DATA_VALUE);
    };
    if !(1..=2000).contains(&count) {
        return Err(ILLEGAL_DATA_VALUE);
    }
    let addresses = cells(vm, table, first, count)?;
    let mut bytes = vec![0u8; addresses.len().div_ceil(8)];
    for (k, a) in addresses.iter().enumerate() {
        if read_value(vm, *a)? == 1 {
            bytes[k / 8] |= 1 << (k % 8);
        }
    }
    let mut out = vec![bytes.len() as u8];
    out.extend(bytes);
    Ok(out)
}

/// 03 / 04: start, quantity 1..125; answer byte count and the registers, high byte
/// first.
fn read_registers(vm: &Vm, table: ModbusTable, data: &[u8]) -> Result<Vec<u8>, u8> {
    let (Some(first), Some(count), 4) = (word(data, 0), word(data, 2), data.len()) else {
        return Err(ILLEGAL_DATA_VALUE);
    };
    if !(1..=125).contains(&count) {
        return Err(ILLEGAL_DATA_VALUE);
    }
    let addresses = cells(vm, table, first, count)?;
    let mut out = vec![(count * 2) as u8];
    for a in addresses {
        out.extend((read_value(vm, a)? as u16).to_be_bytes());
    }
    Ok(out)
}

fn write_value(vm: &mut Vm, a: Address, v: u32) -> Result<(), u8> {
    vm.write(a, v).map_err(|_| ILLEGAL_DATA_ADDRESS)
}

/// 05: address, FF00 (on) or 0000 (off); the answer echoes the request.
fn write_coil(vm: &mut Vm, data: &[u8]) -> Result<Vec<u8>, u8> {
    let (Some(wire), Some(value), 4) = (word(data, 0), word(data, 2), data.len()) else {
        return Err(ILLEGAL_DATA_VALUE);
    };
    let on = match value {
        0xFF00 => 1,
        0x0000 => 0,
        _ => return Err(ILLEGAL_DATA_VALUE),
    };
    let a = cells(vm, ModbusTable::Coil, wire, 1)?[0];
    write_value(vm, a, on)?;
    Ok(data.to_vec())
}

/// 06: address, value; the answer echoes the request.
fn write_register(vm: &mut Vm, data: &[u8]) -> Result<Vec<u8>, u8> {
    let (Some(wire), Some(value), 4) = (word(data, 0), word(data, 2), data.len()) else {
        return Err(ILLEGAL_DATA_VALUE);
    };
    let a = cells(vm, ModbusTable::HoldingRegister, wire, 1)?[0];
    write_value(vm, a, u32::from(value))?;
    Ok(data.to_vec())
}

/// 15: start, quantity 1..1968, byte count, bits LSB first; the answer is start and
/// quantity. Nothing is written unless every coil is served.
fn write_coils(vm: &mut Vm, data: &[u8]) -> Result<Vec<u8>, u8> {
    let (Some(first), Some(count), Some(&n)) = (word(data, 0), word(data, 2), data.get(4)) else {
        return Err(ILLEGAL_DATA_VALUE);
    };
    let bits = &data[5..];
    if !(1..=1968).contains(&count)
        || usize::from(n) != usize::from(count).div_ceil(8)
        || bits.len() != usize::from(n)
    {
        return Err(ILLEGAL_DATA_VALUE);
    }
    let addresses = cells(vm, ModbusTable::Coil, first, count)?;
    for (k, a) in addresses.into_iter().enumerate() {
        write_value(vm, a, u32::from((bits[k / 8] >> (k % 8)) & 1))?;
    }
    Ok(data[..4].to_vec())
}

/// 16: start, quantity 1..123, byte count, registers high byte first; the answer is
/// start and quantity. Nothing is written unless every register is served.
fn write_registers(vm: &mut Vm, data: &[u8]) -> Result<Vec<u8>, u8> {
    let (Some(first), Some(count), Some(&n)) = (word(data, 0), word(data, 2), data.get(4)) else {
        return Err(ILLEGAL_DATA_VALUE);
    };
    let values = &data[5..];
    if !(1..=123).contains(&count)
        || usize::from(n) != usize::from(count) * 2
        || values.len() != usize::from(n)
    {
        return Err(ILLEGAL_DATA_VALUE);
    }
    let addresses = cells(vm, ModbusTable::HoldingRegister, first, count)?;
    for (k, a) in addresses.into_iter().enumerate() {
        let v = u16::from_be_bytes([values[2 * k], values[2 * k + 1]]);
        write_value(vm, a, u32::from(v))?;
    }
    Ok(data[..4].to_vec())
}
