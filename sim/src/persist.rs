//! The simulated PLC's user flash as bytes: what `gutta-sim --flash DIR` keeps across
//! power cycles (the PLC type, whether the flash holds a committed program or was left
//! cleared by a PLC_CLEAR, RUN or STOP, and the pages, the system page with the password
//! among them), encoded with a magic, a version and a CRC-32, and decoded back with a
//! typed error that never panics. [`FlashStore`] is how the PLC makes a state durable;
//! the binary implements it with files, tests with memory. No I/O here.
//!
//! Layout (integers little-endian):
//! `GUTTAFSH` (8 bytes) | version u16 (1) | state u8 | run u8 | type length u8 | type
//! (ASCII) | page count u16 | pages: kind u8, number u8, length u32, bytes | CRC-32
//! (ISO-HDLC) of everything before it, u32.

use std::collections::BTreeMap;

use gutta_format::{PageId, PageKind};

/// The file's first bytes.
pub const MAGIC: [u8; 8] = *b"GUTTAFSH";
/// The layout version this code writes and reads.
pub const VERSION: u16 = 1;

const CRC32: crc::Crc<u32> = crc::Crc::<u32>::new(&crc::CRC_32_ISO_HDLC);

/// What the flash holds, as the last commit left it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FlashState {
    /// A STATUS_RESET committed these pages (none: never programmed, or reset empty).
    Committed,
    /// A PLC_CLEAR erased it and no STATUS_RESET followed: a download was cut short.
    Cleared,
}

impl FlashState {
    fn code(self) -> u8 {
        match self {
            FlashState::Committed => 1,
            FlashState::Cleared => 2,
        }
    }

    fn from_code(code: u8) -> Option<FlashState> {
        match code {
            1 => Some(FlashState::Committed),
            2 => Some(FlashState::Cleared),
            _ => None,
        }
    }
}

/// The content of the flash file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FlashImage {
    /// The PLC type the pages were written on (GET_PLC_NAME).
    pub plc_type: String,
    pub state: FlashState,
    /// RUN (true) or STOP as the last commit left it.
    pub running: bool,
    /// Program, const, data and system pages (the password is in the system page).
    pub pages: BTreeMap<PageId, Vec<u8>>,
}

/// Why bytes are not a flash image.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum DecodeError {
    /// The bytes end before the layout does (`at`: the offset where more was needed).
    Truncated { at: usize },
    /// Not a flash file of ours.
    BadMagic,
    /// A layout version this code does not read.
    UnknownVersion(u16),
    /// The CRC does not match the content: a flipped byte, a torn write.
    BadCrc { stored: u32, computed: u32 },
    /// The CRC matches but a field is impossible (an unknown state, a page kind, bytes
    /// after the last page).
    Malformed(String),
}

impl std::fmt::Display for DecodeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DecodeError::Truncated { at } => write!(f, "truncated at byte {at}"),
            DecodeError::BadMagic => write!(f, "not a GUTTA flash file (bad magic)"),
            DecodeError::UnknownVersion(v) => write!(f, "unknown layout version {v}"),
            DecodeError::BadCrc { stored, computed } => write!(
                f,
                "CRC mismatch: stored {stored:#010x}, computed {computed:#010x}"
            ),
            DecodeError::Malformed(why) => write!(f, "malformed: {why}"),
        }
    }
}

impl std::error::Error for DecodeError {}

fn kind_code(kind: PageKind) -> u8 {
    match kind {
        PageKind::Const => 0,
        PageKind::Argument => 1,
        PageKind::Instruction => 2,
        PageKind::Data => 3,
        PageKind::System => 4,
    }
}

impl FlashImage {
    /// The bytes of the flash file. Fails only for what the layout cannot hold (a PLC
    /// type name over 255 bytes, over 65535 pages or a page over 4 GiB), which no
    /// target allows.
    pub fn encode(&self) -> Result<Vec<u8>, String> {
        let name = self.plc_type.as_bytes();
        let name_len = u8::try_from(name.len())
            .map_err(|_| format!("PLC type name of {} bytes", name.len()))?;
        let count =
            u16::try_from(self.pages.len()).map_err(|_| format!("{} pages", self.pages.len()))?;
        let mut out = Vec::with_capacity(
            24 + name.len() + self.pages.values().map(|p| p.len() + 6).sum::<usize>(),
        );
        out.extend_from_slice(&MAGIC);
        out.extend_from_slice(&VERSION.to_le_bytes());
        out.push(self.state.code());
        out.push(u8::from(self.running));
        out.push(name_len);
        out.extend_from_slice(name);
        out.extend_from_slice(&count.to_le_bytes());
        for (id, bytes) in &self.pages {
            let len = u32::try_from(bytes.len())
                .map_err(|_| format!("page {} of {} bytes", id.file_name(), bytes.len()))?;
            out.push(kind_code(id.kind));
            out.push(id.number);
            out.extend_from_slice(&len.to_le_bytes());
            out.extend_from_slice(bytes);
        }
        let crc = CRC32.checksum(&out);
        out.extend_from_slice(&crc.to_le_bytes());
        Ok(out)
    }

    /// The flash image in `bytes`: the magic, the version and the CRC checked before
    /// any field is believed.
    pub fn decode(bytes: &[u8]) -> Result<FlashImage, DecodeError> {
        if bytes.len() < MAGIC.len() {
            return Err(if MAGIC.starts_with(bytes) {
                DecodeError::Truncated { at: bytes.len() }
            } else {
                DecodeError::BadMagic
            });
        }
        if bytes[..MAGIC.len()] != MAGIC {
            return Err(DecodeError::BadMagic);
        }
        let mut reader = Reader {
            bytes,
            at: MAGIC.len(),
        };
        let version = u16::from_le_bytes(reader.array()?);
        if version != VERSION {
            return Err(DecodeError::UnknownVersion(version));
        }
        // The CRC covers everything before its own 4 bytes.
        let body_end = bytes
            .len()
            .checked_sub(4)
            .filter(|&end| end >= reader.at)
            .ok_or(DecodeError::Truncated { at: bytes.len() })?;
        let stored = u32::from_le_bytes([
            bytes[body_end],
            bytes[body_end + 1],
            bytes[body_end + 2],
            bytes[body_end + 3],
        ]);
        let computed = CRC32.checksum(&bytes[..body_end]);
        if stored != computed {
            // A file cut short fails its CRC too; say truncated when the content
            // itself ends before its declared end.
            if let Err(e @ DecodeError::Truncated { .. }) = parse_body(&mut Reader {
                bytes: &bytes[..body_end],
                at: reader.at,
            }) {
                return Err(e);
            }
            return Err(DecodeError::BadCrc { stored, computed });
        }
        let mut body = Reader {
            bytes: &bytes[..body_end],
            at: reader.at,
        };
        let image = parse_body(&mut body)?;
        if body.at != body_end {
            return Err(DecodeError::Malformed(format!(
                "{} bytes after the last page",
                body_end - body.at
            )));
        }
        Ok(image)
    }

    /// Whether the flash holds a program (an instruction page 0).
    pub fn has_program(&self) -> bool {
        self.pages
            .contains_key(&PageId::new(PageKind::Instruction, 0))
    }
}

/// Everything after the version: state, run, type, pages.
fn parse_body(r: &mut Reader<'_>) -> Result<FlashImage, DecodeError> {
    let [state, run, name_len] = r.array()?;
    let name = r.take(usize::from(name_len))?;
    let count = u16::from_le_bytes(r.array()?);
    let mut pages = BTreeMap::new();
    for _ in 0..count {
        let [kind, number] = r.array()?;
        let len = u32::from_le_bytes(r.array()?);
        let bytes = r.take(usize::try_from(len).unwrap_or(usize::MAX))?;
        let kind = PageKind::ALL
            .into_iter()
            .find(|k| kind_code(*k) == kind)
            .ok_or_else(|| DecodeError::Malformed(format!("page kind {kind}")))?;
        if number > kind.max_number() {
            return Err(DecodeError::Malformed(format!(
                "{} page number {number}",
                kind.keyword()
            )));
        }
        if pages
            .insert(PageId::new(kind, number), bytes.to_vec())
            .is_some()
        {
            return Err(DecodeError::Malformed(format!(
                "{} page {number} twice",
                kind.keyword()
            )));
        }
    }
    let state = FlashState::from_code(state)
        .ok_or_else(|| DecodeError::Malformed(format!("state {state}")))?;
    let running = match run {
        0 => false,
        1 => true,
        other => return Err(DecodeError::Malformed(format!("run flag {other}"))),
    };
    let plc_type = std::str::from_utf8(name)
        .map_err(|_| DecodeError::Malformed("PLC type is not UTF-8".into()))?
        .to_string();
    if state == FlashState::Cleared && (!pages.is_empty() || running) {
        return Err(DecodeError::Malformed(
            "a cleared flash with pages or RUN".into(),
        ));
    }
    Ok(FlashImage {
        plc_type,
        state,
        running,
        pages,
    })
}

/// Bounds-checked reads over a byte slice.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], DecodeError> {
        let end = self
            .at
            .checked_add(n)
            .filter(|&end| end <= self.bytes.len())
            .ok_or(DecodeError::Truncated {
                at: self.bytes.len(),
            })?;
        let out = &self.bytes[self.at..end];
        self.at = end;
        Ok(out)
    }

    fn array<const N: usize>(&mut self) -> Result<[u8; N], DecodeError> {
        let mut out = [0u8; N];
        out.copy_from_slice(self.take(N)?);
        Ok(out)
    }
}

/// Where the PLC makes its flash durable. `commit` returns only once the state is
/// durable (the binary: temp file, fsync, rename, directory fsync); an error means the
/// old state is still what a power-on finds.
pub trait FlashStore: Send + std::fmt::Debug {
    fn commit(&mut self, flash: &FlashImage) -> Result<(), String>;
}

/// A store in memory: every commit kept, for tests (and a failure to inject).
#[derive(Debug, Clone, Default)]
pub struct MemoryStore {
    /// The commits so far, the last one what a power-on would find.
    pub commits: std::sync::Arc<std::sync::Mutex<Vec<FlashImage>>>,
    /// Fail every commit with this message (nothing kept).
    pub fail: std::sync::Arc<std::sync::Mutex<Option<String>>>,
}

impl MemoryStore {
    /// The last committed state, if any.
    pub fn last(&self) -> Option<FlashImage> {
        self.commits.lock().ok()?.last().cloned()
    }
}

impl FlashStore for MemoryStore {
    fn commit(&mut self, flash: &FlashImage) -> Result<(), String> {
        if let Some(why) = self.fail.lock().map_err(|_| "poisoned")?.clone() {
            return Err(why);
        }
        self.commits
            .lock()
            .map_err(|_| "poisoned")?
            .push(flash.clone());
        Ok(())
    }
}
