//! The simulated relay board against every example of seed document 004, byte for byte,
//! through one connection's byte stream (`RelaySession`): Modbus TCP 01/05 on coils
//! 0x0200 + n and 0x1D5C, the board's own three frames on the same connection, the
//! automatic report, Modbus exceptions, and garbage.

use gutta_sim::relay::{RelayBoard, RelaySession};

fn hex(text: &str) -> Vec<u8> {
    text.split_whitespace()
        .map(|b| u8::from_str_radix(b, 16).expect("hex byte"))
        .collect()
}

/// Sends `request` (document hex) and returns the answer bytes.
fn send(board: &mut RelayBoard, request: &str) -> Vec<u8> {
    RelaySession::new()
        .on_bytes(board, &hex(request))
        .expect("stays open")
}

#[test]
fn reporting_switch_off_and_on() {
    let mut board = RelayBoard::default();
    assert!(board.reporting(), "on at power-up");
    let off = "00 00 00 00 00 06 01 05 1D 5C 00 00";
    assert_eq!(send(&mut board, off), hex(off), "function 05 echoes");
    assert!(!board.reporting());
    let on = "00 00 00 00 00 06 01 05 1D 5C FF 00";
    assert_eq!(send(&mut board, on), hex(on));
    assert!(board.reporting());
}

#[test]
fn one_channel_at_a_time() {
    let mut board = RelayBoard::default();
    for (request, channels) in [
        ("00 00 00 00 00 06 01 05 02 00 FF 00", 0b01),
        ("00 00 00 00 00 06 01 05 02 01 FF 00", 0b11),
        ("00 00 00 00 00 06 01 05 02 00 00 00", 0b10),
        ("00 00 00 00 00 06 01 05 02 01 00 00", 0b00),
        // 0A is channel 11, 10 channel 17.
        ("00 00 00 00 00 06 01 05 02 0A FF 00", 1 << 10),
        ("00 00 00 00 00 06 01 05 02 10 FF 00", 1 << 10 | 1 << 16),
    ] {
        assert_eq!(send(&mut board, request), hex(request));
        assert_eq!(board.channels(), channels, "{request}");
    }
    assert!(board.channel(11) && board.channel(17) && !board.channel(1));
}

#[test]
fn read_ten_channels_with_channels_1_to_10_on() {
    let mut board = RelayBoard::default();
    for n in 0..10 {
        send(
            &mut board,
            &format!("00 00 00 00 00 06 01 05 02 {n:02X} FF 00"),
        );
    }
    assert_eq!(
        send(&mut board, "00 00 00 00 00 06 01 01 02 00 00 0A"),
        hex("00 00 00 00 00 05 01 01 02 FF 03")
    );
    // And all 32: four bytes, the last two 0.
    assert_eq!(
        send(&mut board, "00 07 00 00 00 06 01 01 02 00 00 20"),
        hex("00 07 00 00 00 07 01 01 04 FF 03 00 00")
    );
}

#[test]
fn set_32_channels() {
    let mut board = RelayBoard::default();
    for (request, channels) in [
        ("03 01 02 00 00 05 00 20 FF FF FF FF", u32::MAX),
        ("03 01 02 00 00 05 00 20 00 00 00 00", 0),
        ("03 01 02 00 00 05 00 20 03 00 00 00", 0b0011),
        ("03 01 02 00 00 05 00 20 0C 00 00 00", 0b1100),
    ] {
        assert_eq!(send(&mut board, request), Vec::<u8>::new(), "no answer");
        assert_eq!(board.channels(), channels, "{request}");
    }
    // Channels 3 and 4 on, 1 and 2 off, read through Modbus.
    assert_eq!(
        send(&mut board, "00 00 00 00 00 06 01 01 02 00 00 04"),
        hex("00 00 00 00 00 04 01 01 01 0C")
    );
}

#[test]
fn toggle_32_channels() {
    let mut board = RelayBoard::default();
    send(&mut board, "24 01 02 00 00 05 00 01 00 00 00");
    assert_eq!(board.channels(), 0b1);
    send(&mut board, "24 01 02 00 00 05 00 02 00 00 00");
    assert_eq!(board.channels(), 0b11);
    send(&mut board, "24 01 02 00 00 05 00 04 00 00 00");
    assert_eq!(board.channels(), 0b111);
    // Channels 1, 3, 5, 6 change: 1 and 3 go off, 5 and 6 on.
    send(&mut board, "24 01 02 00 00 05 00 35 00 00 00");
    assert_eq!(board.channels(), 0b11_0010);
}

#[test]
fn read_32_channels() {
    let mut board = RelayBoard::default();
    let read = "01 01 02 00 00 05 00 20 00 00 00 00";
    assert_eq!(
        send(&mut board, read),
        hex("01 01 02 01 05 00 00 10 00 00 00 00")
    );
    send(&mut board, "03 01 02 00 00 05 00 20 FF FF FF FF");
    assert_eq!(
        send(&mut board, read),
        hex("01 01 02 01 05 00 00 10 FF FF FF FF")
    );
    send(&mut board, "03 01 02 00 00 05 00 20 AA BB CC DD");
    assert_eq!(
        send(&mut board, read),
        hex("01 01 02 01 05 00 00 10 AA BB CC DD")
    );
    assert!(board.channel(2) && !board.channel(1) && board.channel(32));
}

#[test]
fn both_framings_on_one_connection_in_any_pieces() {
    let mut board = RelayBoard::default();
    let mut session = RelaySession::new();
    let mut stream = hex("03 01 02 00 00 05 00 20 03 00 00 00");
    stream.extend(hex("00 09 00 00 00 06 01 01 02 00 00 04"));
    stream.extend(hex("24 01 02 00 00 05 00 0F 00 00 00"));
    stream.extend(hex("01 01 02 00 00 05 00 20 00 00 00 00"));
    let mut answers = Vec::new();
    for byte in &stream {
        answers.extend(session.on_bytes(&mut board, &[*byte]).expect("open"));
    }
    let mut expected = hex("00 09 00 00 00 04 01 01 01 03");
    expected.extend(hex("01 01 02 01 05 00 00 10 0C 00 00 00"));
    assert_eq!(answers, expected);
}

#[test]
fn automatic_report_after_a_change() {
    let mut board = RelayBoard::default();
    let before = board.channels();
    send(&mut board, "00 00 00 00 00 06 01 05 02 02 FF 00");
    assert_eq!(
        board.report(before).map(|f| f.to_vec()),
        Some(hex("01 01 02 01 05 00 00 10 04 00 00 00"))
    );
    // No change, no report.
    assert_eq!(board.report(board.channels()), None);
    // Reporting off: changes are silent.
    send(&mut board, "00 00 00 00 00 06 01 05 1D 5C 00 00");
    let before = board.channels();
    send(&mut board, "24 01 02 00 00 05 00 01 00 00 00");
    assert_ne!(board.channels(), before);
    assert_eq!(board.report(before), None);
}

#[test]
fn modbus_exceptions() {
    let mut board = RelayBoard::default();
    for (request, answer) in [
        // Function 03: the board has no registers; not supported.
        (
            "00 01 00 00 00 06 01 03 02 00 00 01",
            "00 01 00 00 00 03 01 83 01",
        ),
        // Function 15 is not among the board's.
        (
            "00 01 00 00 00 08 01 0F 02 00 00 01 01 01",
            "00 01 00 00 00 03 01 8F 01",
        ),
        // Channel 33 does not exist; nor does coil 0.
        (
            "00 02 00 00 00 06 01 05 02 20 FF 00",
            "00 02 00 00 00 03 01 85 02",
        ),
        (
            "00 02 00 00 00 06 01 01 00 00 00 01",
            "00 02 00 00 00 03 01 81 02",
        ),
        // Reading 33 channels runs past the last.
        (
            "00 03 00 00 00 06 01 01 02 00 00 21",
            "00 03 00 00 00 03 01 81 02",
        ),
        // A coil value other than FF00/0000, a quantity of 0.
        (
            "00 04 00 00 00 06 01 05 02 00 12 34",
            "00 04 00 00 00 03 01 85 03",
        ),
        (
            "00 05 00 00 00 06 01 01 02 00 00 00",
            "00 05 00 00 00 03 01 81 03",
        ),
    ] {
        assert_eq!(send(&mut board, request), hex(answer), "{request}");
    }
    assert_eq!(board, RelayBoard::default(), "nothing changed");
    // The switch reads back through 01.
    assert_eq!(
        send(&mut board, "00 06 00 00 00 06 01 01 1D 5C 00 01"),
        hex("00 06 00 00 00 04 01 01 01 01")
    );
}

#[test]
fn garbage_closes_the_connection() {
    let mut board = RelayBoard::default();
    let mut session = RelaySession::new();
    assert!(session
        .on_bytes(&mut board, &hex("00 01 00 07 00 06 01 01"))
        .is_err());
    assert!(RelaySession::new()
        .on_bytes(&mut board, &hex("55 01 02 00 00 05 00"))
        .is_err());
    assert!(RelaySession::new()
        .on_bytes(&mut board, &hex("03 01 02 00 00 05 00 21 00 00 00 00"))
        .is_err());
}
