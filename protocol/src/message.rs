//! Typed GUTTA requests and responses (UM4001 "功能码参考"): what the payload of each
//! function is, in both directions. Encodes to and decodes from `GuttaFrame`; payload
//! lengths and packet numbering are checked against the function's row of `registry`.
//! Knows nothing of Modbus framing or of what the PLC does with a request.

use std::fmt;

use crate::function::{Function, PageArea, PageRef};
use crate::gutta::{GuttaError, GuttaFrame, FAILURE_BIT, LAST_PACKET};
use crate::registry::Payload;
use gutta_format::PackedOperand;

/// Bytes of the PLC_ATTACH password and of the GET_PLC_NAME answer.
pub const NAME_LEN: usize = 16;
/// Bytes of the GET_PLC_INFOR answer.
pub const INFOR_LEN: usize = 64;
/// Bytes of the STATUS_DEBUG_INFOR_READ answer.
pub const DEBUG_INFO_LEN: usize = 16;
/// Bytes of the STATUS_DEBUG_INFOR_WRITE request.
pub const BREAKPOINT_LEN: usize = 5;
/// The factory password: 16 x 0xFF.
pub const FACTORY_PASSWORD: [u8; NAME_LEN] = [0xFF; NAME_LEN];

/// Errors of decoding or encoding a typed GUTTA message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum MessageError {
    /// A function code UM4001 does not define.
    UnknownFunction { code: u16 },
    /// A request with the failure bit set.
    FailureBitInRequest { code: u16 },
    /// The payload length is not what the function requires.
    PayloadLength {
        function: Function,
        expected: Payload,
        found: usize,
    },
    /// A single-packet function whose packet number is not 0x8000.
    PacketNumber { function: Function, packet: u16 },
    /// A failure response with a payload (UM4001: failures carry none).
    FailureWithPayload { code: u16 },
    /// A data or system page number above 15.
    PageNumber { page: PageRef },
    /// STATUS_DEBUG_SCAN with a step other than 1, 2, 3.
    DebugStep { value: u8 },
    /// `Reply::Ack` for a function whose success carries a payload.
    NotAnAck { function: Function },
    /// The GUTTA layer refused the frame.
    Gutta(GuttaError),
}

impl fmt::Display for MessageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MessageError::UnknownFunction { code } => {
                write!(f, "function code {code:04X} is not a UM4001 function")
            }
            MessageError::FailureBitInRequest { code } => {
                write!(
                    f,
                    "request function code {code:04X} has the failure bit set"
                )
            }
            MessageError::PayloadLength {
                function,
                expected,
                found,
            } => {
                write!(
                    f,
                    "{function}: payload of {found} bytes, expected {expected}"
                )
            }
            MessageError::PacketNumber { function, packet } => {
                write!(
                    f,
                    "{function}: packet {packet:04X}, a single packet must be 8000"
                )
            }
            MessageError::FailureWithPayload { code } => {
                write!(f, "failure response {code:04X} carries a payload")
            }
            MessageError::PageNumber { page } => write!(f, "page {page:?} out of range 0..=15"),
            MessageError::DebugStep { value } => {
                write!(f, "debug step {value} is not 1 (in), 2 (over) or 3 (out)")
            }
            MessageError::NotAnAck { function } => {
                write!(
                    f,
                    "{function}: success carries a payload, not a bare acknowledgement"
                )
            }
            MessageError::Gutta(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for MessageError {}

impl From<GuttaError> for MessageError {
    fn from(e: GuttaError) -> Self {
        MessageError::Gutta(e)
    }
}

/// STATUS_DEBUG_SCAN's step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DebugStep {
    /// 1 STEP_IN
    In,
    /// 2 STEP_OVER
    Over,
    /// 3 STEP_OUT
    Out,
}

impl DebugStep {
    pub fn byte(self) -> u8 {
        match self {
            DebugStep::In => 1,
            DebugStep::Over => 2,
            DebugStep::Out => 3,
        }
    }
    pub fn from_byte(value: u8) -> Result<Self, MessageError> {
        match value {
            1 => Ok(DebugStep::In),
            2 => Ok(DebugStep::Over),
            3 => Ok(DebugStep::Out),
            _ => Err(MessageError::DebugStep { value }),
        }
    }
}

/// STATUS_DEBUG_INFOR_WRITE's 5 bytes (also the first 5 of DebugInfo): breakpoint
/// function number (byte), network and step (words, high byte first).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Breakpoint {
    pub index: u8,
    pub network: u16,
    pub step: u16,
}

impl Breakpoint {
    fn encode_into(&self, out: &mut Vec<u8>) {
        out.push(self.index);
        out.extend_from_slice(&self.network.to_be_bytes());
        out.extend_from_slice(&self.step.to_be_bytes());
    }
    fn decode(b: &[u8; BREAKPOINT_LEN]) -> Self {
        Breakpoint {
            index: b[0],
            network: u16::from_be_bytes([b[1], b[2]]),
            step: u16::from_be_bytes([b[3], b[4]]),
        }
    }
}

/// STATUS_DEBUG_INFOR_READ's 16 bytes; words high byte first.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct DebugInfo {
    /// Bytes 0-4: DEBUG_INDEX, DEBUG_NETWORK, DEBUG_STEP (the breakpoint).
    pub breakpoint: Breakpoint,
    /// Byte 5 STATE_INDEX: current function number.
    pub state_index: u8,
    /// Bytes 6-7 STATE_NETWORK.
    pub state_network: u16,
    /// Bytes 8-9 STATE_STEP.
    pub state_step: u16,
    /// Bytes 10-11 STACK_DATA: data stack value.
    pub stack_data: u16,
    /// Bytes 12-13 STACK_LOGIC: auxiliary (logic) stack value.
    pub stack_logic: u16,
    /// Byte 14 SP: call depth.
    pub sp: u8,
    /// Byte 15 ERROR code.
    pub error: u8,
}

impl DebugInfo {
    pub fn encode(&self) -> [u8; DEBUG_INFO_LEN] {
        let mut out = Vec::with_capacity(DEBUG_INFO_LEN);
        self.breakpoint.encode_into(&mut out);
        out.push(self.state_index);
        out.extend_from_slice(&self.state_network.to_be_bytes());
        out.extend_from_slice(&self.state_step.to_be_bytes());
        out.extend_from_slice(&self.stack_data.to_be_bytes());
        out.extend_from_slice(&self.stack_logic.to_be_bytes());
        out.push(self.sp);
        out.push(self.error);
        let mut bytes = [0; DEBUG_INFO_LEN];
        bytes.copy_from_slice(&out);
        bytes
    }
    pub fn decode(b: &[u8; DEBUG_INFO_LEN]) -> Self {
        let word = |i: usize| u16::from_be_bytes([b[i], b[i + 1]]);
        DebugInfo {
            breakpoint: Breakpoint {
                index: b[0],
                network: word(1),
                step: word(3),
            },
            state_index: b[5],
            state_network: word(6),
            state_step: word(8),
            stack_data: word(10),
            stack_logic: word(12),
            sp: b[14],
            error: b[15],
        }
    }
}

/// What a request asks, with its payload decoded.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Command {
    PlcClear,
    PlcAttach {
        password: [u8; NAME_LEN],
    },
    PlcDetach,
    GetPlcName,
    GetPlcInfor,
    PageList(PageArea),
    PageAsk(PageRef),
    /// Read packet `Request::packet` of a page (no payload).
    PageRead(PageRef),
    /// Write the bytes of packet `Request::packet` of a page.
    PageWrite(PageRef, Vec<u8>),
    StatusRead,
    /// 0 = stop, anything else = run.
    StatusWrite {
        run: u8,
    },
    /// Scan the stopped PLC this many times.
    StatusScan {
        count: u8,
    },
    StatusReset,
    /// The variables' addresses: packed operand words (gutta-format decodes them).
    VarRead(Vec<PackedOperand>),
    VarWrite(Vec<(PackedOperand, u32)>),
    ForceRead(Vec<PackedOperand>),
    ForceWrite(Vec<(PackedOperand, u32)>),
    DebugRead,
    /// 0 = single-step stop, anything else = run until a breakpoint.
    DebugWrite {
        run: u8,
    },
    DebugScan(DebugStep),
    DebugReset,
    DebugInforRead,
    DebugInforWrite(Breakpoint),
}

impl Command {
    pub fn function(&self) -> Function {
        match self {
            Command::PlcClear => Function::PlcClear,
            Command::PlcAttach { .. } => Function::PlcAttach,
            Command::PlcDetach => Function::PlcDetach,
            Command::GetPlcName => Function::GetPlcName,
            Command::GetPlcInfor => Function::GetPlcInfor,
            Command::PageList(area) => Function::PageList(*area),
            Command::PageAsk(page) => Function::PageAsk(*page),
            Command::PageRead(page) => Function::PageRead(*page),
            Command::PageWrite(page, _) => Function::PageWrite(*page),
            Command::StatusRead => Function::StatusRead,
            Command::StatusWrite { .. } => Function::StatusWrite,
            Command::StatusScan { .. } => Function::StatusScan,
            Command::StatusReset => Function::StatusReset,
            Command::VarRead(_) => Function::VarRead,
            Command::VarWrite(_) => Function::VarWrite,
            Command::ForceRead(_) => Function::ForceRead,
            Command::ForceWrite(_) => Function::ForceWrite,
            Command::DebugRead => Function::DebugRead,
            Command::DebugWrite { .. } => Function::DebugWrite,
            Command::DebugScan(_) => Function::DebugScan,
            Command::DebugReset => Function::DebugReset,
            Command::DebugInforRead => Function::DebugInforRead,
            Command::DebugInforWrite(_) => Function::DebugInforWrite,
        }
    }
}

/// A GUTTA request: the command and its packet number. Single-packet functions always
/// use 0x8000 (`Request::single`); page reads and writes carry packet i (bit 15 on the
/// last one).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Request {
    pub packet: u16,
    pub command: Command,
}

impl Request {
    /// A single-packet request (packet 0x8000).
    pub fn single(command: Command) -> Self {
        Request {
            packet: LAST_PACKET,
            command,
        }
    }

    pub fn function(&self) -> Function {
        self.command.function()
    }

    pub fn encode(&self) -> Result<GuttaFrame, MessageError> {
        let function = self.function();
        check_page(function)?;
        check_packet(function, self.packet)?;
        let payload = match &self.command {
            Command::PlcAttach { password } => password.to_vec(),
            Command::PageWrite(_, data) => data.clone(),
            Command::StatusWrite { run } | Command::DebugWrite { run } => vec![*run],
            Command::StatusScan { count } => vec![*count],
            Command::VarRead(addresses) | Command::ForceRead(addresses) => {
                addresses.iter().flat_map(|a| a.to_le_bytes()).collect()
            }
            Command::VarWrite(pairs) | Command::ForceWrite(pairs) => pairs
                .iter()
                .flat_map(|(a, v)| a.to_le_bytes().into_iter().chain(v.to_le_bytes()))
                .collect(),
            Command::DebugScan(step) => vec![step.byte()],
            Command::DebugInforWrite(bp) => {
                let mut out = Vec::with_capacity(BREAKPOINT_LEN);
                bp.encode_into(&mut out);
                out
            }
            _ => vec![],
        };
        check_length(function, function.spec().request, &payload)?;
        let frame = GuttaFrame::new(function.code(), self.packet, payload);
        frame.encode()?; // the payload must fit the length field
        Ok(frame)
    }

    /// Decodes a request. Payload lengths are checked as UM4001's success conditions
    /// state them ("发送数据长度为 0", "能够被 4 整除", ...): a slave answers a decode
    /// error with the failure form (`GuttaFrame::failure_of`).
    pub fn decode(frame: &GuttaFrame) -> Result<Self, MessageError> {
        let code = frame.function;
        if code & FAILURE_BIT != 0 {
            return Err(MessageError::FailureBitInRequest { code });
        }
        let function = Function::from_code(code).ok_or(MessageError::UnknownFunction { code })?;
        check_packet(function, frame.packet)?;
        let p = frame.payload.as_slice();
        check_length(function, function.spec().request, p)?;
        let command = match function {
            Function::PlcClear => Command::PlcClear,
            Function::PlcAttach => Command::PlcAttach {
                password: fixed(function, p)?,
            },
            Function::PlcDetach => Command::PlcDetach,
            Function::GetPlcName => Command::GetPlcName,
            Function::GetPlcInfor => Command::GetPlcInfor,
            Function::PageList(area) => Command::PageList(area),
            Function::PageAsk(page) => Command::PageAsk(page),
            Function::PageRead(page) => Command::PageRead(page),
            Function::PageWrite(page) => Command::PageWrite(page, p.to_vec()),
            Function::StatusRead => Command::StatusRead,
            Function::StatusWrite => Command::StatusWrite {
                run: one(function, p)?,
            },
            Function::StatusScan => Command::StatusScan {
                count: one(function, p)?,
            },
            Function::StatusReset => Command::StatusReset,
            Function::VarRead => Command::VarRead(addresses(function, p)?),
            Function::VarWrite => Command::VarWrite(pairs(function, p)?),
            Function::ForceRead => Command::ForceRead(addresses(function, p)?),
            Function::ForceWrite => Command::ForceWrite(pairs(function, p)?),
            Function::DebugRead => Command::DebugRead,
            Function::DebugWrite => Command::DebugWrite {
                run: one(function, p)?,
            },
            Function::DebugScan => Command::DebugScan(DebugStep::from_byte(one(function, p)?)?),
            Function::DebugReset => Command::DebugReset,
            Function::DebugInforRead => Command::DebugInforRead,
            Function::DebugInforWrite => {
                Command::DebugInforWrite(Breakpoint::decode(&fixed(function, p)?))
            }
        };
        Ok(Request {
            packet: frame.packet,
            command,
        })
    }
}

/// What a response says, with its payload decoded.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Reply {
    /// The function code with bit 15 set, no payload. `code` is without bit 15 and may be
    /// a code UM4001 does not define (a PLC answers unknown codes this way).
    Failure { code: u16 },
    /// Success without payload: PLC_CLEAR, PLC_ATTACH, PLC_DETACH, page writes,
    /// STATUS_WRITE/SCAN/RESET, VAR_WRITE, FORCE_WRITE, DEBUG_WRITE/SCAN/RESET,
    /// DEBUG_INFOR_WRITE.
    Ack(Function),
    /// GET_PLC_NAME: 16 bytes, zero-terminated if shorter.
    PlcName([u8; NAME_LEN]),
    /// GET_PLC_INFOR: 64 bytes, zero-terminated if shorter.
    PlcInfor([u8; INFOR_LEN]),
    /// DATA_ASK / SYSTEM_ASK / PROGRAM_ASK: one byte per valid page.
    PageList(PageArea, Vec<u8>),
    /// A page ASK: the page's length in bytes.
    PageLength(PageRef, u16),
    /// A page READ: the bytes of packet `Response::packet`.
    PageData(PageRef, Vec<u8>),
    /// STATUS_READ: SYS_STATE.
    Status(u8),
    /// STATUS_VAR_READ: one 32-bit value per address, low byte first on the wire.
    VarValues(Vec<u32>),
    /// STATUS_VAR_FORCE_READ: one 32-bit force value per address.
    ForceValues(Vec<u32>),
    /// STATUS_DEBUG_READ: DEBUG_STATE.
    DebugState(u8),
    /// STATUS_DEBUG_INFOR_READ.
    DebugInfo(DebugInfo),
}

/// SYS_STATE bits of STATUS_READ.
pub mod sys_state {
    pub const RUN: u8 = 0x01;
    pub const RESET: u8 = 0x02;
    pub const ATTACH: u8 = 0x04;
    pub const ERROR: u8 = 0x08;
}

/// DEBUG_STATE bits of STATUS_DEBUG_READ.
pub mod debug_state {
    pub const RUN: u8 = 0x01;
    pub const RESET: u8 = 0x02;
}

/// A GUTTA response: the reply and the packet number it carries (UM4001 echoes the
/// request's packet number, success or failure).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Response {
    pub packet: u16,
    pub reply: Reply,
}

impl Response {
    /// The answer to `request` with this reply (the packet number echoed).
    pub fn to(request: &Request, reply: Reply) -> Self {
        Response {
            packet: request.packet,
            reply,
        }
    }

    /// The function code on the wire (with bit 15 for a failure).
    pub fn code(&self) -> u16 {
        match &self.reply {
            Reply::Failure { code } => code | FAILURE_BIT,
            Reply::Ack(f) => f.code(),
            Reply::PlcName(_) => Function::GetPlcName.code(),
            Reply::PlcInfor(_) => Function::GetPlcInfor.code(),
            Reply::PageList(area, _) => Function::PageList(*area).code(),
            Reply::PageLength(page, _) => Function::PageAsk(*page).code(),
            Reply::PageData(page, _) => Function::PageRead(*page).code(),
            Reply::Status(_) => Function::StatusRead.code(),
            Reply::VarValues(_) => Function::VarRead.code(),
            Reply::ForceValues(_) => Function::ForceRead.code(),
            Reply::DebugState(_) => Function::DebugRead.code(),
            Reply::DebugInfo(_) => Function::DebugInforRead.code(),
        }
    }

    pub fn encode(&self) -> Result<GuttaFrame, MessageError> {
        let payload = match &self.reply {
            Reply::Failure { .. } => vec![],
            Reply::Ack(function) => {
                if !acks(*function) {
                    return Err(MessageError::NotAnAck {
                        function: *function,
                    });
                }
                check_page(*function)?;
                vec![]
            }
            Reply::PlcName(name) => name.to_vec(),
            Reply::PlcInfor(infor) => infor.to_vec(),
            Reply::PageList(_, pages) => pages.clone(),
            Reply::PageLength(page, length) => {
                check_page(Function::PageAsk(*page))?;
                length.to_be_bytes().to_vec()
            }
            Reply::PageData(page, data) => {
                check_page(Function::PageRead(*page))?;
                data.clone()
            }
            Reply::Status(state) | Reply::DebugState(state) => vec![*state],
            Reply::VarValues(values) | Reply::ForceValues(values) => {
                values.iter().flat_map(|v| v.to_le_bytes()).collect()
            }
            Reply::DebugInfo(info) => info.encode().to_vec(),
        };
        if let Some(function) = Function::from_code(self.code()) {
            check_length(function, function.spec().success, &payload)?;
        }
        let frame = GuttaFrame::new(self.code(), self.packet, payload);
        frame.encode()?;
        Ok(frame)
    }

    /// Decodes a response by its own function code (no need to know the request).
    pub fn decode(frame: &GuttaFrame) -> Result<Self, MessageError> {
        let p = frame.payload.as_slice();
        if frame.function & FAILURE_BIT != 0 {
            let code = frame.function & !FAILURE_BIT;
            if !p.is_empty() {
                return Err(MessageError::FailureWithPayload { code });
            }
            return Ok(Response {
                packet: frame.packet,
                reply: Reply::Failure { code },
            });
        }
        let code = frame.function;
        let function = Function::from_code(code).ok_or(MessageError::UnknownFunction { code })?;
        check_length(function, function.spec().success, p)?;
        let reply = match function {
            Function::GetPlcName => Reply::PlcName(fixed(function, p)?),
            Function::GetPlcInfor => Reply::PlcInfor(fixed(function, p)?),
            Function::PageList(area) => Reply::PageList(area, p.to_vec()),
            Function::PageAsk(page) => {
                Reply::PageLength(page, u16::from_be_bytes(fixed(function, p)?))
            }
            Function::PageRead(page) => Reply::PageData(page, p.to_vec()),
            Function::StatusRead => Reply::Status(one(function, p)?),
            Function::VarRead => Reply::VarValues(values(function, p)?),
            Function::ForceRead => Reply::ForceValues(values(function, p)?),
            Function::DebugRead => Reply::DebugState(one(function, p)?),
            Function::DebugInforRead => Reply::DebugInfo(DebugInfo::decode(&fixed(function, p)?)),
            ack if acks(ack) => Reply::Ack(ack),
            other => return Err(MessageError::NotAnAck { function: other }),
        };
        Ok(Response {
            packet: frame.packet,
            reply,
        })
    }
}

/// Functions whose success answer has no payload (the registry's success shape).
fn acks(function: Function) -> bool {
    function.spec().success == Payload::Empty
}

fn check_page(function: Function) -> Result<(), MessageError> {
    match function {
        Function::PageAsk(page) | Function::PageRead(page) | Function::PageWrite(page)
            if !page.is_valid() =>
        {
            Err(MessageError::PageNumber { page })
        }
        _ => Ok(()),
    }
}

/// Single-packet functions must carry 0x8000 (every example in UM4001 does); page reads
/// and writes may carry any packet number.
fn check_packet(function: Function, packet: u16) -> Result<(), MessageError> {
    if function.is_paged() || packet == LAST_PACKET {
        Ok(())
    } else {
        Err(MessageError::PacketNumber { function, packet })
    }
}

/// The payload has the length the function's row gives it (UM4001's success
/// conditions: "发送数据长度为 0", "能够被 4 整除", ...).
fn check_length(function: Function, shape: Payload, p: &[u8]) -> Result<(), MessageError> {
    if shape.accepts(p.len()) {
        Ok(())
    } else {
        Err(MessageError::PayloadLength {
            function,
            expected: shape,
            found: p.len(),
        })
    }
}

fn one(function: Function, p: &[u8]) -> Result<u8, MessageError> {
    fixed::<1>(function, p).map(|[b]| b)
}

fn fixed<const N: usize>(function: Function, p: &[u8]) -> Result<[u8; N], MessageError> {
    <[u8; N]>::try_from(p).map_err(|_| MessageError::PayloadLength {
        function,
        expected: Payload::Bytes(N),
        found: p.len(),
    })
}

fn words(
    function: Function,
    p: &[u8],
    size: usize,
) -> Result<std::slice::ChunksExact<'_, u8>, MessageError> {
    check_length(function, Payload::Multiple(size), p)?;
    Ok(p.chunks_exact(size))
}

fn le32(b: &[u8]) -> u32 {
    u32::from_le_bytes([b[0], b[1], b[2], b[3]])
}

fn addresses(function: Function, p: &[u8]) -> Result<Vec<PackedOperand>, MessageError> {
    Ok(words(function, p, 4)?
        .map(|c| PackedOperand(le32(c)))
        .collect())
}

fn values(function: Function, p: &[u8]) -> Result<Vec<u32>, MessageError> {
    Ok(words(function, p, 4)?.map(le32).collect())
}

fn pairs(function: Function, p: &[u8]) -> Result<Vec<(PackedOperand, u32)>, MessageError> {
    Ok(words(function, p, 8)?
        .map(|c| (PackedOperand(le32(&c[..4])), le32(&c[4..])))
        .collect())
}
