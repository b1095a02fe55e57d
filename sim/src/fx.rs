//! The simulated FX-style programming port (seed 001): a 64 KiB memory behind
//! `gutta_protocol::fx` requests, answering bytes with bytes. No I/O: `gutta-sim --device
//! fx` carries the bytes and applies a baud switch after writing the ACK.
//!
//! Memory map (docs/devices.md, "The FX-style programming port"):
//!
//! | range | what | commands |
//! | --- | --- | --- |
//! | `0000-7FFF` | data area | `30` read, `31` write |
//! | `0000-1FFF` (bits `0000-FFFF`) | bit area: bit address `A` is bit `A & 7` of byte `A >> 3` | `37` force on, `38` force off |
//! | `8000-805B` | configuration block | `E00` read (`E01` too), never written |
//! | `805C-FFFF` | program memory | `E01` read (`E00` too), `E11` write |
//!
//! Factory content: zeros, except `8000-80FD`, which holds the document's `E00` answer
//! (the configuration block and the first 0xA2 bytes of program memory).
//! Bad checksums and malformed frames get NAK; stray bytes between frames get nothing.

use gutta_protocol::fx::{
    BaudRate, FxReply, FxRequest, FxSplitter, FxToken, CONFIG_START, PROGRAM_START,
};

/// The document's `E00 8000 FE` answer, the factory content of `8000-80FD`: the first
/// 508 hex digits (0xFE bytes) of the 511 it prints; the last three, all `0`, lie beyond
/// the requested length.
pub const FACTORY_CONFIG_HEX: &str = concat!(
    "C800FB5E080010000000B3FF00000000000000000A0000000A00000000000000",
    "00000000000000000A0000001800000000000000000000000000000005000000",
    "0200030009A040000000000000000000FFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFF",
    "0000FFFF05000500050005000500050005000500050005000000000000000000",
    "0000000000000000000000000000000000000000000000000000000000000000",
    "0000000000000000000000000000000000000000000000000000000000000000",
    "0000000000000000000000000000000000000000000000000000000000000000",
    "000000000000000000000000000000000115713F10000000000000000000",
);

/// End of the data area (exclusive): `30`/`31` stay below it.
pub const DATA_END: usize = 0x8000;

/// What one feed of bytes produced.
#[derive(Debug, Default, Clone, PartialEq, Eq)]
pub struct FxOutput {
    /// The bytes to send back, in order.
    pub reply: Vec<u8>,
    /// A rate to switch the line to once `reply` has been written (after its ACK).
    pub switch_to: Option<BaudRate>,
}

/// The device: memory, line rate, program-write bookkeeping, and the splitter of
/// [`FxDevice::feed`]'s line.
#[derive(Debug)]
pub struct FxDevice {
    memory: Vec<u8>,
    baud: BaudRate,
    splitter: FxSplitter,
    program_write_open: bool,
    program_writes_ended: u32,
    naks: u64,
}

impl Default for FxDevice {
    fn default() -> Self {
        FxDevice::new()
    }
}

impl FxDevice {
    /// A device with its factory memory, at 9600 baud.
    pub fn new() -> FxDevice {
        let mut memory = vec![0u8; 0x1_0000];
        let factory = factory_config();
        let start = usize::from(CONFIG_START);
        memory[start..start + factory.len()].copy_from_slice(&factory);
        FxDevice {
            memory,
            baud: BaudRate::B9600,
            splitter: FxSplitter::new(),
            program_write_open: false,
            program_writes_ended: 0,
            naks: 0,
        }
    }

    /// The line rate the device listens at now.
    pub fn baud(&self) -> BaudRate {
        self.baud
    }

    /// The whole 64 KiB memory.
    pub fn memory(&self) -> &[u8] {
        &self.memory
    }

    /// How many program writes `E87` has closed.
    pub fn program_writes_ended(&self) -> u32 {
        self.program_writes_ended
    }

    /// How many NAKs the device has sent.
    pub fn naks(&self) -> u64 {
        self.naks
    }

    /// Bytes from the device's one line in, the answer out. Partial frames wait for the
    /// next feed.
    pub fn feed(&mut self, bytes: &[u8]) -> FxOutput {
        let mut splitter = std::mem::take(&mut self.splitter);
        let output = self.feed_from(&mut splitter, bytes);
        self.splitter = splitter;
        output
    }

    /// As [`FxDevice::feed`], for one of several connections to the same device: each
    /// brings its own splitter.
    pub fn feed_from(&mut self, splitter: &mut FxSplitter, bytes: &[u8]) -> FxOutput {
        let mut output = FxOutput::default();
        for token in splitter.push(bytes) {
            let reply = match token {
                FxToken::Enq => Some(FxReply::Ack),
                // A peer's ACK or NAK asks nothing.
                FxToken::Ack | FxToken::Nak => None,
                FxToken::Broken(_) => Some(FxReply::Nak),
                FxToken::Frame(frame) => Some(match FxRequest::decode(&frame) {
                    Ok(request) => {
                        let (reply, switch) = self.answer(&request);
                        if switch.is_some() {
                            output.switch_to = switch;
                        }
                        reply
                    }
                    Err(_) => FxReply::Nak,
                }),
            };
            if let Some(reply) = reply {
                if reply == FxReply::Nak {
                    self.naks += 1;
                }
                output.reply.extend(reply.encode());
            }
        }
        output
    }

    /// One decoded request: the reply and, for `41`, the rate to switch to after it.
    pub fn answer(&mut self, request: &FxRequest) -> (FxReply, Option<BaudRate>) {
        let reply = match request {
            FxRequest::Enquiry => FxReply::Ack,
            FxRequest::Read { address, len } => self.read(*address, *len, 0, DATA_END),
            FxRequest::Write { address, data } => self.write(*address, data, 0, DATA_END),
            FxRequest::ForceOn { bit } => self.force(*bit, true),
            FxRequest::ForceOff { bit } => self.force(*bit, false),
            FxRequest::Baud(rate) => {
                self.baud = *rate;
                return (FxReply::Ack, Some(*rate));
            }
            FxRequest::ReadConfig { address, len } | FxRequest::ReadProgram { address, len } => {
                self.read(*address, *len, usize::from(CONFIG_START), self.memory.len())
            }
            FxRequest::WriteProgram { address, data } => {
                let reply = self.write(
                    *address,
                    data,
                    usize::from(PROGRAM_START),
                    self.memory.len(),
                );
                if reply == FxReply::Ack {
                    self.program_write_open = true;
                }
                reply
            }
            FxRequest::EndProgramWrite => {
                if self.program_write_open {
                    self.program_writes_ended += 1;
                }
                self.program_write_open = false;
                FxReply::Ack
            }
        };
        (reply, None)
    }

    /// `[address, address + len)` when it lies inside `[start, end)` and is not empty.
    fn range(address: u16, len: usize, start: usize, end: usize) -> Option<std::ops::Range<usize>> {
        let from = usize::from(address);
        let to = from + len;
        (len > 0 && from >= start && to <= end).then_some(from..to)
    }

    fn read(&self, address: u16, len: u8, start: usize, end: usize) -> FxReply {
        match FxDevice::range(address, usize::from(len), start, end) {
            Some(range) => FxReply::Data(self.memory[range].to_vec()),
            None => FxReply::Nak,
        }
    }

    fn write(&mut self, address: u16, data: &[u8], start: usize, end: usize) -> FxReply {
        match FxDevice::range(address, data.len(), start, end) {
            Some(range) => {
                self.memory[range].copy_from_slice(data);
                FxReply::Ack
            }
            None => FxReply::Nak,
        }
    }

    fn force(&mut self, bit: u16, on: bool) -> FxReply {
        let byte = &mut self.memory[usize::from(bit >> 3)];
        let mask = 1u8 << (bit & 7);
        if on {
            *byte |= mask;
        } else {
            *byte &= !mask;
        }
        FxReply::Ack
    }
}

/// [`FACTORY_CONFIG_HEX`] as bytes.
pub fn factory_config() -> Vec<u8> {
    FACTORY_CONFIG_HEX
        .as_bytes()
        .chunks(2)
        .map(|pair| {
            let digit = |c: u8| (c as char).to_digit(16).unwrap_or(0) as u8;
            digit(pair[0]) << 4 | digit(pair[1])
        })
        .collect()
}
