//! The FX-style programming port (seed 001, GUTTA.md section 6) as plain data: control
//! bytes, `STX body ETX sumH sumL` frames, typed requests and replies, and a splitter
//! that cuts a byte stream into them. No I/O, no clock; no input makes it panic.
//! Byte tables and the decisions the document leaves open: docs/devices.md, "The
//! FX-style programming port".

use std::fmt;

/// Start of a frame.
pub const STX: u8 = 0x02;
/// End of a frame's body; two checksum characters follow.
pub const ETX: u8 = 0x03;
/// Enquiry (handshake): the device answers [`ACK`].
pub const ENQ: u8 = 0x05;
/// Positive answer.
pub const ACK: u8 = 0x06;
/// Negative answer: bad checksum or malformed frame.
pub const NAK: u8 = 0x15;

/// Most data bytes one request or reply carries: the length field is two hex digits.
pub const MAX_DATA: usize = 0xFF;
/// Longest frame on the wire: an `E11` write of [`MAX_DATA`] bytes
/// (STX, `E11`, 4 address and 2 length digits, the data as hex pairs, ETX, checksum).
pub const MAX_FRAME: usize = 1 + 3 + 4 + 2 + 2 * MAX_DATA + 1 + 2;
/// Where program memory starts (`E11` writes from here, `E01` reads from here).
pub const PROGRAM_START: u16 = 0x805C;
/// Where the configuration block starts (`E00` reads it).
pub const CONFIG_START: u16 = 0x8000;
/// How many bytes one `E01` frame of an upload reads (805C, 815A, 8258, 8356, ...).
pub const PROGRAM_CHUNK: u8 = 0xFE;
/// Program memory's size: from [`PROGRAM_START`] to the end of the 64 KiB address space.
pub const PROGRAM_SIZE: usize = 0x1_0000 - PROGRAM_START as usize;

/// The `E01`/`E11` frames of program memory `[PROGRAM_START, PROGRAM_START + size)`:
/// address and length, [`PROGRAM_CHUNK`] bytes each but the last (`size` at most
/// [`PROGRAM_SIZE`]).
pub fn program_chunks(size: usize) -> impl Iterator<Item = (u16, usize)> {
    let chunk = usize::from(PROGRAM_CHUNK);
    (0..size.min(PROGRAM_SIZE))
        .step_by(chunk)
        .map(move |offset| {
            // offset < PROGRAM_SIZE keeps every address inside 0x805C..=0xFFFF.
            let address = PROGRAM_START.wrapping_add(offset as u16);
            (address, chunk.min(size.min(PROGRAM_SIZE) - offset))
        })
}

/// Everything that can be wrong with a frame or a request.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FxError {
    /// Fewer bytes than the shortest frame (`STX ETX sumH sumL`).
    TooShort { len: usize },
    /// The frame does not start with STX.
    NoStx { found: u8 },
    /// No ETX three bytes before the end.
    NoEtx,
    /// The checksum characters are not the sum of the body and ETX.
    Checksum { computed: u8, found: [u8; 2] },
    /// A character that should be an ASCII hex digit is not one (index in the frame).
    NotHex { index: usize, byte: u8 },
    /// A command byte (or `E` sub-command) this port does not know.
    UnknownCommand { command: Vec<u8> },
    /// A body whose length does not fit its command.
    BadLength { expected: usize, found: usize },
    /// More data than a two-digit length field can describe.
    DataTooLong { len: usize },
    /// A frame longer than [`MAX_FRAME`] without its ETX.
    FrameTooLong,
    /// A new STX arrived before the frame in progress was complete.
    Interrupted,
}

impl fmt::Display for FxError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FxError::TooShort { len } => write!(f, "frame of {len} bytes is too short"),
            FxError::NoStx { found } => write!(f, "frame starts with {found:02X}, not STX 02"),
            FxError::NoEtx => write!(f, "no ETX 03 before the two checksum characters"),
            FxError::Checksum { computed, found } => write!(
                f,
                "checksum {:?} in the frame, {computed:02X} computed",
                String::from_utf8_lossy(found)
            ),
            FxError::NotHex { index, byte } => {
                write!(f, "byte {index} ({byte:02X}) is not an ASCII hex digit")
            }
            FxError::UnknownCommand { command } => {
                write!(f, "unknown command {:?}", String::from_utf8_lossy(command))
            }
            FxError::BadLength { expected, found } => {
                write!(
                    f,
                    "body of {found} bytes where the command needs {expected}"
                )
            }
            FxError::DataTooLong { len } => {
                write!(
                    f,
                    "{len} data bytes, more than the {MAX_DATA} a frame carries"
                )
            }
            FxError::FrameTooLong => write!(f, "frame longer than {MAX_FRAME} bytes"),
            FxError::Interrupted => write!(f, "frame interrupted by a new STX"),
        }
    }
}

impl std::error::Error for FxError {}

/// The checksum of a frame: the low byte of the sum of every byte after STX up to and
/// including ETX. `body` is what lies between STX and ETX.
pub fn checksum(body: &[u8]) -> u8 {
    body.iter().fold(ETX, |sum, &byte| sum.wrapping_add(byte))
}

const HEX_DIGITS: &[u8; 16] = b"0123456789ABCDEF";

/// A byte as two upper-case ASCII hex digits.
pub fn hex_pair(byte: u8) -> [u8; 2] {
    [
        HEX_DIGITS[usize::from(byte >> 4)],
        HEX_DIGITS[usize::from(byte & 0x0F)],
    ]
}

fn push_hex(out: &mut Vec<u8>, bytes: &[u8]) {
    for &byte in bytes {
        out.extend_from_slice(&hex_pair(byte));
    }
}

fn hex_value(byte: u8) -> Option<u8> {
    match byte {
        b'0'..=b'9' => Some(byte - b'0'),
        b'A'..=b'F' => Some(byte - b'A' + 10),
        b'a'..=b'f' => Some(byte - b'a' + 10),
        _ => None,
    }
}

/// ASCII hex pairs to bytes; `offset` is where `text` starts in the frame (for errors).
fn parse_hex(text: &[u8], offset: usize) -> Result<Vec<u8>, FxError> {
    if !text.len().is_multiple_of(2) {
        return Err(FxError::BadLength {
            expected: text.len() + 1,
            found: text.len(),
        });
    }
    text.chunks(2)
        .enumerate()
        .map(|(n, pair)| {
            let digit = |i: usize| {
                hex_value(pair[i]).ok_or(FxError::NotHex {
                    index: offset + 2 * n + i,
                    byte: pair[i],
                })
            };
            Ok(digit(0)? << 4 | digit(1)?)
        })
        .collect()
}

/// `STX body ETX sumH sumL`.
pub fn encode_frame(body: &[u8]) -> Vec<u8> {
    let mut frame = Vec::with_capacity(body.len() + 4);
    frame.push(STX);
    frame.extend_from_slice(body);
    frame.push(ETX);
    frame.extend_from_slice(&hex_pair(checksum(body)));
    frame
}

/// The body of a whole frame (between STX and ETX), its checksum checked.
pub fn decode_frame(frame: &[u8]) -> Result<&[u8], FxError> {
    if frame.len() < 4 {
        return Err(FxError::TooShort { len: frame.len() });
    }
    if frame[0] != STX {
        return Err(FxError::NoStx { found: frame[0] });
    }
    let etx = frame.len() - 3;
    if frame[etx] != ETX {
        return Err(FxError::NoEtx);
    }
    let body = &frame[1..etx];
    let found = [frame[etx + 1], frame[etx + 2]];
    let computed = checksum(body);
    let matches = match (hex_value(found[0]), hex_value(found[1])) {
        (Some(high), Some(low)) => high << 4 | low == computed,
        _ => false,
    };
    if !matches {
        return Err(FxError::Checksum { computed, found });
    }
    Ok(body)
}

/// The rates of command `41`; the byte after `41` selects one, any other byte 9600.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BaudRate {
    B9600,
    B19200,
    B38400,
    B57600,
    B115200,
}

impl BaudRate {
    /// All rates, slowest first.
    pub const ALL: [BaudRate; 5] = [
        BaudRate::B9600,
        BaudRate::B19200,
        BaudRate::B38400,
        BaudRate::B57600,
        BaudRate::B115200,
    ];

    /// The selector byte after `41`; 9600 is sent as `30` (the document: "other").
    pub fn code(self) -> u8 {
        match self {
            BaudRate::B9600 => 0x30,
            BaudRate::B19200 => 0x31,
            BaudRate::B38400 => 0x32,
            BaudRate::B57600 => 0x33,
            BaudRate::B115200 => 0x35,
        }
    }

    /// The rate a selector byte chooses: `31` 19200, `32` 38400, `33` 57600,
    /// `35` 115200, anything else 9600.
    pub fn from_code(code: u8) -> BaudRate {
        match code {
            0x31 => BaudRate::B19200,
            0x32 => BaudRate::B38400,
            0x33 => BaudRate::B57600,
            0x35 => BaudRate::B115200,
            _ => BaudRate::B9600,
        }
    }

    /// Bits per second.
    pub fn bits_per_second(self) -> u32 {
        match self {
            BaudRate::B9600 => 9600,
            BaudRate::B19200 => 19200,
            BaudRate::B38400 => 38400,
            BaudRate::B57600 => 57600,
            BaudRate::B115200 => 115_200,
        }
    }

    /// The rate of a number of bits per second, if the port has it.
    pub fn from_bits_per_second(bps: u32) -> Option<BaudRate> {
        BaudRate::ALL
            .into_iter()
            .find(|rate| rate.bits_per_second() == bps)
    }
}

impl fmt::Display for BaudRate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.bits_per_second())
    }
}

/// A request to the port. Addresses are device addresses (docs/devices.md, memory map).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FxRequest {
    /// `ENQ` alone (not a frame): the device answers ACK.
    Enquiry,
    /// `30`: read `len` bytes from `address` (address high byte first).
    Read { address: u16, len: u8 },
    /// `31`: write `data` at `address`.
    Write { address: u16, data: Vec<u8> },
    /// `37`: force the bit at bit address `bit` on (address low byte first).
    ForceOn { bit: u16 },
    /// `38`: force the bit off.
    ForceOff { bit: u16 },
    /// `41`: switch the line's rate after the ACK.
    Baud(BaudRate),
    /// `E00`: read `len` bytes of the configuration block from `address`.
    ReadConfig { address: u16, len: u8 },
    /// `E01`: read `len` bytes of program memory from `address`.
    ReadProgram { address: u16, len: u8 },
    /// `E11`: write `data` into program memory at `address`.
    WriteProgram { address: u16, data: Vec<u8> },
    /// `E87`: end of a program write.
    EndProgramWrite,
}

const CMD_READ: u8 = 0x30;
const CMD_WRITE: u8 = 0x31;
const CMD_FORCE_ON: u8 = 0x37;
const CMD_FORCE_OFF: u8 = 0x38;
const CMD_BAUD: u8 = 0x41;
const CMD_E: u8 = 0x45;

fn push_address_len(body: &mut Vec<u8>, address: u16, len: u8) {
    push_hex(body, &address.to_be_bytes());
    push_hex(body, &[len]);
}

fn data_len(data: &[u8]) -> Result<u8, FxError> {
    u8::try_from(data.len()).map_err(|_| FxError::DataTooLong { len: data.len() })
}

/// `address(4) len(2)` at `fields` (frame offset `offset`), and the hex data after them
/// when `with_data`: exactly `len` pairs.
fn parse_address_len(
    fields: &[u8],
    offset: usize,
    with_data: bool,
) -> Result<(u16, u8, Vec<u8>), FxError> {
    if fields.len() < 6 || (!with_data && fields.len() != 6) {
        return Err(FxError::BadLength {
            expected: 6,
            found: fields.len(),
        });
    }
    let head = parse_hex(&fields[..6], offset)?;
    let address = u16::from_be_bytes([head[0], head[1]]);
    let len = head[2];
    if !with_data {
        return Ok((address, len, Vec::new()));
    }
    let text = &fields[6..];
    if text.len() != 2 * usize::from(len) {
        return Err(FxError::BadLength {
            expected: 6 + 2 * usize::from(len),
            found: fields.len(),
        });
    }
    Ok((address, len, parse_hex(text, offset + 6)?))
}

impl FxRequest {
    /// The bytes on the wire: a frame, or the single ENQ byte.
    pub fn encode(&self) -> Result<Vec<u8>, FxError> {
        let mut body = Vec::new();
        match self {
            FxRequest::Enquiry => return Ok(vec![ENQ]),
            FxRequest::Read { address, len } => {
                body.push(CMD_READ);
                push_address_len(&mut body, *address, *len);
            }
            FxRequest::Write { address, data } => {
                body.push(CMD_WRITE);
                push_address_len(&mut body, *address, data_len(data)?);
                push_hex(&mut body, data);
            }
            FxRequest::ForceOn { bit } | FxRequest::ForceOff { bit } => {
                body.push(if matches!(self, FxRequest::ForceOn { .. }) {
                    CMD_FORCE_ON
                } else {
                    CMD_FORCE_OFF
                });
                push_hex(&mut body, &bit.to_le_bytes());
            }
            FxRequest::Baud(rate) => {
                body.push(CMD_BAUD);
                body.push(rate.code());
            }
            FxRequest::ReadConfig { address, len } => {
                body.extend_from_slice(b"E00");
                push_address_len(&mut body, *address, *len);
            }
            FxRequest::ReadProgram { address, len } => {
                body.extend_from_slice(b"E01");
                push_address_len(&mut body, *address, *len);
            }
            FxRequest::WriteProgram { address, data } => {
                body.extend_from_slice(b"E11");
                push_address_len(&mut body, *address, data_len(data)?);
                push_hex(&mut body, data);
            }
            FxRequest::EndProgramWrite => body.extend_from_slice(b"E87"),
        }
        Ok(encode_frame(&body))
    }

    /// A whole frame (STX through the checksum) as a request. ENQ is a splitter token,
    /// not a frame: see [`FxToken::Enq`].
    pub fn decode(frame: &[u8]) -> Result<FxRequest, FxError> {
        let body = decode_frame(frame)?;
        let Some((&command, fields)) = body.split_first() else {
            return Err(FxError::UnknownCommand {
                command: Vec::new(),
            });
        };
        // Frame offset of `fields`: STX and the command byte come first.
        let offset = 2;
        match command {
            CMD_READ => {
                let (address, len, _) = parse_address_len(fields, offset, false)?;
                Ok(FxRequest::Read { address, len })
            }
            CMD_WRITE => {
                let (address, _, data) = parse_address_len(fields, offset, true)?;
                Ok(FxRequest::Write { address, data })
            }
            CMD_FORCE_ON | CMD_FORCE_OFF => {
                if fields.len() != 4 {
                    return Err(FxError::BadLength {
                        expected: 4,
                        found: fields.len(),
                    });
                }
                let bytes = parse_hex(fields, offset)?;
                let bit = u16::from_le_bytes([bytes[0], bytes[1]]);
                Ok(if command == CMD_FORCE_ON {
                    FxRequest::ForceOn { bit }
                } else {
                    FxRequest::ForceOff { bit }
                })
            }
            CMD_BAUD => match fields {
                [code] => Ok(FxRequest::Baud(BaudRate::from_code(*code))),
                _ => Err(FxError::BadLength {
                    expected: 1,
                    found: fields.len(),
                }),
            },
            CMD_E => {
                if fields.len() < 2 {
                    return Err(FxError::UnknownCommand {
                        command: body.to_vec(),
                    });
                }
                let (sub, rest) = fields.split_at(2);
                let offset = offset + 2;
                match sub {
                    b"00" => {
                        let (address, len, _) = parse_address_len(rest, offset, false)?;
                        Ok(FxRequest::ReadConfig { address, len })
                    }
                    b"01" => {
                        let (address, len, _) = parse_address_len(rest, offset, false)?;
                        Ok(FxRequest::ReadProgram { address, len })
                    }
                    b"11" => {
                        let (address, _, data) = parse_address_len(rest, offset, true)?;
                        Ok(FxRequest::WriteProgram { address, data })
                    }
                    b"87" if rest.is_empty() => Ok(FxRequest::EndProgramWrite),
                    b"87" => Err(FxError::BadLength {
                        expected: 0,
                        found: rest.len(),
                    }),
                    _ => Err(FxError::UnknownCommand {
                        command: body[..3].to_vec(),
                    }),
                }
            }
            _ => Err(FxError::UnknownCommand {
                command: vec![command],
            }),
        }
    }
}

/// What the device answers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FxReply {
    Ack,
    Nak,
    /// `STX data-as-hex-pairs ETX sumH sumL`, the answer to `30`, `E00` and `E01`.
    Data(Vec<u8>),
}

impl FxReply {
    /// The bytes on the wire.
    pub fn encode(&self) -> Vec<u8> {
        match self {
            FxReply::Ack => vec![ACK],
            FxReply::Nak => vec![NAK],
            FxReply::Data(data) => {
                let mut body = Vec::with_capacity(2 * data.len());
                push_hex(&mut body, data);
                encode_frame(&body)
            }
        }
    }

    /// A splitter token as a reply; ENQ and broken frames are errors here.
    pub fn from_token(token: FxToken) -> Result<FxReply, FxError> {
        match token {
            FxToken::Ack => Ok(FxReply::Ack),
            FxToken::Nak => Ok(FxReply::Nak),
            FxToken::Enq => Err(FxError::UnknownCommand { command: vec![ENQ] }),
            FxToken::Frame(frame) => FxReply::decode_data(&frame),
            FxToken::Broken(error) => Err(error),
        }
    }

    /// A whole data frame as a reply.
    pub fn decode_data(frame: &[u8]) -> Result<FxReply, FxError> {
        let body = decode_frame(frame)?;
        Ok(FxReply::Data(parse_hex(body, 1)?))
    }
}

/// One unit of a byte stream: a control byte, a whole frame (not yet decoded), or a
/// frame the splitter had to give up on.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FxToken {
    Enq,
    Ack,
    Nak,
    /// STX through the second checksum character.
    Frame(Vec<u8>),
    /// A frame cut short by a new STX, or longer than [`MAX_FRAME`].
    Broken(FxError),
}

/// Cuts a byte stream into [`FxToken`]s. Outside a frame, bytes other than STX, ENQ,
/// ACK and NAK are dropped (counted in [`FxSplitter::dropped`]); inside one, every byte
/// belongs to the frame until ETX and two more, except STX, which starts a new one.
#[derive(Debug, Default)]
pub struct FxSplitter {
    frame: Vec<u8>,
    in_frame: bool,
    /// Checksum characters still expected after ETX, when ETX has been seen.
    after_etx: Option<u8>,
    /// Bytes between frames that were not control bytes.
    pub dropped: u64,
    /// Bytes of a too-long frame still to skip, up to the next STX.
    skipping: bool,
}

impl FxSplitter {
    pub fn new() -> FxSplitter {
        FxSplitter::default()
    }

    /// Feeds bytes; returns every token they complete, in order.
    pub fn push(&mut self, bytes: &[u8]) -> Vec<FxToken> {
        let mut tokens = Vec::new();
        for &byte in bytes {
            if let Some(token) = self.push_byte(byte) {
                tokens.push(token);
            }
        }
        tokens
    }

    /// True when a frame has started and is not complete yet.
    pub fn is_mid_frame(&self) -> bool {
        self.in_frame
    }

    fn push_byte(&mut self, byte: u8) -> Option<FxToken> {
        if byte == STX {
            let interrupted = self.in_frame;
            self.start_frame();
            return interrupted.then_some(FxToken::Broken(FxError::Interrupted));
        }
        if !self.in_frame {
            return match byte {
                ENQ if !self.skipping => Some(FxToken::Enq),
                ACK if !self.skipping => Some(FxToken::Ack),
                NAK if !self.skipping => Some(FxToken::Nak),
                _ => {
                    self.dropped += 1;
                    None
                }
            };
        }
        self.frame.push(byte);
        match self.after_etx {
            Some(1) => {
                self.in_frame = false;
                self.after_etx = None;
                Some(FxToken::Frame(std::mem::take(&mut self.frame)))
            }
            Some(n) => {
                self.after_etx = Some(n - 1);
                None
            }
            None if byte == ETX => {
                self.after_etx = Some(2);
                None
            }
            None if self.frame.len() > MAX_FRAME - 2 => {
                self.in_frame = false;
                self.skipping = true;
                self.frame.clear();
                Some(FxToken::Broken(FxError::FrameTooLong))
            }
            None => None,
        }
    }

    fn start_frame(&mut self) {
        self.frame.clear();
        self.frame.push(STX);
        self.in_frame = true;
        self.after_etx = None;
        self.skipping = false;
    }
}
