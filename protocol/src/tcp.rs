//! Modbus TCP framing: the 7-byte MBAP header (transaction id, protocol id 0, length,
//! unit id) followed by the PDU. RTU-over-TCP needs nothing here: it is RTU frames on a
//! stream (see `stream::RtuSplitter`).

use crate::rtu::FrameError;

/// Bytes of the MBAP header.
pub const MBAP_LEN: usize = 7;

/// The largest MBAP length field the Modbus TCP specification allows (unit id + a PDU
/// of at most 253 bytes). GUTTA frames can be longer; `TcpSplitter` takes its own limit.
pub const MAX_STANDARD_MBAP_LENGTH: u16 = 254;

/// The MBAP header. `length` counts the unit id and the PDU.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MbapHeader {
    pub transaction: u16,
    pub protocol: u16,
    pub length: u16,
    pub unit: u8,
}

impl MbapHeader {
    /// All fields high byte first.
    pub fn encode(&self) -> [u8; MBAP_LEN] {
        let t = self.transaction.to_be_bytes();
        let p = self.protocol.to_be_bytes();
        let l = self.length.to_be_bytes();
        [t[0], t[1], p[0], p[1], l[0], l[1], self.unit]
    }

    /// Reads the first 7 bytes; checks the protocol id and that the length field covers
    /// at least the unit id and a function code.
    pub fn decode(bytes: &[u8]) -> Result<Self, FrameError> {
        let Some(h) = bytes.get(..MBAP_LEN) else {
            return Err(FrameError::TooShort {
                len: bytes.len(),
                min: MBAP_LEN,
            });
        };
        let header = MbapHeader {
            transaction: u16::from_be_bytes([h[0], h[1]]),
            protocol: u16::from_be_bytes([h[2], h[3]]),
            length: u16::from_be_bytes([h[4], h[5]]),
            unit: h[6],
        };
        if header.protocol != 0 {
            return Err(FrameError::ProtocolId {
                found: header.protocol,
            });
        }
        if header.length < 2 {
            return Err(FrameError::BadLength {
                function: 0,
                detail: "MBAP length below 2",
            });
        }
        Ok(header)
    }

    /// Bytes of the whole frame this header announces.
    pub fn frame_len(&self) -> usize {
        MBAP_LEN - 1 + usize::from(self.length)
    }
}

/// One Modbus TCP frame: transaction id, unit id and PDU (protocol id is always 0).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TcpFrame {
    pub transaction: u16,
    pub unit: u8,
    pub pdu: Vec<u8>,
}

impl TcpFrame {
    /// The frame on the wire; `None` if the PDU is empty or too long for the 16-bit
    /// length field.
    pub fn encode(&self) -> Option<Vec<u8>> {
        encode_tcp(self.transaction, self.unit, &self.pdu)
    }
}

/// MBAP header + PDU; `None` if the PDU is empty or longer than 65534 bytes.
pub fn encode_tcp(transaction: u16, unit: u8, pdu: &[u8]) -> Option<Vec<u8>> {
    if pdu.is_empty() {
        return None;
    }
    let length = u16::try_from(pdu.len() + 1).ok()?;
    let header = MbapHeader {
        transaction,
        protocol: 0,
        length,
        unit,
    };
    let mut out = header.encode().to_vec();
    out.extend_from_slice(pdu);
    Some(out)
}

/// Decodes exactly one whole frame (the length field must match the bytes given).
pub fn decode_tcp(bytes: &[u8]) -> Result<TcpFrame, FrameError> {
    let header = MbapHeader::decode(bytes)?;
    let pdu = &bytes[MBAP_LEN..];
    if header.frame_len() != bytes.len() {
        return Err(FrameError::LengthMismatch {
            field: usize::from(header.length),
            actual: bytes.len() - (MBAP_LEN - 1),
        });
    }
    Ok(TcpFrame {
        transaction: header.transaction,
        unit: header.unit,
        pdu: pdu.to_vec(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn read_holding_registers_in_mbap() {
        // The AN2002 capture's request 01 03 00 08 00 04 as Modbus TCP, transaction 7.
        let bytes = encode_tcp(7, 1, &[0x03, 0x00, 0x08, 0x00, 0x04]).expect("fits");
        assert_eq!(bytes, [0, 7, 0, 0, 0, 6, 1, 0x03, 0x00, 0x08, 0x00, 0x04]);
        let frame = decode_tcp(&bytes).expect("decodes");
        assert_eq!(frame.transaction, 7);
        assert_eq!(frame.unit, 1);
        assert_eq!(frame.encode(), Some(bytes));
    }

    #[test]
    fn header_errors() {
        assert!(matches!(
            decode_tcp(&[0, 1, 0, 0, 0]),
            Err(FrameError::TooShort { .. })
        ));
        assert_eq!(
            decode_tcp(&[0, 1, 0, 1, 0, 2, 1, 3]),
            Err(FrameError::ProtocolId { found: 1 })
        );
        assert!(matches!(
            decode_tcp(&[0, 1, 0, 0, 0, 1, 1]),
            Err(FrameError::BadLength { .. })
        ));
        assert_eq!(
            decode_tcp(&[0, 1, 0, 0, 0, 3, 1, 3]),
            Err(FrameError::LengthMismatch {
                field: 3,
                actual: 2
            })
        );
        assert_eq!(encode_tcp(0, 0, &[]), None);
    }
}
