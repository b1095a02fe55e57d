//! The simulated FX-style programming port: the document's exchanges, the memory map's
//! edges, NAK for broken input, the baud switch, and arbitrary bytes.

use gutta_protocol::fx::{
    encode_frame, BaudRate, FxReply, FxRequest, FxSplitter, ACK, ENQ, NAK, PROGRAM_CHUNK,
    PROGRAM_START,
};
use gutta_sim::fx::{factory_config, FxDevice, FxOutput, DATA_END};
use proptest::prelude::*;

fn bytes(text: &str) -> Vec<u8> {
    text.split_whitespace()
        .map(|pair| u8::from_str_radix(pair, 16).expect("bytes"))
        .collect()
}

fn ask(device: &mut FxDevice, request: FxRequest) -> Vec<u8> {
    let output = device.feed(&request.encode().expect("ask"));
    assert_eq!(output.switch_to, None);
    output.reply
}

#[test]
fn enq_is_answered_ack() {
    let mut device = FxDevice::new();
    assert_eq!(device.feed(&[ENQ]).reply, vec![ACK]);
}

#[test]
fn document_read_and_write_at_0e02() {
    let mut device = FxDevice::new();
    // Write 11 22 at 0E02 (document frame, checksum per the rule): ACK.
    let write = device.feed(&bytes("02 31 30 45 30 32 30 32 31 31 32 32 03 33 33"));
    assert_eq!(write.reply, vec![ACK]);
    let read = device.feed(&bytes("02 30 30 45 30 32 30 32 03 36 43"));
    assert_eq!(read.reply, FxReply::Data(vec![0x11, 0x22]).encode());
    // The document's answer B1 5E, once the memory holds it.
    assert_eq!(
        ask(
            &mut device,
            FxRequest::Write {
                address: 0x0E02,
                data: vec![0xB1, 0x5E]
            }
        ),
        vec![ACK]
    );
    let read = device.feed(&bytes("02 30 30 45 30 32 30 32 03 36 43"));
    assert_eq!(read.reply, bytes("02 42 31 35 45 03 46 30"));
}

#[test]
fn factory_e00_answer_is_the_documents() {
    let text = include_str!("data/fx_e00_answer.txt");
    let printed: Vec<u8> = text
        .lines()
        .filter(|line| !line.starts_with('#'))
        .flat_map(bytes)
        .collect();
    assert_eq!(printed.len(), 512);
    let mut device = FxDevice::new();
    let answer = device
        .feed(&bytes("02 45 30 30 38 30 30 30 46 45 03 46 42"))
        .reply;
    // STX, 0xFE bytes as 508 hex digits, ETX, two checksum digits.
    assert_eq!(answer.len(), 1 + 508 + 3);
    assert_eq!(
        answer[..509],
        printed[..509],
        "the document's first 509 bytes"
    );
    // What the document prints beyond the length is three '0' digits.
    assert_eq!(printed[509..], *b"000");
    assert_eq!(FxReply::Data(factory_config()).encode(), answer);
}

#[test]
fn program_upload_series_reads_program_memory() {
    let mut device = FxDevice::new();
    let program: Vec<u8> = (0..=254u8).collect();
    assert_eq!(
        ask(
            &mut device,
            FxRequest::WriteProgram {
                address: PROGRAM_START,
                data: program.clone()
            }
        ),
        vec![ACK]
    );
    assert_eq!(ask(&mut device, FxRequest::EndProgramWrite), vec![ACK]);
    assert_eq!(device.program_writes_ended(), 1);
    let first = device
        .feed(&bytes("02 45 30 31 38 30 35 43 46 45 03 31 34"))
        .reply;
    assert_eq!(first, FxReply::Data(program[..254].to_vec()).encode());
    let second = device
        .feed(&bytes("02 45 30 31 38 31 35 41 46 45 03 31 33"))
        .reply;
    let mut expected = vec![program[254]];
    expected.extend(std::iter::repeat_n(0, usize::from(PROGRAM_CHUNK) - 1));
    assert_eq!(second, FxReply::Data(expected).encode());
    for frame in [
        "02 45 30 31 38 32 35 38 46 45 03 30 42",
        "02 45 30 31 38 33 35 36 46 45 03 30 41",
    ] {
        let reply = device.feed(&bytes(frame)).reply;
        assert_eq!(reply, FxReply::Data(vec![0; 254]).encode());
    }
}

#[test]
fn force_on_and_off_set_bits_of_the_data_area() {
    let mut device = FxDevice::new();
    // Bit 0x0801: byte 0x0100, bit 1.
    assert_eq!(
        ask(&mut device, FxRequest::ForceOn { bit: 0x0801 }),
        vec![ACK]
    );
    assert_eq!(device.memory()[0x0100], 0b10);
    assert_eq!(
        ask(&mut device, FxRequest::ForceOn { bit: 0xFFFF }),
        vec![ACK]
    );
    assert_eq!(device.memory()[0x1FFF], 0x80);
    let read = ask(
        &mut device,
        FxRequest::Read {
            address: 0x0100,
            len: 1,
        },
    );
    assert_eq!(read, FxReply::Data(vec![0b10]).encode());
    assert_eq!(
        ask(&mut device, FxRequest::ForceOff { bit: 0x0801 }),
        vec![ACK]
    );
    assert_eq!(device.memory()[0x0100], 0);
}

#[test]
fn memory_map_edges_are_naked() {
    let mut device = FxDevice::new();
    let last = u16::try_from(DATA_END - 1).unwrap();
    assert_eq!(
        ask(
            &mut device,
            FxRequest::Read {
                address: last,
                len: 1
            }
        ),
        FxReply::Data(vec![0]).encode()
    );
    for request in [
        FxRequest::Read {
            address: last,
            len: 2,
        },
        FxRequest::Read { address: 0, len: 0 },
        FxRequest::Read {
            address: 0x8000,
            len: 1,
        },
        FxRequest::Write {
            address: last,
            data: vec![1, 2],
        },
        FxRequest::ReadConfig {
            address: 0x7FFF,
            len: 1,
        },
        FxRequest::ReadProgram {
            address: 0xFFFF,
            len: 2,
        },
        // The configuration block is read only.
        FxRequest::WriteProgram {
            address: PROGRAM_START - 1,
            data: vec![1],
        },
        FxRequest::WriteProgram {
            address: 0xFFFF,
            data: vec![1, 2],
        },
    ] {
        assert_eq!(ask(&mut device, request.clone()), vec![NAK], "{request:?}");
    }
    assert_eq!(device.naks(), 8);
    assert_eq!(device.memory()[0x8000..0x80FE], factory_config()[..]);
}

#[test]
fn bad_checksums_and_malformed_frames_get_nak_stray_bytes_nothing() {
    let mut device = FxDevice::new();
    assert_eq!(
        device
            .feed(&bytes("02 30 30 45 30 32 30 32 03 36 44"))
            .reply,
        vec![NAK]
    );
    assert_eq!(device.feed(&encode_frame(b"Z")).reply, vec![NAK]);
    assert_eq!(device.feed(&encode_frame(b"00E0")).reply, vec![NAK]);
    assert_eq!(
        device.feed(&[0x41, 0x00, ACK, NAK, 0x7F]).reply,
        Vec::<u8>::new()
    );
    // A frame cut by a new STX: NAK for it, the answer for the second.
    let mut stream = bytes("02 30 30 45");
    stream.extend(bytes("02 30 30 45 30 32 30 32 03 36 43"));
    let mut expected = vec![NAK];
    expected.extend(FxReply::Data(vec![0, 0]).encode());
    assert_eq!(device.feed(&stream).reply, expected);
    // A frame in pieces is answered when its last byte arrives.
    let frame = bytes("02 30 30 45 30 32 30 32 03 36 43");
    assert_eq!(device.feed(&frame[..5]).reply, Vec::<u8>::new());
    assert_eq!(
        device.feed(&frame[5..]).reply,
        FxReply::Data(vec![0, 0]).encode()
    );
}

#[test]
fn baud_switches_after_the_ack() {
    let mut device = FxDevice::new();
    assert_eq!(device.baud(), BaudRate::B9600);
    let output = device.feed(&bytes("02 41 35 03 37 39"));
    assert_eq!(
        output,
        FxOutput {
            reply: vec![ACK],
            switch_to: Some(BaudRate::B115200)
        }
    );
    assert_eq!(device.baud(), BaudRate::B115200);
    let output = device.feed(&encode_frame(&[0x41, 0x39]));
    assert_eq!(output.switch_to, Some(BaudRate::B9600));
}

proptest! {
    #[test]
    fn arbitrary_bytes_never_panic_and_keep_the_configuration(
        chunks in proptest::collection::vec(proptest::collection::vec(any::<u8>(), 0..64), 0..8)
    ) {
        let mut device = FxDevice::new();
        for chunk in &chunks {
            let output = device.feed(chunk);
            // Whatever comes back is ACKs, NAKs and well-formed data frames, nothing else.
            let mut splitter = FxSplitter::new();
            for token in splitter.push(&output.reply) {
                prop_assert!(FxReply::from_token(token).is_ok());
            }
            prop_assert!(!splitter.is_mid_frame());
            prop_assert_eq!(splitter.dropped, 0);
        }
        prop_assert_eq!(&device.memory()[0x8000..0x805C], &factory_config()[..0x5C]);
    }
}
