//! The registry of Modbus function codes: one row per function code the toolchain
//! frames, like `registry.rs` for the UM4001 functions. A row says the code, the name,
//! the shapes of its request and answer PDUs (enough to tell an RTU frame's length from
//! its first bytes on either side of the line), who answers it, and whether a broadcast
//! is answered. The stream splitter (`stream::rtu_frame_len`), the `modbus` codec's
//! exception check, the master's broadcast rule, gutta-sim's Modbus slave
//! (`sim/src/modbus_data.rs`, which functions it serves; it answers every other code
//! with exception 01) and docs/protocol.md's Modbus tables (`reference_markdown`,
//! `splitter_markdown`, kept in sync by `tests/docs.rs`) all come from here.
//!
//! A code without a row is unknown: the splitter cannot frame it (it resynchronises) and
//! the simulator answers exception 01 over Modbus TCP. Lookups go through a `const`
//! table indexed by the code: no search, no allocation.

use crate::gutta::MODBUS_FUNCTION_GUTTA;
use crate::modbus::{
    EXCEPTION_BIT, MAX_READ_BITS, MAX_READ_REGISTERS, MAX_WRITE_BITS, MAX_WRITE_REGISTERS,
    READ_COILS, READ_DISCRETE_INPUTS, READ_HOLDING_REGISTERS, READ_INPUT_REGISTERS,
    WRITE_MULTIPLE_COILS, WRITE_MULTIPLE_REGISTERS, WRITE_SINGLE_COIL, WRITE_SINGLE_REGISTER,
};
use crate::rtu::FrameError;
use crate::stream::Side;

/// Bytes of an RTU frame around its PDU: the station before it, the CRC after it.
pub const RTU_OVERHEAD: usize = 3;

/// The shape of a request or answer PDU, as far as its length goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    /// Always this many PDU bytes (the function code included).
    Fixed(usize),
    /// `head` PDU bytes ending in a byte count, then that many bytes. A count of 0 is
    /// impossible, and so is an odd one when `even` (registers).
    Counted { head: usize, even: bool },
    /// GUTTA data (`gutta.rs`): the function code, a length high byte first, then that
    /// many bytes; a length below 4 (the GUTTA function and packet) is impossible.
    Gutta,
}

/// An exception answer: the function code with bit 7 set, the exception code.
pub const EXCEPTION: Shape = Shape::Fixed(2);

impl Shape {
    /// The length of the RTU frame at the start of `b` (station, function code `function`
    /// at `b[1]`, ...) of this shape; `Ok(None)` if more bytes are needed to tell.
    pub fn rtu_frame_len(self, function: u8, b: &[u8]) -> Result<Option<usize>, FrameError> {
        let bad = |detail| Err(FrameError::BadLength { function, detail });
        match self {
            Shape::Fixed(pdu) => Ok(Some(RTU_OVERHEAD + pdu)),
            // The count is PDU byte `head - 1`, frame byte `head`.
            Shape::Counted { head, even } => match b.get(head) {
                None => Ok(None),
                Some(0) => bad("byte count 0"),
                Some(&count) if even && count % 2 != 0 => bad("odd register byte count"),
                Some(&count) => Ok(Some(RTU_OVERHEAD + head + usize::from(count))),
            },
            Shape::Gutta => {
                let Some(&[hi, lo]) = b.get(2..4) else {
                    return Ok(None);
                };
                let length = u16::from_be_bytes([hi, lo]);
                if length < 4 {
                    return bad("GUTTA length below 4");
                }
                Ok(Some(RTU_OVERHEAD + 3 + usize::from(length)))
            }
        }
    }

    /// The RTU frame length as docs/protocol.md's splitter table says it.
    fn frame_doc(self) -> String {
        match self {
            Shape::Fixed(pdu) => format!("{} bytes", RTU_OVERHEAD + pdu),
            Shape::Counted { head, even } => format!(
                "{} + byte count (byte {head}); count 0{} is impossible",
                RTU_OVERHEAD + head,
                if even { " or odd" } else { "" }
            ),
            Shape::Gutta => format!(
                "{} + GUTTA length (bytes 2-3); length < 4 is impossible",
                RTU_OVERHEAD + 3
            ),
        }
    }
}

/// Who answers a function in gutta-sim.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Handler {
    /// A data function: `modbus::ModbusRequest`/`ModbusResponse` encode and decode it,
    /// the one Modbus slave (`sim/src/modbus_data.rs`) serves it on a PLC's memory or a
    /// device's objects.
    Slave,
    /// UM4001 messages in function 13 (`gutta.rs`, `message.rs`): the PLC answers them
    /// (`sim/src/session.rs` to `sim/src/plc.rs`).
    Plc,
}

/// One Modbus function code.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ModbusFunction {
    pub code: u8,
    pub name: &'static str,
    /// The request PDU's shape (what a slave-side splitter reads).
    pub request: Shape,
    /// The success answer PDU's shape (what a master-side splitter reads).
    pub response: Shape,
    /// The request PDU field by field, for the docs.
    pub request_doc: &'static str,
    /// The largest quantity a request may carry (the Modbus specification's limits;
    /// `modbus.rs` checks them), if it carries one.
    pub max_quantity: Option<u16>,
    /// The answer PDU field by field, for the docs.
    pub response_doc: &'static str,
    pub handler: Handler,
    /// Whether a request to station 0 (broadcast) is answered (AN2002: only GUTTA
    /// function 13, from the PLC's own station).
    pub answers_broadcast: bool,
}

const fn data(
    code: u8,
    name: &'static str,
    request: Shape,
    request_doc: &'static str,
    max_quantity: Option<u16>,
    response: Shape,
    response_doc: &'static str,
) -> ModbusFunction {
    ModbusFunction {
        code,
        name,
        request,
        response,
        request_doc,
        max_quantity,
        response_doc,
        handler: Handler::Slave,
        answers_broadcast: false,
    }
}

const READ_REQUEST: Shape = Shape::Fixed(5);
const BITS: Shape = Shape::Counted {
    head: 2,
    even: false,
};
const REGISTERS: Shape = Shape::Counted {
    head: 2,
    even: true,
};
const WRITE_MULTIPLE: Shape = Shape::Counted {
    head: 6,
    even: false,
};
const ADDRESS_QUANTITY: Shape = Shape::Fixed(5);

/// Every Modbus function code the toolchain frames, by code.
pub const MODBUS_FUNCTIONS: &[ModbusFunction] = &[
    data(
        READ_COILS,
        "read coils",
        READ_REQUEST,
        "`fc addr(2) qty(2)`",
        Some(MAX_READ_BITS),
        BITS,
        "`fc count(1) bits`, first bit in bit 0, unused high bits 0",
    ),
    data(
        READ_DISCRETE_INPUTS,
        "read discrete inputs",
        READ_REQUEST,
        "`fc addr(2) qty(2)`",
        Some(MAX_READ_BITS),
        BITS,
        "`fc count(1) bits`, first bit in bit 0, unused high bits 0",
    ),
    data(
        READ_HOLDING_REGISTERS,
        "read holding registers",
        READ_REQUEST,
        "`fc addr(2) qty(2)`",
        Some(MAX_READ_REGISTERS),
        REGISTERS,
        "`fc count(1) registers` (each high byte first)",
    ),
    data(
        READ_INPUT_REGISTERS,
        "read input registers",
        READ_REQUEST,
        "`fc addr(2) qty(2)`",
        Some(MAX_READ_REGISTERS),
        REGISTERS,
        "`fc count(1) registers` (each high byte first)",
    ),
    data(
        WRITE_SINGLE_COIL,
        "write single coil",
        Shape::Fixed(5),
        "`fc addr(2) FF00/0000`",
        None,
        Shape::Fixed(5),
        "echo",
    ),
    data(
        WRITE_SINGLE_REGISTER,
        "write single register",
        Shape::Fixed(5),
        "`fc addr(2) value(2)`",
        None,
        Shape::Fixed(5),
        "echo",
    ),
    ModbusFunction {
        code: MODBUS_FUNCTION_GUTTA,
        name: "GUTTA (UM4001)",
        request: Shape::Gutta,
        response: Shape::Gutta,
        request_doc: "`fc length(2) function(2) packet(2) payload`, above",
        max_quantity: None,
        response_doc: "the same, bit 15 of function set on failure",
        handler: Handler::Plc,
        answers_broadcast: true,
    },
    data(
        WRITE_MULTIPLE_COILS,
        "write multiple coils",
        WRITE_MULTIPLE,
        "`fc addr(2) qty(2) count(1) bits`",
        Some(MAX_WRITE_BITS),
        ADDRESS_QUANTITY,
        "`fc addr(2) qty(2)`",
    ),
    data(
        WRITE_MULTIPLE_REGISTERS,
        "write multiple registers",
        WRITE_MULTIPLE,
        "`fc addr(2) qty(2) count(1) registers`",
        Some(MAX_WRITE_REGISTERS),
        ADDRESS_QUANTITY,
        "`fc addr(2) qty(2)`",
    ),
];

/// `BY_CODE[code]` is 1 + the row's index in `MODBUS_FUNCTIONS`, 0 for no row. Built at
/// compile time, which also refuses two rows with one code or a code with bit 7 set.
const BY_CODE: [u8; 128] = {
    let mut table = [0u8; 128];
    let mut i = 0;
    while i < MODBUS_FUNCTIONS.len() {
        let code = MODBUS_FUNCTIONS[i].code as usize;
        assert!(code != 0 && code < 128, "a Modbus function code is 1..=127");
        assert!(table[code] == 0, "two rows with one Modbus function code");
        table[code] = (i + 1) as u8;
        i += 1;
    }
    table
};

/// The row of function `code` (bit 7 clear), if the toolchain knows it.
#[inline]
pub fn lookup(code: u8) -> Option<&'static ModbusFunction> {
    match BY_CODE.get(usize::from(code)) {
        Some(&row) if row != 0 => Some(&MODBUS_FUNCTIONS[usize::from(row) - 1]),
        _ => None,
    }
}

/// Whether `code` is a data function the `modbus` codec and the Modbus slave handle.
#[inline]
pub fn is_data_function(code: u8) -> bool {
    lookup(code).is_some_and(|f| f.handler == Handler::Slave)
}

/// The shape of the PDU with function code `function` as `side` reads it: a slave
/// reads requests, a master reads answers, among them exceptions (bit 7 set on a
/// known code). `None`: the code is unknown on that side.
#[inline]
pub fn shape(side: Side, function: u8) -> Option<Shape> {
    match lookup(function) {
        Some(row) if side == Side::Master => Some(row.response),
        Some(row) => Some(row.request),
        None if side == Side::Master
            && function & EXCEPTION_BIT != 0
            && lookup(function & !EXCEPTION_BIT).is_some() =>
        {
            Some(EXCEPTION)
        }
        None => None,
    }
}

/// docs/protocol.md's Modbus function table, generated from the registry (between its
/// `<!-- modbus functions -->` markers; `tests/docs.rs` keeps it in sync).
pub fn reference_markdown() -> String {
    let mut out = String::from(
        "| fc | name | request PDU | answer PDU | answered by gutta-sim's | broadcast answered |\n\
         | --- | --- | --- | --- | --- | --- |\n",
    );
    for f in MODBUS_FUNCTIONS {
        let request = match f.max_quantity {
            Some(max) => format!("{}, qty 1..{max}", f.request_doc),
            None => f.request_doc.to_string(),
        };
        let handler = match f.handler {
            Handler::Slave => "Modbus slave (`sim/src/modbus_data.rs`)",
            Handler::Plc => "PLC (`sim/src/plc.rs`)",
        };
        let broadcast = if f.answers_broadcast { "yes" } else { "no" };
        out.push_str(&format!(
            "| {:02} | {} | {request} | {} | {handler} | {broadcast} |\n",
            f.code, f.name, f.response_doc
        ));
    }
    out.push_str(
        "| fc \\| 0x80 of a row above | exception | | `fc | 0x80, code` | | |\n\
         | any other | | | | exception 01 | |\n",
    );
    out
}

/// docs/protocol.md's table of RTU frame lengths (the splitter's), generated from the
/// registry's shapes (between its `<!-- modbus frame lengths -->` markers).
pub fn splitter_markdown() -> String {
    let mut out = String::from(
        "| function | slave side (requests) | master side (answers) |\n\
         | --- | --- | --- |\n",
    );
    for f in MODBUS_FUNCTIONS {
        let request = f.request.frame_doc();
        let response = f.response.frame_doc();
        let response = if response == request {
            "same".to_string()
        } else {
            response
        };
        out.push_str(&format!("| {:02} | {request} | {response} |\n", f.code));
    }
    out.push_str(&format!(
        "| fc \\| 0x80 of the above | unknown | {} |\n\
         | anything else | unknown | unknown |\n",
        EXCEPTION.frame_doc()
    ));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::modbus::{ModbusRequest, ModbusResponse};
    use crate::rtu::encode_rtu;

    #[test]
    fn rows_are_sorted_and_found_by_their_code() {
        for pair in MODBUS_FUNCTIONS.windows(2) {
            assert!(pair[0].code < pair[1].code, "{}", pair[1].name);
        }
        for code in 0..=u8::MAX {
            let row = MODBUS_FUNCTIONS.iter().find(|f| f.code == code);
            assert_eq!(lookup(code), row, "{code}");
        }
        // Only GUTTA answers a broadcast, and only the PLC answers GUTTA.
        for f in MODBUS_FUNCTIONS {
            let gutta = f.code == MODBUS_FUNCTION_GUTTA;
            assert_eq!(f.answers_broadcast, gutta, "{}", f.name);
            assert_eq!(f.handler == Handler::Plc, gutta, "{}", f.name);
            assert_eq!(f.request == Shape::Gutta, gutta, "{}", f.name);
            assert_eq!(f.response == Shape::Gutta, gutta, "{}", f.name);
        }
    }

    /// Every data row's shapes frame what the `modbus` codec encodes, at its smallest
    /// and largest quantity, on the side that reads it.
    #[test]
    fn shapes_frame_what_the_codec_encodes() {
        let frame_len = |shape: Shape, pdu: &[u8]| {
            let frame = encode_rtu(1, pdu);
            shape.rtu_frame_len(pdu[0], &frame)
        };
        for f in MODBUS_FUNCTIONS
            .iter()
            .filter(|f| f.handler == Handler::Slave)
        {
            let quantities = match f.max_quantity {
                Some(max) => vec![1, max],
                None => vec![1],
            };
            for q in quantities {
                let n = usize::from(q);
                let (request, response) = match f.code {
                    READ_COILS | READ_DISCRETE_INPUTS => {
                        let request = ModbusRequest::ReadCoils {
                            address: 0,
                            quantity: q,
                        };
                        let bytes = crate::modbus::pack_bits(&vec![true; n]);
                        (request, ModbusResponse::ReadCoils(bytes))
                    }
                    READ_HOLDING_REGISTERS | READ_INPUT_REGISTERS => (
                        ModbusRequest::ReadHoldingRegisters {
                            address: 0,
                            quantity: q,
                        },
                        ModbusResponse::ReadHoldingRegisters(vec![7; n]),
                    ),
                    WRITE_SINGLE_COIL => (
                        ModbusRequest::WriteSingleCoil {
                            address: 1,
                            value: true,
                        },
                        ModbusResponse::WriteSingleCoil {
                            address: 1,
                            value: true,
                        },
                    ),
                    WRITE_SINGLE_REGISTER => (
                        ModbusRequest::WriteSingleRegister {
                            address: 1,
                            value: 2,
                        },
                        ModbusResponse::WriteSingleRegister {
                            address: 1,
                            value: 2,
                        },
                    ),
                    WRITE_MULTIPLE_COILS => (
                        ModbusRequest::WriteMultipleCoils {
                            address: 0,
                            values: vec![true; n],
                        },
                        ModbusResponse::WriteMultipleCoils {
                            address: 0,
                            quantity: q,
                        },
                    ),
                    WRITE_MULTIPLE_REGISTERS => (
                        ModbusRequest::WriteMultipleRegisters {
                            address: 0,
                            values: vec![3; n],
                        },
                        ModbusResponse::WriteMultipleRegisters {
                            address: 0,
                            quantity: q,
                        },
                    ),
                    code => panic!("a data row without a codec case: {code}"),
                };
                let mut request = request.encode().expect("request");
                let mut response = response.encode().expect("response");
                // The cases share a variant per family; the row's own code goes first.
                request[0] = f.code;
                response[0] = f.code;
                assert_eq!(
                    frame_len(f.request, &request),
                    Ok(Some(request.len() + RTU_OVERHEAD)),
                    "{} request, qty {q}",
                    f.name
                );
                assert_eq!(
                    frame_len(f.response, &response),
                    Ok(Some(response.len() + RTU_OVERHEAD)),
                    "{} answer, qty {q}",
                    f.name
                );
                assert!(ModbusRequest::decode(&request).is_ok(), "{}", f.name);
                assert!(ModbusResponse::decode(&response).is_ok(), "{}", f.name);
            }
        }
        // The codec takes exactly the data rows.
        for code in 0..EXCEPTION_BIT {
            let exception = ModbusResponse::Exception {
                function: code,
                code: 1,
            };
            assert_eq!(exception.encode().is_ok(), is_data_function(code), "{code}");
        }
    }

    #[test]
    fn exceptions_are_answers_to_known_codes_only() {
        assert_eq!(shape(Side::Master, 0x83), Some(EXCEPTION));
        assert_eq!(shape(Side::Master, 0x8D), Some(EXCEPTION));
        assert_eq!(shape(Side::Slave, 0x83), None);
        assert_eq!(shape(Side::Master, 0x97), None);
        assert_eq!(shape(Side::Slave, 23), None);
        assert!(is_data_function(16) && !is_data_function(13) && !is_data_function(23));
    }
}
