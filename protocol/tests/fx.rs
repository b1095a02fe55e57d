//! The FX-style programming port (seed 001): every frame of the document byte for byte,
//! checksum and framing errors, the splitter, and round trips under proptest.

use gutta_protocol::fx::{
    checksum, decode_frame, encode_frame, BaudRate, FxError, FxReply, FxRequest, FxSplitter,
    FxToken, ACK, ENQ, MAX_FRAME, NAK, STX,
};
use proptest::prelude::*;

fn bytes(text: &str) -> Vec<u8> {
    text.split_whitespace()
        .map(|pair| u8::from_str_radix(pair, 16).expect("bytes"))
        .collect()
}

fn request(text: &str) -> FxRequest {
    FxRequest::decode(&bytes(text)).expect("request")
}

#[test]
fn document_read_request_0e02_len_2() {
    let frame = "02 30 30 45 30 32 30 32 03 36 43";
    let read = FxRequest::Read {
        address: 0x0E02,
        len: 2,
    };
    assert_eq!(request(frame), read);
    assert_eq!(read.encode().unwrap(), bytes(frame));
}

#[test]
fn document_read_answer_b1_5e() {
    let frame = "02 42 31 35 45 03 46 30";
    let answer = FxReply::Data(vec![0xB1, 0x5E]);
    assert_eq!(FxReply::decode_data(&bytes(frame)).unwrap(), answer);
    assert_eq!(answer.encode(), bytes(frame));
}

#[test]
fn document_write_request_0e02_11_22() {
    // The document prints the checksum as "XX XX"; ours is the rule's sum: 0x233 -> "33".
    let frame = "02 31 30 45 30 32 30 32 31 31 32 32 03 33 33";
    let write = FxRequest::Write {
        address: 0x0E02,
        data: vec![0x11, 0x22],
    };
    assert_eq!(write.encode().unwrap(), bytes(frame));
    assert_eq!(request(frame), write);
}

#[test]
fn document_read_config_8000_fe() {
    let frame = "02 45 30 30 38 30 30 30 46 45 03 46 42";
    let read = FxRequest::ReadConfig {
        address: 0x8000,
        len: 0xFE,
    };
    assert_eq!(request(frame), read);
    assert_eq!(read.encode().unwrap(), bytes(frame));
}

#[test]
fn document_read_program_series() {
    let series = [
        (0x805C, "02 45 30 31 38 30 35 43 46 45 03 31 34"),
        (0x815A, "02 45 30 31 38 31 35 41 46 45 03 31 33"),
        (0x8258, "02 45 30 31 38 32 35 38 46 45 03 30 42"),
        (0x8356, "02 45 30 31 38 33 35 36 46 45 03 30 41"),
    ];
    for (address, frame) in series {
        let read = FxRequest::ReadProgram { address, len: 0xFE };
        assert_eq!(request(frame), read, "{frame}");
        assert_eq!(read.encode().unwrap(), bytes(frame), "{address:04X}");
    }
    // 0xFE bytes a frame: each address is the previous one plus 0xFE.
    assert!(series.windows(2).all(|w| w[1].0 - w[0].0 == 0xFE));
}

#[test]
fn control_bytes_of_the_document() {
    assert_eq!(FxRequest::Enquiry.encode().unwrap(), vec![0x05]);
    assert_eq!(FxReply::Ack.encode(), vec![0x06]);
    assert_eq!(FxReply::Nak.encode(), vec![0x15]);
    let mut splitter = FxSplitter::new();
    assert_eq!(
        splitter.push(&[ENQ, ACK, NAK]),
        vec![FxToken::Enq, FxToken::Ack, FxToken::Nak]
    );
}

#[test]
fn force_addresses_go_low_byte_first() {
    let on = FxRequest::ForceOn { bit: 0x0801 };
    // 37, then "01" (low byte) "08" (high byte), ETX, 0x37+0x30+0x31+0x30+0x38+0x03 = 0x103.
    assert_eq!(on.encode().unwrap(), bytes("02 37 30 31 30 38 03 30 33"));
    let off = FxRequest::ForceOff { bit: 0x0801 };
    assert_eq!(off.encode().unwrap(), bytes("02 38 30 31 30 38 03 30 34"));
    assert_eq!(request("02 38 30 31 30 38 03 30 34"), off);
}

#[test]
fn baud_selectors_of_the_document() {
    for (code, rate) in [
        (0x31, 19200),
        (0x32, 38400),
        (0x33, 57600),
        (0x35, 115_200),
        (0x34, 9600),
        (0x30, 9600),
        (0x7F, 9600),
    ] {
        let frame = encode_frame(&[0x41, code]);
        assert_eq!(frame[..3], [STX, 0x41, code]);
        let FxRequest::Baud(decoded) = FxRequest::decode(&frame).unwrap() else {
            panic!("not a baud request: {frame:02X?}");
        };
        assert_eq!(decoded.bits_per_second(), rate, "code {code:02X}");
    }
    // 19200: 02 41 31 03, 0x41 + 0x31 + 0x03 = 0x75.
    assert_eq!(
        FxRequest::Baud(BaudRate::B19200).encode().unwrap(),
        bytes("02 41 31 03 37 35")
    );
}

#[test]
fn end_of_program_write_and_write_program() {
    assert_eq!(
        FxRequest::EndProgramWrite.encode().unwrap(),
        encode_frame(b"E87")
    );
    let write = FxRequest::WriteProgram {
        address: 0x805C,
        data: vec![0x01, 0xAB],
    };
    let frame = write.encode().unwrap();
    assert_eq!(&frame[..15], b"\x02E11805C0201AB\x03".as_slice());
    assert_eq!(FxRequest::decode(&frame).unwrap(), write);
}

#[test]
fn checksum_is_low_byte_of_sum_after_stx_through_etx() {
    assert_eq!(checksum(b""), 0x03);
    assert_eq!(checksum(&[0xFF, 0x01]), 0x03);
    let frame = bytes("02 42 31 35 45 03 46 30");
    let sum: u32 = frame[1..6].iter().map(|&b| u32::from(b)).sum();
    assert_eq!(sum & 0xFF, 0xF0);
}

#[test]
fn checksum_errors() {
    let mut frame = bytes("02 30 30 45 30 32 30 32 03 36 43");
    frame[10] = b'D';
    assert_eq!(
        FxRequest::decode(&frame),
        Err(FxError::Checksum {
            computed: 0x6C,
            found: *b"6D"
        })
    );
    frame[10] = b'x';
    assert!(matches!(
        FxRequest::decode(&frame),
        Err(FxError::Checksum { .. })
    ));
    // Lower-case checksum digits are accepted.
    assert!(decode_frame(&bytes("02 42 31 35 45 03 66 30")).is_ok());
}

#[test]
fn malformed_frames() {
    let cases: Vec<(Vec<u8>, FxError)> = vec![
        (vec![0x02, 0x03], FxError::TooShort { len: 2 }),
        (bytes("30 30 45 03 36 43"), FxError::NoStx { found: 0x30 }),
        (bytes("02 30 30 45 30 32 30 32 36 43"), FxError::NoEtx),
        (
            encode_frame(b"9"),
            FxError::UnknownCommand {
                command: b"9".to_vec(),
            },
        ),
        (
            encode_frame(b"E99"),
            FxError::UnknownCommand {
                command: b"E99".to_vec(),
            },
        ),
        (
            encode_frame(b"00E02"),
            FxError::BadLength {
                expected: 6,
                found: 4,
            },
        ),
        (
            encode_frame(b"00G0202"),
            FxError::NotHex {
                index: 3,
                byte: b'G',
            },
        ),
        (
            encode_frame(b"10E020211"),
            FxError::BadLength {
                expected: 10,
                found: 8,
            },
        ),
        (
            encode_frame(b"7010"),
            FxError::BadLength {
                expected: 4,
                found: 3,
            },
        ),
        (
            encode_frame(b"A"),
            FxError::BadLength {
                expected: 1,
                found: 0,
            },
        ),
        (
            encode_frame(b"E87X"),
            FxError::BadLength {
                expected: 0,
                found: 1,
            },
        ),
        (
            encode_frame(b""),
            FxError::UnknownCommand {
                command: Vec::new(),
            },
        ),
    ];
    for (frame, error) in cases {
        assert_eq!(FxRequest::decode(&frame), Err(error), "{frame:02X?}");
    }
    assert_eq!(
        FxReply::decode_data(&encode_frame(b"B15")),
        Err(FxError::BadLength {
            expected: 4,
            found: 3
        })
    );
    assert_eq!(
        FxRequest::Write {
            address: 0,
            data: vec![0; 256]
        }
        .encode(),
        Err(FxError::DataTooLong { len: 256 })
    );
}

#[test]
fn splitter_cuts_a_stream_and_drops_noise() {
    let read = bytes("02 30 30 45 30 32 30 32 03 36 43");
    let mut stream = vec![0x41, ENQ];
    stream.extend_from_slice(&read);
    stream.push(0x00);
    stream.extend_from_slice(&read[..4]);
    stream.extend_from_slice(&read);
    let mut splitter = FxSplitter::new();
    let tokens = splitter.push(&stream);
    assert_eq!(
        tokens,
        vec![
            FxToken::Enq,
            FxToken::Frame(read.clone()),
            FxToken::Broken(FxError::Interrupted),
            FxToken::Frame(read.clone()),
        ]
    );
    assert_eq!(splitter.dropped, 2);
    assert!(!splitter.is_mid_frame());
}

#[test]
fn splitter_gives_up_on_a_frame_without_end() {
    let mut splitter = FxSplitter::new();
    let mut stream = vec![STX];
    stream.extend(std::iter::repeat_n(b'0', MAX_FRAME + 10));
    stream.push(ENQ);
    let tokens = splitter.push(&stream);
    assert_eq!(tokens, vec![FxToken::Broken(FxError::FrameTooLong)]);
    // The next STX starts afresh.
    let read = bytes("02 30 30 45 30 32 30 32 03 36 43");
    assert_eq!(splitter.push(&read), vec![FxToken::Frame(read)]);
}

#[test]
fn longest_write_fits_the_splitter() {
    let write = FxRequest::WriteProgram {
        address: 0x805C,
        data: vec![0xA5; 255],
    };
    let frame = write.encode().unwrap();
    assert_eq!(frame.len(), MAX_FRAME);
    let tokens = FxSplitter::new().push(&frame);
    assert_eq!(tokens, vec![FxToken::Frame(frame)]);
}

fn any_request() -> impl Strategy<Value = FxRequest> {
    let data = proptest::collection::vec(any::<u8>(), 0..=255);
    prop_oneof![
        Just(FxRequest::Enquiry),
        (any::<u16>(), any::<u8>()).prop_map(|(address, len)| FxRequest::Read { address, len }),
        (any::<u16>(), data.clone()).prop_map(|(address, data)| FxRequest::Write { address, data }),
        any::<u16>().prop_map(|bit| FxRequest::ForceOn { bit }),
        any::<u16>().prop_map(|bit| FxRequest::ForceOff { bit }),
        proptest::sample::select(BaudRate::ALL.to_vec()).prop_map(FxRequest::Baud),
        (any::<u16>(), any::<u8>())
            .prop_map(|(address, len)| FxRequest::ReadConfig { address, len }),
        (any::<u16>(), any::<u8>())
            .prop_map(|(address, len)| FxRequest::ReadProgram { address, len }),
        (any::<u16>(), data).prop_map(|(address, data)| FxRequest::WriteProgram { address, data }),
        Just(FxRequest::EndProgramWrite),
    ]
}

proptest! {
    #[test]
    fn requests_round_trip_through_the_splitter(
        requests in proptest::collection::vec(any_request(), 1..6),
        cut in 1usize..40,
    ) {
        let mut stream = Vec::new();
        for request in &requests {
            stream.extend(request.encode().unwrap());
        }
        let mut splitter = FxSplitter::new();
        let mut decoded = Vec::new();
        for chunk in stream.chunks(cut) {
            for token in splitter.push(chunk) {
                decoded.push(match token {
                    FxToken::Enq => FxRequest::Enquiry,
                    FxToken::Frame(frame) => FxRequest::decode(&frame).unwrap(),
                    other => panic!("unexpected {other:?}"),
                });
            }
        }
        prop_assert_eq!(decoded, requests);
    }

    #[test]
    fn data_replies_round_trip(data in proptest::collection::vec(any::<u8>(), 0..=255)) {
        let reply = FxReply::Data(data);
        let frame = reply.encode();
        prop_assert_eq!(FxReply::decode_data(&frame).unwrap(), reply);
    }

    #[test]
    fn decoders_accept_only_what_they_re_encode(frame in proptest::collection::vec(any::<u8>(), 0..40)) {
        if let Ok(request) = FxRequest::decode(&frame) {
            // Hex digits may come lower case; the 41 selector may be any byte.
            let again = request.encode().unwrap();
            prop_assert_eq!(FxRequest::decode(&again).unwrap(), request);
        }
        let _ = FxSplitter::new().push(&frame);
    }

    #[test]
    fn any_single_byte_change_is_caught(index in 1usize..8, delta in 1u8..=255) {
        let mut frame = bytes("02 30 30 45 30 32 30 32 03 36 43");
        frame[index] = frame[index].wrapping_add(delta);
        prop_assert!(FxRequest::decode(&frame).is_err());
    }
}

#[test]
fn program_memory_goes_in_frames_of_fe_bytes_from_805c() {
    use gutta_protocol::fx::{program_chunks, PROGRAM_SIZE};
    let chunks: Vec<(u16, usize)> = program_chunks(0x200).collect();
    assert_eq!(
        chunks,
        [(0x805C, 0xFE), (0x815A, 0xFE), (0x8258, 0x04)],
        "the E01 series of seed 001"
    );
    let all: Vec<(u16, usize)> = program_chunks(PROGRAM_SIZE).collect();
    assert_eq!(all.iter().map(|(_, n)| n).sum::<usize>(), PROGRAM_SIZE);
    let (last, len) = all[all.len() - 1];
    assert_eq!(usize::from(last) + len, 0x1_0000);
    assert_eq!(program_chunks(0).count(), 0);
}
