//! Standard Modbus data functions on a simulated PLC's memory (the rows of
//! gutta-protocol's `modbus_registry` answered by the slave): 01 read coils (Q), 02
//! read discrete inputs (I), 03 read holding registers (AQ, M, V, T, C, HC, SM, J), 04
//! read input registers (AI), 05 write single coil, 06 write single register, 15 write
//! multiple coils, 16 write multiple registers. The mapping is the target's
//! (ManagerVar.xml `Modbus`/`ModbusStart`, via `MemoryMap::modbus_cell`): a register is
//! the little-endian word at its byte offset, sent high byte first.
//!
//! This is the toolchain's one Modbus slave. It serves any [`ModbusObjects`]: the VM's
//! memory through the target's mapping (`impl ModbusObjects for Vm`), or another
//! simulated device's objects (the relay board's coils, `relay.rs`). `serve` (on a VM;
//! `serve_objects` on any `ModbusObjects`) takes a request PDU (function code and data,
//! no station, no CRC or MBAP) and returns the response PDU or the exception PDU; `answer_frame` and `answer_rtu` are a slave at a station on an RTU line (station
//! filter, broadcast, CRC), for EXCH peers and tests. Requests are decoded and answers
//! encoded by gutta-protocol (which checks the Modbus limits); this module does no I/O.
//! Exceptions (Modbus application protocol 1.1b3, 7): 01 an unknown function, 02 an address range not wholly served by the table, 03 a bad
//! quantity, byte count or coil value, or a request of the wrong length.

use gutta_catalog::{Address, ModbusTable};
use gutta_protocol::modbus::{pack_bits, ExceptionCode, ModbusRequest, ModbusResponse};
use gutta_protocol::modbus_registry;
use gutta_protocol::rtu::{decode_rtu, RtuFrame};
use gutta_vm::Vm;

/// Whether `function` is one `serve` handles: its row in gutta-protocol's
/// `modbus_registry` says the Modbus slave answers it (01-06, 15, 16).
pub fn is_data_function(function: u8) -> bool {
    modbus_registry::is_data_function(function)
}

/// The objects a Modbus slave serves: which functions it takes, which objects exist,
/// and their values (a bit is 0 or 1, a register 16 bits). `serve` checks every object
/// of a request with `serves` before it reads or writes any.
pub trait ModbusObjects {
    /// Whether the slave takes `function` (one of `is_data_function`'s); others answer
    /// exception 01.
    fn supports(&self, function: u8) -> bool {
        is_data_function(function)
    }
    /// Whether object `wire` of `table` exists.
    fn serves(&self, table: ModbusTable, wire: u16) -> bool;
    /// The value of a served object.
    fn read_object(&self, table: ModbusTable, wire: u16) -> Result<u32, ExceptionCode>;
    /// Sets a served object.
    fn write_object(
        &mut self,
        table: ModbusTable,
        wire: u16,
        value: u32,
    ) -> Result<(), ExceptionCode>;
}

/// The PLC: every function, objects through the target's mapping onto the VM's memory.
impl ModbusObjects for Vm {
    fn serves(&self, table: ModbusTable, wire: u16) -> bool {
        self.target().memory.modbus_cell(table, wire).is_some()
    }

    fn read_object(&self, table: ModbusTable, wire: u16) -> Result<u32, ExceptionCode> {
        let a = cell(self, table, wire)?;
        self.read(a).map_err(|_| ExceptionCode::IllegalDataAddress)
    }

    fn write_object(
        &mut self,
        table: ModbusTable,
        wire: u16,
        value: u32,
    ) -> Result<(), ExceptionCode> {
        let a = cell(self, table, wire)?;
        self.write(a, value)
            .map_err(|_| ExceptionCode::IllegalDataAddress)
    }
}

fn cell(vm: &Vm, table: ModbusTable, wire: u16) -> Result<Address, ExceptionCode> {
    vm.target()
        .memory
        .modbus_cell(table, wire)
        .map(|c| c.address())
        .ok_or(ExceptionCode::IllegalDataAddress)
}

/// The exception response to `function`.
pub fn exception(function: u8, code: ExceptionCode) -> Vec<u8> {
    gutta_protocol::modbus::exception(function, code)
}

/// Serve one request PDU on `vm`'s memory.
pub fn serve(vm: &mut Vm, pdu: &[u8]) -> Vec<u8> {
    serve_objects(vm, pdu)
}

/// Serve one request PDU on any slave's objects (a `Vm`'s memory, or another device's).
pub fn serve_objects<O: ModbusObjects + ?Sized>(vm: &mut O, pdu: &[u8]) -> Vec<u8> {
    let function = pdu.first().copied().unwrap_or(0);
    if !vm.supports(function) {
        return exception(function, ExceptionCode::IllegalFunction);
    }
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

fn answer<O: ModbusObjects + ?Sized>(
    vm: &mut O,
    request: ModbusRequest,
) -> Result<ModbusResponse, ExceptionCode> {
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
            let w = cells(vm, ModbusTable::Coil, address, 1)?[0];
            vm.write_object(ModbusTable::Coil, w, u32::from(value))?;
            A::WriteSingleCoil { address, value }
        }
        Q::WriteSingleRegister { address, value } => {
            let w = cells(vm, ModbusTable::HoldingRegister, address, 1)?[0];
            vm.write_object(ModbusTable::HoldingRegister, w, u32::from(value))?;
            A::WriteSingleRegister { address, value }
        }
        // Multiple writes write nothing unless every object is served.
        Q::WriteMultipleCoils { address, values } => {
            let quantity = values.len() as u16;
            let objects = cells(vm, ModbusTable::Coil, address, quantity)?;
            for (w, v) in objects.into_iter().zip(values) {
                vm.write_object(ModbusTable::Coil, w, u32::from(v))?;
            }
            A::WriteMultipleCoils { address, quantity }
        }
        Q::WriteMultipleRegisters { address, values } => {
            let quantity = values.len() as u16;
            let objects = cells(vm, ModbusTable::HoldingRegister, address, quantity)?;
            for (w, v) in objects.into_iter().zip(values) {
                vm.write_object(ModbusTable::HoldingRegister, w, u32::from(v))?;
            }
            A::WriteMultipleRegisters { address, quantity }
        }
    })
}

/// Objects `first..first + count` of `table`, each checked with `serves`, or exception 02.
fn cells<O: ModbusObjects + ?Sized>(
    vm: &O,
    table: ModbusTable,
    first: u16,
    count: u16,
) -> Result<Vec<u16>, ExceptionCode> {
    (0..count)
        .map(|k| {
            first
                .checked_add(k)
                .filter(|&wire| vm.serves(table, wire))
                .ok_or(ExceptionCode::IllegalDataAddress)
        })
        .collect()
}

/// 01 / 02: the bits, packed LSB first.
fn read_bits<O: ModbusObjects + ?Sized>(
    vm: &O,
    table: ModbusTable,
    first: u16,
    count: u16,
) -> Result<Vec<u8>, ExceptionCode> {
    let bits = cells(vm, table, first, count)?
        .into_iter()
        .map(|w| vm.read_object(table, w).map(|v| v == 1))
        .collect::<Result<Vec<bool>, _>>()?;
    Ok(pack_bits(&bits))
}

/// 03 / 04: each register is the little-endian word at its offset.
fn read_registers<O: ModbusObjects + ?Sized>(
    vm: &O,
    table: ModbusTable,
    first: u16,
    count: u16,
) -> Result<Vec<u16>, ExceptionCode> {
    cells(vm, table, first, count)?
        .into_iter()
        .map(|w| vm.read_object(table, w).map(|v| v as u16))
        .collect()
}
