//! The 32-channel Modbus-TCP relay board's own frames (seed document 004) and how they
//! are told apart from Modbus TCP on the same connection. No I/O; the board itself is
//! `gutta_sim::relay`, its Modbus side the one Modbus slave.
//!
//! Three frames of the board's own, all beginning `CMD 01 02 00 00 05 00`:
//!
//! | frame | bytes |
//! | --- | --- |
//! | set 32 channels | `03 01 02 00 00 05 00 20 AA BB CC DD` |
//! | toggle 32 channels | `24 01 02 00 00 05 00 AA BB CC DD` |
//! | read 32 channels | `01 01 02 00 00 05 00 20 00 00 00 00` |
//! | its answer (and the automatic report) | `01 01 02 01 05 00 00 10 AA BB CC DD` |
//!
//! `AA BB CC DD` are the channels 1..32, one bit each, channel 1 in bit 0 of `AA`
//! (the order of Modbus coils), so they are the little-endian `u32` of [`Channels`].
//!
//! Telling them apart: read as an MBAP header, bytes 2 and 3 are the protocol id, which
//! Modbus TCP requires to be `00 00`; the board's frames have `02 00` there. So a
//! frame whose bytes 2-3 are `00 00` is Modbus TCP; one that starts with one of the three
//! prefixes is the board's own; anything else is neither (the board closes the
//! connection, as for a malformed MBAP header). Seven bytes decide (`classify`).

use crate::tcp::{MbapHeader, MAX_STANDARD_MBAP_LENGTH, MBAP_LEN};

/// The 32 channels, bit n = channel n + 1 (1 = on).
pub type Channels = u32;

/// The bytes after the command byte that all three request frames share.
pub const OWN_PREFIX: [u8; 6] = [0x01, 0x02, 0x00, 0x00, 0x05, 0x00];

/// Command byte of "set 32 channels".
pub const SET: u8 = 0x03;
/// Command byte of "toggle 32 channels".
pub const TOGGLE: u8 = 0x24;
/// Command byte of "read 32 channels" (and of its answer).
pub const READ: u8 = 0x01;
/// The count byte of set and read: 0x20, 32 channels.
pub const CHANNEL_COUNT: u8 = 0x20;

/// The byte the document's status frames carry where it says "XX: ignore" (every
/// example shows 10); the board sends it, clients ignore it.
pub const STATUS_XX: u8 = 0x10;

/// Bytes of a set or read frame and of the status frame.
pub const LONG_FRAME: usize = 12;
/// Bytes of a toggle frame.
pub const TOGGLE_FRAME: usize = 11;

/// A request in the board's own framing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RelayRequest {
    /// Channels become exactly these.
    Set(Channels),
    /// Channels whose bit is 1 change state.
    Toggle(Channels),
    /// Answered with the status frame.
    Read,
}

impl RelayRequest {
    /// The frame on the wire. `Read` carries four zero bytes, as in the document.
    pub fn encode(&self) -> Vec<u8> {
        let (command, count, data) = match *self {
            RelayRequest::Set(c) => (SET, Some(CHANNEL_COUNT), c),
            RelayRequest::Toggle(c) => (TOGGLE, None, c),
            RelayRequest::Read => (READ, Some(CHANNEL_COUNT), 0),
        };
        let mut out = vec![command];
        out.extend_from_slice(&OWN_PREFIX);
        out.extend(count);
        out.extend_from_slice(&data.to_le_bytes());
        out
    }

    /// Decodes exactly one whole frame. A read's four data bytes are ignored.
    pub fn decode(bytes: &[u8]) -> Result<Self, RelayError> {
        let command = *bytes.first().ok_or(RelayError::NotOwnFrame)?;
        let expected = own_frame_len(command).ok_or(RelayError::NotOwnFrame)?;
        if bytes.get(1..7) != Some(&OWN_PREFIX[..]) {
            return Err(RelayError::NotOwnFrame);
        }
        if bytes.len() != expected {
            return Err(RelayError::Length {
                command,
                expected,
                found: bytes.len(),
            });
        }
        let data = |from: usize| {
            Channels::from_le_bytes([
                bytes[from],
                bytes[from + 1],
                bytes[from + 2],
                bytes[from + 3],
            ])
        };
        if command != TOGGLE && bytes[7] != CHANNEL_COUNT {
            return Err(RelayError::Count { found: bytes[7] });
        }
        Ok(match command {
            SET => RelayRequest::Set(data(8)),
            TOGGLE => RelayRequest::Toggle(data(7)),
            _ => RelayRequest::Read,
        })
    }

    /// The channels after this request is carried out on `channels`.
    pub fn apply(&self, channels: Channels) -> Channels {
        match *self {
            RelayRequest::Set(c) => c,
            RelayRequest::Toggle(c) => channels ^ c,
            RelayRequest::Read => channels,
        }
    }
}

/// The status frame: the answer to `Read` and the automatic report.
pub fn status_frame(channels: Channels) -> [u8; LONG_FRAME] {
    let d = channels.to_le_bytes();
    [
        0x01, 0x01, 0x02, 0x01, 0x05, 0x00, 0x00, STATUS_XX, d[0], d[1], d[2], d[3],
    ]
}

/// The channels of a status frame (its XX byte ignored, as the document says).
pub fn decode_status(bytes: &[u8]) -> Result<Channels, RelayError> {
    match bytes {
        [0x01, 0x01, 0x02, 0x01, 0x05, 0x00, 0x00, _xx, a, b, c, d] => {
            Ok(Channels::from_le_bytes([*a, *b, *c, *d]))
        }
        _ => Err(RelayError::NotOwnFrame),
    }
}

/// Errors of the board's own frames.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RelayError {
    /// Not one of the three frames (nor a status frame).
    NotOwnFrame,
    /// The frame's length does not fit its command.
    Length {
        command: u8,
        expected: usize,
        found: usize,
    },
    /// Set or read with a count other than 0x20.
    Count { found: u8 },
}

impl std::fmt::Display for RelayError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RelayError::NotOwnFrame => f.write_str("not a relay board frame"),
            RelayError::Length {
                command,
                expected,
                found,
            } => write!(
                f,
                "relay frame {command:02X}: {found} bytes, expected {expected}"
            ),
            RelayError::Count { found } => {
                write!(f, "relay frame: channel count {found:02X}, expected 20")
            }
        }
    }
}

impl std::error::Error for RelayError {}

/// What the bytes at the start of a connection's buffer are.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Classified {
    /// Too few bytes to tell, or the frame is not complete yet.
    NeedMore,
    /// A Modbus TCP frame of this many bytes (its header checked: protocol id 0,
    /// length 2..=254).
    Mbap(usize),
    /// One of the board's own frames, this many bytes.
    Own(usize),
    /// Neither: a malformed MBAP header or an unknown frame.
    Invalid,
}

/// Bytes of the board's frame with this command byte.
fn own_frame_len(command: u8) -> Option<usize> {
    match command {
        SET | READ => Some(LONG_FRAME),
        TOGGLE => Some(TOGGLE_FRAME),
        _ => None,
    }
}

/// Tells the frame at the start of `buffer` (see the module documentation).
pub fn classify(buffer: &[u8]) -> Classified {
    if buffer.len() < MBAP_LEN {
        return Classified::NeedMore;
    }
    let whole = |len: usize| buffer.len() >= len;
    if buffer[2..4] == [0, 0] {
        return match MbapHeader::decode(buffer) {
            Ok(h) if h.length <= MAX_STANDARD_MBAP_LENGTH => {
                let len = h.frame_len();
                if whole(len) {
                    Classified::Mbap(len)
                } else {
                    Classified::NeedMore
                }
            }
            _ => Classified::Invalid,
        };
    }
    match own_frame_len(buffer[0]) {
        Some(len) if buffer[1..7] == OWN_PREFIX => {
            if whole(len) {
                Classified::Own(len)
            } else {
                Classified::NeedMore
            }
        }
        _ => Classified::Invalid,
    }
}
