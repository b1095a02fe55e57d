//! The registry of UM4001 functions: one row per function (a page function's 16 or 256
//! codes are one row with the page in the code's low bits), like the compiler's
//! diagnostic codes. A row says the code, the name, what the PLC needs for it (a login,
//! a stopped PLC), whether it moves in packets, and the shapes of its request and
//! success payloads. `Function`'s classification, the payload length checks of
//! `message`, the simulator's login and stop rules and docs/protocol.md's function
//! table (`reference_markdown`, kept in sync by `tests/docs.rs`) all come from here.
//! It knows no payload's meaning beyond its shape.

use std::fmt;

use crate::function::Function::{self, *};
use crate::function::{PageArea, PageRef};
use Payload::{Any, Bytes, Empty, Multiple};

/// What the PLC needs before it executes a function (UM4001's success conditions).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Needs {
    /// No login: PLC_CLEAR, PLC_ATTACH (it is the login), PLC_DETACH and the resets.
    Nothing,
    /// PLC_ATTACH succeeded ("PLC 被登陆").
    Login,
    /// A login and a PLC that is not running (page writes).
    LoginStopped,
}

impl Needs {
    pub fn login(self) -> bool {
        self != Needs::Nothing
    }
    pub fn stop(self) -> bool {
        self == Needs::LoginStopped
    }
}

/// How a function's messages are numbered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Packets {
    /// One packet, number 0x8000.
    Single,
    /// Packets 0, 1, ... of a page, bit 15 on the last (page reads and writes).
    Paged,
}

/// Where a function code carries its page number.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PageField {
    /// The code is one code.
    None,
    /// The low 4 bits: data and system pages 0..=15 (`022X`).
    Low4,
    /// The low 8 bits: argument and instruction pages 0..=255 (`04XX`).
    Low8,
}

impl PageField {
    /// The bits of the code that hold the page.
    pub fn mask(self) -> u16 {
        match self {
            PageField::None => 0,
            PageField::Low4 => 0x0F,
            PageField::Low8 => 0xFF,
        }
    }
}

/// The shape of a request or success payload: what its length must be.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Payload {
    /// No bytes (a success without payload is an acknowledgement).
    Empty,
    /// Exactly this many bytes.
    Bytes(usize),
    /// A multiple of this many bytes (addresses, values, address/value pairs).
    Multiple(usize),
    /// Any number of bytes (a packet of a page, a page list).
    Any,
}

impl Payload {
    /// Whether a payload of `len` bytes has this shape.
    pub fn accepts(self, len: usize) -> bool {
        match self {
            Empty => len == 0,
            Bytes(n) => len == n,
            Multiple(n) => n != 0 && len.is_multiple_of(n),
            Any => true,
        }
    }

    /// The shape as the docs table writes it ("none", "16 bytes", "4n bytes", ...).
    fn doc(self) -> String {
        match self {
            Empty => "none".into(),
            Bytes(1) => "1 byte".into(),
            Bytes(n) => format!("{n} bytes"),
            Multiple(n) => format!("{n}n bytes"),
            Any => "n bytes".into(),
        }
    }
}

/// The length a payload must have, as error messages say it ("0", "16", "a multiple
/// of 4").
impl fmt::Display for Payload {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Empty => f.write_str("0"),
            Bytes(n) => write!(f, "{n}"),
            Multiple(n) => write!(f, "a multiple of {n}"),
            Any => f.write_str("any length"),
        }
    }
}

/// One row of the registry.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FunctionSpec {
    /// The UM4001 name (page functions without their page number).
    pub name: &'static str,
    /// The function on page 0 (for page functions), the one this row classifies.
    pub function: Function,
    /// The code with the page field 0.
    pub code: u16,
    pub page_field: PageField,
    pub needs: Needs,
    pub packets: Packets,
    pub request: Payload,
    pub success: Payload,
    /// What the request payload holds (docs).
    pub request_doc: &'static str,
    /// What the success payload holds (docs).
    pub success_doc: &'static str,
    /// Further conditions and effects (docs).
    pub note: &'static str,
}

impl FunctionSpec {
    /// The bits of the code that hold the page number.
    pub fn page_mask(&self) -> u16 {
        self.page_field.mask()
    }

    /// Whether `code` is one of this row's codes.
    pub fn covers(&self, code: u16) -> bool {
        code & !self.page_mask() == self.code
    }

    /// The code as UM4001 writes it: `0100`, `022X`, `04XX`.
    pub fn code_doc(&self) -> String {
        let hex = format!("{:04X}", self.code);
        match self.page_field {
            PageField::None => hex,
            PageField::Low4 => format!("{}X", &hex[..3]),
            PageField::Low8 => format!("{}XX", &hex[..2]),
        }
    }
}

macro_rules! functions {
    ($($name:ident: $pattern:pat => $function:expr, $code:literal $page:ident,
        $needs:ident $packets:ident,
        $request:expr, $request_doc:literal, $success:expr, $success_doc:literal,
        $note:literal;)*) => {
        $(
            const $name: FunctionSpec = FunctionSpec {
                name: stringify!($name),
                function: $function,
                code: $code,
                page_field: PageField::$page,
                needs: Needs::$needs,
                packets: Packets::$packets,
                request: $request,
                success: $success,
                request_doc: $request_doc,
                success_doc: $success_doc,
                note: $note,
            };
        )*

        /// Every row, in code order.
        pub const FUNCTIONS: &[FunctionSpec] = &[$($name,)*];

        /// The row of a function (the match is exhaustive: a function without a row
        /// does not compile).
        pub(crate) fn spec_of(function: Function) -> &'static FunctionSpec {
            match function {
                $($pattern => &$name,)*
            }
        }
    };
}

functions! {
    // name: pattern => function on page 0, code page-field, needs packets,
    //   request shape, "what it holds", success shape, "what it holds", "notes";
    PLC_CLEAR: PlcClear => PlcClear, 0x0100 None, Nothing Single,
        Empty, "", Empty, "",
        "erases user flash incl. password, stops, unlocks flash; port back to 19200 8E1";
    PLC_ATTACH: PlcAttach => PlcAttach, 0x0110 None, Nothing Single,
        Bytes(16), "password (factory: 16 x FF)", Empty, "",
        "it is the login: the password equals the system page's; sets ATTACH";
    PLC_DETACH: PlcDetach => PlcDetach, 0x0111 None, Nothing Single,
        Empty, "", Empty, "not shown in UM4001; **we** use the echo",
        "UM4001 lists no login; clears ATTACH";
    GET_PLC_NAME: GetPlcName => GetPlcName, 0x0120 None, Login Single,
        Empty, "", Bytes(16), "zero-terminated if shorter", "";
    GET_PLC_INFOR: GetPlcInfor => GetPlcInfor, 0x0121 None, Login Single,
        Empty, "", Bytes(64), "zero-terminated if shorter", "";
    DATA_ASK: PageList(PageArea::Data) => PageList(PageArea::Data), 0x0210 None, Login Single,
        Empty, "", Any, "one page number per valid data page", "";
    DATA_PAGE_ASK: PageAsk(PageRef::Data(_)) => PageAsk(PageRef::Data(0)), 0x0220 Low4,
        Login Single,
        Empty, "", Bytes(2), "length of data page X, high byte first", "X = 0..15";
    DATA_PAGE_READ: PageRead(PageRef::Data(_)) => PageRead(PageRef::Data(0)), 0x0230 Low4,
        Login Paged,
        Empty, "",
        Any, "bytes of packet i: from i x ExchPackSize, up to ExchPackSize or the page end",
        "";
    DATA_PAGE_WRITE: PageWrite(PageRef::Data(_)) => PageWrite(PageRef::Data(0)), 0x0240 Low4,
        LoginStopped Paged,
        Any, "packet i's bytes", Empty, "", "";
    SYSTEM_ASK: PageList(PageArea::System) => PageList(PageArea::System), 0x0260 None,
        Login Single,
        Empty, "", Any, "valid system page numbers", "";
    SYSTEM_PAGE_ASK: PageAsk(PageRef::System(_)) => PageAsk(PageRef::System(0)), 0x0270 Low4,
        Login Single,
        Empty, "", Bytes(2), "length, high byte first", "X = 0..15";
    SYSTEM_PAGE_READ: PageRead(PageRef::System(_)) => PageRead(PageRef::System(0)), 0x0280 Low4,
        Login Paged,
        Empty, "", Any, "packet i's bytes", "";
    SYSTEM_PAGE_WRITE: PageWrite(PageRef::System(_)) => PageWrite(PageRef::System(0)),
        0x0290 Low4, LoginStopped Paged,
        Any, "packet i's bytes", Empty, "", "";
    PROGRAM_ASK: PageList(PageArea::Program) => PageList(PageArea::Program), 0x0300 None,
        Login Single,
        Empty, "", Any, "valid program page numbers", "";
    PROGRAM_CONST_ASK: PageAsk(PageRef::Const) => PageAsk(PageRef::Const), 0x0310 None,
        Login Single,
        Empty, "", Bytes(2), "length of the const page", "";
    PROGRAM_CONST_READ: PageRead(PageRef::Const) => PageRead(PageRef::Const), 0x0311 None,
        Login Paged,
        Empty, "", Any, "packet i's bytes", "";
    PROGRAM_CONST_WRITE: PageWrite(PageRef::Const) => PageWrite(PageRef::Const), 0x0312 None,
        LoginStopped Paged,
        Any, "packet i's bytes", Empty, "", "";
    PROGRAM_ARGUMENT_ASK: PageAsk(PageRef::Argument(_)) => PageAsk(PageRef::Argument(0)),
        0x0400 Low8, Login Single,
        Empty, "", Bytes(2), "length of argument page XX", "XX = 0..255";
    PROGRAM_ARGUMENT_READ: PageRead(PageRef::Argument(_)) => PageRead(PageRef::Argument(0)),
        0x0500 Low8, Login Paged,
        Empty, "", Any, "packet i's bytes", "";
    PROGRAM_ARGUMENT_WRITE: PageWrite(PageRef::Argument(_)) => PageWrite(PageRef::Argument(0)),
        0x0600 Low8, LoginStopped Paged,
        Any, "packet i's bytes", Empty, "", "";
    PROGRAM_INSTRUCTION_ASK: PageAsk(PageRef::Instruction(_)) => PageAsk(PageRef::Instruction(0)),
        0x0700 Low8, Login Single,
        Empty, "", Bytes(2), "length of program page XX", "";
    PROGRAM_INSTRUCTION_READ: PageRead(PageRef::Instruction(_))
        => PageRead(PageRef::Instruction(0)), 0x0800 Low8, Login Paged,
        Empty, "", Any, "packet i's bytes", "";
    PROGRAM_INSTRUCTION_WRITE: PageWrite(PageRef::Instruction(_))
        => PageWrite(PageRef::Instruction(0)), 0x0900 Low8, LoginStopped Paged,
        Any, "packet i's bytes", Empty, "", "";
    STATUS_READ: StatusRead => StatusRead, 0x0A00 None, Login Single,
        Empty, "", Bytes(1), "SYS_STATE: bit0 RUN, bit1 RESET, bit2 ATTACH, bit3 ERROR", "";
    STATUS_WRITE: StatusWrite => StatusWrite, 0x0A01 None, Login Single,
        Bytes(1), "0 stop, else run", Empty, "", "";
    STATUS_SCAN: StatusScan => StatusScan, 0x0A02 None, Login Single,
        Bytes(1), "number of main scans while stopped", Empty, "sent before the scans finish", "";
    STATUS_RESET: StatusReset => StatusReset, 0x0A03 None, Nothing Single,
        Empty, "", Empty, "sent before the reset", "re-locks flash, requests reset";
    STATUS_VAR_READ: VarRead => VarRead, 0x0A10 None, Login Single,
        Multiple(4), "n addresses, each low byte first",
        Multiple(4), "the 4 bytes at each address (SLOT + OFFSET only), low byte first", "";
    STATUS_VAR_WRITE: VarWrite => VarWrite, 0x0A11 None, Login Single,
        Multiple(8), "(address, value) pairs, each low byte first", Empty, "",
        "SLOT, WIDTH, BIT_OFFSET, OFFSET decide what is written; \
         a forced variable's force value changes too";
    STATUS_VAR_FORCE_READ: ForceRead => ForceRead, 0x0A20 None, Login Single,
        Multiple(4), "addresses", Multiple(4), "force values", "";
    STATUS_VAR_FORCE_WRITE: ForceWrite => ForceWrite, 0x0A21 None, Login Single,
        Multiple(8), "(address, force value) pairs", Empty, "", "";
    STATUS_DEBUG_READ: DebugRead => DebugRead, 0x0A30 None, Login Single,
        Empty, "", Bytes(1), "DEBUG_STATE: bit0 RUN, bit1 RESET", "";
    STATUS_DEBUG_WRITE: DebugWrite => DebugWrite, 0x0A31 None, Login Single,
        Bytes(1), "0 single-step stop, else run until a breakpoint", Empty, "", "";
    STATUS_DEBUG_SCAN: DebugScan => DebugScan, 0x0A32 None, Login Single,
        Bytes(1), "1 STEP_IN, 2 STEP_OVER, 3 STEP_OUT", Empty, "", "";
    STATUS_DEBUG_RESET: DebugReset => DebugReset, 0x0A33 None, Nothing Single,
        Empty, "", Empty, "sent before the reset",
        "UM4001 lists no login; reset into single-step stop";
    STATUS_DEBUG_INFOR_READ: DebugInforRead => DebugInforRead, 0x0A34 None, Login Single,
        Empty, "", Bytes(16), "DEBUG_INFOR, below", "";
    STATUS_DEBUG_INFOR_WRITE: DebugInforWrite => DebugInforWrite, 0x0A35 None, Login Single,
        Bytes(5), "breakpoint function (byte), network (word), step (word)", Empty, "", "";
}

/// docs/protocol.md's function table, generated from the registry (between its
/// `<!-- functions -->` markers; `tests/docs.rs` keeps it in sync).
pub fn reference_markdown() -> String {
    let mut out = String::from(
        "| code | name | needs | packets | request payload | success payload | notes |\n\
         | --- | --- | --- | --- | --- | --- | --- |\n",
    );
    for spec in FUNCTIONS {
        let needs = match spec.needs {
            Needs::Nothing => "no login",
            Needs::Login => "login",
            Needs::LoginStopped => "login, PLC stopped",
        };
        let packets = match spec.packets {
            Packets::Single => "8000",
            Packets::Paged => "0, 1, ...",
        };
        let request = described(spec.request.doc(), spec.request_doc);
        let success = match spec.success {
            Empty if spec.success_doc.is_empty() => "ack".to_string(),
            Empty => format!("ack ({})", spec.success_doc),
            shape => described(shape.doc(), spec.success_doc),
        };
        out.push_str(&format!(
            "| {} | {} | {needs} | {packets} | {request} | {success} | {} |\n",
            spec.code_doc(),
            spec.name,
            spec.note
        ));
    }
    out
}

fn described(shape: String, what: &str) -> String {
    if what.is_empty() {
        shape
    } else {
        format!("{shape}: {what}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_row_classifies_its_codes_and_no_two_rows_overlap() {
        for spec in FUNCTIONS {
            assert_eq!(spec.code & spec.page_mask(), 0, "{}", spec.name);
            assert_eq!(spec.function.spec(), spec, "{}", spec.name);
            assert_eq!(Function::from_code(spec.code), Some(spec.function));
            assert_eq!(spec.function.code(), spec.code, "{}", spec.name);
            let others = FUNCTIONS.iter().filter(|o| o.name != spec.name);
            for other in others {
                assert!(!other.covers(spec.code), "{} and {}", spec.name, other.name);
            }
            // Page writes are the only functions that need a stopped PLC, and only
            // page reads and writes are paged (UM4001).
            let write = matches!(spec.function, PageWrite(_));
            let paged = matches!(spec.function, PageRead(_) | PageWrite(_));
            assert_eq!(spec.needs.stop(), write, "{}", spec.name);
            assert_eq!(spec.packets == Packets::Paged, paged, "{}", spec.name);
        }
    }

    #[test]
    fn shapes_accept_exactly_their_lengths() {
        assert!(Empty.accepts(0) && !Empty.accepts(1));
        assert!(Bytes(16).accepts(16) && !Bytes(16).accepts(15));
        assert!(Multiple(8).accepts(0) && Multiple(8).accepts(16) && !Multiple(8).accepts(12));
        assert!(Any.accepts(0) && Any.accepts(1023));
        assert_eq!(Multiple(4).to_string(), "a multiple of 4");
        assert_eq!(STATUS_VAR_READ.code_doc(), "0A10");
        assert_eq!(DATA_PAGE_ASK.code_doc(), "022X");
        assert_eq!(PROGRAM_ARGUMENT_WRITE.code_doc(), "06XX");
    }
}
