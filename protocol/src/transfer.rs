//! Packetisation of pages (UM4001, the page READ/WRITE functions): packet i carries the
//! bytes from i x ExchPackSize, at most ExchPackSize of them; the last packet has bit 15
//! set. Splitting for the sender, slicing for a slave answering a read, and a checked
//! reassembler for the receiver. No framing, no I/O.

use std::fmt;

use crate::gutta::LAST_PACKET;

/// Largest packet index (15 bits; bit 15 is the last-packet flag).
pub const MAX_PACKET_INDEX: u16 = 0x7FFF;

/// ExchPackSize of PlcType.xml: the most payload bytes of one packet, 64 <= n < 1024.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct PackSize(u16);

impl PackSize {
    pub const MIN: u16 = 64;
    pub const MAX: u16 = 1023;

    pub fn new(size: u16) -> Result<Self, TransferError> {
        if (Self::MIN..=Self::MAX).contains(&size) {
            Ok(PackSize(size))
        } else {
            Err(TransferError::PackSize { size })
        }
    }

    pub fn get(self) -> usize {
        usize::from(self.0)
    }
}

/// Errors of splitting or reassembling a transfer.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum TransferError {
    /// ExchPackSize outside 64..=1023.
    PackSize { size: u16 },
    /// The page is longer than its 16-bit length can say, or than the limit.
    TooLarge { len: usize, limit: usize },
    /// A packet index other than the next one expected.
    OutOfOrder { expected: u16, found: u16 },
    /// A packet after the last one (other than a repeat of the last).
    AfterLast { found: u16 },
    /// A packet carries more than ExchPackSize bytes.
    PacketTooLong { len: usize, max: usize },
    /// A packet that is not the last carries fewer than ExchPackSize bytes, so the next
    /// packet's offset (i x ExchPackSize) would leave a gap.
    ShortPacket {
        index: u16,
        len: usize,
        expected: usize,
    },
    /// A repeated packet whose bytes differ from the first copy.
    ConflictingRepeat { index: u16 },
    /// A read asks for a packet starting beyond the end of the page.
    BeyondEnd { index: u16, page_len: usize },
    /// `finish` before the last packet arrived.
    Incomplete { received: usize },
}

impl fmt::Display for TransferError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TransferError::PackSize { size } => {
                write!(f, "ExchPackSize {size} is outside 64..=1023")
            }
            TransferError::TooLarge { len, limit } => {
                write!(f, "transfer of {len} bytes exceeds the limit {limit}")
            }
            TransferError::OutOfOrder { expected, found } => {
                write!(f, "packet {found} arrived, expected packet {expected}")
            }
            TransferError::AfterLast { found } => {
                write!(f, "packet {found} arrived after the last packet")
            }
            TransferError::PacketTooLong { len, max } => {
                write!(f, "packet of {len} bytes exceeds ExchPackSize {max}")
            }
            TransferError::ShortPacket {
                index,
                len,
                expected,
            } => write!(
                f,
                "packet {index} is not the last but has {len} bytes, expected {expected}"
            ),
            TransferError::ConflictingRepeat { index } => {
                write!(f, "packet {index} repeated with different bytes")
            }
            TransferError::BeyondEnd { index, page_len } => {
                write!(
                    f,
                    "packet {index} starts beyond the end of a {page_len}-byte page"
                )
            }
            TransferError::Incomplete { received } => {
                write!(
                    f,
                    "transfer incomplete after {received} bytes (no last packet)"
                )
            }
        }
    }
}

impl std::error::Error for TransferError {}

/// Number of packets that move a page of `len` bytes (at least 1: an empty page is one
/// empty packet 0x8000).
pub fn packet_count(len: usize, pack: PackSize) -> usize {
    len.div_ceil(pack.get()).max(1)
}

/// The packet number (index, plus bit 15 on the last) of packet `index` of `count`.
pub fn packet_number(index: u16, count: usize) -> u16 {
    if usize::from(index) + 1 >= count {
        index | LAST_PACKET
    } else {
        index
    }
}

/// Splits a page into `(packet number, bytes)` for a page WRITE. The page length must fit
/// 16 bits (the ASK answer is a 16-bit length).
pub fn split_page(page: &[u8], pack: PackSize) -> Result<Vec<(u16, &[u8])>, TransferError> {
    if page.len() > usize::from(u16::MAX) {
        return Err(TransferError::TooLarge {
            len: page.len(),
            limit: usize::from(u16::MAX),
        });
    }
    if page.is_empty() {
        return Ok(vec![(LAST_PACKET, page)]);
    }
    let count = packet_count(page.len(), pack);
    Ok(page
        .chunks(pack.get())
        .enumerate()
        .map(|(i, chunk)| (packet_number(i as u16, count), chunk))
        .collect())
}

/// The packet numbers a master sends to READ a page of `len` bytes (from its ASK).
pub fn read_packets(len: u16, pack: PackSize) -> Vec<u16> {
    let count = packet_count(usize::from(len), pack);
    (0..count).map(|i| packet_number(i as u16, count)).collect()
}

/// What a slave answers to a READ of packet `packet`: the bytes from
/// index x ExchPackSize to the end of the page or ExchPackSize bytes, whichever is
/// first. Packet 0 of an empty page is empty; a packet starting beyond the end is an
/// error (answer failure).
pub fn read_slice(page: &[u8], packet: u16, pack: PackSize) -> Result<&[u8], TransferError> {
    let index = packet & !LAST_PACKET;
    let start = usize::from(index) * pack.get();
    if start > page.len() || (start == page.len() && index != 0) {
        return Err(TransferError::BeyondEnd {
            index,
            page_len: page.len(),
        });
    }
    let end = (start + pack.get()).min(page.len());
    Ok(&page[start..end])
}

/// What `Reassembler::push` made of a packet.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Progress {
    /// Accepted; more packets to come.
    More,
    /// Accepted the last packet; `finish` gives the page.
    Complete,
    /// A repeat of the previous packet with the same bytes (the master retried because
    /// our answer was lost); nothing changed.
    Repeat,
}

/// Collects packets 0, 1, ... into one page; checks order, sizes, the last bit and a size
/// limit. Packet 0 while a transfer is under way starts it again (a master that gave up
/// and restarted). A repeat of the last accepted packet with equal bytes is harmless.
#[derive(Debug, Clone)]
pub struct Reassembler {
    pack: PackSize,
    limit: usize,
    data: Vec<u8>,
    /// Index and bytes-range of the last accepted packet.
    last_accepted: Option<(u16, usize)>,
    complete: bool,
}

impl Reassembler {
    /// `limit` is the largest page accepted (e.g. ProgramBlockInstructionBinarySize);
    /// it is capped at 65535, the largest 16-bit page length.
    pub fn new(pack: PackSize, limit: usize) -> Self {
        Reassembler {
            pack,
            limit: limit.min(usize::from(u16::MAX)),
            data: Vec::new(),
            last_accepted: None,
            complete: false,
        }
    }

    pub fn is_complete(&self) -> bool {
        self.complete
    }

    /// Bytes received so far.
    pub fn received(&self) -> usize {
        self.data.len()
    }

    pub fn push(&mut self, packet: u16, bytes: &[u8]) -> Result<Progress, TransferError> {
        let index = packet & !LAST_PACKET;
        let last = packet & LAST_PACKET != 0;
        let max = self.pack.get();
        if bytes.len() > max {
            return Err(TransferError::PacketTooLong {
                len: bytes.len(),
                max,
            });
        }
        if let Some((prev, start)) = self.last_accepted {
            if prev == index && last == self.complete {
                if self.data.get(start..) == Some(bytes) {
                    return Ok(Progress::Repeat);
                }
                if index != 0 {
                    return Err(TransferError::ConflictingRepeat { index });
                }
                // A different packet 0: a new transfer, handled below.
            }
        }
        if index == 0 {
            self.data.clear();
            self.last_accepted = None;
            self.complete = false;
        } else if self.complete {
            return Err(TransferError::AfterLast { found: index });
        }
        let expected = self
            .last_accepted
            .map_or(0, |(prev, _)| prev.saturating_add(1));
        if index != expected {
            return Err(TransferError::OutOfOrder {
                expected,
                found: index,
            });
        }
        if !last && bytes.len() != max {
            return Err(TransferError::ShortPacket {
                index,
                len: bytes.len(),
                expected: max,
            });
        }
        let len = self.data.len() + bytes.len();
        if len > self.limit {
            return Err(TransferError::TooLarge {
                len,
                limit: self.limit,
            });
        }
        let start = self.data.len();
        self.data.extend_from_slice(bytes);
        self.last_accepted = Some((index, start));
        self.complete = last;
        Ok(if last {
            Progress::Complete
        } else {
            Progress::More
        })
    }

    /// The page, once the last packet arrived.
    pub fn finish(self) -> Result<Vec<u8>, TransferError> {
        if self.complete {
            Ok(self.data)
        } else {
            Err(TransferError::Incomplete {
                received: self.data.len(),
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Found by the `frames` fuzz target: full packets may be followed by an empty last
    /// packet (UM4001's rule "packet i covers bytes from i x ExchPackSize" allows it);
    /// the page is the same as when the last full packet carries the last bit.
    #[test]
    fn an_empty_last_packet_after_full_ones_completes_the_page() {
        let pack = PackSize::new(64).expect("size");
        let mut r = Reassembler::new(pack, 300);
        assert_eq!(r.push(0, &[7; 64]), Ok(Progress::More));
        assert_eq!(r.push(LAST_PACKET | 1, &[]), Ok(Progress::Complete));
        assert_eq!(r.finish(), Ok(vec![7; 64]));
        assert_eq!(
            split_page(&[7; 64], pack).expect("fits"),
            vec![(LAST_PACKET, &[7u8; 64][..])]
        );
    }

    fn pack64() -> PackSize {
        PackSize::new(64).expect("64 is the smallest ExchPackSize")
    }

    #[test]
    fn pack_size_limits_from_plctype() {
        assert!(PackSize::new(63).is_err());
        assert!(PackSize::new(64).is_ok());
        assert!(PackSize::new(1023).is_ok());
        assert_eq!(
            PackSize::new(1024),
            Err(TransferError::PackSize { size: 1024 })
        );
    }

    #[test]
    fn split_sets_offsets_and_last_bit() {
        let page: Vec<u8> = (0..150u8).collect();
        let packets = split_page(&page, pack64()).expect("fits");
        let numbers: Vec<u16> = packets.iter().map(|p| p.0).collect();
        assert_eq!(numbers, [0x0000, 0x0001, 0x8002]);
        assert_eq!(packets[1].1, &page[64..128]);
        assert_eq!(packets[2].1, &page[128..]);
        assert_eq!(split_page(&[], pack64()), Ok(vec![(0x8000, &[][..])]));
        assert_eq!(split_page(&[1; 64], pack64()).map(|p| p.len()), Ok(1));
        assert_eq!(read_packets(150, pack64()), [0x0000, 0x0001, 0x8002]);
        assert_eq!(read_packets(0, pack64()), [0x8000]);
        assert_eq!(read_slice(&page, 0x8002, pack64()), Ok(&page[128..]));
        assert_eq!(read_slice(&[], 0x8000, pack64()), Ok(&[][..]));
        assert_eq!(
            read_slice(&page, 3, pack64()),
            Err(TransferError::BeyondEnd {
                index: 3,
                page_len: 150
            })
        );
    }

    #[test]
    fn reassembles_and_checks() {
        let page: Vec<u8> = (0..150u8).collect();
        let mut r = Reassembler::new(pack64(), 1000);
        for (number, bytes) in split_page(&page, pack64()).expect("fits") {
            let progress = r.push(number, bytes).expect("in order");
            assert_eq!(progress == Progress::Complete, number & 0x8000 != 0);
        }
        assert_eq!(r.push(0x8002, &page[128..]), Ok(Progress::Repeat));
        assert_eq!(
            r.push(0x8003, &[]),
            Err(TransferError::AfterLast { found: 3 })
        );
        assert_eq!(r.finish(), Ok(page.clone()));

        let mut r = Reassembler::new(pack64(), 1000);
        assert_eq!(
            r.push(1, &page[..64]),
            Err(TransferError::OutOfOrder {
                expected: 0,
                found: 1
            })
        );
        assert_eq!(
            r.push(0, &page[..10]),
            Err(TransferError::ShortPacket {
                index: 0,
                len: 10,
                expected: 64
            })
        );
        assert_eq!(r.push(0, &page[..64]), Ok(Progress::More));
        assert_eq!(r.push(0, &page[..64]), Ok(Progress::Repeat));
        assert_eq!(
            r.push(2, &page[..64]),
            Err(TransferError::OutOfOrder {
                expected: 1,
                found: 2
            })
        );
        assert_eq!(r.push(1, &page[64..128]), Ok(Progress::More));
        assert_eq!(
            r.push(1, &page[..64]),
            Err(TransferError::ConflictingRepeat { index: 1 })
        );
        // A different packet 0 starts a new transfer.
        assert_eq!(r.push(0, &page[1..65]), Ok(Progress::More));
        assert_eq!(r.received(), 64);
        assert_eq!(
            r.push(1, &[0; 65]),
            Err(TransferError::PacketTooLong { len: 65, max: 64 })
        );
        assert!(!r.is_complete());
        assert_eq!(
            r.clone().finish(),
            Err(TransferError::Incomplete { received: 64 })
        );

        let mut small = Reassembler::new(pack64(), 100);
        assert_eq!(small.push(0, &page[..64]), Ok(Progress::More));
        assert_eq!(
            small.push(0x8001, &page[64..128]),
            Err(TransferError::TooLarge {
                len: 128,
                limit: 100
            })
        );
    }
}
