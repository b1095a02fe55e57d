//! The Modbus examples of AN2002 (seed 003): the request/response tables of functions
//! 01-06/15/16 (station 17, CRC shown as "--" in the document, so PDUs only) and the real
//! serial capture of sample 3, through RTU framing and the typed decoders.

use gutta_protocol::modbus::{exception, pack_bits, unpack_bits};
use gutta_protocol::{
    decode_rtu, encode_rtu, ExceptionCode, ModbusError, ModbusRequest, ModbusResponse,
};

fn round_trip_request(pdu: &[u8], expected: ModbusRequest) {
    let request = ModbusRequest::decode(pdu).expect("decodes");
    assert_eq!(request, expected);
    assert_eq!(request.encode().expect("encodes"), pdu);
    let wire = encode_rtu(0x11, pdu);
    assert_eq!(decode_rtu(&wire).expect("checks").pdu, pdu);
}

fn round_trip_response(pdu: &[u8], expected: ModbusResponse) {
    let response = ModbusResponse::decode(pdu).expect("decodes");
    assert_eq!(response, expected);
    assert_eq!(response.encode().expect("encodes"), pdu);
}

#[test]
fn function_01_read_coils_20_to_56() {
    round_trip_request(
        &[0x01, 0x00, 0x13, 0x00, 0x25],
        ModbusRequest::ReadCoils {
            address: 0x13,
            quantity: 37,
        },
    );
    let packed = vec![0xCD, 0x6B, 0xB2, 0x0E, 0x1B];
    round_trip_response(
        &[0x01, 0x05, 0xCD, 0x6B, 0xB2, 0x0E, 0x1B],
        ModbusResponse::ReadCoils(packed.clone()),
    );
    let coils = unpack_bits(&packed, 37);
    // Coil 20 is bit 0 of CD (1), coil 21 bit 1 (0), coil 27 bit 7 (1).
    assert_eq!((coils[0], coils[1], coils[7]), (true, false, true));
    assert_eq!(pack_bits(&coils), packed);
}

#[test]
fn function_02_read_inputs_10197_to_10218() {
    round_trip_request(
        &[0x02, 0x00, 0xC4, 0x00, 0x16],
        ModbusRequest::ReadDiscreteInputs {
            address: 0xC4,
            quantity: 22,
        },
    );
    round_trip_response(
        &[0x02, 0x03, 0xAC, 0xDB, 0x35],
        ModbusResponse::ReadDiscreteInputs(vec![0xAC, 0xDB, 0x35]),
    );
}

#[test]
fn function_03_read_holding_40108_to_40110() {
    round_trip_request(
        &[0x03, 0x00, 0x6B, 0x00, 0x03],
        ModbusRequest::ReadHoldingRegisters {
            address: 0x6B,
            quantity: 3,
        },
    );
    round_trip_response(
        &[0x03, 0x06, 0x02, 0x2B, 0x00, 0x00, 0x00, 0x64],
        ModbusResponse::ReadHoldingRegisters(vec![555, 0, 100]),
    );
}

#[test]
fn function_04_read_input_register_30009() {
    round_trip_request(
        &[0x04, 0x00, 0x08, 0x00, 0x01],
        ModbusRequest::ReadInputRegisters {
            address: 8,
            quantity: 1,
        },
    );
    // AN2002 prints this answer's function code as 16#03, a typo: an answer echoes 04.
    round_trip_response(
        &[0x04, 0x02, 0x00, 0x0A],
        ModbusResponse::ReadInputRegisters(vec![10]),
    );
}

#[test]
fn function_05_force_coil_173_on() {
    let pdu = [0x05, 0x00, 0xAC, 0xFF, 0x00];
    round_trip_request(
        &pdu,
        ModbusRequest::WriteSingleCoil {
            address: 0xAC,
            value: true,
        },
    );
    round_trip_response(
        &pdu,
        ModbusResponse::WriteSingleCoil {
            address: 0xAC,
            value: true,
        },
    );
    let bad = ModbusRequest::decode(&[0x05, 0x00, 0xAC, 0x12, 0x34]);
    assert_eq!(bad, Err(ModbusError::CoilValue { value: 0x1234 }));
    assert_eq!(
        bad.map_err(|e| e.exception_code()),
        Err(ExceptionCode::IllegalDataValue)
    );
}

#[test]
fn function_06_preset_register_40002() {
    let pdu = [0x06, 0x00, 0x01, 0x00, 0x03];
    round_trip_request(
        &pdu,
        ModbusRequest::WriteSingleRegister {
            address: 1,
            value: 3,
        },
    );
    round_trip_response(
        &pdu,
        ModbusResponse::WriteSingleRegister {
            address: 1,
            value: 3,
        },
    );
}

#[test]
fn function_15_force_ten_coils_from_20() {
    let values = vec![
        true, false, true, true, false, false, true, true, true, false,
    ];
    round_trip_request(
        &[0x0F, 0x00, 0x13, 0x00, 0x0A, 0x02, 0xCD, 0x01],
        ModbusRequest::WriteMultipleCoils {
            address: 0x13,
            values,
        },
    );
    round_trip_response(
        &[0x0F, 0x00, 0x13, 0x00, 0x0A],
        ModbusResponse::WriteMultipleCoils {
            address: 0x13,
            quantity: 10,
        },
    );
    // Unused bits of the last byte must be 0 ("多余的位需要被 0 填充").
    let padded = ModbusRequest::decode(&[0x0F, 0x00, 0x13, 0x00, 0x0A, 0x02, 0xCD, 0x81]);
    assert_eq!(padded, Err(ModbusError::Padding { function: 0x0F }));
}

#[test]
fn function_16_preset_40002_and_40003() {
    round_trip_request(
        &[0x10, 0x00, 0x01, 0x00, 0x02, 0x04, 0x00, 0x0A, 0x01, 0x02],
        ModbusRequest::WriteMultipleRegisters {
            address: 1,
            values: vec![0x000A, 0x0102],
        },
    );
    round_trip_response(
        &[0x10, 0x00, 0x01, 0x00, 0x02],
        ModbusResponse::WriteMultipleRegisters {
            address: 1,
            quantity: 2,
        },
    );
}

#[test]
fn sample_3_capture() {
    let request = decode_rtu(&[0x01, 0x02, 0x00, 0x04, 0x00, 0x04, 0x38, 0x08]).expect("checks");
    assert_eq!(
        ModbusRequest::decode(&request.pdu),
        Ok(ModbusRequest::ReadDiscreteInputs {
            address: 4,
            quantity: 4
        })
    );
    let answer = decode_rtu(&[0x01, 0x02, 0x01, 0x00, 0xA1, 0x88]).expect("checks");
    assert_eq!(
        ModbusResponse::decode(&answer.pdu),
        Ok(ModbusResponse::ReadDiscreteInputs(vec![0]))
    );
    let request = decode_rtu(&[0x01, 0x03, 0x00, 0x08, 0x00, 0x04, 0xC5, 0xCB]).expect("checks");
    assert_eq!(
        ModbusRequest::decode(&request.pdu),
        Ok(ModbusRequest::ReadHoldingRegisters {
            address: 8,
            quantity: 4
        })
    );
    let answer =
        decode_rtu(&[0x01, 0x03, 0x08, 0x0C, 0x2B, 0, 0, 0, 0, 0, 0, 0x0E, 0x80]).expect("checks");
    assert_eq!(
        ModbusResponse::decode(&answer.pdu),
        Ok(ModbusResponse::ReadHoldingRegisters(vec![0x0C2B, 0, 0, 0]))
    );
}

#[test]
fn limits_map_to_exceptions() {
    let code = |pdu: &[u8]| ModbusRequest::decode(pdu).map_err(|e| e.exception_code());
    use ExceptionCode::*;
    assert_eq!(code(&[0x01, 0, 0, 0x07, 0xD0]).map(|r| r.function()), Ok(1)); // 2000 bits
    assert_eq!(code(&[0x01, 0, 0, 0x07, 0xD1]), Err(IllegalDataValue));
    assert_eq!(code(&[0x02, 0, 0, 0, 0]), Err(IllegalDataValue));
    assert_eq!(code(&[0x03, 0, 0, 0, 125]).map(|r| r.function()), Ok(3));
    assert_eq!(code(&[0x04, 0, 0, 0, 126]), Err(IllegalDataValue));
    assert_eq!(code(&[0x03, 0xFF, 0xFF, 0, 2]), Err(IllegalDataAddress));
    assert_eq!(code(&[0x03, 0, 0, 0]), Err(IllegalDataValue));
    assert_eq!(code(&[0x07]), Err(IllegalFunction));
    assert_eq!(code(&[]), Err(IllegalFunction));
    // 15: 1968 bits = 246 bytes is the most; 16: 123 registers.
    let mut coils = vec![0x0F, 0, 0, 0x07, 0xB0, 246];
    coils.extend([0u8; 246]);
    assert!(code(&coils).is_ok());
    coils[4] = 0xB1;
    assert_eq!(code(&coils), Err(IllegalDataValue));
    let mut regs = vec![0x10, 0, 0, 0, 123, 246];
    regs.extend([0u8; 246]);
    assert!(code(&regs).is_ok());
    regs[4] = 124;
    assert_eq!(code(&regs), Err(IllegalDataValue));
    // Byte count that does not match the quantity.
    assert_eq!(
        code(&[0x10, 0, 1, 0, 2, 3, 0, 0x0A, 1]),
        Err(IllegalDataValue)
    );
    // Encoding checks the same limits.
    let too_many = ModbusRequest::WriteMultipleRegisters {
        address: 0,
        values: vec![0; 124],
    };
    assert!(matches!(
        too_many.encode(),
        Err(ModbusError::Quantity { quantity: 124, .. })
    ));
}

#[test]
fn exception_responses() {
    assert_eq!(
        exception(0x03, ExceptionCode::IllegalDataAddress),
        [0x83, 0x02]
    );
    assert_eq!(
        exception(0x0D, ExceptionCode::IllegalFunction),
        [0x8D, 0x01]
    );
    round_trip_response(
        &[0x81, 0x03],
        ModbusResponse::Exception {
            function: 0x01,
            code: 3,
        },
    );
    assert_eq!(
        ModbusResponse::decode(&[0x87, 0x01]),
        Err(ModbusError::UnknownFunction { function: 0x87 })
    );
    assert!(ModbusResponse::decode(&[0x83, 0x01, 0x00]).is_err());
}
