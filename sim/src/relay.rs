//! The simulated 32-channel Modbus-TCP relay board (seed document 004), without I/O:
//! its state (`RelayBoard`) and one connection's byte stream (`RelaySession`). Modbus
//! TCP goes through the one Modbus slave (`modbus_data::serve_objects` on the board's
//! `ModbusObjects`); the board's own frames through `gutta_protocol::relay`. The
//! binary (`gutta-sim --device relay-board`) does the I/O and sends the reports.
//!
//! - Modbus: functions 01 and 05 only (others answer exception 01). Coils `0x0200 + n`
//!   are channel n + 1 (n = 0..=31); coil `0x1D5C` is the automatic-reporting switch
//!   (readable too). Any other coil answers exception 02, a bad quantity or coil value
//!   exception 03. Every unit id is answered.
//! - Own frames: set and toggle are carried out without an answer (the document shows
//!   none); read is answered with the status frame.
//! - Automatic reporting (on at power-up, as the document implies by telling the user to
//!   switch it off for debugging): after any change of the channels, whoever made it,
//!   the board sends the status frame `01 01 02 01 05 00 00 10 AA BB CC DD` on every
//!   connection ([`RelayBoard::report`]).
//! - A frame that is neither Modbus TCP nor an own frame ends the connection.

use gutta_catalog::ModbusTable;
use gutta_protocol::modbus::{ExceptionCode, READ_COILS, WRITE_SINGLE_COIL};
use gutta_protocol::relay::{classify, status_frame, Channels, Classified, RelayRequest};
use gutta_protocol::tcp::{decode_tcp, encode_tcp};

use crate::modbus_data::{serve_objects, ModbusObjects};
use crate::session::SessionError;

/// Coil of channel 1; channel n + 1 is `FIRST_CHANNEL_COIL + n`.
pub const FIRST_CHANNEL_COIL: u16 = 0x0200;
/// The number of channels.
pub const CHANNELS: u16 = 32;
/// The automatic-reporting switch (FF00 on, 0000 off).
pub const REPORTING_COIL: u16 = 0x1D5C;

/// The board: 32 channels and the reporting switch.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RelayBoard {
    channels: Channels,
    reporting: bool,
}

impl Default for RelayBoard {
    /// Power-up: every channel off, reporting on.
    fn default() -> Self {
        RelayBoard {
            channels: 0,
            reporting: true,
        }
    }
}

impl RelayBoard {
    pub fn channels(&self) -> Channels {
        self.channels
    }

    pub fn reporting(&self) -> bool {
        self.reporting
    }

    /// Channel `n` (1..=32) on?
    pub fn channel(&self, n: u8) -> bool {
        (1..=32).contains(&n) && self.channels & (1 << (n - 1)) != 0
    }

    /// What the board sends on every connection after its channels changed from
    /// `before`: the status frame when reporting is on, else nothing.
    pub fn report(&self, before: Channels) -> Option<[u8; 12]> {
        (self.reporting && self.channels != before).then(|| status_frame(self.channels))
    }

    /// Carries out one of the board's own requests; the answer, if it has one.
    pub fn own(&mut self, request: RelayRequest) -> Option<[u8; 12]> {
        self.channels = request.apply(self.channels);
        (request == RelayRequest::Read).then(|| status_frame(self.channels))
    }

    /// Answers one Modbus request PDU.
    pub fn modbus(&mut self, pdu: &[u8]) -> Vec<u8> {
        serve_objects(self, pdu)
    }
}

impl ModbusObjects for RelayBoard {
    fn supports(&self, function: u8) -> bool {
        matches!(function, READ_COILS | WRITE_SINGLE_COIL)
    }

    fn serves(&self, table: ModbusTable, wire: u16) -> bool {
        table == ModbusTable::Coil
            && (wire == REPORTING_COIL
                || (FIRST_CHANNEL_COIL..FIRST_CHANNEL_COIL + CHANNELS).contains(&wire))
    }

    fn read_object(&self, table: ModbusTable, wire: u16) -> Result<u32, ExceptionCode> {
        if !self.serves(table, wire) {
            return Err(ExceptionCode::IllegalDataAddress);
        }
        Ok(if wire == REPORTING_COIL {
            u32::from(self.reporting)
        } else {
            (self.channels >> (wire - FIRST_CHANNEL_COIL)) & 1
        })
    }

    fn write_object(
        &mut self,
        table: ModbusTable,
        wire: u16,
        value: u32,
    ) -> Result<(), ExceptionCode> {
        if !self.serves(table, wire) {
            return Err(ExceptionCode::IllegalDataAddress);
        }
        let on = value != 0;
        if wire == REPORTING_COIL {
            self.reporting = on;
        } else {
            let bit = 1 << (wire - FIRST_CHANNEL_COIL);
            self.channels = if on {
                self.channels | bit
            } else {
                self.channels & !bit
            };
        }
        Ok(())
    }
}

/// One connection to the board: its unsplit bytes.
#[derive(Debug, Default)]
pub struct RelaySession {
    buffer: Vec<u8>,
}

impl RelaySession {
    pub fn new() -> Self {
        RelaySession::default()
    }

    /// Bytes received; the answers to send (possibly none), or why the connection
    /// must close. Reports are the caller's (`RelayBoard::report`).
    pub fn on_bytes(
        &mut self,
        board: &mut RelayBoard,
        bytes: &[u8],
    ) -> Result<Vec<u8>, SessionError> {
        self.buffer.extend_from_slice(bytes);
        let mut out = Vec::new();
        loop {
            match classify(&self.buffer) {
                Classified::NeedMore => return Ok(out),
                Classified::Invalid => {
                    return Err(SessionError(
                        "neither a Modbus TCP frame nor a relay board frame".into(),
                    ))
                }
                Classified::Mbap(len) => {
                    let frame =
                        decode_tcp(&self.buffer[..len]).map_err(|e| SessionError(e.to_string()))?;
                    let pdu = board.modbus(&frame.pdu);
                    out.extend(encode_tcp(frame.transaction, frame.unit, &pdu).unwrap_or_default());
                    self.buffer.drain(..len);
                }
                Classified::Own(len) => {
                    let request = RelayRequest::decode(&self.buffer[..len])
                        .map_err(|e| SessionError(e.to_string()))?;
                    out.extend(board.own(request).into_iter().flatten());
                    self.buffer.drain(..len);
                }
            }
        }
    }
}
