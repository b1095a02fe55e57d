//! The syntax tree of a .lad file. Names and mnemonics are spans into the source (no
//! copies); every node keeps its span. Nodes the parser could not read are `Error`
//! nodes, already reported: later stages skip them silently.

use crate::source::Span;

/// A whole source file.
#[derive(Debug, Clone, Default)]
pub struct Program {
    /// `PLC_TYPE CPU-EC20`: the name as written, and its span.
    pub plc_type: Option<(String, Span)>,
    pub symbols: Vec<SymbolDecl>,
    pub units: Vec<Unit>,
    pub data_blocks: Vec<DataBlock>,
    /// Micro/WIN data block exports (`DATA_BLOCK_TAB` files, `syntax/data_block_tab.rs`).
    pub data_block_tabs: Vec<DataBlockTab>,
    pub system_blocks: Vec<SystemBlock>,
}

/// `Name : ADDRESS // comment` or `Name : ADDRESS : TYPE // comment` in a SYMBOLS
/// section, or a row of a symbol table (`Name,ADDRESS:TYPE,comment`).
#[derive(Debug, Clone)]
pub struct SymbolDecl {
    pub name: Span,
    pub address: Span,
    /// The declared data type's keyword, when written.
    pub data_type: Option<Span>,
    pub comment: Option<Span>,
    /// The comment is a quoted CSV field whose `""` stand for `"`.
    pub comment_escaped: bool,
}

impl SymbolDecl {
    /// The comment's text (`""` unescaped in a quoted CSV field), trimmed.
    pub fn comment_text(&self, text: &str) -> Option<String> {
        let raw = text.get(self.comment?.range())?.trim();
        Some(if self.comment_escaped {
            raw.replace("\"\"", "\"")
        } else {
            raw.to_string()
        })
    }
}

/// Kind of program unit, as the header names it: `ORGANIZATION_BLOCK` and
/// `INTERRUPT_BLOCK` are interrupt routines (MAIN is INT0), `SUBROUTINE_BLOCK` a
/// subroutine. The catalog's type, so the checker, the image and the VM share it.
pub use gutta_catalog::BlockKind;

/// The `NAME:SBR0` part of a block header.
#[derive(Debug, Clone)]
pub struct BlockHeader {
    /// The keyword line (`SUBROUTINE_BLOCK ...`) as a whole.
    pub span: Span,
    /// Symbolic name (`ADD3`); may equal the numbered name when only `SBR0` is written.
    pub name: Span,
    /// The numbered name (`SBR0`, `INT1`, `OB1`, `DAT0`) if written.
    pub number: Option<(BlockNumber, Span)>,
}

/// A numbered block name: prefix and number.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BlockNumber {
    pub prefix: BlockPrefix,
    pub number: u32,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BlockPrefix {
    Ob,
    Int,
    Sbr,
    Dat,
}

impl BlockPrefix {
    pub fn as_str(self) -> &'static str {
        match self {
            BlockPrefix::Ob => "OB",
            BlockPrefix::Int => "INT",
            BlockPrefix::Sbr => "SBR",
            BlockPrefix::Dat => "DAT",
        }
    }
}

/// A program unit: MAIN, an interrupt routine or a subroutine.
#[derive(Debug, Clone)]
pub struct Unit {
    pub kind: BlockKind,
    pub header: BlockHeader,
    pub title: Option<Span>,
    pub vars: Vec<VarDecl>,
    pub networks: Vec<Network>,
    /// The `END_...` line, if there was one.
    pub end: Option<Span>,
}

/// Which VAR section a local belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum VarSection {
    Input,
    InOut,
    Output,
    Temp,
}

impl VarSection {
    pub fn keyword(self) -> &'static str {
        match self {
            VarSection::Input => "VAR_INPUT",
            VarSection::InOut => "VAR_IN_OUT",
            VarSection::Output => "VAR_OUTPUT",
            VarSection::Temp => "VAR",
        }
    }
}

/// `name : TYPE;` in a VAR section.
#[derive(Debug, Clone)]
pub struct VarDecl {
    pub section: VarSection,
    pub name: Span,
    pub ty: Span,
    pub comment: Option<Span>,
}

/// `Network n // title` and its instructions.
#[derive(Debug, Clone)]
pub struct Network {
    /// The network number as written (`None`: not written, or no NETWORK line at all).
    pub number: Option<u32>,
    /// The `NETWORK` line; `None` for instructions before any NETWORK line.
    pub header: Option<Span>,
    /// The header line, or the first instruction for an implicit network.
    pub span: Span,
    pub title: Option<Span>,
    pub instructions: Vec<Instruction>,
    /// Operands of all instructions, in order; instructions index into it.
    pub operands: Vec<Operand>,
}

impl Network {
    /// The network's number: as written, else the previous numbered network's + 1
    /// (`previous`: the number of the last network that had a NETWORK line); instructions
    /// before any NETWORK line are network 0. The checker and the ladder number alike.
    pub fn number_after(&self, previous: Option<u32>) -> u32 {
        match (self.number, previous) {
            (Some(n), _) => n,
            (None, Some(prev)) => prev + 1,
            (None, None) => u32::from(self.header.is_some()),
        }
    }

    pub fn operands_of(&self, ins: &Instruction) -> &[Operand] {
        &self.operands[ins.operands.0 as usize..ins.operands.1 as usize]
    }
}

/// One STL instruction line.
#[derive(Debug, Clone)]
pub struct Instruction {
    /// The mnemonic as written (may be several adjacent tokens: `LDW>=`, `+I`).
    pub mnemonic: Span,
    /// Range into `Network::operands`.
    pub operands: (u32, u32),
    /// Mnemonic through last operand.
    pub span: Span,
    /// The operands did not parse (already reported): later stages report nothing
    /// more about this line, not even an unknown mnemonic.
    pub syntax_error: bool,
}

/// An operand as written.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Operand {
    pub span: Span,
    pub kind: OperandKind,
}

/// `&` or `*` in front of a name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Prefix {
    None,
    /// `&MB24`
    AddressOf,
    /// `*MD4`
    Pointer,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OperandKind {
    /// A direct address, a symbol or a block name (`MW10`, `Start`, `ADD3`), or with
    /// `local` a `#name`. `name` spans the name without `#`, `&` or `*`.
    Name {
        prefix: Prefix,
        local: bool,
        name: Span,
    },
    Integer(i64),
    Real(f64),
    /// Already reported by the parser.
    Error,
}

/// `DATA_BLOCK name:DATn` ... `END_DATA_BLOCK`.
#[derive(Debug, Clone)]
pub struct DataBlock {
    pub header: BlockHeader,
    pub rows: Vec<DataRow>,
    pub end: Option<Span>,
}

/// `MW22 UINT 6 // comment`.
#[derive(Debug, Clone)]
pub struct DataRow {
    pub span: Span,
    pub address: Span,
    pub ty: Option<Span>,
    pub value: Operand,
}

/// A Micro/WIN data block export: `DATA_BLOCK_TAB name`, `BEGIN`, rows,
/// `END_DATA_BLOCK_TAB` (docs/microwin.md, "Data block exports").
#[derive(Debug, Clone)]
pub struct DataBlockTab {
    /// The `DATA_BLOCK_TAB ...` line.
    pub header: Span,
    /// The name after `DATA_BLOCK_TAB`, when written.
    pub name: Option<Span>,
    pub rows: Vec<TabRow>,
    /// The `END_DATA_BLOCK_TAB` line; None when the file ends first (reported).
    pub end: Option<Span>,
}

/// `VB40 1, 2, 3 // comment` with its continuation lines: values at consecutive
/// addresses from `address` on, each as wide as the address (a character one byte).
#[derive(Debug, Clone)]
pub struct TabRow {
    /// The row's first line, without its comment.
    pub span: Span,
    pub address: Span,
    pub values: Vec<TabValue>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct TabValue {
    pub span: Span,
    pub kind: TabValueKind,
}

#[derive(Debug, Clone, PartialEq)]
pub enum TabValueKind {
    Integer(i64),
    Real(f64),
    /// `'AB'`: ASCII characters, one byte each.
    Chars(Vec<u8>),
    /// `"AB"`: an S7-200 string, a length byte and then the ASCII characters.
    String(Vec<u8>),
}

/// `SYSTEM_BLOCK` ... `END_SYSTEM_BLOCK`.
#[derive(Debug, Clone)]
pub struct SystemBlock {
    pub span: Span,
    pub entries: Vec<SystemEntry>,
    pub end: Option<Span>,
}

/// `PORT0.BAUD = 38400` or `PASSWORD = "1234"`.
#[derive(Debug, Clone)]
pub struct SystemEntry {
    pub span: Span,
    /// `PORT0.BAUD` as a whole (dots included).
    pub key: Span,
    pub value: SystemValue,
}

#[derive(Debug, Clone, PartialEq)]
pub enum SystemValue {
    Integer(i64, Span),
    Word(Span),
    /// Span of the string including its quotes; text is the unescaped contents.
    Str(String, Span),
    Error,
}
