//! Every frame of seed document 004 (the Modbus-TCP relay board), byte for byte: the
//! Modbus TCP requests (reporting switch, one channel on/off, read n channels and its
//! answer) through MBAP and the Modbus codecs, the board's own three frames and its
//! status answer through `relay`, and how `classify` tells the two apart.

use gutta_protocol::relay::{
    classify, decode_status, status_frame, Classified, RelayError, RelayRequest,
};
use gutta_protocol::{decode_tcp, encode_tcp, ModbusRequest, ModbusResponse};

/// Hex bytes as the document writes them.
fn hex(text: &str) -> Vec<u8> {
    text.split_whitespace()
        .map(|b| u8::from_str_radix(b, 16).expect("hex byte"))
        .collect()
}

/// A document request through MBAP and the Modbus decoder, and back.
fn modbus_request(text: &str, expected: ModbusRequest) {
    let bytes = hex(text);
    assert_eq!(classify(&bytes), Classified::Mbap(bytes.len()), "{text}");
    let frame = decode_tcp(&bytes).expect("MBAP");
    assert_eq!((frame.transaction, frame.unit), (0, 1));
    let request = ModbusRequest::decode(&frame.pdu).expect("decodes");
    assert_eq!(request, expected, "{text}");
    let pdu = request.encode().expect("encodes");
    assert_eq!(encode_tcp(0, 1, &pdu), Some(bytes), "{text}");
}

#[test]
fn reporting_switch_is_coil_1d5c() {
    let coil = |value| ModbusRequest::WriteSingleCoil {
        address: 0x1D5C,
        value,
    };
    modbus_request("00 00 00 00 00 06 01 05 1D 5C 00 00", coil(false));
    modbus_request("00 00 00 00 00 06 01 05 1D 5C FF 00", coil(true));
}

#[test]
fn one_channel_on_and_off() {
    let coil = |address, value| ModbusRequest::WriteSingleCoil { address, value };
    modbus_request("00 00 00 00 00 06 01 05 02 00 FF 00", coil(0x0200, true));
    modbus_request("00 00 00 00 00 06 01 05 02 00 00 00", coil(0x0200, false));
    modbus_request("00 00 00 00 00 06 01 05 02 01 FF 00", coil(0x0201, true));
    modbus_request("00 00 00 00 00 06 01 05 02 01 00 00", coil(0x0201, false));
}

#[test]
fn read_ten_channels_and_the_answer() {
    modbus_request(
        "00 00 00 00 00 06 01 01 02 00 00 0A",
        ModbusRequest::ReadCoils {
            address: 0x0200,
            quantity: 10,
        },
    );
    let answer = hex("00 00 00 00 00 05 01 01 02 ff 03");
    let frame = decode_tcp(&answer).expect("MBAP");
    let response = ModbusResponse::decode(&frame.pdu).expect("decodes");
    assert_eq!(response, ModbusResponse::ReadCoils(vec![0xFF, 0x03]));
    assert_eq!(
        encode_tcp(0, 1, &response.encode().expect("encodes")),
        Some(answer)
    );
}

/// A document frame of the board's own, decoded and encoded back.
fn own(text: &str, expected: RelayRequest) {
    let bytes = hex(text);
    assert_eq!(classify(&bytes), Classified::Own(bytes.len()), "{text}");
    assert_eq!(RelayRequest::decode(&bytes), Ok(expected), "{text}");
    assert_eq!(expected.encode(), bytes, "{text}");
}

#[test]
fn set_32_channels() {
    own(
        "03 01 02 00 00 05 00 20 FF FF FF FF",
        RelayRequest::Set(u32::MAX),
    );
    own("03 01 02 00 00 05 00 20 00 00 00 00", RelayRequest::Set(0));
    // Channels 1 and 2 on, 3 and 4 off; then the other way round.
    own(
        "03 01 02 00 00 05 00 20 03 00 00 00",
        RelayRequest::Set(0b0011),
    );
    own(
        "03 01 02 00 00 05 00 20 0C 00 00 00",
        RelayRequest::Set(0b1100),
    );
    // The generic form: AA is channels 1-8, DD channels 25-32.
    own(
        "03 01 02 00 00 05 00 20 AA BB CC DD",
        RelayRequest::Set(0xDDCC_BBAA),
    );
}

#[test]
fn toggle_32_channels() {
    own("24 01 02 00 00 05 00 01 00 00 00", RelayRequest::Toggle(1));
    own(
        "24 01 02 00 00 05 00 02 00 00 00",
        RelayRequest::Toggle(1 << 1),
    );
    own(
        "24 01 02 00 00 05 00 04 00 00 00",
        RelayRequest::Toggle(1 << 2),
    );
    // Channels 1, 3, 5 and 6.
    own(
        "24 01 02 00 00 05 00 35 00 00 00",
        RelayRequest::Toggle(0b11_0101),
    );
    own(
        "24 01 02 00 00 05 00 AA BB CC DD",
        RelayRequest::Toggle(0xDDCC_BBAA),
    );
    assert_eq!(RelayRequest::Toggle(0b0101).apply(0b0110), 0b0011);
}

#[test]
fn read_32_channels_and_its_answers() {
    own("01 01 02 00 00 05 00 20 00 00 00 00", RelayRequest::Read);
    assert_eq!(
        status_frame(u32::MAX).to_vec(),
        hex("01 01 02 01 05 00 00 10 FF FF FF FF")
    );
    assert_eq!(
        status_frame(0).to_vec(),
        hex("01 01 02 01 05 00 00 10 00 00 00 00")
    );
    // XX is ignored when decoding.
    assert_eq!(
        decode_status(&hex("01 01 02 01 05 00 00 77 AA BB CC DD")),
        Ok(0xDDCC_BBAA)
    );
    assert_eq!(
        decode_status(&hex("01 01 02 01 05 00 00 10 AA BB CC")),
        Err(RelayError::NotOwnFrame)
    );
}

#[test]
fn classify_waits_rejects_and_splits() {
    assert_eq!(classify(&hex("00 00 00 00 00 06")), Classified::NeedMore);
    assert_eq!(
        classify(&hex("00 00 00 00 00 06 01 05 02")),
        Classified::NeedMore
    );
    assert_eq!(
        classify(&hex("03 01 02 00 00 05 00 20 FF")),
        Classified::NeedMore
    );
    // Two frames back to back: the first one's length.
    let mut two = hex("24 01 02 00 00 05 00 01 00 00 00");
    two.extend(hex("00 00 00 00 00 06 01 01 02 00 00 0A"));
    assert_eq!(classify(&two), Classified::Own(11));
    assert_eq!(classify(&two[11..]), Classified::Mbap(12));
    // Neither Modbus TCP (protocol id not 0) nor an own frame.
    assert_eq!(
        classify(&hex("00 01 00 01 00 06 01 01 02 00 00 0A")),
        Classified::Invalid
    );
    assert_eq!(
        classify(&hex("05 01 02 00 00 05 00 20 00 00 00 00")),
        Classified::Invalid
    );
    // An MBAP length the specification does not allow.
    assert_eq!(classify(&hex("00 00 00 00 01 00 01")), Classified::Invalid);
    assert_eq!(classify(&hex("00 00 00 00 00 01 01")), Classified::Invalid);
    // A set or read with a count other than 32.
    assert_eq!(
        RelayRequest::decode(&hex("03 01 02 00 00 05 00 10 00 00 00 00")),
        Err(RelayError::Count { found: 0x10 })
    );
    assert_eq!(
        RelayRequest::decode(&hex("24 01 02 00 00 05 00 01 00 00")),
        Err(RelayError::Length {
            command: 0x24,
            expected: 11,
            found: 10
        })
    );
}
