//! The GUTTA data carried in Modbus function 13 (UM4001 "封包结构"):
//! `length(2) function(2) packet(2) payload`, all three fields high byte first,
//! `length = 4 + payload bytes`. Which function a code is lives in `function` and
//! `registry`; what each function's payload means is `message`'s business.

use std::fmt;

/// The Modbus function code that carries GUTTA data.
pub const MODBUS_FUNCTION_GUTTA: u8 = 13;
/// Bit 15 of the packet number: this is the last packet of a transfer.
pub const LAST_PACKET: u16 = 0x8000;
/// Bit 15 of a response's function code: the PLC failed to execute the function.
pub const FAILURE_BIT: u16 = 0x8000;
/// Bytes of the length, function and packet fields.
pub const GUTTA_HEADER_LEN: usize = 6;
/// Largest payload the 16-bit length field can describe.
pub const MAX_GUTTA_PAYLOAD: usize = u16::MAX as usize - 4;

/// Errors of the GUTTA layer.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum GuttaError {
    /// Fewer than the 6 header bytes.
    TooShort { len: usize },
    /// The length field is below 4 or does not match the bytes that follow it.
    LengthMismatch { field: u16, actual: usize },
    /// The payload does not fit the 16-bit length field.
    PayloadTooLong { len: usize },
    /// The Modbus PDU is not function 13.
    NotGutta { function: Option<u8> },
}

impl fmt::Display for GuttaError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GuttaError::TooShort { len } => {
                write!(
                    f,
                    "GUTTA data of {len} bytes is shorter than its 6-byte header"
                )
            }
            GuttaError::LengthMismatch { field, actual } => write!(
                f,
                "GUTTA length field is {field} but {actual} bytes follow it (must be 4 + payload)"
            ),
            GuttaError::PayloadTooLong { len } => {
                write!(
                    f,
                    "GUTTA payload of {len} bytes exceeds {MAX_GUTTA_PAYLOAD}"
                )
            }
            GuttaError::NotGutta {
                function: Some(code),
            } => {
                write!(f, "Modbus function {code} is not 13 (GUTTA)")
            }
            GuttaError::NotGutta { function: None } => write!(f, "empty Modbus PDU"),
        }
    }
}

impl std::error::Error for GuttaError {}

/// One GUTTA message: function code, packet number (bit 15 = last) and payload.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GuttaFrame {
    pub function: u16,
    pub packet: u16,
    pub payload: Vec<u8>,
}

impl GuttaFrame {
    pub fn new(function: u16, packet: u16, payload: Vec<u8>) -> Self {
        GuttaFrame {
            function,
            packet,
            payload,
        }
    }

    /// A single-packet message (packet 0x8000).
    pub fn single(function: u16, payload: Vec<u8>) -> Self {
        GuttaFrame {
            function,
            packet: LAST_PACKET,
            payload,
        }
    }

    /// The failure answer to `request`: function with bit 15 set, same packet, no payload.
    pub fn failure_of(request: &GuttaFrame) -> Self {
        GuttaFrame {
            function: request.function | FAILURE_BIT,
            packet: request.packet,
            payload: vec![],
        }
    }

    /// Bit 15 of the packet number.
    pub fn is_last(&self) -> bool {
        self.packet & LAST_PACKET != 0
    }

    /// The packet number without the last-packet bit.
    pub fn number(&self) -> u16 {
        self.packet & !LAST_PACKET
    }

    /// Bit 15 of the function code (meaningful in responses).
    pub fn is_failure(&self) -> bool {
        self.function & FAILURE_BIT != 0
    }

    /// The GUTTA data: length, function, packet (high byte first), payload.
    pub fn encode(&self) -> Result<Vec<u8>, GuttaError> {
        let length =
            u16::try_from(self.payload.len() + 4).map_err(|_| GuttaError::PayloadTooLong {
                len: self.payload.len(),
            })?;
        let mut out = Vec::with_capacity(GUTTA_HEADER_LEN + self.payload.len());
        out.extend_from_slice(&length.to_be_bytes());
        out.extend_from_slice(&self.function.to_be_bytes());
        out.extend_from_slice(&self.packet.to_be_bytes());
        out.extend_from_slice(&self.payload);
        Ok(out)
    }

    /// Decodes exactly one GUTTA data block (the length field must match).
    pub fn decode(data: &[u8]) -> Result<Self, GuttaError> {
        if data.len() < GUTTA_HEADER_LEN {
            return Err(GuttaError::TooShort { len: data.len() });
        }
        let field = u16::from_be_bytes([data[0], data[1]]);
        if field < 4 || usize::from(field) != data.len() - 2 {
            return Err(GuttaError::LengthMismatch {
                field,
                actual: data.len() - 2,
            });
        }
        Ok(GuttaFrame {
            function: u16::from_be_bytes([data[2], data[3]]),
            packet: u16::from_be_bytes([data[4], data[5]]),
            payload: data[GUTTA_HEADER_LEN..].to_vec(),
        })
    }

    /// The Modbus PDU `[0x0D][GUTTA data]`.
    pub fn to_pdu(&self) -> Result<Vec<u8>, GuttaError> {
        let mut out = vec![MODBUS_FUNCTION_GUTTA];
        out.extend(self.encode()?);
        Ok(out)
    }

    /// Decodes a Modbus PDU that must be function 13.
    pub fn from_pdu(pdu: &[u8]) -> Result<Self, GuttaError> {
        match pdu.split_first() {
            Some((&MODBUS_FUNCTION_GUTTA, data)) => GuttaFrame::decode(data),
            other => Err(GuttaError::NotGutta {
                function: other.map(|(f, _)| *f),
            }),
        }
    }
}

#[cfg(test)]
mod tests {

    use super::*;

    #[test]
    fn plc_clear_gutta_data_from_um4001() {
        let frame = GuttaFrame::single(0x0100, vec![]);
        assert_eq!(frame.encode(), Ok(vec![0x00, 0x04, 0x01, 0x00, 0x80, 0x00]));
        let decoded = GuttaFrame::decode(&[0x00, 0x04, 0x01, 0x00, 0x80, 0x00]).expect("valid");
        assert_eq!(decoded, frame);
        assert!(decoded.is_last());
        assert_eq!(decoded.number(), 0);
        // Failure: 00 04 81 00 80 00.
        let failure = GuttaFrame::failure_of(&frame);
        assert_eq!(
            failure.encode(),
            Ok(vec![0x00, 0x04, 0x81, 0x00, 0x80, 0x00])
        );
        assert!(failure.is_failure());
        assert_eq!(
            frame.to_pdu(),
            Ok(vec![0x0D, 0x00, 0x04, 0x01, 0x00, 0x80, 0x00])
        );
    }

    #[test]
    fn length_field_errors() {
        assert_eq!(
            GuttaFrame::decode(&[0, 4, 1, 0, 0x80]),
            Err(GuttaError::TooShort { len: 5 })
        );
        assert_eq!(
            GuttaFrame::decode(&[0, 5, 1, 0, 0x80, 0]),
            Err(GuttaError::LengthMismatch {
                field: 5,
                actual: 4
            })
        );
        assert_eq!(
            GuttaFrame::decode(&[0, 3, 1, 0, 0x80, 0, 0]),
            Err(GuttaError::LengthMismatch {
                field: 3,
                actual: 5
            })
        );
        assert_eq!(
            GuttaFrame::from_pdu(&[3]),
            Err(GuttaError::NotGutta { function: Some(3) })
        );
        assert_eq!(
            GuttaFrame::from_pdu(&[]),
            Err(GuttaError::NotGutta { function: None })
        );
        let big = GuttaFrame::single(0x0240, vec![0; MAX_GUTTA_PAYLOAD + 1]);
        assert!(matches!(
            big.encode(),
            Err(GuttaError::PayloadTooLong { .. })
        ));
    }
}
