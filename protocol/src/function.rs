//! What a UM4001 function code names: `Function` (every code, page functions with their
//! page), `PageRef` and `PageArea`. Everything a function *is* (its code, name, login
//! and stop conditions, packets, payload shapes) comes from its row in `registry`; this
//! module only turns a code into a `Function` and back. It knows no payload bytes.

use std::fmt;

use crate::registry::{FunctionSpec, FUNCTIONS};

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

    /// The page number (0 for the const page).
    pub fn number(self) -> u8 {
        match self {
            PageRef::Data(n)
            | PageRef::System(n)
            | PageRef::Argument(n)
            | PageRef::Instruction(n) => n,
            PageRef::Const => 0,
        }
    }

    /// The same kind of page, numbered `number` (the const page stays the const page).
    pub fn numbered(self, number: u8) -> PageRef {
        match self {
            PageRef::Data(_) => PageRef::Data(number),
            PageRef::System(_) => PageRef::System(number),
            PageRef::Const => PageRef::Const,
            PageRef::Argument(_) => PageRef::Argument(number),
            PageRef::Instruction(_) => PageRef::Instruction(number),
        }
    }
}

/// Every UM4001 function code, classified. Page functions carry their page. Each
/// variant (each page kind of a page function) is one row of `registry::FUNCTIONS`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Function {
    PlcClear,
    PlcAttach,
    PlcDetach,
    GetPlcName,
    GetPlcInfor,
    /// DATA_ASK, SYSTEM_ASK, PROGRAM_ASK: the list of valid page numbers.
    PageList(PageArea),
    /// A page's length (16-bit, high byte first).
    PageAsk(PageRef),
    /// Read a page, packet by packet.
    PageRead(PageRef),
    /// Write a page, packet by packet.
    PageWrite(PageRef),
    StatusRead,
    StatusWrite,
    StatusScan,
    StatusReset,
    VarRead,
    VarWrite,
    ForceRead,
    ForceWrite,
    DebugRead,
    DebugWrite,
    DebugScan,
    DebugReset,
    DebugInforRead,
    DebugInforWrite,
}

impl Function {
    /// The 16-bit code: the row's code with the page number in its field. Page numbers
    /// are masked to their field (4 or 8 bits); check `PageRef::is_valid` first where
    /// that matters (`message` does).
    pub fn code(self) -> u16 {
        let spec = self.spec();
        spec.code | (u16::from(self.page_number()) & spec.page_mask())
    }

    /// Classifies a code (without the failure bit); `None` if UM4001 does not define it.
    pub fn from_code(code: u16) -> Option<Self> {
        let spec = FUNCTIONS.iter().find(|spec| spec.covers(code))?;
        // The page field is at most 8 bits wide.
        let page = (code & spec.page_mask()) as u8;
        Some(spec.function.with_page(page))
    }

    /// The function's row of the registry: everything UM4001 says of it.
    pub fn spec(self) -> &'static FunctionSpec {
        crate::registry::spec_of(self)
    }

    /// The UM4001 name (page functions without their page number).
    pub fn name(self) -> &'static str {
        self.spec().name
    }

    /// Whether UM4001 lists "PLC 被登陆" among the success conditions (the row's
    /// `needs`).
    pub fn needs_login(self) -> bool {
        self.spec().needs.login()
    }

    /// Whether the function succeeds only while the PLC is not running (page writes).
    pub fn needs_stop(self) -> bool {
        self.spec().needs.stop()
    }

    /// Page reads and writes use packet numbers 0, 1, ...; everything else is a single
    /// packet 0x8000.
    pub fn is_paged(self) -> bool {
        self.spec().packets == crate::registry::Packets::Paged
    }

    /// The page a page function carries.
    pub fn page(self) -> Option<PageRef> {
        match self {
            Function::PageAsk(page) | Function::PageRead(page) | Function::PageWrite(page) => {
                Some(page)
            }
            _ => None,
        }
    }

    fn page_number(self) -> u8 {
        self.page().map_or(0, PageRef::number)
    }

    /// The same function on page `number` (functions without a page are unchanged).
    fn with_page(self, number: u8) -> Function {
        match self {
            Function::PageAsk(page) => Function::PageAsk(page.numbered(number)),
            Function::PageRead(page) => Function::PageRead(page.numbered(number)),
            Function::PageWrite(page) => Function::PageWrite(page.numbered(number)),
            other => other,
        }
    }
}

impl fmt::Display for Function {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:04X} {}", self.code(), self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn page_functions_name_image_pages() {
        use gutta_format::{PageId, PageKind};
        let page = |code| {
            Function::from_code(code)
                .and_then(Function::page)
                .map(PageRef::page_id)
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
        // A data page number above 15 is masked to its field.
        assert_eq!(Function::PageWrite(PageRef::Data(0x13)).code(), 0x0243);
    }
}
