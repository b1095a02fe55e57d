//! Splitting frames out of a byte stream (serial line, pipe, RTU-over-TCP, Modbus TCP).
//! An RTU frame's length is deduced from its function code and contents, not from
//! inter-character silence, so the splitter works on any chunking of the stream.
//! Resynchronisation policy: an unknown function code, an impossible length or a CRC
//! mismatch is reported once as an error and exactly one byte (the presumed station
//! byte) is dropped; splitting then restarts at the next byte. No I/O.

use crate::modbus_registry;
use crate::rtu::{crc16, FrameError, MIN_RTU_FRAME};
use crate::tcp::{MbapHeader, MBAP_LEN};

/// The largest GUTTA RTU frame with ExchPackSize at its maximum (1023): station,
/// function 13, length field, function, packet, 1023 payload bytes, CRC.
pub const DEFAULT_MAX_RTU_FRAME: usize = 1 + 1 + 2 + 4 + 1023 + 2;

/// Which end of the line the splitter sits at: a slave reads requests, a master reads
/// responses. The two directions size the same function codes differently.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Side {
    Slave,
    Master,
}

/// RTU frame splitter. `push` bytes as they arrive, then call `next_frame` until it
/// returns `None`. Frames come out whole, CRC checked, CRC included.
#[derive(Debug, Clone)]
pub struct RtuSplitter {
    side: Side,
    max_frame: usize,
    buf: ByteQueue,
}

impl RtuSplitter {
    pub fn new(side: Side) -> Self {
        Self::with_max_frame(side, DEFAULT_MAX_RTU_FRAME)
    }

    /// A deduced length above `max_frame` is an error (and resynchronises).
    pub fn with_max_frame(side: Side, max_frame: usize) -> Self {
        RtuSplitter {
            side,
            max_frame: max_frame.max(MIN_RTU_FRAME),
            buf: ByteQueue::default(),
        }
    }

    pub fn push(&mut self, bytes: &[u8]) {
        self.buf.push(bytes);
    }

    /// Bytes received but not yet returned as a frame.
    pub fn buffered(&self) -> usize {
        self.buf.len()
    }

    /// Forgets every buffered byte (a master does this before sending a new request).
    pub fn clear(&mut self) {
        self.buf.clear();
    }

    /// The next whole frame, an error (after which one byte has been dropped), or `None`
    /// when more bytes are needed.
    pub fn next_frame(&mut self) -> Option<Result<Vec<u8>, FrameError>> {
        let len = match rtu_frame_len(self.side, self.buf.bytes()) {
            Ok(None) => return None,
            Ok(Some(len)) if len > self.max_frame => {
                return Some(self.resync(FrameError::TooLong {
                    len,
                    max: self.max_frame,
                }))
            }
            Ok(Some(len)) => len,
            Err(e) => return Some(self.resync(e)),
        };
        let frame = self.buf.bytes().get(..len)?;
        let (body, crc) = frame.split_at(len - 2);
        let found = u16::from_le_bytes([crc[0], crc[1]]);
        let computed = crc16(body);
        if found != computed {
            return Some(self.resync(FrameError::CrcMismatch { computed, found }));
        }
        Some(Ok(self.buf.take(len)))
    }

    fn resync(&mut self, error: FrameError) -> Result<Vec<u8>, FrameError> {
        self.buf.take(1);
        Err(error)
    }
}

/// A byte buffer consumed from the front in O(1) (an offset), compacted when the
/// consumed part is at least half of it.
#[derive(Debug, Clone, Default)]
struct ByteQueue {
    buf: Vec<u8>,
    start: usize,
}

impl ByteQueue {
    fn bytes(&self) -> &[u8] {
        &self.buf[self.start..]
    }

    fn len(&self) -> usize {
        self.buf.len() - self.start
    }

    fn push(&mut self, bytes: &[u8]) {
        if self.start > 0 && self.start >= self.buf.len() / 2 {
            self.buf.drain(..self.start);
            self.start = 0;
        }
        self.buf.extend_from_slice(bytes);
    }

    /// Removes and returns up to `n` bytes from the front.
    fn take(&mut self, n: usize) -> Vec<u8> {
        let n = n.min(self.len());
        let out = self.buf[self.start..self.start + n].to_vec();
        self.start += n;
        if self.start == self.buf.len() {
            self.buf.clear();
            self.start = 0;
        }
        out
    }

    fn clear(&mut self) {
        self.buf.clear();
        self.start = 0;
    }
}

/// The length of the RTU frame at the start of `b` as seen from `side`; `Ok(None)` if
/// more bytes are needed to tell. The function code's row in `modbus_registry` says the
/// shape of a request (slave side) or an answer (master side); an exception (a known
/// code with bit 7 set) is an answer of 5 bytes; any other code is unknown.
/// docs/protocol.md's splitter table is generated from the same rows.
pub fn rtu_frame_len(side: Side, b: &[u8]) -> Result<Option<usize>, FrameError> {
    let Some(&function) = b.get(1) else {
        return Ok(None);
    };
    match modbus_registry::shape(side, function) {
        Some(shape) => shape.rtu_frame_len(function, b),
        None => Err(FrameError::UnknownFunction { function }),
    }
}

/// Modbus TCP frame splitter by the MBAP length field. Same policy as `RtuSplitter`: a
/// bad header (protocol id not 0, length below 2 or above the limit) is reported once
/// and one byte is dropped. Over TCP a caller may prefer to close the connection.
#[derive(Debug, Clone)]
pub struct TcpSplitter {
    max_length: u16,
    buf: ByteQueue,
}

impl TcpSplitter {
    /// `max_length` bounds the MBAP length field (unit id + PDU);
    /// `tcp::MAX_STANDARD_MBAP_LENGTH` is the Modbus TCP limit, GUTTA frames need more.
    pub fn new(max_length: u16) -> Self {
        TcpSplitter {
            max_length,
            buf: ByteQueue::default(),
        }
    }

    pub fn push(&mut self, bytes: &[u8]) {
        self.buf.push(bytes);
    }

    pub fn buffered(&self) -> usize {
        self.buf.len()
    }

    pub fn clear(&mut self) {
        self.buf.clear();
    }

    /// The next whole frame (header included), an error, or `None` for more bytes.
    pub fn next_frame(&mut self) -> Option<Result<Vec<u8>, FrameError>> {
        if self.buf.len() < MBAP_LEN {
            return None;
        }
        let header = match MbapHeader::decode(self.buf.bytes()) {
            Ok(header) => header,
            Err(e) => return Some(self.resync(e)),
        };
        if header.length > self.max_length {
            let error = FrameError::TooLong {
                len: header.frame_len(),
                max: MBAP_LEN - 1 + usize::from(self.max_length),
            };
            return Some(self.resync(error));
        }
        let len = header.frame_len();
        if self.buf.len() < len {
            return None;
        }
        Some(Ok(self.buf.take(len)))
    }

    fn resync(&mut self, error: FrameError) -> Result<Vec<u8>, FrameError> {
        self.buf.take(1);
        Err(error)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rtu::encode_rtu;

    const REQUESTS: [&[u8]; 2] = [
        &[0x01, 0x02, 0x00, 0x04, 0x00, 0x04, 0x38, 0x08],
        &[0x01, 0x03, 0x00, 0x08, 0x00, 0x04, 0xC5, 0xCB],
    ];
    const RESPONSES: [&[u8]; 2] = [
        &[0x01, 0x02, 0x01, 0x00, 0xA1, 0x88],
        &[
            0x01, 0x03, 0x08, 0x0C, 0x2B, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x0E, 0x80,
        ],
    ];

    fn drain(s: &mut RtuSplitter) -> Vec<Result<Vec<u8>, FrameError>> {
        std::iter::from_fn(|| s.next_frame()).collect()
    }

    #[test]
    fn capture_byte_by_byte() {
        let mut slave = RtuSplitter::new(Side::Slave);
        let mut master = RtuSplitter::new(Side::Master);
        let mut got_requests = vec![];
        let mut got_responses = vec![];
        for (req, resp) in REQUESTS.iter().zip(RESPONSES) {
            for &byte in *req {
                slave.push(&[byte]);
                got_requests.extend(drain(&mut slave));
            }
            for &byte in resp {
                master.push(&[byte]);
                got_responses.extend(drain(&mut master));
            }
        }
        assert_eq!(got_requests, REQUESTS.map(|r| Ok(r.to_vec())));
        assert_eq!(got_responses, RESPONSES.map(|r| Ok(r.to_vec())));
    }

    #[test]
    fn gutta_and_multiple_writes_and_exceptions() {
        let clear = encode_rtu(0, &[0x0D, 0x00, 0x04, 0x01, 0x00, 0x80, 0x00]);
        let write16 = encode_rtu(0x11, &[0x10, 0, 1, 0, 2, 4, 0, 0x0A, 1, 2]);
        let mut slave = RtuSplitter::new(Side::Slave);
        slave.push(&[clear.clone(), write16.clone()].concat());
        assert_eq!(drain(&mut slave), [Ok(clear.clone()), Ok(write16)]);

        let exception = encode_rtu(0x11, &[0x83, 0x02]);
        let mut master = RtuSplitter::new(Side::Master);
        master.push(&[exception.clone(), clear.clone()].concat());
        assert_eq!(drain(&mut master), [Ok(exception), Ok(clear)]);
    }

    #[test]
    fn resync_after_garbage_and_crc_error() {
        let good = REQUESTS[0];
        let mut bad = good.to_vec();
        bad[7] ^= 0xFF;
        let mut slave = RtuSplitter::new(Side::Slave);
        slave.push(&[0x01, 0x99]); // unknown function 99
        slave.push(&bad);
        slave.push(good);
        let out = drain(&mut slave);
        assert_eq!(out.last(), Some(&Ok(good.to_vec())));
        assert!(out[..out.len() - 1].iter().all(Result::is_err));
        assert_eq!(out[0], Err(FrameError::UnknownFunction { function: 0x99 }));
        assert_eq!(slave.buffered(), 0);
    }

    #[test]
    fn impossible_lengths() {
        assert!(matches!(
            rtu_frame_len(Side::Slave, &[1, 13, 0, 3]),
            Err(FrameError::BadLength { function: 13, .. })
        ));
        assert!(matches!(
            rtu_frame_len(Side::Master, &[1, 3, 3]),
            Err(FrameError::BadLength { .. })
        ));
        assert!(matches!(
            rtu_frame_len(Side::Master, &[1, 1, 0]),
            Err(FrameError::BadLength { .. })
        ));
        assert!(matches!(
            rtu_frame_len(Side::Slave, &[1, 15, 0, 0, 0, 1, 0]),
            Err(FrameError::BadLength { .. })
        ));
        assert_eq!(
            rtu_frame_len(Side::Slave, &[1, 0x83]),
            Err(FrameError::UnknownFunction { function: 0x83 })
        );
        assert_eq!(rtu_frame_len(Side::Master, &[1, 0x83]), Ok(Some(5)));
        assert_eq!(
            rtu_frame_len(Side::Master, &[1, 0x87]),
            Err(FrameError::UnknownFunction { function: 0x87 })
        );
        let mut s = RtuSplitter::with_max_frame(Side::Slave, 20);
        s.push(&[1, 13, 0, 100]);
        assert_eq!(
            s.next_frame(),
            Some(Err(FrameError::TooLong { len: 106, max: 20 }))
        );
        assert_eq!(s.buffered(), 3);
    }

    #[test]
    fn tcp_splitter() {
        let a = crate::tcp::encode_tcp(1, 1, &[3, 0, 8, 0, 4]).expect("fits");
        let b = crate::tcp::encode_tcp(2, 1, &[0x0D, 0, 4, 1, 0, 0x80, 0]).expect("fits");
        let mut s = TcpSplitter::new(crate::tcp::MAX_STANDARD_MBAP_LENGTH);
        let stream = [a.clone(), b.clone()].concat();
        let mut out = vec![];
        for chunk in stream.chunks(3) {
            s.push(chunk);
            out.extend(std::iter::from_fn(|| s.next_frame()));
        }
        assert_eq!(out, [Ok(a), Ok(b)]);
        s.push(&[0, 1, 0, 0, 0x10, 0, 1]);
        assert!(matches!(
            s.next_frame(),
            Some(Err(FrameError::TooLong { .. }))
        ));
        s.clear();
        s.push(&[0, 1, 0, 5, 0, 2, 1, 3]);
        assert_eq!(
            s.next_frame(),
            Some(Err(FrameError::ProtocolId { found: 5 }))
        );
    }
}
