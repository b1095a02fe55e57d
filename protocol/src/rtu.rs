//! Modbus RTU framing: `[station][PDU][CRC16/MODBUS low byte first]`, and the framing
//! errors shared by the RTU, TCP and stream modules. Knows nothing of what a PDU means.

use std::fmt;

/// CRC-16/MODBUS (poly 0x8005 reflected, init 0xFFFF), as AN2002 requires for RTU: the
/// toolchain's one implementation, which the image manifest uses too.
pub use gutta_format::crc16;

/// Smallest RTU frame: station, function code, two CRC bytes.
pub const MIN_RTU_FRAME: usize = 4;

/// One RTU frame without its CRC: the station (0 = broadcast) and the PDU
/// (function code followed by data).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RtuFrame {
    pub station: u8,
    pub pdu: Vec<u8>,
}

impl RtuFrame {
    /// The function code (first PDU byte), if the PDU is not empty.
    pub fn function(&self) -> Option<u8> {
        self.pdu.first().copied()
    }

    /// The frame on the wire, CRC appended.
    pub fn encode(&self) -> Vec<u8> {
        encode_rtu(self.station, &self.pdu)
    }
}

/// Framing errors: of a whole RTU frame, of an MBAP frame, or of splitting a stream.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FrameError {
    /// Fewer bytes than the smallest frame of this kind.
    TooShort { len: usize, min: usize },
    /// The CRC in the frame (`found`) is not the CRC of its bytes (`computed`).
    CrcMismatch { computed: u16, found: u16 },
    /// A function code the splitter cannot size (unknown, or not valid in this direction).
    UnknownFunction { function: u8 },
    /// A length or byte-count field that no valid frame of this function can have.
    BadLength { function: u8, detail: &'static str },
    /// The deduced frame length exceeds the configured maximum.
    TooLong { len: usize, max: usize },
    /// MBAP protocol identifier other than 0 (Modbus).
    ProtocolId { found: u16 },
    /// MBAP length field does not match the bytes that follow.
    LengthMismatch { field: usize, actual: usize },
}

impl fmt::Display for FrameError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FrameError::TooShort { len, min } => {
                write!(f, "frame of {len} bytes is shorter than the minimum {min}")
            }
            FrameError::CrcMismatch { computed, found } => {
                write!(
                    f,
                    "CRC mismatch: computed {computed:04X}, frame has {found:04X}"
                )
            }
            FrameError::UnknownFunction { function } => {
                write!(f, "function code {function:02X} cannot be framed")
            }
            FrameError::BadLength { function, detail } => {
                write!(f, "function {function:02X}: impossible length ({detail})")
            }
            FrameError::TooLong { len, max } => {
                write!(f, "frame of {len} bytes exceeds the maximum {max}")
            }
            FrameError::ProtocolId { found } => {
                write!(f, "MBAP protocol id {found} is not 0 (Modbus)")
            }
            FrameError::LengthMismatch { field, actual } => {
                write!(f, "MBAP length field says {field} bytes, {actual} follow")
            }
        }
    }
}

impl std::error::Error for FrameError {}

/// `[station][pdu][crc low][crc high]`.
pub fn encode_rtu(station: u8, pdu: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(pdu.len() + 3);
    out.push(station);
    out.extend_from_slice(pdu);
    let crc = crc16(&out);
    out.extend_from_slice(&crc.to_le_bytes());
    out
}

/// Checks the CRC of a whole frame and splits it into station and PDU.
pub fn decode_rtu(frame: &[u8]) -> Result<RtuFrame, FrameError> {
    if frame.len() < MIN_RTU_FRAME {
        return Err(FrameError::TooShort {
            len: frame.len(),
            min: MIN_RTU_FRAME,
        });
    }
    let (body, crc) = frame.split_at(frame.len() - 2);
    let found = u16::from_le_bytes([crc[0], crc[1]]);
    let computed = crc16(body);
    if found != computed {
        return Err(FrameError::CrcMismatch { computed, found });
    }
    Ok(RtuFrame {
        station: body[0],
        pdu: body[1..].to_vec(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The AN2002 serial capture (sample 3), every line.
    const CAPTURE: [&[u8]; 4] = [
        &[0x01, 0x02, 0x00, 0x04, 0x00, 0x04, 0x38, 0x08],
        &[0x01, 0x02, 0x01, 0x00, 0xA1, 0x88],
        &[0x01, 0x03, 0x00, 0x08, 0x00, 0x04, 0xC5, 0xCB],
        &[
            0x01, 0x03, 0x08, 0x0C, 0x2B, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x0E, 0x80,
        ],
    ];

    #[test]
    fn an2002_capture_lines_check_and_round_trip() {
        for line in CAPTURE {
            let frame = decode_rtu(line).expect("capture line checks");
            assert_eq!(frame.station, 1);
            assert_eq!(frame.encode(), line);
        }
        let frame = decode_rtu(CAPTURE[3]).expect("checks");
        assert_eq!(frame.pdu, [0x03, 0x08, 0x0C, 0x2B, 0, 0, 0, 0, 0, 0]);
    }

    #[test]
    fn crc_low_byte_first() {
        assert_eq!(crc16(&[0x01, 0x02, 0x00, 0x04, 0x00, 0x04]), 0x0838);
        assert_eq!(encode_rtu(1, &[0x02, 0x01, 0x00]), CAPTURE[1]);
    }

    #[test]
    fn corrupted_and_short_frames_are_errors() {
        let mut bad = CAPTURE[0].to_vec();
        bad[3] ^= 0x01;
        assert!(matches!(
            decode_rtu(&bad),
            Err(FrameError::CrcMismatch { found: 0x0838, .. })
        ));
        assert_eq!(
            decode_rtu(&[1, 2, 3]),
            Err(FrameError::TooShort { len: 3, min: 4 })
        );
        assert_eq!(
            decode_rtu(&[]),
            Err(FrameError::TooShort { len: 0, min: 4 })
        );
    }
}
