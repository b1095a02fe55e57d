//! One client connection's byte stream, without I/O: bytes in, answer bytes out. Modbus
//! TCP (MBAP) or Modbus RTU (on a serial line or over TCP); frames are split with
//! gutta-protocol's splitters and answered by the PLC.
//!
//! - RTU: a frame with a bad CRC is dropped without an answer, as Modbus RTU requires;
//!   the splitter resynchronises. A frame for another station is ignored. Broadcast
//!   (station 0) is answered for function 13 (UM4001) and executed without an answer
//!   for the data functions.
//! - TCP: every unit id is answered (the simulator is the only device behind its
//!   address); a frame whose MBAP header is malformed (protocol id not 0, impossible
//!   length) ends the connection.
//! - Function 13 with malformed GUTTA data answers exception 03; one the download
//!   safety rule refuses (another connection's download window is open) answers
//!   exception 06, Server Device Busy, so the client can tell "busy" from the failure
//!   form UM4001 gives every other refusal.
//! - Each session carries the `ConnectionId` the binary gave its connection; the PLC
//!   keys download windows on it.

use gutta_protocol::gutta::GuttaFrame;
use gutta_protocol::rtu::{decode_rtu, encode_rtu};
use gutta_protocol::stream::{RtuSplitter, Side, TcpSplitter};
use gutta_protocol::tcp::{decode_tcp, encode_tcp};

use crate::modbus_data::{exception, is_data_function};
use crate::plc::{ConnectionId, Plc, Refusal};
use gutta_protocol::modbus::ExceptionCode;

/// Modbus function 13: the GUTTA protocol.
pub const GUTTA_FUNCTION: u8 = 0x0D;

/// How a connection frames Modbus.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Framing {
    /// Modbus TCP: MBAP header, no CRC.
    Tcp,
    /// Modbus RTU: station, PDU, CRC (serial lines and RTU over TCP).
    Rtu,
}

/// Why a connection must be closed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SessionError(pub String);

impl std::fmt::Display for SessionError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for SessionError {}

/// The state of one connection.
#[derive(Debug)]
pub struct Session {
    framing: Framing,
    connection: ConnectionId,
    rtu: RtuSplitter,
    tcp: TcpSplitter,
    /// Frames dropped (bad CRC, resynchronisation), for logs.
    pub dropped: u64,
    /// Requests refused as busy (another connection's download window), for logs.
    pub busy: u64,
}

/// The answer PDU to a request PDU from `from`.
pub fn answer(plc: &mut Plc, from: ConnectionId, pdu: &[u8], now_ms: u64) -> Vec<u8> {
    answer_counting(plc, from, pdu, now_ms, &mut 0)
}

/// `answer`, counting busy refusals in `busy`.
fn answer_counting(
    plc: &mut Plc,
    from: ConnectionId,
    pdu: &[u8],
    now_ms: u64,
    busy: &mut u64,
) -> Vec<u8> {
    match pdu.first() {
        Some(&GUTTA_FUNCTION) => match GuttaFrame::from_pdu(pdu) {
            Ok(request) => {
                let frame = plc.answer(from, &request, now_ms);
                match plc.last_refusal() {
                    Some(Refusal::Busy { .. }) => {
                        *busy += 1;
                        return exception(GUTTA_FUNCTION, ExceptionCode::ServerDeviceBusy);
                    }
                    // The failure form cannot say why; the lockout must not read as a
                    // wrong password (docs/simulator.md, password policy).
                    Some(Refusal::LockedOut { .. }) => {
                        return exception(GUTTA_FUNCTION, ExceptionCode::ServerDeviceFailure);
                    }
                    _ => {}
                }
                frame
                    .to_pdu()
                    .unwrap_or_else(|_| exception(GUTTA_FUNCTION, ExceptionCode::IllegalDataValue))
            }
            Err(_) => exception(GUTTA_FUNCTION, ExceptionCode::IllegalDataValue),
        },
        Some(&f) if is_data_function(f) => plc.modbus(pdu),
        Some(&f) => exception(f, ExceptionCode::IllegalFunction),
        None => exception(0, ExceptionCode::IllegalFunction),
    }
}

impl Session {
    pub fn connection(&self) -> ConnectionId {
        self.connection
    }

    /// A session of connection `connection` (the binary numbers its connections).
    pub fn new(framing: Framing, connection: ConnectionId) -> Session {
        Session {
            framing,
            connection,
            rtu: RtuSplitter::new(Side::Slave),
            tcp: TcpSplitter::new(260),
            dropped: 0,
            busy: 0,
        }
    }

    /// Bytes received; the answer bytes to send (possibly none).
    pub fn on_bytes(
        &mut self,
        plc: &mut Plc,
        bytes: &[u8],
        now_ms: u64,
    ) -> Result<Vec<u8>, SessionError> {
        let mut out = Vec::new();
        match self.framing {
            Framing::Tcp => {
                self.tcp.push(bytes);
                while let Some(frame) = self.tcp.next_frame() {
                    let frame = frame.map_err(|e| SessionError(e.to_string()))?;
                    let frame = decode_tcp(&frame).map_err(|e| SessionError(e.to_string()))?;
                    let pdu =
                        answer_counting(plc, self.connection, &frame.pdu, now_ms, &mut self.busy);
                    if let Some(bytes) = encode_tcp(frame.transaction, frame.unit, &pdu) {
                        out.extend(bytes);
                    }
                }
            }
            Framing::Rtu => {
                self.rtu.push(bytes);
                while let Some(frame) = self.rtu.next_frame() {
                    let Ok(frame) = frame else {
                        self.dropped += 1;
                        continue;
                    };
                    let Ok(frame) = decode_rtu(&frame) else {
                        self.dropped += 1;
                        continue;
                    };
                    let station = plc.station();
                    let broadcast = frame.station == 0;
                    if frame.station != station && !broadcast {
                        continue;
                    }
                    let pdu =
                        answer_counting(plc, self.connection, &frame.pdu, now_ms, &mut self.busy);
                    if !broadcast || frame.function() == Some(GUTTA_FUNCTION) {
                        // A broadcast is answered with the PLC's own station.
                        out.extend(encode_rtu(station, &pdu));
                    }
                }
            }
        }
        Ok(out)
    }
}
