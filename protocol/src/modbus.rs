//! Standard Modbus PDUs the GUTTA PLC serves (AN2002): 01-06, 15, 16, and exception
//! responses. Encode/decode with the quantity limits of the Modbus specification; every
//! decode error maps to the exception code a slave answers. PDUs only: no station, no
//! CRC, no I/O.

use std::fmt;

pub const READ_COILS: u8 = 0x01;
pub const READ_DISCRETE_INPUTS: u8 = 0x02;
pub const READ_HOLDING_REGISTERS: u8 = 0x03;
pub const READ_INPUT_REGISTERS: u8 = 0x04;
pub const WRITE_SINGLE_COIL: u8 = 0x05;
pub const WRITE_SINGLE_REGISTER: u8 = 0x06;
pub const WRITE_MULTIPLE_COILS: u8 = 0x0F;
pub const WRITE_MULTIPLE_REGISTERS: u8 = 0x10;

/// Bit 7 of the function code in an exception response.
pub const EXCEPTION_BIT: u8 = 0x80;

/// Quantity limits of the Modbus application protocol specification.
pub const MAX_READ_BITS: u16 = 2000;
pub const MAX_READ_REGISTERS: u16 = 125;
pub const MAX_WRITE_BITS: u16 = 1968;
pub const MAX_WRITE_REGISTERS: u16 = 123;

/// Coil values of function 05.
pub const COIL_ON: u16 = 0xFF00;
pub const COIL_OFF: u16 = 0x0000;

/// Exception codes a GUTTA slave uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ExceptionCode {
    /// 01: function not supported.
    IllegalFunction,
    /// 02: address (or address + quantity) outside the area.
    IllegalDataAddress,
    /// 03: a value in the request is not allowed (quantity, byte count, coil value).
    IllegalDataValue,
    /// 04: Server Device Failure: gutta-sim's answer to a PLC_ATTACH while the login is
    /// locked out after repeated wrong passwords (docs/simulator.md, password policy).
    ServerDeviceFailure,
    /// 06: Server Device Busy, "engaged in processing a long-duration program command;
    /// retransmit later": gutta-sim's answer to a GUTTA request another connection's
    /// download forbids (docs/simulator.md, the download safety rule).
    ServerDeviceBusy,
}

impl ExceptionCode {
    pub fn byte(self) -> u8 {
        match self {
            ExceptionCode::IllegalFunction => 1,
            ExceptionCode::IllegalDataAddress => 2,
            ExceptionCode::IllegalDataValue => 3,
            ExceptionCode::ServerDeviceFailure => 4,
            ExceptionCode::ServerDeviceBusy => 6,
        }
    }
}

/// The exception response PDU `[function | 0x80][code]`.
pub fn exception(function: u8, code: ExceptionCode) -> Vec<u8> {
    vec![function | EXCEPTION_BIT, code.byte()]
}

/// An answer PDU in the exact shape of a Modbus exception, `[function | 0x80][code]`
/// (two bytes, nothing else): the function (without the exception bit) and the code as
/// received. The one reading of that shape: the master's exception event and the
/// client's Modbus TCP answers both go through it.
pub fn exception_of(pdu: &[u8]) -> Option<(u8, u8)> {
    match *pdu {
        [f, code] if f & EXCEPTION_BIT != 0 => Some((f & !EXCEPTION_BIT, code)),
        _ => None,
    }
}

/// Errors of decoding or encoding a Modbus PDU.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ModbusError {
    /// No function code.
    Empty,
    /// A function code not in 01-06/15/16 (for responses: nor an exception of one).
    UnknownFunction { function: u8 },
    /// The PDU length does not fit the function.
    Length {
        function: u8,
        expected: usize,
        found: usize,
    },
    /// Quantity outside the specification's range for this function.
    Quantity {
        function: u8,
        quantity: u16,
        max: u16,
    },
    /// Byte count that does not match the quantity or the data.
    ByteCount { function: u8, count: u8 },
    /// Function 05 value other than FF00 or 0000.
    CoilValue { value: u16 },
    /// Bits above the quantity in the last byte of function 15 are not 0.
    Padding { function: u8 },
    /// Address + quantity beyond 65536.
    AddressOverflow {
        function: u8,
        address: u16,
        quantity: u16,
    },
}

impl ModbusError {
    /// The exception a slave answers to a request that fails to decode with this error.
    pub fn exception_code(&self) -> ExceptionCode {
        match self {
            ModbusError::Empty | ModbusError::UnknownFunction { .. } => {
                ExceptionCode::IllegalFunction
            }
            ModbusError::AddressOverflow { .. } => ExceptionCode::IllegalDataAddress,
            _ => ExceptionCode::IllegalDataValue,
        }
    }
}

impl fmt::Display for ModbusError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ModbusError::Empty => write!(f, "empty Modbus PDU"),
            ModbusError::UnknownFunction { function } => {
                write!(f, "Modbus function {function:02X} is not supported")
            }
            ModbusError::Length { function, expected, found } => write!(
                f,
                "Modbus function {function:02X}: PDU of {found} bytes, expected {expected}"
            ),
            ModbusError::Quantity { function, quantity, max } => write!(
                f,
                "Modbus function {function:02X}: quantity {quantity} outside 1..={max}"
            ),
            ModbusError::ByteCount { function, count } => {
                write!(f, "Modbus function {function:02X}: byte count {count} does not fit")
            }
            ModbusError::CoilValue { value } => {
                write!(f, "coil value {value:04X} is neither FF00 nor 0000")
            }
            ModbusError::Padding { function } => {
                write!(f, "Modbus function {function:02X}: unused bits of the last byte are not 0")
            }
            ModbusError::AddressOverflow { function, address, quantity } => write!(
                f,
                "Modbus function {function:02X}: address {address} + quantity {quantity} passes 65535"
            ),
        }
    }
}

impl std::error::Error for ModbusError {}

/// A request of functions 01-06, 15, 16. Addresses are 0-based, as on the wire.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ModbusRequest {
    ReadCoils { address: u16, quantity: u16 },
    ReadDiscreteInputs { address: u16, quantity: u16 },
    ReadHoldingRegisters { address: u16, quantity: u16 },
    ReadInputRegisters { address: u16, quantity: u16 },
    WriteSingleCoil { address: u16, value: bool },
    WriteSingleRegister { address: u16, value: u16 },
    WriteMultipleCoils { address: u16, values: Vec<bool> },
    WriteMultipleRegisters { address: u16, values: Vec<u16> },
}

impl ModbusRequest {
    pub fn function(&self) -> u8 {
        match self {
            ModbusRequest::ReadCoils { .. } => READ_COILS,
            ModbusRequest::ReadDiscreteInputs { .. } => READ_DISCRETE_INPUTS,
            ModbusRequest::ReadHoldingRegisters { .. } => READ_HOLDING_REGISTERS,
            ModbusRequest::ReadInputRegisters { .. } => READ_INPUT_REGISTERS,
            ModbusRequest::WriteSingleCoil { .. } => WRITE_SINGLE_COIL,
            ModbusRequest::WriteSingleRegister { .. } => WRITE_SINGLE_REGISTER,
            ModbusRequest::WriteMultipleCoils { .. } => WRITE_MULTIPLE_COILS,
            ModbusRequest::WriteMultipleRegisters { .. } => WRITE_MULTIPLE_REGISTERS,
        }
    }

    /// The PDU; checks the same limits as `decode`.
    pub fn encode(&self) -> Result<Vec<u8>, ModbusError> {
        let function = self.function();
        let mut out = vec![function];
        match self {
            ModbusRequest::ReadCoils { address, quantity }
            | ModbusRequest::ReadDiscreteInputs { address, quantity } => {
                check_range(function, *address, *quantity, MAX_READ_BITS)?;
                push_words(&mut out, &[*address, *quantity]);
            }
            ModbusRequest::ReadHoldingRegisters { address, quantity }
            | ModbusRequest::ReadInputRegisters { address, quantity } => {
                check_range(function, *address, *quantity, MAX_READ_REGISTERS)?;
                push_words(&mut out, &[*address, *quantity]);
            }
            ModbusRequest::WriteSingleCoil { address, value } => {
                push_words(
                    &mut out,
                    &[*address, if *value { COIL_ON } else { COIL_OFF }],
                );
            }
            ModbusRequest::WriteSingleRegister { address, value } => {
                push_words(&mut out, &[*address, *value]);
            }
            ModbusRequest::WriteMultipleCoils { address, values } => {
                let quantity = quantity_of(function, values.len(), MAX_WRITE_BITS)?;
                check_range(function, *address, quantity, MAX_WRITE_BITS)?;
                let packed = pack_bits(values);
                push_words(&mut out, &[*address, quantity]);
                out.push(packed.len() as u8);
                out.extend(packed);
            }
            ModbusRequest::WriteMultipleRegisters { address, values } => {
                let quantity = quantity_of(function, values.len(), MAX_WRITE_REGISTERS)?;
                check_range(function, *address, quantity, MAX_WRITE_REGISTERS)?;
                push_words(&mut out, &[*address, quantity]);
                out.push((values.len() * 2) as u8);
                push_words(&mut out, values);
            }
        }
        Ok(out)
    }

    pub fn decode(pdu: &[u8]) -> Result<Self, ModbusError> {
        let (&function, data) = pdu.split_first().ok_or(ModbusError::Empty)?;
        match function {
            READ_COILS | READ_DISCRETE_INPUTS | READ_HOLDING_REGISTERS | READ_INPUT_REGISTERS => {
                let [address, quantity] = fixed_words(function, pdu)?;
                let max = if function <= READ_DISCRETE_INPUTS {
                    MAX_READ_BITS
                } else {
                    MAX_READ_REGISTERS
                };
                check_range(function, address, quantity, max)?;
                Ok(match function {
                    READ_COILS => ModbusRequest::ReadCoils { address, quantity },
                    READ_DISCRETE_INPUTS => ModbusRequest::ReadDiscreteInputs { address, quantity },
                    READ_HOLDING_REGISTERS => {
                        ModbusRequest::ReadHoldingRegisters { address, quantity }
                    }
                    _ => ModbusRequest::ReadInputRegisters { address, quantity },
                })
            }
            WRITE_SINGLE_COIL => {
                let [address, value] = fixed_words(function, pdu)?;
                let value = match value {
                    COIL_ON => true,
                    COIL_OFF => false,
                    value => return Err(ModbusError::CoilValue { value }),
                };
                Ok(ModbusRequest::WriteSingleCoil { address, value })
            }
            WRITE_SINGLE_REGISTER => {
                let [address, value] = fixed_words(function, pdu)?;
                Ok(ModbusRequest::WriteSingleRegister { address, value })
            }
            WRITE_MULTIPLE_COILS | WRITE_MULTIPLE_REGISTERS => {
                if data.len() < 5 {
                    return Err(ModbusError::Length {
                        function,
                        expected: 6,
                        found: pdu.len(),
                    });
                }
                let address = u16::from_be_bytes([data[0], data[1]]);
                let quantity = u16::from_be_bytes([data[2], data[3]]);
                let count = data[4];
                let bytes = &data[5..];
                let (max, expected) = if function == WRITE_MULTIPLE_COILS {
                    (MAX_WRITE_BITS, usize::from(quantity).div_ceil(8))
                } else {
                    (MAX_WRITE_REGISTERS, usize::from(quantity) * 2)
                };
                check_range(function, address, quantity, max)?;
                if usize::from(count) != expected || bytes.len() != expected {
                    return Err(ModbusError::ByteCount { function, count });
                }
                if function == WRITE_MULTIPLE_COILS {
                    let values = unpack_bits(bytes, usize::from(quantity));
                    if pack_bits(&values) != bytes {
                        return Err(ModbusError::Padding { function });
                    }
                    Ok(ModbusRequest::WriteMultipleCoils { address, values })
                } else {
                    let values = bytes
                        .chunks_exact(2)
                        .map(|w| u16::from_be_bytes([w[0], w[1]]))
                        .collect();
                    Ok(ModbusRequest::WriteMultipleRegisters { address, values })
                }
            }
            function => Err(ModbusError::UnknownFunction { function }),
        }
    }
}

/// A response to functions 01-06, 15, 16, or an exception.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ModbusResponse {
    /// Function 01: the coils packed 8 per byte, first coil in bit 0, unused bits 0.
    ReadCoils(Vec<u8>),
    /// Function 02: packed like `ReadCoils`.
    ReadDiscreteInputs(Vec<u8>),
    ReadHoldingRegisters(Vec<u16>),
    ReadInputRegisters(Vec<u16>),
    /// Function 05 echoes the request.
    WriteSingleCoil {
        address: u16,
        value: bool,
    },
    /// Function 06 echoes the request.
    WriteSingleRegister {
        address: u16,
        value: u16,
    },
    WriteMultipleCoils {
        address: u16,
        quantity: u16,
    },
    WriteMultipleRegisters {
        address: u16,
        quantity: u16,
    },
    /// `function` without bit 7; `code` as received (any value).
    Exception {
        function: u8,
        code: u8,
    },
}

impl ModbusResponse {
    pub fn function(&self) -> u8 {
        match self {
            ModbusResponse::ReadCoils(_) => READ_COILS,
            ModbusResponse::ReadDiscreteInputs(_) => READ_DISCRETE_INPUTS,
            ModbusResponse::ReadHoldingRegisters(_) => READ_HOLDING_REGISTERS,
            ModbusResponse::ReadInputRegisters(_) => READ_INPUT_REGISTERS,
            ModbusResponse::WriteSingleCoil { .. } => WRITE_SINGLE_COIL,
            ModbusResponse::WriteSingleRegister { .. } => WRITE_SINGLE_REGISTER,
            ModbusResponse::WriteMultipleCoils { .. } => WRITE_MULTIPLE_COILS,
            ModbusResponse::WriteMultipleRegisters { .. } => WRITE_MULTIPLE_REGISTERS,
            ModbusResponse::Exception { function, .. } => function | EXCEPTION_BIT,
        }
    }

    pub fn encode(&self) -> Result<Vec<u8>, ModbusError> {
        let function = self.function();
        let mut out = vec![function];
        match self {
            ModbusResponse::ReadCoils(packed) | ModbusResponse::ReadDiscreteInputs(packed) => {
                let count = byte_count(
                    function,
                    packed.len(),
                    usize::from(MAX_READ_BITS).div_ceil(8),
                )?;
                out.push(count);
                out.extend_from_slice(packed);
            }
            ModbusResponse::ReadHoldingRegisters(values)
            | ModbusResponse::ReadInputRegisters(values) => {
                let count = byte_count(
                    function,
                    values.len() * 2,
                    usize::from(MAX_READ_REGISTERS) * 2,
                )?;
                out.push(count);
                push_words(&mut out, values);
            }
            ModbusResponse::WriteSingleCoil { address, value } => {
                push_words(
                    &mut out,
                    &[*address, if *value { COIL_ON } else { COIL_OFF }],
                );
            }
            ModbusResponse::WriteSingleRegister { address, value } => {
                push_words(&mut out, &[*address, *value]);
            }
            ModbusResponse::WriteMultipleCoils { address, quantity }
            | ModbusResponse::WriteMultipleRegisters { address, quantity } => {
                push_words(&mut out, &[*address, *quantity]);
            }
            ModbusResponse::Exception { function, code } => {
                if !is_supported(*function) {
                    return Err(ModbusError::UnknownFunction {
                        function: *function,
                    });
                }
                out.push(*code);
            }
        }
        Ok(out)
    }

    /// Decodes a response by its own function code. Register byte counts must be even
    /// and non-zero; bit byte counts non-zero.
    pub fn decode(pdu: &[u8]) -> Result<Self, ModbusError> {
        let (&function, data) = pdu.split_first().ok_or(ModbusError::Empty)?;
        match function {
            READ_COILS..=READ_INPUT_REGISTERS => {
                let (&count, bytes) = data.split_first().ok_or(ModbusError::Length {
                    function,
                    expected: 3,
                    found: pdu.len(),
                })?;
                let registers = function >= READ_HOLDING_REGISTERS;
                let max = if registers {
                    usize::from(MAX_READ_REGISTERS) * 2
                } else {
                    250
                };
                if count == 0 || usize::from(count) > max || (registers && count % 2 != 0) {
                    return Err(ModbusError::ByteCount { function, count });
                }
                if bytes.len() != usize::from(count) {
                    return Err(ModbusError::Length {
                        function,
                        expected: 2 + usize::from(count),
                        found: pdu.len(),
                    });
                }
                let words = || {
                    bytes
                        .chunks_exact(2)
                        .map(|w| u16::from_be_bytes([w[0], w[1]]))
                        .collect()
                };
                Ok(match function {
                    READ_COILS => ModbusResponse::ReadCoils(bytes.to_vec()),
                    READ_DISCRETE_INPUTS => ModbusResponse::ReadDiscreteInputs(bytes.to_vec()),
                    READ_HOLDING_REGISTERS => ModbusResponse::ReadHoldingRegisters(words()),
                    _ => ModbusResponse::ReadInputRegisters(words()),
                })
            }
            WRITE_SINGLE_COIL => match ModbusRequest::decode(pdu)? {
                ModbusRequest::WriteSingleCoil { address, value } => {
                    Ok(ModbusResponse::WriteSingleCoil { address, value })
                }
                _ => Err(ModbusError::UnknownFunction { function }),
            },
            WRITE_SINGLE_REGISTER | WRITE_MULTIPLE_COILS | WRITE_MULTIPLE_REGISTERS => {
                let [address, value] = fixed_words(function, pdu)?;
                Ok(match function {
                    WRITE_SINGLE_REGISTER => ModbusResponse::WriteSingleRegister { address, value },
                    WRITE_MULTIPLE_COILS => ModbusResponse::WriteMultipleCoils {
                        address,
                        quantity: value,
                    },
                    _ => ModbusResponse::WriteMultipleRegisters {
                        address,
                        quantity: value,
                    },
                })
            }
            f if f & EXCEPTION_BIT != 0 && is_supported(f & !EXCEPTION_BIT) => match data {
                [code] => Ok(ModbusResponse::Exception {
                    function: f & !EXCEPTION_BIT,
                    code: *code,
                }),
                _ => Err(ModbusError::Length {
                    function,
                    expected: 2,
                    found: pdu.len(),
                }),
            },
            function => Err(ModbusError::UnknownFunction { function }),
        }
    }
}

/// Packs bits 8 per byte, first bit in bit 0 of the first byte, unused high bits 0.
pub fn pack_bits(bits: &[bool]) -> Vec<u8> {
    bits.chunks(8)
        .map(|chunk| {
            chunk
                .iter()
                .enumerate()
                .fold(0u8, |byte, (i, &b)| byte | (u8::from(b) << i))
        })
        .collect()
}

/// The first `quantity` bits of packed bytes (fewer if the bytes run out).
pub fn unpack_bits(bytes: &[u8], quantity: usize) -> Vec<bool> {
    (0..quantity.min(bytes.len() * 8))
        .map(|i| bytes[i / 8] & (1 << (i % 8)) != 0)
        .collect()
}

/// The data functions (`modbus_registry`'s rows the Modbus slave serves).
fn is_supported(function: u8) -> bool {
    crate::modbus_registry::is_data_function(function)
}

fn push_words(out: &mut Vec<u8>, words: &[u16]) {
    for w in words {
        out.extend_from_slice(&w.to_be_bytes());
    }
}

/// A 5-byte PDU `function, word, word`.
fn fixed_words(function: u8, pdu: &[u8]) -> Result<[u16; 2], ModbusError> {
    match pdu {
        [_, a, b, c, d] => Ok([u16::from_be_bytes([*a, *b]), u16::from_be_bytes([*c, *d])]),
        _ => Err(ModbusError::Length {
            function,
            expected: 5,
            found: pdu.len(),
        }),
    }
}

fn check_range(function: u8, address: u16, quantity: u16, max: u16) -> Result<(), ModbusError> {
    if quantity == 0 || quantity > max {
        return Err(ModbusError::Quantity {
            function,
            quantity,
            max,
        });
    }
    if u32::from(address) + u32::from(quantity) > 0x1_0000 {
        return Err(ModbusError::AddressOverflow {
            function,
            address,
            quantity,
        });
    }
    Ok(())
}

fn quantity_of(function: u8, len: usize, max: u16) -> Result<u16, ModbusError> {
    u16::try_from(len)
        .ok()
        .filter(|q| (1..=max).contains(q))
        .ok_or(ModbusError::Quantity {
            function,
            quantity: len.min(usize::from(u16::MAX)) as u16,
            max,
        })
}

fn byte_count(function: u8, len: usize, max: usize) -> Result<u8, ModbusError> {
    if len == 0 || len > max {
        return Err(ModbusError::ByteCount {
            function,
            count: len.min(255) as u8,
        });
    }
    Ok(len as u8)
}
