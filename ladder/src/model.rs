//! The ladder model (docs/ladder.md): a program as blocks of networks, each network
//! either one rung (a series-parallel power path from the left rail into parallel
//! outputs) or its STL with the reason it is not one rung. Plain data: `build.rs` makes
//! it from a checked program, `svg.rs` draws it, the live view evaluates it. Every
//! drawn element has an `id`, unique in its network, in drawing order.

/// A whole program's ladder.
#[derive(Debug, Clone, PartialEq)]
pub struct Ladder {
    /// The PLC type the program was checked against.
    pub plc: String,
    pub blocks: Vec<Block>,
}

/// A program block (MAIN, a subroutine, an interrupt routine).
#[derive(Debug, Clone, PartialEq)]
pub struct Block {
    /// The block's name as the program names it (`MAIN`, `ADD3`): `data-block`.
    pub name: String,
    /// Its numbered name (`OB1`, `SBR0`, `INT1`).
    pub numbered: String,
    pub title: Option<String>,
    pub networks: Vec<Network>,
}

/// One network.
#[derive(Debug, Clone, PartialEq)]
pub struct Network {
    /// The network number (`data-network`).
    pub number: u32,
    /// The text after `NETWORK n //`.
    pub title: Option<String>,
    /// Comment lines inside the network before its first instruction (without `//`).
    pub comment: Vec<String>,
    /// The network's STL lines as written (trimmed), for the STL view and tooltips.
    pub stl: Vec<String>,
    /// 1-based line of the NETWORK line (or the first instruction) in its file.
    pub line: u32,
    pub body: Body,
    /// For a network shown as STL: its instructions, each with its line in `stl`, for
    /// the live view's per-line status (`live::stl_status`); empty for a rung.
    pub stl_code: Vec<StlInstruction>,
}

/// One instruction of a network shown as STL.
#[derive(Debug, Clone, PartialEq)]
pub struct StlInstruction {
    /// Its index in `Network::stl` (`data-index` of its `stl-line`).
    pub index: usize,
    /// The mnemonic as the catalog spells it (as written when the catalog does not
    /// know it).
    pub mnemonic: String,
    /// Its operands, resolved as a rung's are.
    pub operands: Vec<Operand>,
}

/// A network drawn as a rung, or shown as STL.
#[derive(Debug, Clone, PartialEq)]
pub enum Body {
    Rung(Rung),
    /// Not one rung: `reason` says why (`data-reason`), e.g. "two power paths from the
    /// left rail (LD at line 12 starts a second rung)".
    Stl {
        reason: String,
    },
}

/// One rung: the power path from the left rail, then the outputs in parallel.
#[derive(Debug, Clone, PartialEq)]
pub struct Rung {
    /// The path from the left rail; `None` for an element on the rail itself (an
    /// unconditional `LBL`, `NEXT`, `RET` drawn as a box without power input).
    pub input: Option<Node>,
    /// The outputs at the end of `input`, top to bottom (at least one).
    pub outputs: Vec<Branch>,
}

/// A piece of power path.
#[derive(Debug, Clone, PartialEq)]
pub enum Node {
    Contact(Contact),
    /// A box in series (EN in, ENO or its done output out): `TON`, `MOVW` between
    /// contacts and a coil, `CTU` whose extra power inputs (R) have their own paths.
    Box(BoxElement),
    /// Left to right; at least two.
    Series(Vec<Node>),
    /// Top to bottom, rejoining on the right; at least two.
    Parallel(Vec<Node>),
}

/// A branch of the outputs: its own series elements after the split, then its end.
#[derive(Debug, Clone, PartialEq)]
pub struct Branch {
    /// Series elements after the split (LPS/LRD/LPP branches have their contacts here).
    pub path: Vec<Node>,
    pub end: BranchEnd,
}

#[derive(Debug, Clone, PartialEq)]
pub enum BranchEnd {
    Coil(Coil),
    /// A box at the end of a branch (`MOVW` as an output, `JMP`, `CALL`).
    Box(BoxElement),
    /// A further split: these branches in parallel (nested LPS).
    Split(Vec<Branch>),
}

/// What a contact tests (`data-kind`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ContactKind {
    /// `LD`, `A`, `O` (`no`); with `immediate` `LDI`, `AI`, `OI`.
    NormallyOpen,
    /// `LDN`, `AN`, `ON` (`nc`).
    NormallyClosed,
    /// `EU` (`pos-edge`).
    PositiveEdge,
    /// `ED` (`neg-edge`).
    NegativeEdge,
    /// `NOT` (`not`).
    Not,
    /// `LDW>=`, `AB=`, `OR<` ... (`compare`).
    Compare,
}

impl ContactKind {
    /// The `data-kind` value.
    pub fn data_kind(self) -> &'static str {
        match self {
            ContactKind::NormallyOpen => "no",
            ContactKind::NormallyClosed => "nc",
            ContactKind::PositiveEdge => "pos-edge",
            ContactKind::NegativeEdge => "neg-edge",
            ContactKind::Not => "not",
            ContactKind::Compare => "compare",
        }
    }
}

/// A contact.
#[derive(Debug, Clone, PartialEq)]
pub struct Contact {
    pub id: u32,
    pub kind: ContactKind,
    /// The instruction's mnemonic as the catalog spells it (`LDN`, `AW>=`, `EU`).
    pub mnemonic: String,
    /// Immediate (`LDI`, `ANI`): drawn with an `I` in the contact.
    pub immediate: bool,
    /// The bit (one operand), both operands of a compare (`MW20`, `100`), none for
    /// EU/ED/NOT.
    pub operands: Vec<Operand>,
    /// For a compare: the relation and type as drawn inside (`>=W`, `=B`, `<R`).
    pub relation: Option<String>,
    /// 1-based source line of its instruction.
    pub line: u32,
}

/// What a coil does (`data-kind`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CoilKind {
    Out,
    Set,
    Reset,
    OutImmediate,
    SetImmediate,
    ResetImmediate,
}

impl CoilKind {
    /// The `data-kind` value.
    pub fn data_kind(self) -> &'static str {
        match self {
            CoilKind::Out => "out",
            CoilKind::Set => "set",
            CoilKind::Reset => "reset",
            CoilKind::OutImmediate => "out-immediate",
            CoilKind::SetImmediate => "set-immediate",
            CoilKind::ResetImmediate => "reset-immediate",
        }
    }
}

/// A coil.
#[derive(Debug, Clone, PartialEq)]
pub struct Coil {
    pub id: u32,
    pub kind: CoilKind,
    pub mnemonic: String,
    /// The bit.
    pub operand: Operand,
    /// `S Q0.0, 3`: the count of bits (drawn under the coil).
    pub count: Option<Operand>,
    pub line: u32,
}

/// A box: a non-bit instruction with EN/ENO and a pin per operand.
#[derive(Debug, Clone, PartialEq)]
pub struct BoxElement {
    pub id: u32,
    /// `data-mnemonic`: `MOVW`, `TON`, `CALL`, `+I`.
    pub mnemonic: String,
    /// The title inside the box: the mnemonic, the timer or counter (`T37`) for timers
    /// and counters, the subroutine's name for CALL.
    pub title: String,
    /// Every operand on its pin, in the catalog's order (CALL: the subroutine's
    /// parameter names). A timer's T and a CALL's block are the title, not pins.
    pub pins: Vec<Pin>,
    /// Power inputs besides EN/IN from the series path, each with its own path from the
    /// left rail: a counter's R (CTU) or CD and R (CTUD), named by pin.
    pub power_inputs: Vec<(String, Node)>,
    /// The name of the main power input (`EN`, `IN` for timers, `CU` for counters).
    pub enable: String,
    /// The name of the power output (`ENO`, `Q`), or None for a box that ends power
    /// (`JMP`, `RET`, `LBL`).
    pub output: Option<String>,
    pub line: u32,
    /// A timer's or counter's number as an operand (`T37`, or the symbol naming it),
    /// drawn above the box as contacts draw their operands; `title` keeps its written
    /// form for the STL. `None` for other boxes.
    pub counted: Option<Box<Operand>>,
    /// A timer's resolution in milliseconds (`Target::timer_resolution`), drawn in the
    /// box and used for the preset's duration; `None` when unknown or not a timer.
    pub resolution_ms: Option<u32>,
    /// How the box is drawn: a box, a jump coil (`JMP`), a label box (`LBL`).
    pub shape: BoxShape,
}

/// How a box is drawn (docs/ladder.md, "Elements"), as Micro/WIN draws it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BoxShape {
    /// A box with EN and a pin per operand.
    #[default]
    Box,
    /// A jump: a coil holding the box's label, its label number above (`JMP`).
    Jump,
    /// A label: a box on the rung's start, its number above, without pins (`LBL`).
    Label,
}

/// Whether a box's mnemonic is a sequence control relay line of a Micro/WIN export
/// (`LSCR`, `SCRT`, `SCRE`, `CSCRE`), which the builder draws with the label and jump
/// shapes though the catalog has no instruction for it.
pub fn is_scr(mnemonic: &str) -> bool {
    gutta_catalog::s7200::SCR_MNEMONICS.contains(&mnemonic)
}

/// An operand on a pin.
#[derive(Debug, Clone, PartialEq)]
pub struct Pin {
    /// `IN`, `OUT`, `PT`, a CALL parameter's name.
    pub name: String,
    /// Input pins are drawn on the left, outputs on the right.
    pub output: bool,
    pub operand: Operand,
    /// An output that the instruction also reads (`+I`'s OUT) is drawn on both sides:
    /// the name of its input pin (`IN1`).
    pub input: Option<String>,
}

/// An operand as drawn: the symbol above the address.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Operand {
    /// As written in the source (`Start`, `MW20`, `#count`, `16#FF`, `&VB100`).
    pub written: String,
    /// The canonical direct address (`I0.0`, `MW20`), when the operand is one (a symbol
    /// resolved, a direct address normalised): `data-operand`. `None` for constants,
    /// locals, pointers and block names.
    pub address: Option<String>,
    /// The symbol's name, when the operand is a symbol, or the name of the system bit
    /// or byte its address is (`Always_On` for `SM0.0`; docs/ladder.md, "System names").
    pub symbol: Option<String>,
    /// The symbol's comment (its table's comment column; a system bit's description),
    /// shown in tooltips and the symbol information; `None` without a symbol or comment.
    pub comment: Option<String>,
    /// The symbol's type as the symbol information shows it: the declared type
    /// (`INT`), else the address's width (`BOOL`, `BYTE`, `WORD`, `DWORD`); `None`
    /// without a symbol.
    pub data_type: Option<String>,
}
