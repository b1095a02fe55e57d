//! A Modbus RTU <-> Modbus TCP gateway as plain data: an RTU request frame from a serial
//! master (a PLC's EXCH) becomes a Modbus TCP request, the TCP answer becomes the RTU
//! answer frame. What a serial-to-Ethernet gateway does between its two sides; the
//! sockets are the caller's (gutta-sim's `--port0 modbus-tcp:`). No I/O, no clock.
//!
//! Rules: the request's CRC must check and its station must be 0 (broadcast) or
//! 1..=247, or the frame is dropped (the master hears silence, as from a real gateway).
//! The unit id is the station. A broadcast expects no answer, except GUTTA function 13
//! (as the master's rule, `master::expects_answer`). An answer belongs to the request
//! when its transaction id, unit id and function (or its exception) match; anything
//! else on the TCP side is not the answer and is skipped.

use std::fmt;

use crate::master::expects_answer;
use crate::modbus::EXCEPTION_BIT;
use crate::rtu::{decode_rtu, encode_rtu, FrameError};
use crate::tcp::{decode_tcp, encode_tcp};

/// The highest station of a Modbus slave (248..=255 are reserved).
pub const MAX_STATION: u8 = 247;

/// Why a request frame from the serial side is dropped.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum DropReason {
    /// Too short, or its CRC does not check.
    Frame(FrameError),
    /// A reserved station (248..=255).
    ReservedStation(u8),
}

impl fmt::Display for DropReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DropReason::Frame(e) => write!(f, "request dropped: {e}"),
            DropReason::ReservedStation(s) => {
                write!(f, "request dropped: station {s} is reserved")
            }
        }
    }
}

impl std::error::Error for DropReason {}

/// A request on its way to the TCP side.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Forwarded {
    pub transaction: u16,
    /// The RTU station, sent as the unit id.
    pub station: u8,
    pub function: u8,
    /// The Modbus TCP frame to send (MBAP header and PDU).
    pub tcp: Vec<u8>,
    /// Whether the serial master waits for an answer (not for a broadcast).
    pub answered: bool,
}

/// Why a TCP frame is not the answer to a forwarded request.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum NotTheAnswer {
    /// Not a whole Modbus TCP frame.
    Frame(FrameError),
    Transaction {
        found: u16,
    },
    Unit {
        found: u8,
    },
    Function {
        found: u8,
    },
}

impl fmt::Display for NotTheAnswer {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NotTheAnswer::Frame(e) => write!(f, "not a Modbus TCP frame: {e}"),
            NotTheAnswer::Transaction { found } => write!(f, "other transaction {found}"),
            NotTheAnswer::Unit { found } => write!(f, "other unit {found}"),
            NotTheAnswer::Function { found } => write!(f, "other function {found:02X}"),
        }
    }
}

impl std::error::Error for NotTheAnswer {}

/// The gateway's state: the transaction id of the next request (1, 2, ... wrapping).
#[derive(Debug, Clone, Default)]
pub struct Gateway {
    last_transaction: u16,
}

impl Gateway {
    pub fn new() -> Self {
        Gateway::default()
    }

    /// Checks an RTU request frame (CRC included) and turns it into a Modbus TCP
    /// request under the next transaction id.
    pub fn forward(&mut self, rtu: &[u8]) -> Result<Forwarded, DropReason> {
        let frame = decode_rtu(rtu).map_err(DropReason::Frame)?;
        if frame.station > MAX_STATION {
            return Err(DropReason::ReservedStation(frame.station));
        }
        // decode_rtu leaves at least the function code in the PDU.
        let function = frame.function().unwrap_or(0);
        let tcp = encode_tcp(
            self.last_transaction.wrapping_add(1),
            frame.station,
            &frame.pdu,
        )
        .ok_or(DropReason::Frame(FrameError::TooShort {
            len: rtu.len(),
            min: crate::rtu::MIN_RTU_FRAME,
        }))?;
        self.last_transaction = self.last_transaction.wrapping_add(1);
        Ok(Forwarded {
            transaction: self.last_transaction,
            station: frame.station,
            function,
            tcp,
            answered: expects_answer(frame.station, function),
        })
    }
}

/// The RTU answer frame (CRC appended) for `request` from one whole Modbus TCP frame.
pub fn answer_to_rtu(request: &Forwarded, tcp: &[u8]) -> Result<Vec<u8>, NotTheAnswer> {
    let frame = decode_tcp(tcp).map_err(NotTheAnswer::Frame)?;
    if frame.transaction != request.transaction {
        return Err(NotTheAnswer::Transaction {
            found: frame.transaction,
        });
    }
    if frame.unit != request.station {
        return Err(NotTheAnswer::Unit { found: frame.unit });
    }
    let function = frame.pdu[0];
    if function & !EXCEPTION_BIT != request.function {
        return Err(NotTheAnswer::Function { found: function });
    }
    Ok(encode_rtu(frame.unit, &frame.pdu))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// AN2002's capture: read 4 discrete inputs from 0x0004 at station 1.
    const RTU_REQUEST: [u8; 8] = [0x01, 0x02, 0x00, 0x04, 0x00, 0x04, 0x38, 0x08];
    const RTU_ANSWER: [u8; 6] = [0x01, 0x02, 0x01, 0x00, 0xA1, 0x88];

    #[test]
    fn an_rtu_request_becomes_mbap_with_the_station_as_unit() {
        let mut g = Gateway::new();
        let f = g.forward(&RTU_REQUEST).expect("forwarded");
        assert_eq!(
            f.tcp,
            [0, 1, 0, 0, 0, 6, 0x01, 0x02, 0x00, 0x04, 0x00, 0x04]
        );
        assert_eq!((f.transaction, f.station, f.function), (1, 1, 0x02));
        assert!(f.answered);
        let f = g.forward(&RTU_REQUEST).expect("forwarded");
        assert_eq!(
            &f.tcp[..2],
            [0, 2],
            "the next request, the next transaction"
        );
    }

    #[test]
    fn the_tcp_answer_becomes_rtu_with_its_crc() {
        let mut g = Gateway::new();
        let f = g.forward(&RTU_REQUEST).expect("forwarded");
        let tcp = [0, 1, 0, 0, 0, 4, 0x01, 0x02, 0x01, 0x00];
        assert_eq!(answer_to_rtu(&f, &tcp), Ok(RTU_ANSWER.to_vec()));
        // An exception answer passes through too.
        let exception = [0, 1, 0, 0, 0, 3, 0x01, 0x82, 0x02];
        let rtu = answer_to_rtu(&f, &exception).expect("the answer");
        assert_eq!(rtu, encode_rtu(1, &[0x82, 0x02]));
        assert_eq!(decode_rtu(&rtu).expect("checks").pdu, [0x82, 0x02]);
    }

    #[test]
    fn write_single_coil_on_a_relay_board_address_both_ways() {
        // 05 0200 FF00: channel 0 of the relay board on; the answer echoes the request.
        let pdu = [0x05, 0x02, 0x00, 0xFF, 0x00];
        let mut g = Gateway::new();
        let f = g.forward(&encode_rtu(1, &pdu)).expect("forwarded");
        assert_eq!(f.tcp, [0, 1, 0, 0, 0, 6, 1, 0x05, 0x02, 0x00, 0xFF, 0x00]);
        assert_eq!(answer_to_rtu(&f, &f.tcp), Ok(encode_rtu(1, &pdu)));
    }

    #[test]
    fn bad_crc_short_frames_and_reserved_stations_are_dropped() {
        let mut g = Gateway::new();
        let mut bad = RTU_REQUEST;
        bad[4] ^= 0x10;
        assert!(matches!(
            g.forward(&bad),
            Err(DropReason::Frame(FrameError::CrcMismatch { .. }))
        ));
        assert!(matches!(
            g.forward(&[0x01, 0x02, 0x03]),
            Err(DropReason::Frame(FrameError::TooShort { .. }))
        ));
        assert_eq!(
            g.forward(&encode_rtu(248, &[0x01, 0, 0, 0, 1])),
            Err(DropReason::ReservedStation(248))
        );
        // Nothing dropped used a transaction id.
        assert_eq!(g.forward(&RTU_REQUEST).expect("forwarded").transaction, 1);
    }

    #[test]
    fn a_broadcast_is_forwarded_as_unit_0_without_an_answer() {
        let mut g = Gateway::new();
        let f = g
            .forward(&encode_rtu(0, &[0x05, 0x00, 0x00, 0xFF, 0x00]))
            .expect("forwarded");
        assert_eq!(f.tcp[6], 0);
        assert!(!f.answered);
        // GUTTA function 13 to station 0 is answered (UM4001), as the master expects.
        let gutta = [0x0D, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00];
        let f = g.forward(&encode_rtu(0, &gutta)).expect("forwarded");
        assert!(f.answered);
    }

    #[test]
    fn other_transactions_units_functions_and_garbage_are_not_the_answer() {
        let mut g = Gateway::new();
        let f = g.forward(&RTU_REQUEST).expect("forwarded");
        assert_eq!(
            answer_to_rtu(&f, &[0, 9, 0, 0, 0, 4, 0x01, 0x02, 0x01, 0x00]),
            Err(NotTheAnswer::Transaction { found: 9 })
        );
        assert_eq!(
            answer_to_rtu(&f, &[0, 1, 0, 0, 0, 4, 0x02, 0x02, 0x01, 0x00]),
            Err(NotTheAnswer::Unit { found: 2 })
        );
        assert_eq!(
            answer_to_rtu(&f, &[0, 1, 0, 0, 0, 4, 0x01, 0x01, 0x01, 0x00]),
            Err(NotTheAnswer::Function { found: 0x01 })
        );
        assert!(matches!(
            answer_to_rtu(&f, &[0, 1, 0, 1, 0, 4, 0x01, 0x02, 0x01, 0x00]),
            Err(NotTheAnswer::Frame(FrameError::ProtocolId { found: 1 }))
        ));
        assert!(matches!(
            answer_to_rtu(&f, &[0, 1]),
            Err(NotTheAnswer::Frame(_))
        ));
    }

    #[test]
    fn transaction_ids_wrap() {
        let mut g = Gateway {
            last_transaction: u16::MAX,
        };
        assert_eq!(g.forward(&RTU_REQUEST).expect("forwarded").transaction, 0);
    }
}
