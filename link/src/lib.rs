//! The client side of the GUTTA protocol: a `Client` over a transport (Modbus TCP, RTU
//! over TCP, serial RTU) with the PLC operations of UM4001, and the download of an
//! image as the vendor tool does it. No printing: callers report progress.

pub mod plan;
pub mod session;
pub mod transport;
pub mod var;

use std::collections::BTreeMap;

use gutta_format::{Image, LineSettings, PackedOperand, PageId, PageKind};
use gutta_protocol::function::{Function, PageArea, PageRef};
use gutta_protocol::gutta::GuttaFrame;
use gutta_protocol::message::{
    Breakpoint, Command, DebugInfo, DebugStep, MessageError, Reply, Request, Response,
};
use gutta_protocol::modbus::ExceptionCode;
use gutta_protocol::transfer::{split_page, PackSize};

/// The typed GUTTA messages the client's operations take and return.
pub use gutta_protocol::message;
pub use session::{
    Credentials, LinkConfig, LoginError, NoPrompt, PasswordPrompt, PasswordSource, Session,
    PASSWORD_ENV,
};
pub use transport::{Answer, Transport};
pub use var::Var;

/// The factory password: 16 x 0xFF.
pub const FACTORY_PASSWORD: [u8; 16] = [0xFF; 16];

/// Why an operation failed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LinkError {
    /// The transport could not be opened: `message` says where and why, `failure` which
    /// of the cases a caller can give advice for.
    Connect {
        message: String,
        failure: ConnectFailure,
    },
    /// The transport failed (read, write, a socket option).
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
    /// Another client is downloading into the PLC: the simulator refused `what` with
    /// Modbus exception 06, Server Device Busy (docs/simulator.md, the download safety
    /// rule). Nothing was changed by the refused request.
    Busy { what: String },
    /// The PLC refuses every login for a while after repeated wrong passwords: the
    /// simulator answers a locked PLC_ATTACH with Modbus exception 04, Server Device
    /// Failure (docs/simulator.md, password policy). A wrong password is `Refused`.
    LockedOut,
}

/// Why a transport could not be opened.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConnectFailure {
    /// Nothing listens at the TCP address: the connection was refused.
    Refused,
    /// The serial device does not exist.
    NoDevice,
    /// Anything else: an unknown host, no route, a timeout, no permission.
    Other,
}

impl std::fmt::Display for LinkError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LinkError::Connect { message, .. } => f.write_str(message),
            LinkError::Io(e) => write!(f, "{e}"),
            LinkError::Timeout { attempts } => write!(
                f,
                "no answer after {}",
                gutta_catalog::plural::count(*attempts, "attempt")
            ),
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
            LinkError::Busy { .. } => f.write_str(
                "busy: another client is downloading into this PLC; \
                 try again when it has finished",
            ),
            LinkError::LockedOut => f.write_str(
                "locked: the PLC refuses logins for a while after repeated wrong passwords; \
                 wait and retry",
            ),
        }
    }
}

impl std::error::Error for LinkError {}

/// A PLC on a transport.
///
/// Any [`Transport`] will do. Here it is a simulated PLC (gutta-sim) in the same
/// process, each request PDU answered by its session, running a program that writes
/// 3585 to MW24: log in, ask its name and status, read MW24.
///
/// ```rust
/// use std::sync::Arc;
///
/// use gutta_compiler::{compile, source::SourceFile};
/// use gutta_format::{Operand, PackedOperand};
/// use gutta_link::{Answer, Client, LinkError, Transport, FACTORY_PASSWORD};
/// use gutta_sim::plc::{ConnectionId, Plc};
///
/// #[derive(Debug)]
/// struct InProcess(Plc);
///
/// impl Transport for InProcess {
///     fn exchange(&mut self, _station: u8, pdu: &[u8]) -> Result<Answer, LinkError> {
///         let pdu = gutta_sim::session::answer(&mut self.0, ConnectionId(1), pdu, 0);
///         Ok(Answer::from_pdu(pdu))
///     }
/// }
///
/// let text = "\
/// ORGANIZATION_BLOCK MAIN:OB1
/// BEGIN
/// NETWORK 1
/// LD     SM0.0
/// MOVW   3585, MW24
/// END_ORGANIZATION_BLOCK
/// ";
/// let target = gutta_catalog::stdlib::shared(gutta_catalog::stdlib::DEFAULT)?;
/// let image = compile(SourceFile::new("main.lad", text), None)
///     .image
///     .expect("the program compiles");
/// let mut plc = Plc::new(Arc::clone(&target), image.pages, Default::default())?;
/// plc.scan()?;
///
/// let mut client = Client::new(Box::new(InProcess(plc)), 1);
/// client.attach(&FACTORY_PASSWORD)?;
/// assert_eq!(client.plc_name()?, "CPU-EC20");
/// let status = client.status()?; // bit0 RUN, bit1 RESET, bit2 ATTACH, bit3 ERROR
/// assert_eq!(status & 0b1101, 0b0101, "running, logged in, no error");
/// let mw24 = target.memory.parse_address("MW24").expect("an address");
/// let values = client.read_vars(&[PackedOperand::encode(Operand::Value(mw24)).0])?;
/// assert_eq!(u32::from_le_bytes(values[0]) & 0xFFFF, 3585);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct Client {
    transport: Box<dyn Transport>,
    station: u8,
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

    /// The station address requests go to (0: broadcast, which a GUTTA PLC answers for
    /// function 13).
    pub fn station(&self) -> u8 {
        self.station
    }

    pub fn set_station(&mut self, station: u8) {
        self.station = station;
    }

    /// Switch the serial line (if the transport has one) to `line`.
    pub fn set_line(&mut self, line: LineSettings) -> Result<(), LinkError> {
        self.transport.set_line(line)
    }

    /// One GUTTA request, encoded and its answer decoded by gutta-protocol's typed
    /// messages; the reply, or `Refused` for the failure form. `what` names the
    /// operation in errors.
    pub fn request(&mut self, request: &Request, what: &str) -> Result<Reply, LinkError> {
        let function = request.function().code();
        let pdu = request
            .encode()
            .and_then(|frame| frame.to_pdu().map_err(Into::into))
            .map_err(|e| LinkError::Protocol(e.to_string()))?;
        let answer = match self.transport.exchange(self.station, &pdu)? {
            Answer::Pdu(answer) => answer,
            Answer::Exception { function, code }
                if code == ExceptionCode::ServerDeviceBusy.byte()
                    && pdu.first() == Some(&function) =>
            {
                return Err(LinkError::Busy {
                    what: what.to_string(),
                })
            }
            Answer::Exception { function, code } => {
                return Err(LinkError::Exception { function, code })
            }
        };
        let response = GuttaFrame::from_pdu(&answer)
            .map_err(MessageError::from)
            .and_then(|frame| Response::decode(&frame))
            .map_err(|e| LinkError::Protocol(e.to_string()))?;
        if response.packet != request.packet {
            return Err(LinkError::Protocol(format!(
                "answer to packet {:04X} carries packet {:04X}",
                request.packet, response.packet
            )));
        }
        let code = response.code();
        match response.reply {
            Reply::Failure { code } if code == function => Err(LinkError::Refused {
                function,
                what: what.to_string(),
            }),
            reply if code == function => Ok(reply),
            _ => Err(LinkError::Protocol(format!(
                "answer {code:04X} to request {function:04X}"
            ))),
        }
    }

    /// A single-packet request whose success is a bare acknowledgement.
    /// `ack`, a refusal naming the function (its registry name).
    fn ack_named(&mut self, command: Command) -> Result<(), LinkError> {
        let what = command.function().name();
        self.ack(command, what)
    }

    fn ack(&mut self, command: Command, what: &str) -> Result<(), LinkError> {
        match self.request(&Request::single(command), what)? {
            Reply::Ack(_) => Ok(()),
            other => Err(unexpected(what, &other)),
        }
    }

    /// A standard Modbus request PDU; the answer PDU (exceptions are errors).
    pub fn modbus(&mut self, pdu: &[u8]) -> Result<Vec<u8>, LinkError> {
        match self.transport.exchange(self.station, pdu)? {
            Answer::Pdu(answer) => Ok(answer),
            Answer::Exception { function, code } => Err(LinkError::Exception { function, code }),
        }
    }

    /// PLC_ATTACH, the login. A wrong password is `Refused` (function 0110); a PLC
    /// that locks logins after repeated failures answers `LockedOut` meanwhile, even to
    /// the right password.
    pub fn attach(&mut self, password: &[u8; 16]) -> Result<(), LinkError> {
        let locked = ExceptionCode::ServerDeviceFailure.byte();
        match self.ack(
            Command::PlcAttach {
                password: *password,
            },
            "the login (PLC_ATTACH): wrong password",
        ) {
            Err(LinkError::Exception { code, .. }) if code == locked => Err(LinkError::LockedOut),
            other => other,
        }
    }

    pub fn detach(&mut self) -> Result<(), LinkError> {
        self.ack_named(Command::PlcDetach)
    }

    /// GET_PLC_NAME, without its zero padding.
    pub fn plc_name(&mut self) -> Result<String, LinkError> {
        let what = "GET_PLC_NAME";
        match self.request(&Request::single(Command::GetPlcName), what)? {
            Reply::PlcName(bytes) => {
                let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
                Ok(String::from_utf8_lossy(&bytes[..end]).into_owned())
            }
            other => Err(unexpected(what, &other)),
        }
    }

    pub fn clear(&mut self) -> Result<(), LinkError> {
        self.ack_named(Command::PlcClear)
    }

    pub fn reset(&mut self) -> Result<(), LinkError> {
        self.ack_named(Command::StatusReset)
    }

    /// STATUS_READ: bit0 RUN, bit1 RESET, bit2 ATTACH, bit3 ERROR.
    pub fn status(&mut self) -> Result<u8, LinkError> {
        let what = "STATUS_READ";
        match self.request(&Request::single(Command::StatusRead), what)? {
            Reply::Status(state) => Ok(state),
            other => Err(unexpected(what, &other)),
        }
    }

    /// STATUS_WRITE: RUN (true) or STOP.
    pub fn set_running(&mut self, run: bool) -> Result<(), LinkError> {
        self.ack(
            Command::StatusWrite { run: u8::from(run) },
            "STATUS_WRITE (a PLC without a valid program cannot run)",
        )
    }

    /// STATUS_VAR_READ: 4 bytes from each packed address.
    pub fn read_vars(&mut self, addresses: &[u32]) -> Result<Vec<[u8; 4]>, LinkError> {
        let what = "STATUS_VAR_READ (outside an area?)";
        let command = Command::VarRead(addresses.iter().map(|&a| PackedOperand(a)).collect());
        match self.request(&Request::single(command), what)? {
            Reply::VarValues(values) if values.len() == addresses.len() => {
                Ok(values.into_iter().map(u32::to_le_bytes).collect())
            }
            Reply::VarValues(_) => Err(LinkError::Protocol(
                "STATUS_VAR_READ answered the wrong length".into(),
            )),
            other => Err(unexpected(what, &other)),
        }
    }

    /// STATUS_VAR_FORCE_READ: 4 bytes of the force value image from each packed address
    /// (0 where nothing is forced).
    pub fn read_forces(&mut self, addresses: &[u32]) -> Result<Vec<[u8; 4]>, LinkError> {
        let what = "STATUS_VAR_FORCE_READ (outside an area?)";
        let command = Command::ForceRead(addresses.iter().map(|&a| PackedOperand(a)).collect());
        match self.request(&Request::single(command), what)? {
            Reply::ForceValues(values) if values.len() == addresses.len() => {
                Ok(values.into_iter().map(u32::to_le_bytes).collect())
            }
            Reply::ForceValues(_) => Err(LinkError::Protocol(
                "STATUS_VAR_FORCE_READ answered the wrong length".into(),
            )),
            other => Err(unexpected(what, &other)),
        }
    }

    /// STATUS_VAR_WRITE (`force`: STATUS_VAR_FORCE_WRITE) of (packed address, value).
    pub fn write_vars(&mut self, pairs: &[(u32, u32)], force: bool) -> Result<(), LinkError> {
        let pairs: Vec<(PackedOperand, u32)> =
            pairs.iter().map(|&(a, v)| (PackedOperand(a), v)).collect();
        if force {
            self.ack(
                Command::ForceWrite(pairs),
                "STATUS_VAR_FORCE_WRITE (only I and Q can be forced)",
            )
        } else {
            self.ack(
                Command::VarWrite(pairs),
                "STATUS_VAR_WRITE (outside an area?)",
            )
        }
    }

    /// DATA_ASK, SYSTEM_ASK or PROGRAM_ASK: the numbers of the pages present.
    pub fn page_list(&mut self, area: PageArea) -> Result<Vec<u8>, LinkError> {
        let what = Function::PageList(area).name();
        match self.request(&Request::single(Command::PageList(area)), what)? {
            Reply::PageList(_, pages) => Ok(pages),
            other => Err(unexpected(what, &other)),
        }
    }

    /// STATUS_DEBUG_INFOR_WRITE: set the breakpoint, or clear it (`None`).
    pub fn set_breakpoint(&mut self, at: Option<Breakpoint>) -> Result<(), LinkError> {
        let (breakpoint, what) = match at {
            Some(b) => (b, "the breakpoint (no instruction there?)"),
            None => (
                Breakpoint {
                    index: 0xFF,
                    network: 0xFFFF,
                    step: 0xFFFF,
                },
                "clearing the breakpoint",
            ),
        };
        self.ack(Command::DebugInforWrite(breakpoint), what)
    }

    /// STATUS_DEBUG_WRITE: run until a breakpoint (true) or single-step stop.
    pub fn debug_run(&mut self, run: bool) -> Result<(), LinkError> {
        let what = if run {
            "run until a breakpoint"
        } else {
            "single-step stop"
        };
        self.ack(Command::DebugWrite { run: u8::from(run) }, what)
    }

    /// STATUS_DEBUG_SCAN: one step in, over or out.
    pub fn debug_step(&mut self, step: DebugStep) -> Result<(), LinkError> {
        self.ack(
            Command::DebugScan(step),
            "the step (is the program paused?)",
        )
    }

    /// STATUS_DEBUG_RESET.
    pub fn debug_reset(&mut self) -> Result<(), LinkError> {
        self.ack_named(Command::DebugReset)
    }

    /// STATUS_DEBUG_READ (the DEBUG_STATE byte) and STATUS_DEBUG_INFOR_READ.
    pub fn debug_info(&mut self) -> Result<(u8, DebugInfo), LinkError> {
        let what = "STATUS_DEBUG_INFOR_READ";
        let info = match self.request(&Request::single(Command::DebugInforRead), what)? {
            Reply::DebugInfo(info) => info,
            other => return Err(unexpected(what, &other)),
        };
        let what = "STATUS_DEBUG_READ";
        match self.request(&Request::single(Command::DebugRead), what)? {
            Reply::DebugState(state) => Ok((state, info)),
            other => Err(unexpected(what, &other)),
        }
    }

    /// Write a page in packets of `pack` bytes; `sent` is told the bytes after each.
    pub fn write_page(
        &mut self,
        id: PageId,
        bytes: &[u8],
        pack: usize,
        sent: &mut dyn FnMut(usize),
    ) -> Result<usize, LinkError> {
        let page = page_ref(id)?;
        let what = format!(
            "writing {} (is the PLC stopped and cleared?)",
            id.file_name()
        );
        let pack = u16::try_from(pack)
            .ok()
            .and_then(|p| PackSize::new(p).ok())
            .ok_or_else(|| {
                LinkError::Protocol(format!("packet size {pack} is outside UM4001's 64..=1023"))
            })?;
        let packets = split_page(bytes, pack).map_err(|e| LinkError::Protocol(e.to_string()))?;
        let count = packets.len();
        for (packet, chunk) in packets {
            let request = Request {
                packet,
                command: Command::PageWrite(page, chunk.to_vec()),
            };
            match self.request(&request, &what)? {
                Reply::Ack(_) => sent(chunk.len()),
                other => return Err(unexpected(&what, &other)),
            }
        }
        Ok(count)
    }

    /// Read a page: ask its length, then read its packets.
    pub fn read_page(&mut self, id: PageId, pack: usize) -> Result<Vec<u8>, LinkError> {
        let page = page_ref(id)?;
        let what = format!("reading {}", id.file_name());
        let len = match self.request(&Request::single(Command::PageAsk(page)), &what)? {
            Reply::PageLength(_, len) => usize::from(len),
            other => return Err(unexpected(&what, &other)),
        };
        let count = len.div_ceil(pack.max(1)).max(1);
        let mut out = Vec::with_capacity(len);
        for i in 0..count {
            let request = Request {
                packet: last(i, count),
                command: Command::PageRead(page),
            };
            match self.request(&request, &what)? {
                Reply::PageData(_, data) => out.extend(data),
                other => return Err(unexpected(&what, &other)),
            }
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

fn unexpected(what: &str, reply: &Reply) -> LinkError {
    LinkError::Protocol(format!("{what}: unexpected answer {reply:?}"))
}

fn page_ref(id: PageId) -> Result<PageRef, LinkError> {
    PageRef::of(id)
        .ok_or_else(|| LinkError::Protocol(format!("page {} has no protocol code", id.file_name())))
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
/// type, PLC_CLEAR (erases the old program and password, stops; the client follows the
/// PLC to station 1 and a 19200 8E1 line), log in with the factory password, write every page in packets of `pack` bytes, read every page back
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
    let (name, mut requests) = log_in_and_name(client, password)?;
    if name != image.plc_type {
        return Err(LinkError::WrongPlc {
            plc: name,
            image: image.plc_type.clone(),
        });
    }
    client.clear()?;
    // PLC_CLEAR erased the system page: the PLC answers at station 1 now, on a serial
    // line at 19200 8E1 (UM4001). Follow it; a broadcast client stays on 0.
    if client.station() != 0 {
        client.set_station(1);
    }
    client.set_line(LineSettings::DEFAULT)?;
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

/// PLC_ATTACH, then GET_PLC_NAME: the PLC type and the requests it took. A login
/// belongs to the PLC, not to a connection, so another client's STATUS_RESET or
/// PLC_DETACH can end it between the two (two clients downloading one after the other
/// do exactly that); a GET_PLC_NAME refused right after a successful login therefore
/// logs in once more before it counts as refused.
fn log_in_and_name(client: &mut Client, password: &[u8; 16]) -> Result<(String, usize), LinkError> {
    client.attach(password)?;
    match client.plc_name() {
        Ok(name) => Ok((name, 2)),
        Err(LinkError::Refused { .. }) => {
            client.attach(password)?;
            Ok((client.plc_name()?, 4))
        }
        Err(e) => Err(e),
    }
}

/// Upload the program in the PLC: its PLC type (GET_PLC_NAME), the page lists (data,
/// system, program), and every page present (the const page, and for every program
/// page its argument and instruction pages), each read in packets of `pack` bytes. The
/// image holds only what the PLC holds, so written out it is byte for byte the image
/// directory that was downloaded, `manifest.json` included.
pub fn upload(client: &mut Client, password: &[u8; 16], pack: usize) -> Result<Image, LinkError> {
    let (plc_type, _) = log_in_and_name(client, password)?;
    let data = client.page_list(PageArea::Data)?;
    let system = client.page_list(PageArea::System)?;
    let program = client.page_list(PageArea::Program)?;
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
