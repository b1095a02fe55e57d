//! The GUTTA data carried in Modbus function 13 (UM4001 "封包结构"):
//! `length(2) function(2) packet(2) payload`, all three fields high byte first,
//! `length = 4 + payload bytes`; and the classification of every UM4001 function code.
//! What each function's payload means is `message`'s business, not this module's.

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

/// The page lists of UM4001: 0210 DATA_ASK, 0260 SYSTEM_ASK, 0300 PROGRAM_ASK.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PageArea {
    Data,
    System,
    Program,
}

/// A page of the transfer protocol. Data and system pages are numbered 0..=15 (low 4
/// bits of the function code), argument and instruction pages 0..=255 (low 8 bits);
/// there is one const page.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PageRef {
    Data(u8),
    System(u8),
    Const,
    Argument(u8),
    Instruction(u8),
}

impl PageRef {
    /// The image page a protocol page is (docs/image-format.md page kinds).
    pub fn page_id(self) -> gutta_format::PageId {
        use gutta_format::{PageId, PageKind};
        match self {
            PageRef::Data(n) => PageId::new(PageKind::Data, n),
            PageRef::System(n) => PageId::new(PageKind::System, n),
            PageRef::Const => PageId::new(PageKind::Const, 0),
            PageRef::Argument(n) => PageId::new(PageKind::Argument, n),
            PageRef::Instruction(n) => PageId::new(PageKind::Instruction, n),
        }
    }

    /// The protocol page of an image page; `None` for a data or system page number
    /// above 15, which has no function code.
    pub fn of(id: gutta_format::PageId) -> Option<PageRef> {
        use gutta_format::PageKind;
        let page = match id.kind {
            PageKind::Data => PageRef::Data(id.number),
            PageKind::System => PageRef::System(id.number),
            PageKind::Const => PageRef::Const,
            PageKind::Argument => PageRef::Argument(id.number),
            PageKind::Instruction => PageRef::Instruction(id.number),
        };
        page.is_valid().then_some(page)
    }

    /// Whether the page number fits its field (data/system pages are 0..=15).
    pub fn is_valid(self) -> bool {
        match self {
            PageRef::Data(p) | PageRef::System(p) => p <= 0x0F,
            _ => true,
        }
    }
}

/// Every UM4001 function code, classified. Page functions carry their page.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Function {
    /// 0100 PLC_CLEAR: erase user flash (incl. password), stop, unlock flash. No login.
    PlcClear,
    /// 0110 PLC_ATTACH: log in with a 16-byte password.
    PlcAttach,
    /// 0111 PLC_DETACH: log out.
    PlcDetach,
    /// 0120 GET_PLC_NAME: 16 bytes.
    GetPlcName,
    /// 0121 GET_PLC_INFOR: 64 bytes.
    GetPlcInfor,
    /// 0210 DATA_ASK, 0260 SYSTEM_ASK, 0300 PROGRAM_ASK: list of valid page numbers.
    PageList(PageArea),
    /// 022X, 027X, 0310, 04XX, 07XX: length of a page (16-bit, high byte first).
    PageAsk(PageRef),
    /// 023X, 028X, 0311, 05XX, 08XX: read a page, packet by packet.
    PageRead(PageRef),
    /// 024X, 029X, 0312, 06XX, 09XX: write a page, packet by packet.
    PageWrite(PageRef),
    /// 0A00 STATUS_READ
    StatusRead,
    /// 0A01 STATUS_WRITE
    StatusWrite,
    /// 0A02 STATUS_SCAN
    StatusScan,
    /// 0A03 STATUS_RESET (no login)
    StatusReset,
    /// 0A10 STATUS_VAR_READ
    VarRead,
    /// 0A11 STATUS_VAR_WRITE
    VarWrite,
    /// 0A20 STATUS_VAR_FORCE_READ
    ForceRead,
    /// 0A21 STATUS_VAR_FORCE_WRITE
    ForceWrite,
    /// 0A30 STATUS_DEBUG_READ
    DebugRead,
    /// 0A31 STATUS_DEBUG_WRITE
    DebugWrite,
    /// 0A32 STATUS_DEBUG_SCAN
    DebugScan,
    /// 0A33 STATUS_DEBUG_RESET (no login)
    DebugReset,
    /// 0A34 STATUS_DEBUG_INFOR_READ
    DebugInforRead,
    /// 0A35 STATUS_DEBUG_INFOR_WRITE
    DebugInforWrite,
}

impl Function {
    /// The 16-bit code. Page numbers are masked to their field (4 or 8 bits); check
    /// `PageRef::is_valid` first where that matters (`message` does).
    pub fn code(self) -> u16 {
        match self {
            Function::PlcClear => 0x0100,
            Function::PlcAttach => 0x0110,
            Function::PlcDetach => 0x0111,
            Function::GetPlcName => 0x0120,
            Function::GetPlcInfor => 0x0121,
            Function::PageList(PageArea::Data) => 0x0210,
            Function::PageList(PageArea::System) => 0x0260,
            Function::PageList(PageArea::Program) => 0x0300,
            Function::PageAsk(page) => page_code(page, 0x0220, 0x0270, 0x0310, 0x0400, 0x0700),
            Function::PageRead(page) => page_code(page, 0x0230, 0x0280, 0x0311, 0x0500, 0x0800),
            Function::PageWrite(page) => page_code(page, 0x0240, 0x0290, 0x0312, 0x0600, 0x0900),
            Function::StatusRead => 0x0A00,
            Function::StatusWrite => 0x0A01,
            Function::StatusScan => 0x0A02,
            Function::StatusReset => 0x0A03,
            Function::VarRead => 0x0A10,
            Function::VarWrite => 0x0A11,
            Function::ForceRead => 0x0A20,
            Function::ForceWrite => 0x0A21,
            Function::DebugRead => 0x0A30,
            Function::DebugWrite => 0x0A31,
            Function::DebugScan => 0x0A32,
            Function::DebugReset => 0x0A33,
            Function::DebugInforRead => 0x0A34,
            Function::DebugInforWrite => 0x0A35,
        }
    }

    /// Classifies a code (without the failure bit); `None` if UM4001 does not define it.
    pub fn from_code(code: u16) -> Option<Self> {
        let low4 = (code & 0x0F) as u8;
        let low8 = (code & 0xFF) as u8;
        Some(match code {
            0x0100 => Function::PlcClear,
            0x0110 => Function::PlcAttach,
            0x0111 => Function::PlcDetach,
            0x0120 => Function::GetPlcName,
            0x0121 => Function::GetPlcInfor,
            0x0210 => Function::PageList(PageArea::Data),
            0x0220..=0x022F => Function::PageAsk(PageRef::Data(low4)),
            0x0230..=0x023F => Function::PageRead(PageRef::Data(low4)),
            0x0240..=0x024F => Function::PageWrite(PageRef::Data(low4)),
            0x0260 => Function::PageList(PageArea::System),
            0x0270..=0x027F => Function::PageAsk(PageRef::System(low4)),
            0x0280..=0x028F => Function::PageRead(PageRef::System(low4)),
            0x0290..=0x029F => Function::PageWrite(PageRef::System(low4)),
            0x0300 => Function::PageList(PageArea::Program),
            0x0310 => Function::PageAsk(PageRef::Const),
            0x0311 => Function::PageRead(PageRef::Const),
            0x0312 => Function::PageWrite(PageRef::Const),
            0x0400..=0x04FF => Function::PageAsk(PageRef::Argument(low8)),
            0x0500..=0x05FF => Function::PageRead(PageRef::Argument(low8)),
            0x0600..=0x06FF => Function::PageWrite(PageRef::Argument(low8)),
            0x0700..=0x07FF => Function::PageAsk(PageRef::Instruction(low8)),
            0x0800..=0x08FF => Function::PageRead(PageRef::Instruction(low8)),
            0x0900..=0x09FF => Function::PageWrite(PageRef::Instruction(low8)),
            0x0A00 => Function::StatusRead,
            0x0A01 => Function::StatusWrite,
            0x0A02 => Function::StatusScan,
            0x0A03 => Function::StatusReset,
            0x0A10 => Function::VarRead,
            0x0A11 => Function::VarWrite,
            0x0A20 => Function::ForceRead,
            0x0A21 => Function::ForceWrite,
            0x0A30 => Function::DebugRead,
            0x0A31 => Function::DebugWrite,
            0x0A32 => Function::DebugScan,
            0x0A33 => Function::DebugReset,
            0x0A34 => Function::DebugInforRead,
            0x0A35 => Function::DebugInforWrite,
            _ => return None,
        })
    }

    /// The UM4001 name (page functions without their page number).
    pub fn name(self) -> &'static str {
        match self {
            Function::PlcClear => "PLC_CLEAR",
            Function::PlcAttach => "PLC_ATTACH",
            Function::PlcDetach => "PLC_DETACH",
            Function::GetPlcName => "GET_PLC_NAME",
            Function::GetPlcInfor => "GET_PLC_INFOR",
            Function::PageList(PageArea::Data) => "DATA_ASK",
            Function::PageList(PageArea::System) => "SYSTEM_ASK",
            Function::PageList(PageArea::Program) => "PROGRAM_ASK",
            Function::PageAsk(p) => page_name(
                p,
                "DATA_PAGE_ASK",
                "SYSTEM_PAGE_ASK",
                "PROGRAM_CONST_ASK",
                "PROGRAM_ARGUMENT_ASK",
                "PROGRAM_INSTRUCTION_ASK",
            ),
            Function::PageRead(p) => page_name(
                p,
                "DATA_PAGE_READ",
                "SYSTEM_PAGE_READ",
                "PROGRAM_CONST_READ",
                "PROGRAM_ARGUMENT_READ",
                "PROGRAM_INSTRUCTION_READ",
            ),
            Function::PageWrite(p) => page_name(
                p,
                "DATA_PAGE_WRITE",
                "SYSTEM_PAGE_WRITE",
                "PROGRAM_CONST_WRITE",
                "PROGRAM_ARGUMENT_WRITE",
                "PROGRAM_INSTRUCTION_WRITE",
            ),
            Function::StatusRead => "STATUS_READ",
            Function::StatusWrite => "STATUS_WRITE",
            Function::StatusScan => "STATUS_SCAN",
            Function::StatusReset => "STATUS_RESET",
            Function::VarRead => "STATUS_VAR_READ",
            Function::VarWrite => "STATUS_VAR_WRITE",
            Function::ForceRead => "STATUS_VAR_FORCE_READ",
            Function::ForceWrite => "STATUS_VAR_FORCE_WRITE",
            Function::DebugRead => "STATUS_DEBUG_READ",
            Function::DebugWrite => "STATUS_DEBUG_WRITE",
            Function::DebugScan => "STATUS_DEBUG_SCAN",
            Function::DebugReset => "STATUS_DEBUG_RESET",
            Function::DebugInforRead => "STATUS_DEBUG_INFOR_READ",
            Function::DebugInforWrite => "STATUS_DEBUG_INFOR_WRITE",
        }
    }

    /// Whether UM4001 lists "PLC 被登陆" among the success conditions: every function
    /// except PLC_CLEAR, PLC_ATTACH (it is the login), PLC_DETACH, STATUS_RESET and
    /// STATUS_DEBUG_RESET, whose conditions name only the payload length (and for
    /// PLC_ATTACH the password).
    pub fn needs_login(self) -> bool {
        !matches!(
            self,
            Function::PlcClear
                | Function::PlcAttach
                | Function::PlcDetach
                | Function::StatusReset
                | Function::DebugReset
        )
    }

    /// UM4001: page writes succeed only while the PLC is not running.
    pub fn needs_stop(self) -> bool {
        matches!(self, Function::PageWrite(_))
    }

    /// Page reads and writes use packet numbers 0, 1, ...; everything else is a single
    /// packet 0x8000.
    pub fn is_paged(self) -> bool {
        matches!(self, Function::PageRead(_) | Function::PageWrite(_))
    }
}

impl fmt::Display for Function {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:04X} {}", self.code(), self.name())
    }
}

fn page_code(page: PageRef, data: u16, system: u16, konst: u16, arg: u16, ins: u16) -> u16 {
    match page {
        PageRef::Data(p) => data | u16::from(p & 0x0F),
        PageRef::System(p) => system | u16::from(p & 0x0F),
        PageRef::Const => konst,
        PageRef::Argument(p) => arg | u16::from(p),
        PageRef::Instruction(p) => ins | u16::from(p),
    }
}

fn page_name(
    page: PageRef,
    data: &'static str,
    system: &'static str,
    konst: &'static str,
    arg: &'static str,
    ins: &'static str,
) -> &'static str {
    match page {
        PageRef::Data(_) => data,
        PageRef::System(_) => system,
        PageRef::Const => konst,
        PageRef::Argument(_) => arg,
        PageRef::Instruction(_) => ins,
    }
}

#[cfg(test)]
mod tests {

    #[test]
    fn page_functions_name_image_pages() {
        use gutta_format::{PageId, PageKind};
        let page = |code| match Function::from_code(code) {
            Some(Function::PageAsk(p) | Function::PageRead(p) | Function::PageWrite(p)) => {
                Some(p.page_id())
            }
            _ => None,
        };
        assert_eq!(page(0x0223), Some(PageId::new(PageKind::Data, 3)));
        assert_eq!(page(0x0245), Some(PageId::new(PageKind::Data, 5)));
        assert_eq!(page(0x028F), Some(PageId::new(PageKind::System, 15)));
        assert_eq!(page(0x0311), Some(PageId::new(PageKind::Const, 0)));
        assert_eq!(page(0x05AB), Some(PageId::new(PageKind::Argument, 0xAB)));
        assert_eq!(page(0x0908), Some(PageId::new(PageKind::Instruction, 8)));
        assert_eq!(page(0x0250), None);
        for id in [
            PageId::new(PageKind::Data, 15),
            PageId::new(PageKind::Argument, 200),
        ] {
            assert_eq!(PageRef::of(id).map(PageRef::page_id), Some(id));
        }
        assert_eq!(PageRef::of(PageId::new(PageKind::System, 16)), None);
    }
    use super::*;

    #[test]
    fn plc_clear_gutta_data_from_um4001() {
        let frame = GuttaFrame::single(Function::PlcClear.code(), vec![]);
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
    fn every_code_classifies_and_round_trips() {
        let mut defined = 0;
        for code in 0..=u16::MAX {
            if let Some(function) = Function::from_code(code) {
                defined += 1;
                assert_eq!(function.code(), code, "{function:?}");
            }
        }
        // 5 control + 3 lists + 3 x 16 data + 3 x 16 system + 3 const + 3 x 256 argument
        // + 3 x 256 instruction + 14 status/debug.
        assert_eq!(defined, 5 + 3 + 48 + 48 + 3 + 768 + 768 + 14);
        assert_eq!(Function::from_code(0x8100), None);
        assert_eq!(Function::from_code(0x0250), None);
        assert_eq!(Function::from_code(0x0A04), None);
    }

    #[test]
    fn login_and_stop_conditions() {
        let no_login: Vec<&str> = (0..=u16::MAX)
            .filter_map(Function::from_code)
            .filter(|f| !f.needs_login())
            .map(Function::name)
            .collect();
        assert_eq!(
            no_login,
            [
                "PLC_CLEAR",
                "PLC_ATTACH",
                "PLC_DETACH",
                "STATUS_RESET",
                "STATUS_DEBUG_RESET"
            ]
        );
        assert!(Function::PageWrite(PageRef::Const).needs_stop());
        assert!(!Function::VarWrite.needs_stop());
        assert!(Function::PageRead(PageRef::Argument(9)).is_paged());
        assert!(!Function::PageAsk(PageRef::Argument(9)).is_paged());
        assert_eq!(
            Function::PageAsk(PageRef::Data(3)).to_string(),
            "0223 DATA_PAGE_ASK"
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
