//! The client side of the GUTTA protocol: a `Client` over a transport (Modbus TCP, RTU
//! over TCP, serial RTU) with the PLC operations of UM4001, and the download of an
//! image as the vendor tool does it. No printing: callers report progress.

pub mod transport;

use std::collections::BTreeMap;

use gutta_format::{Image, PageId, PageKind};
use gutta_protocol::gutta::{GuttaFrame, PageRef};

pub use transport::Transport;

/// The factory password: 16 x 0xFF.
pub const FACTORY_PASSWORD: [u8; 16] = [0xFF; 16];

/// Why an operation failed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LinkError {
    /// The transport failed (connect, read, write).
    Io(String),
    /// No answer after every attempt.
    Timeout { attempts: u32 },
    /// An answer that does not parse, or answers the wrong thing.
    Protocol(String),
    /// The PLC answered the GUTTA function with its failure form.
    Refused { function: u16, what: String },
    /// A Modbus exception instead of an answer.
    Exception { function: u8, code: u8 },
    /// The PLC is another PLC type than the image's.
    WrongPlc { plc: String, image: String },
    /// A page read back differs from what was written.
    Mismatch { page: String },
}

impl std::fmt::Display for LinkError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LinkError::Io(e) => write!(f, "{e}"),
            LinkError::Timeout { attempts } => write!(f, "no answer after {attempts} attempt(s)"),
            LinkError::Protocol(e) => write!(f, "protocol error: {e}"),
            LinkError::Refused { function, what } => {
                write!(f, "the PLC refused {what} (function {function:04X})")
            }
            LinkError::Exception { function, code } => {
                write!(f, "Modbus exception {code:02X} to function {function:02X}")
            }
            LinkError::WrongPlc { plc, image } => {
                write!(f, "the PLC is a {plc}, the image is for {image}")
            }
            LinkError::Mismatch { page } => {
                write!(f, "{page} reads back different from what was written")
            }
        }
    }
}

impl std::error::Error for LinkError {}

/// A PLC on a transport.
#[derive(Debug)]
pub struct Client {
    transport: Box<dyn Transport>,
    station: u8,
}

/// The function codes of a page: (ask, read, write).
fn page_codes(id: PageId) -> Option<(u16, u16, u16)> {
    use gutta_protocol::gutta::Function;
    let page = PageRef::of(id)?;
    Some((
        Function::PageAsk(page).code(),
        Function::PageRead(page).code(),
        Function::PageWrite(page).code(),
    ))
}

fn last(index: usize, count: usize) -> u16 {
    let n = u16::try_from(index).unwrap_or(u16::MAX) & 0x7FFF;
    if index + 1 == count {
        n | 0x8000
    } else {
        n
    }
}

impl Client {
    pub fn new(transport: Box<dyn Transport>, station: u8) -> Client {
        Client { transport, station }
    }

    /// One GUTTA request; the answer's payload, or `Refused` for the failure form.
    pub fn gutta(
        &mut self,
        function: u16,
        packet: u16,
        payload: &[u8],
        what: &str,
    ) -> Result<Vec<u8>, LinkError> {
        let pdu = GuttaFrame::new(function, packet, payload.to_vec())
            .to_pdu()
            .map_err(|e| LinkError::Protocol(e.to_string()))?;
        let answer = self.transport.exchange(self.station, &pdu)?;
        if let [f, code] = answer[..] {
            if f & 0x80 != 0 {
                return Err(LinkError::Exception {
                    function: f & 0x7F,
                    code,
                });
            }
        }
        let reply =
            GuttaFrame::from_pdu(&answer).map_err(|e| LinkError::Protocol(e.to_string()))?;
        if reply.function == function | 0x8000 {
            return Err(LinkError::Refused {
                function,
                what: what.to_string(),
            });
        }
        if reply.function != function || reply.packet != packet {
            return Err(LinkError::Protocol(format!(
                "answer {:04X}/{:04X} to request {function:04X}/{packet:04X}",
                reply.function, reply.packet
            )));
        }
        Ok(reply.payload)
    }

    /// A standard Modbus request PDU; the answer PDU (exceptions are errors).
    pub fn modbus(&mut self, pdu: &[u8]) -> Result<Vec<u8>, LinkError> {
        let answer = self.transport.exchange(self.station, pdu)?;
        match answer[..] {
            [f, code] if f & 0x80 != 0 => Err(LinkError::Exception {
                function: f & 0x7F,
                code,
            }),
            _ => Ok(answer),
        }
    }

    pub fn attach(&mut self, password: &[u8; 16]) -> Result<(), LinkError> {
        self.gutta(
            0x0110,
            0x8000,
            password,
            "the login (PLC_ATTACH: wrong password?)",
        )
        .map(|_| ())
    }

    pub fn detach(&mut self) -> Result<(), LinkError> {
        self.gutta(0x0111, 0x8000, &[], "PLC_DETACH").map(|_| ())
    }

    /// GET_PLC_NAME, without its zero padding.
    pub fn plc_name(&mut self) -> Result<String, LinkError> {
        let bytes = self.gutta(0x0120, 0x8000, &[], "GET_PLC_NAME")?;
        let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
        Ok(String::from_utf8_lossy(&bytes[..end]).into_owned())
    }

    pub fn clear(&mut self) -> Result<(), LinkError> {
        self.gutta(0x0100, 0x8000, &[], "PLC_CLEAR").map(|_| ())
    }

    pub fn reset(&mut self) -> Result<(), LinkError> {
        self.gutta(0x0A03, 0x8000, &[], "STATUS_RESET").map(|_| ())
    }

    /// STATUS_READ: bit0 RUN, bit1 RESET, bit2 ATTACH, bit3 ERROR.
    pub fn status(&mut self) -> Result<u8, LinkError> {
        let b = self.gutta(0x0A00, 0x8000, &[], "STATUS_READ")?;
        b.first()
            .copied()
            .ok_or_else(|| LinkError::Protocol("STATUS_READ without its byte".into()))
    }

    /// STATUS_WRITE: RUN (true) or STOP.
    pub fn set_running(&mut self, run: bool) -> Result<(), LinkError> {
        self.gutta(
            0x0A01,
            0x8000,
            &[u8::from(run)],
            "STATUS_WRITE (a PLC without a valid program cannot run)",
        )
        .map(|_| ())
    }

    /// STATUS_VAR_READ: 4 bytes from each packed address.
    pub fn read_vars(&mut self, addresses: &[u32]) -> Result<Vec<[u8; 4]>, LinkError> {
        let payload: Vec<u8> = addresses.iter().flat_map(|a| a.to_le_bytes()).collect();
        let b = self.gutta(
            0x0A10,
            0x8000,
            &payload,
            "STATUS_VAR_READ (outside an area?)",
        )?;
        if b.len() != payload.len() {
            return Err(LinkError::Protocol(
                "STATUS_VAR_READ answered the wrong length".into(),
            ));
        }
        Ok(b.chunks_exact(4)
            .map(|c| [c[0], c[1], c[2], c[3]])
            .collect())
    }

    /// STATUS_VAR_WRITE (`force`: STATUS_VAR_FORCE_WRITE) of (packed address, value).
    pub fn write_vars(&mut self, pairs: &[(u32, u32)], force: bool) -> Result<(), LinkError> {
        let payload: Vec<u8> = pairs
            .iter()
            .flat_map(|(a, v)| a.to_le_bytes().into_iter().chain(v.to_le_bytes()))
            .collect();
        let (function, what) = if force {
            (
                0x0A21,
                "STATUS_VAR_FORCE_WRITE (only I and Q can be forced)",
            )
        } else {
            (0x0A11, "STATUS_VAR_WRITE (outside an area?)")
        };
        self.gutta(function, 0x8000, &payload, what).map(|_| ())
    }

    /// Write a page in packets of `pack` bytes; `sent` is told the bytes after each.
    pub fn write_page(
        &mut self,
        id: PageId,
        bytes: &[u8],
        pack: usize,
        sent: &mut dyn FnMut(usize),
    ) -> Result<usize, LinkError> {
        let (_, _, write) = page_codes(id).ok_or_else(|| {
            LinkError::Protocol(format!("page {} has no protocol code", id.file_name()))
        })?;
        let chunks: Vec<&[u8]> = if bytes.is_empty() {
            vec![&[]]
        } else {
            bytes.chunks(pack.max(1)).collect()
        };
        for (i, chunk) in chunks.iter().enumerate() {
            let what = format!(
                "writing {} (is the PLC stopped and cleared?)",
                id.file_name()
            );
            self.gutta(write, last(i, chunks.len()), chunk, &what)?;
            sent(chunk.len());
        }
        Ok(chunks.len())
    }

    /// Read a page: ask its length, then read its packets.
    pub fn read_page(&mut self, id: PageId, pack: usize) -> Result<Vec<u8>, LinkError> {
        let (ask, read, _) = page_codes(id).ok_or_else(|| {
            LinkError::Protocol(format!("page {} has no protocol code", id.file_name()))
        })?;
        let what = format!("reading {}", id.file_name());
        let len = self.gutta(ask, 0x8000, &[], &what)?;
        let [hi, lo] = len[..] else {
            return Err(LinkError::Protocol("a page length is 2 bytes".into()));
        };
        let len = usize::from(u16::from_be_bytes([hi, lo]));
        let count = len.div_ceil(pack.max(1)).max(1);
        let mut out = Vec::with_capacity(len);
        for i in 0..count {
            out.extend(self.gutta(read, last(i, count), &[], &what)?);
        }
        if out.len() != len {
            return Err(LinkError::Protocol(format!(
                "{} announced {len} bytes and sent {}",
                id.file_name(),
                out.len()
            )));
        }
        Ok(out)
    }
}

/// What a download did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DownloadReport {
    pub pages: usize,
    pub bytes: usize,
    /// Requests sent (every packet of every page, written and read back, and the
    /// control requests).
    pub requests: usize,
}

/// Download `image` as UM4001 says: log in, check GET_PLC_NAME against the image's PLC
/// type, PLC_CLEAR (erases the old program and password, stops), log in with the
/// factory password, write every page in packets of `pack` bytes, read every page back
/// and compare, STATUS_RESET (the PLC verifies and runs the image). If anything fails
/// before the reset, the PLC stays cleared and stopped: it never runs half an image.
/// `progress` is told the bytes of each packet written and of each page read back, so
/// it counts up to twice the image's bytes.
pub fn download(
    client: &mut Client,
    image: &Image,
    password: &[u8; 16],
    pack: usize,
    progress: &mut dyn FnMut(usize),
) -> Result<DownloadReport, LinkError> {
    let mut requests = 0;
    client.attach(password)?;
    let name = client.plc_name()?;
    requests += 2;
    if name != image.plc_type {
        return Err(LinkError::WrongPlc {
            plc: name,
            image: image.plc_type.clone(),
        });
    }
    client.clear()?;
    client.attach(&FACTORY_PASSWORD)?;
    requests += 2;
    let mut bytes = 0;
    for (id, page) in &image.pages {
        requests += client.write_page(*id, page, pack, progress)?;
        bytes += page.len();
    }
    let mut read: BTreeMap<PageId, Vec<u8>> = BTreeMap::new();
    for id in image.pages.keys() {
        let page = client.read_page(*id, pack)?;
        progress(page.len());
        requests += 1 + page.len().div_ceil(pack.max(1)).max(1);
        read.insert(*id, page);
    }
    for (id, page) in &image.pages {
        if read.get(id) != Some(page) {
            return Err(LinkError::Mismatch {
                page: id.file_name(),
            });
        }
    }
    client.reset()?;
    requests += 1;
    Ok(DownloadReport {
        pages: image.pages.len(),
        bytes,
        requests,
    })
}

/// Upload the program in the PLC: its PLC type (GET_PLC_NAME), the page lists (data,
/// system, program), and every page present (the const page, and for every program
/// page its argument and instruction pages), each read in packets of `pack` bytes. The
/// image holds only what the PLC holds, so written out it is byte for byte the image
/// directory that was downloaded, `manifest.json` included.
pub fn upload(client: &mut Client, password: &[u8; 16], pack: usize) -> Result<Image, LinkError> {
    client.attach(password)?;
    let plc_type = client.plc_name()?;
    let list =
        |client: &mut Client, function: u16, what: &str| client.gutta(function, 0x8000, &[], what);
    let data = list(client, 0x0210, "DATA_ASK")?;
    let system = list(client, 0x0260, "SYSTEM_ASK")?;
    let program = list(client, 0x0300, "PROGRAM_ASK")?;
    let mut ids = vec![PageId::new(PageKind::Const, 0)];
    for &n in &program {
        ids.push(PageId::new(PageKind::Argument, n));
        ids.push(PageId::new(PageKind::Instruction, n));
    }
    ids.extend(data.iter().map(|&n| PageId::new(PageKind::Data, n)));
    ids.extend(system.iter().map(|&n| PageId::new(PageKind::System, n)));
    let mut pages = BTreeMap::new();
    for id in ids {
        pages.insert(id, client.read_page(id, pack)?);
    }
    Ok(Image { plc_type, pages })
}
