//! Why an image does not verify: one typed variant per rule, each with a stable code
//! (`V0001`...) from the registry below and, where it has one, the page and byte offset.
//! Codes are never reused; docs/image-format.md "Verifying an image" explains each.

use std::fmt;

use gutta_catalog::{plural, BlockKind, LoopRole, Width};

use crate::{DecodeError, PackedOperand, PageId, UnitRef};

/// A byte in a page.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Location {
    pub page: PageId,
    /// Byte offset in the page.
    pub offset: usize,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} at byte {}", self.page.file_name(), self.offset)
    }
}

/// Declares `VerifyCode` with its `V` number and a one-line summary per variant.
macro_rules! codes {
    ($($variant:ident = $code:literal, $summary:literal;)*) => {
        /// The stable code of each kind of verification error.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub enum VerifyCode {
            $($variant,)*
        }

        impl VerifyCode {
            /// Every code, in number order.
            pub const ALL: &'static [VerifyCode] = &[$(VerifyCode::$variant,)*];

            /// `V0001`, ...
            pub fn as_str(self) -> &'static str {
                match self {
                    $(VerifyCode::$variant => $code,)*
                }
            }

            /// What the rule is, in one line.
            pub fn summary(self) -> &'static str {
                match self {
                    $(VerifyCode::$variant => $summary,)*
                }
            }
        }
    };
}

codes! {
    PlcTypeMismatch = "V0001", "the image is for another PLC type";
    PageNotOnTarget = "V0002", "a page number the target does not have";
    MissingConstPage = "V0003", "no const page";
    MissingMain = "V0004", "no MAIN (argument and instruction page 0)";
    UnpairedPage = "V0005", "an argument page without its instruction page, or the reverse";
    SizeLimit = "V0006", "a page or the image exceeds a PlcType limit";
    Decode = "V0007", "a page does not decode";
    UnitHeader = "V0008", "an argument page's unit kind or number disagrees with its page number";
    InterruptParameter = "V0009", "an interrupt routine has a VAR_INPUT, VAR_IN_OUT or VAR_OUTPUT";
    LocalOrder = "V0010", "locals not in the order VAR_INPUT, VAR_IN_OUT, VAR_OUTPUT, VAR";
    UnknownOpcode = "V0011", "an opcode the instruction set does not have";
    NotInUnit = "V0012", "an instruction in a kind of unit its Units do not allow";
    OperandCount = "V0013", "wrong number of operands";
    UseNotAllowed = "V0014", "a USE the operand does not accept";
    MalformedOperand = "V0015", "an operand field holds an impossible value";
    ValueOutOfRange = "V0016", "a label or literal outside its range";
    NoSuchArea = "V0017", "a SLOT that is no area of the target";
    WidthMismatch = "V0018", "an operand's WIDTH is not the width its type needs";
    WidthNotAllowed = "V0019", "the area does not allow the access width";
    BitOffset = "V0020", "BIT_OFFSET above 7, or not 0 for a byte, word or dword";
    OutOfArea = "V0021", "an access reaching past the end of its area";
    Misaligned = "V0022", "a byte offset that is not a whole number of the area's units";
    AreaNotAllowed = "V0023", "an area the operand does not accept";
    NotPointerArea = "V0024", "a pointer (USE 2) in an area that cannot hold pointers";
    NotAddressOfArea = "V0025", "an address-of (USE 1) of an area that does not allow `&`";
    WriteToReadOnly = "V0026", "a written operand in an area programs cannot write";
    BlockKindMismatch = "V0027", "a unit operand of the wrong kind";
    NoSuchUnit = "V0028", "a unit operand naming a unit the image does not have";
    JumpWithoutLabel = "V0029", "a JMP without its LBL in the same page";
    DuplicateLabel = "V0030", "a label defined twice in one page";
    CallCycle = "V0031", "a subroutine that calls itself";
    CallDepth = "V0032", "calls nested deeper than CallDepth";
    DataValue = "V0033", "a data item's value is not its width sign- or zero-extended";
    SystemVersion = "V0034", "an unknown system page layout version";
    SystemPortCount = "V0035", "a system page with another number of ports than the target";
    SystemValue = "V0036", "a port setting outside its range";
    SystemPassword = "V0037", "a password that is neither ASCII nor the factory password";
    UnknownEvent = "V0038", "an interrupt event number the target does not have";
    ReservedNotZero = "V0039", "a reserved byte that is not 0";
    UnmatchedLoop = "V0040", "a FOR without its NEXT, or a NEXT without its FOR, in one page";
    OverlappingLocals = "V0041", "two locals of one unit share bits of L";
    LoopDepth = "V0042", "FOR loops nested deeper than ForDepth";
}

impl fmt::Display for VerifyCode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Why an image does not verify against a target.
///
/// `operand` fields describe the operand for people: `OUT (operand 1) of MOVW`,
/// `local 3`, `data item 0`, `argument 2 of CALL to page 08`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum VerifyError {
    PlcTypeMismatch {
        image: String,
        target: String,
    },
    PageNotOnTarget {
        page: PageId,
        /// Pages of the kind the target has (numbers 0..count).
        count: u32,
        /// The PlcType attribute (or rule) that gives `count`.
        limit: &'static str,
    },
    MissingConstPage,
    MissingMain,
    UnpairedPage {
        page: PageId,
        missing: PageId,
    },
    SizeLimit {
        /// The page, or `None` for a limit on the whole image.
        page: Option<PageId>,
        /// What is counted: `bytes`, `locals`, `data items`.
        what: &'static str,
        size: u64,
        limit: String,
        max: u64,
    },
    Decode {
        page: PageId,
        error: DecodeError,
    },
    UnitHeader {
        at: Location,
        expected: (BlockKind, u8),
        found: (BlockKind, u8),
    },
    InterruptParameter {
        at: Location,
        local: usize,
    },
    LocalOrder {
        at: Location,
        local: usize,
    },
    UnknownOpcode {
        at: Location,
        opcode: u16,
    },
    NotInUnit {
        at: Location,
        mnemonic: String,
        /// `MAIN`, `INT3`, `SBR0`.
        unit: String,
        /// Where the instruction may stand, in words.
        allowed: String,
    },
    OperandCount {
        at: Location,
        mnemonic: String,
        expected: usize,
        found: usize,
    },
    UseNotAllowed {
        at: Location,
        operand: String,
        use_code: u8,
    },
    MalformedOperand {
        at: Location,
        operand: String,
        value: PackedOperand,
        reason: &'static str,
    },
    ValueOutOfRange {
        at: Location,
        operand: String,
        value: u16,
        min: i64,
        max: i64,
    },
    NoSuchArea {
        at: Location,
        operand: String,
        slot: u8,
    },
    WidthMismatch {
        at: Location,
        operand: String,
        expected: Width,
        found: u8,
    },
    WidthNotAllowed {
        at: Location,
        operand: String,
        area: String,
        width: Width,
    },
    BitOffset {
        at: Location,
        operand: String,
        bit: u8,
        width: Width,
    },
    OutOfArea {
        at: Location,
        operand: String,
        area: String,
        offset: u16,
        bytes: u32,
        size: u32,
    },
    Misaligned {
        at: Location,
        operand: String,
        area: String,
        offset: u16,
        unit: Width,
    },
    AreaNotAllowed {
        at: Location,
        operand: String,
        area: String,
        /// The areas that are accepted, in words.
        allowed: String,
    },
    NotPointerArea {
        at: Location,
        operand: String,
        area: String,
    },
    NotAddressOfArea {
        at: Location,
        operand: String,
        area: String,
    },
    WriteToReadOnly {
        at: Location,
        operand: String,
        area: String,
    },
    BlockKindMismatch {
        at: Location,
        operand: String,
        expected: BlockKind,
        found: BlockKind,
        number: u16,
    },
    NoSuchUnit {
        at: Location,
        operand: String,
        kind: BlockKind,
        number: u16,
    },
    JumpWithoutLabel {
        at: Location,
        label: u16,
    },
    DuplicateLabel {
        at: Location,
        label: u16,
        /// Offset of the first `LBL` with the number.
        first: usize,
    },
    /// Two locals of one argument page cover the same bits of L (a CALL would pass two
    /// parameters through one variable).
    OverlappingLocals {
        at: Location,
        local: usize,
        /// The earlier local it overlaps.
        other: usize,
    },
    /// A `FOR` opened while ForDepth loops are already open.
    LoopDepth {
        at: Location,
        /// Loops open with this one.
        depth: usize,
        /// ForDepth of the instruction set.
        max: u8,
    },
    /// A `FOR` never closed by a `NEXT` of the same page, or a `NEXT` with no open `FOR`.
    UnmatchedLoop {
        at: Location,
        /// `FOR` or `NEXT`: the instruction at `at`.
        mnemonic: String,
        /// Its part in the loop: a start without its end, or an end without its start.
        role: LoopRole,
    },
    CallCycle {
        /// The `CALL` that closes the cycle.
        at: Location,
        /// The subroutine called again, by page number.
        callee: u8,
    },
    CallDepth {
        /// The instruction page of the interrupt routine the calls start from.
        page: PageId,
        depth: usize,
        max: usize,
    },
    DataValue {
        at: Location,
        item: usize,
        value: u32,
        width: Width,
    },
    SystemVersion {
        at: Location,
        found: u8,
    },
    SystemPortCount {
        at: Location,
        found: u8,
        expected: u8,
    },
    SystemValue {
        at: Location,
        port: usize,
        field: &'static str,
        value: u8,
        allowed: &'static str,
    },
    SystemPassword {
        at: Location,
    },
    UnknownEvent {
        at: Location,
        operand: String,
        event: u16,
    },
    ReservedNotZero {
        at: Location,
        value: u8,
    },
}

/// `INT3` / `SBR0` / `MAIN`: `UnitRef`'s name.
fn unit_name(kind: BlockKind, number: u16) -> String {
    UnitRef { kind, number }.to_string()
}

fn kind_word(kind: BlockKind) -> &'static str {
    match kind {
        BlockKind::Interrupt => "an interrupt routine",
        BlockKind::Subroutine => "a subroutine",
    }
}

impl VerifyError {
    pub fn code(&self) -> VerifyCode {
        use VerifyError as E;
        match self {
            E::PlcTypeMismatch { .. } => VerifyCode::PlcTypeMismatch,
            E::PageNotOnTarget { .. } => VerifyCode::PageNotOnTarget,
            E::MissingConstPage => VerifyCode::MissingConstPage,
            E::MissingMain => VerifyCode::MissingMain,
            E::UnpairedPage { .. } => VerifyCode::UnpairedPage,
            E::SizeLimit { .. } => VerifyCode::SizeLimit,
            E::Decode { .. } => VerifyCode::Decode,
            E::UnitHeader { .. } => VerifyCode::UnitHeader,
            E::InterruptParameter { .. } => VerifyCode::InterruptParameter,
            E::LocalOrder { .. } => VerifyCode::LocalOrder,
            E::UnknownOpcode { .. } => VerifyCode::UnknownOpcode,
            E::NotInUnit { .. } => VerifyCode::NotInUnit,
            E::OperandCount { .. } => VerifyCode::OperandCount,
            E::UseNotAllowed { .. } => VerifyCode::UseNotAllowed,
            E::MalformedOperand { .. } => VerifyCode::MalformedOperand,
            E::ValueOutOfRange { .. } => VerifyCode::ValueOutOfRange,
            E::NoSuchArea { .. } => VerifyCode::NoSuchArea,
            E::WidthMismatch { .. } => VerifyCode::WidthMismatch,
            E::WidthNotAllowed { .. } => VerifyCode::WidthNotAllowed,
            E::BitOffset { .. } => VerifyCode::BitOffset,
            E::OutOfArea { .. } => VerifyCode::OutOfArea,
            E::Misaligned { .. } => VerifyCode::Misaligned,
            E::AreaNotAllowed { .. } => VerifyCode::AreaNotAllowed,
            E::NotPointerArea { .. } => VerifyCode::NotPointerArea,
            E::NotAddressOfArea { .. } => VerifyCode::NotAddressOfArea,
            E::WriteToReadOnly { .. } => VerifyCode::WriteToReadOnly,
            E::BlockKindMismatch { .. } => VerifyCode::BlockKindMismatch,
            E::NoSuchUnit { .. } => VerifyCode::NoSuchUnit,
            E::JumpWithoutLabel { .. } => VerifyCode::JumpWithoutLabel,
            E::DuplicateLabel { .. } => VerifyCode::DuplicateLabel,
            E::UnmatchedLoop { .. } => VerifyCode::UnmatchedLoop,
            E::OverlappingLocals { .. } => VerifyCode::OverlappingLocals,
            E::LoopDepth { .. } => VerifyCode::LoopDepth,
            E::CallCycle { .. } => VerifyCode::CallCycle,
            E::CallDepth { .. } => VerifyCode::CallDepth,
            E::DataValue { .. } => VerifyCode::DataValue,
            E::SystemVersion { .. } => VerifyCode::SystemVersion,
            E::SystemPortCount { .. } => VerifyCode::SystemPortCount,
            E::SystemValue { .. } => VerifyCode::SystemValue,
            E::SystemPassword { .. } => VerifyCode::SystemPassword,
            E::UnknownEvent { .. } => VerifyCode::UnknownEvent,
            E::ReservedNotZero { .. } => VerifyCode::ReservedNotZero,
        }
    }

    /// The page the error is in, if it is in one.
    pub fn page(&self) -> Option<PageId> {
        use VerifyError as E;
        match self {
            E::PlcTypeMismatch { .. } | E::MissingConstPage | E::MissingMain => None,
            E::PageNotOnTarget { page, .. }
            | E::UnpairedPage { page, .. }
            | E::Decode { page, .. }
            | E::CallDepth { page, .. } => Some(*page),
            E::SizeLimit { page, .. } => *page,
            other => other.location().map(|l| l.page),
        }
    }

    /// The page and byte offset of the error, if it has one.
    pub fn location(&self) -> Option<Location> {
        use VerifyError as E;
        match self {
            E::PlcTypeMismatch { .. }
            | E::PageNotOnTarget { .. }
            | E::MissingConstPage
            | E::MissingMain
            | E::UnpairedPage { .. }
            | E::SizeLimit { .. }
            | E::CallDepth { .. } => None,
            E::Decode { page, error } => Some(Location {
                page: *page,
                offset: error.offset,
            }),
            E::UnitHeader { at, .. }
            | E::InterruptParameter { at, .. }
            | E::LocalOrder { at, .. }
            | E::UnknownOpcode { at, .. }
            | E::NotInUnit { at, .. }
            | E::OperandCount { at, .. }
            | E::UseNotAllowed { at, .. }
            | E::MalformedOperand { at, .. }
            | E::ValueOutOfRange { at, .. }
            | E::NoSuchArea { at, .. }
            | E::WidthMismatch { at, .. }
            | E::WidthNotAllowed { at, .. }
            | E::BitOffset { at, .. }
            | E::OutOfArea { at, .. }
            | E::Misaligned { at, .. }
            | E::AreaNotAllowed { at, .. }
            | E::NotPointerArea { at, .. }
            | E::NotAddressOfArea { at, .. }
            | E::WriteToReadOnly { at, .. }
            | E::BlockKindMismatch { at, .. }
            | E::NoSuchUnit { at, .. }
            | E::JumpWithoutLabel { at, .. }
            | E::DuplicateLabel { at, .. }
            | E::UnmatchedLoop { at, .. }
            | E::OverlappingLocals { at, .. }
            | E::LoopDepth { at, .. }
            | E::CallCycle { at, .. }
            | E::DataValue { at, .. }
            | E::SystemVersion { at, .. }
            | E::SystemPortCount { at, .. }
            | E::SystemValue { at, .. }
            | E::SystemPassword { at }
            | E::UnknownEvent { at, .. }
            | E::ReservedNotZero { at, .. } => Some(*at),
        }
    }

    /// The message without code and location.
    pub fn message(&self) -> String {
        use VerifyError as E;
        match self {
            E::PlcTypeMismatch { image, target } => {
                format!("the image is for PLC type `{image}`, the target is `{target}`")
            }
            E::PageNotOnTarget { page, count, limit } => format!(
                "{} page {} does not exist on the target: it has {count} ({limit})",
                page.kind.keyword(),
                page.number
            ),
            E::MissingConstPage => "the image has no const page (const.bin)".to_string(),
            E::MissingMain => {
                "the image has no MAIN (argument/00.bin and instruction/00.bin)".to_string()
            }
            E::UnpairedPage { missing, .. } => {
                format!("{} is missing: program pages come in pairs", missing.file_name())
            }
            E::SizeLimit {
                what,
                size,
                limit,
                max,
                ..
            } => format!("{size} {what} exceed {limit} = {max}"),
            E::Decode { error, .. } => error.reason.clone(),
            E::UnitHeader {
                expected, found, ..
            } => format!(
                "the header describes {} but the page number gives {}",
                unit_name(found.0, found.1 as u16),
                unit_name(expected.0, expected.1 as u16)
            ),
            E::InterruptParameter { local, .. } => format!(
                "local {local}: interrupt routines have only temporaries (VAR), no parameters"
            ),
            E::LocalOrder { local, .. } => format!(
                "local {local} is out of order: VAR_INPUT, VAR_IN_OUT, VAR_OUTPUT, then VAR"
            ),
            E::UnknownOpcode { opcode, .. } => {
                format!("opcode 0x{opcode:04X} is not in the instruction set")
            }
            E::NotInUnit {
                mnemonic,
                unit,
                allowed,
                ..
            } => format!("{mnemonic} stands in {unit}; it is allowed only in {allowed}"),
            E::OperandCount {
                mnemonic,
                expected,
                found,
                ..
            } => format!("{mnemonic} takes {expected} operands, the record has {found}"),
            E::UseNotAllowed {
                operand, use_code, ..
            } => format!("{operand} does not take USE {use_code}"),
            E::MalformedOperand {
                operand,
                value,
                reason,
                ..
            } => format!("{operand} is 0x{:08X}: {reason}", value.0),
            E::ValueOutOfRange {
                operand,
                value,
                min,
                max,
                ..
            } => format!("{operand} is {value}, outside {min}..{max}"),
            E::NoSuchArea { operand, slot, .. } => {
                format!("{operand}: the target has no area in slot {slot}")
            }
            E::WidthMismatch {
                operand,
                expected,
                found,
                ..
            } => format!(
                "{operand} has WIDTH {found}, its type needs {} ({expected})",
                *expected as u8
            ),
            E::WidthNotAllowed {
                operand,
                area,
                width,
                ..
            } => format!("{operand}: area {area} has no {width} access"),
            E::BitOffset {
                operand,
                bit,
                width,
                ..
            } => format!("{operand}: BIT_OFFSET {bit} with WIDTH {width}"),
            E::OutOfArea {
                operand,
                area,
                offset,
                bytes,
                size,
                ..
            } => format!(
                "{operand}: {} at offset {offset} reach past the {size} bytes of {area}",
                plural::count(*bytes, "byte")
            ),
            E::Misaligned {
                operand,
                area,
                offset,
                unit,
                ..
            } => format!("{operand}: offset {offset} in {area}, which counts in {unit}s"),
            E::AreaNotAllowed {
                operand,
                area,
                allowed,
                ..
            } => format!("{operand} is in area {area}; it must be in {allowed}"),
            E::NotPointerArea { operand, area, .. } => {
                format!("{operand}: area {area} cannot hold pointers")
            }
            E::NotAddressOfArea { operand, area, .. } => {
                format!("{operand}: area {area} does not allow taking addresses")
            }
            E::WriteToReadOnly { operand, area, .. } => {
                format!("{operand} is written, and programs cannot write area {area}")
            }
            E::BlockKindMismatch {
                operand,
                expected,
                found,
                number,
                ..
            } => format!(
                "{operand} names {}, it needs {}{}",
                unit_name(*found, *number),
                kind_word(*expected),
                if *expected == BlockKind::Interrupt {
                    " other than MAIN"
                } else {
                    ""
                }
            ),
            E::NoSuchUnit {
                operand,
                kind,
                number,
                ..
            } => format!(
                "{operand} names {}, which the image does not have",
                unit_name(*kind, *number)
            ),
            E::JumpWithoutLabel { label, .. } => {
                format!("no LBL {label} in this page")
            }
            E::DuplicateLabel { label, first, .. } => {
                format!("LBL {label} is defined twice (first at byte {first})")
            }
            E::LoopDepth { depth, max, .. } => {
                format!("this FOR opens loop {depth}; FOR loops nest at most {max} deep (ForDepth)")
            }
            E::OverlappingLocals { local, other, .. } => format!(
                "local {local} shares bits of L with local {other}: every local is its own variable"
            ),
            E::UnmatchedLoop {
                role: LoopRole::End,
                ..
            } => {
                "this NEXT closes no FOR: every NEXT ends the innermost open FOR of its page"
                    .to_string()
            }
            E::UnmatchedLoop { mnemonic, .. } => {
                format!("this {mnemonic} has no NEXT after it in its page")
            }
            E::CallCycle { callee, .. } => format!(
                "this CALL closes a cycle through the subroutine of page {callee:02X}: subroutines may not recurse"
            ),
            E::CallDepth { depth, max, .. } => {
                format!("calls from this routine nest {depth} deep; CallDepth is {max}")
            }
            E::DataValue {
                item, value, width, ..
            } => format!(
                "data item {item}: 0x{value:08X} is not a {width} value sign- or zero-extended to 32 bits"
            ),
            E::SystemVersion { found, .. } => {
                format!("system page layout {found} is not {}", crate::SYSTEM_LAYOUT_VERSION)
            }
            E::SystemPortCount {
                found, expected, ..
            } => format!("the system page has {found} ports, the target {expected}"),
            E::SystemValue {
                port,
                field,
                value,
                allowed,
                ..
            } => format!("port {port}: {field} {value} is not {allowed}"),
            E::SystemPassword { .. } => "the password is neither 1..16 ASCII characters padded with zeros nor 16 x 0xFF".to_string(),
            E::UnknownEvent { operand, event, .. } => {
                format!("{operand}: the target has no interrupt event {event}")
            }
            E::ReservedNotZero { value, .. } => {
                format!("reserved byte is {value}, not 0")
            }
        }
    }
}

impl fmt::Display for VerifyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let code = self.code();
        match (self.location(), self) {
            (Some(at), _) => write!(f, "{code} {at}: {}", self.message()),
            (None, VerifyError::PlcTypeMismatch { .. }) => {
                write!(f, "{code} manifest.json: {}", self.message())
            }
            (None, _) => match self.page() {
                Some(page) => write!(f, "{code} {}: {}", page.file_name(), self.message()),
                None => write!(f, "{code} image: {}", self.message()),
            },
        }
    }
}

impl std::error::Error for VerifyError {}
