//! The checker: syntax tree + target description -> checked program and diagnostics.
//! It resolves every name and operand against the target's ManagerVar.xml and
//! ManagerFun.xml, enforces the PlcType limits, and records definitions and references
//! for the language server. It skips parser error nodes without reporting them again.

mod address;
mod aeno_lines;
mod bit_lines;
mod calls;
mod code;
mod constants;
mod data;
mod data_block_tab;
mod instruction;
mod l_temporaries;
mod memory;
mod names;
mod operands;
pub mod program;
mod sequence;
mod symbols;
mod system;
mod units;

use std::collections::HashMap;

use gutta_catalog::{Address, BlockKind, InstrId, Target};

use crate::diagnostics::Diagnostic;
use crate::source::Span;
use crate::syntax::ast::Program;
pub use aeno_lines::AenoMeaning;
pub use bit_lines::{BitLines, BitOp, BitUse, TimerBox};
pub use l_temporaries::{LTemporaries, LTemporaryPlacement};
pub use program::*;
pub use sequence::{SOperand, ScrLine, ScrOp, SequenceConvention, SequenceLines};
pub use system::PORT_KEYS;

/// What a definition is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DefKind {
    Symbol,
    Local,
    Unit,
    DataBlock,
    Label,
}

/// A named thing, for navigation and hover.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Definition {
    pub name: String,
    pub kind: DefKind,
    /// The name's span at its definition.
    pub span: Span,
    /// One line for hover: `Start : I0.0 (push button)`, `#a : INT (VAR_INPUT, LW0)`.
    pub detail: String,
    /// The unit a local or label belongs to.
    pub unit: Option<usize>,
}

/// A use of a definition.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Reference {
    pub span: Span,
    pub definition: usize,
}

/// Everything the checker learned about one file.
#[derive(Debug, Clone, Default)]
pub struct CheckOutput {
    /// The checked program: from [`check`] always (with what checked of a program with
    /// errors); the pipeline (`crate::check_source`) keeps it only when no diagnostic
    /// of any stage is an error.
    pub program: Option<CheckedProgram>,
    pub diagnostics: Vec<Diagnostic>,
    pub definitions: Vec<Definition>,
    pub references: Vec<Reference>,
    /// Resolved direct addresses in operands (for hover).
    pub addresses: Vec<(Span, Address)>,
    /// Mnemonic spans with their instruction (for hover).
    pub mnemonics: Vec<(Span, gutta_catalog::InstrId)>,
    /// Lines that use a timer's or counter's bit and the timer boxes, where the
    /// conventions ask for them (`bit_lines.rs`), for the pass after checking.
    pub bit_lines: BitLines,
    /// The blocks whose Micro/WIN temporaries L60-L63 were placed in the target's L
    /// (`l_temporaries.rs`), in check order.
    pub l_temporaries: Vec<LTemporaryPlacement>,
    /// SCR lines and S operands, where the conventions ask for them (`sequence.rs`),
    /// for the pass after checking.
    pub sequence: SequenceLines,
}

/// What a stage before the checker (a dialect's: `crate::microwin`) settled, as plain
/// data the checker applies without knowing why. The default is GUTTA's own language.
#[derive(Debug, Clone, Default)]
pub struct Conventions {
    /// Names that stand for an address unless a symbol of the program takes them
    /// (case-insensitive, the first match wins); also offered as suggestions.
    pub predefined_names: Vec<PredefinedName>,
    /// A block operand `INTn` names interrupt routine INT(n + this).
    pub interrupt_operand_offset: u32,
    /// Literal operands an earlier stage already turned into the number to check, by
    /// span; None where it refused the operand (and reported it).
    pub renumbered_literals: HashMap<Span, Option<i64>>,
    /// E0408's help (the program has no MAIN), when it must say more than the default.
    pub missing_main_help: Option<String>,
    /// E0206's help (no block of that name) for block operands, by the operand's span,
    /// when it must say more than the default (a block of another file of an export).
    pub block_elsewhere_help: HashMap<Span, String>,
    /// The instructions whose lines use a timer's or counter's bit when their first
    /// operand is a timer or counter (`LD T37`), and what each does; None: no line does
    /// (`bit_lines.rs`). When set, timer and counter boxes are recorded too.
    pub timer_bit_lines: Option<HashMap<InstrId, BitOp>>,
    /// What `AENO` after each instruction of the target compiles to; None: `AENO` is
    /// no line of the language (`aeno_lines.rs`).
    pub aeno: Option<HashMap<InstrId, AenoMeaning>>,
    /// Where a block's L addresses past the target's L go (Micro/WIN's LAD temporaries
    /// L60-L63); None: they are out of range (`l_temporaries.rs`).
    pub l_temporaries: Option<LTemporaries>,
    /// Where the S7-200's S area lives and that `LSCR`/`SCRT`/`SCRE`/`CSCRE` lines are
    /// left for a later pass (`sequence.rs`); None: S operands are E0221, SCR lines E0220.
    pub sequence: Option<SequenceConvention>,
}

/// A name the program may use without declaring it ([`Conventions::predefined_names`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PredefinedName {
    pub name: String,
    /// None: offered as a suggestion, but it resolves to nothing.
    pub address: Option<Address>,
}

/// Per-unit facts gathered before the code is checked.
#[derive(Debug, Clone)]
pub(crate) struct UnitInfo {
    pub kind: BlockKind,
    pub number: u32,
    pub name: String,
    /// Index into `ast.units`.
    pub ast_index: usize,
    pub locals: Vec<Local>,
    /// Definition index of each local, parallel to `locals`.
    pub local_defs: Vec<usize>,
    pub definition: usize,
}

pub(crate) struct Checker<'a> {
    pub text: &'a str,
    pub target: &'a Target,
    pub ast: &'a Program,
    pub diags: Vec<Diagnostic>,
    pub out: CheckOutput,
    /// Upper-case symbol name -> (address, definition index).
    pub symbols: HashMap<String, (Address, usize)>,
    /// Upper-case unit name (symbolic and numbered) -> index into `units`.
    pub unit_names: HashMap<String, usize>,
    pub units: Vec<UnitInfo>,
    /// Data block names, to explain "is a data block" in operands.
    pub data_names: HashMap<String, usize>,
    /// Upper-case names that resolved to nothing: their one diagnostic and later uses.
    pub unknown_names: HashMap<String, names::UnknownName>,
    pub conventions: &'a Conventions,
    /// The current block's operands placed as Micro/WIN temporaries (`l_temporaries.rs`).
    pub l_temporary_uses: Vec<Span>,
    /// Upper-case predefined name -> its address ([`Conventions::predefined_names`],
    /// the first of a name), looked up for every name operand: a map, as an export's
    /// predefined names count in the hundreds (SMART's I/O names).
    pub predefined: HashMap<String, Option<Address>>,
    /// What `sequence.rs` records for the pass after checking.
    pub sequence: SequenceLines,
}

impl<'a> Checker<'a> {
    pub fn slice(&self, s: Span) -> &'a str {
        self.text.get(s.range()).unwrap_or("")
    }

    pub fn report(&mut self, d: Diagnostic) {
        self.diags.push(d);
    }

    pub fn define(
        &mut self,
        name: String,
        kind: DefKind,
        span: Span,
        detail: String,
        unit: Option<usize>,
    ) -> usize {
        self.out.definitions.push(Definition {
            name,
            kind,
            span,
            detail,
            unit,
        });
        self.out.definitions.len() - 1
    }

    pub fn reference(&mut self, span: Span, definition: usize) {
        self.out.references.push(Reference { span, definition });
    }
}

/// Check a parsed program against a target, applying what an earlier stage settled
/// (`Conventions::default()` for GUTTA's own language).
pub fn check(text: &str, ast: &Program, target: &Target, conventions: &Conventions) -> CheckOutput {
    let mut c = Checker {
        text,
        target,
        ast,
        diags: Vec::new(),
        out: CheckOutput::default(),
        symbols: HashMap::new(),
        unit_names: HashMap::new(),
        units: Vec::new(),
        data_names: HashMap::new(),
        unknown_names: HashMap::new(),
        conventions,
        l_temporary_uses: Vec::new(),
        predefined: HashMap::new(),
        sequence: SequenceLines::default(),
    };
    for p in conventions.predefined_names.iter().rev() {
        c.predefined.insert(p.name.to_ascii_uppercase(), p.address);
    }
    c.symbols();
    c.units();
    let data_blocks = c.data_blocks();
    let system = c.system_block();
    let (units, bit_lines) = c.code();
    c.list_later_uses();
    let mut out = std::mem::take(&mut c.out);
    out.diagnostics = c.diags;
    out.bit_lines = bit_lines;
    out.sequence = c.sequence;
    out.program = Some(CheckedProgram {
        target_name: target.name().to_string(),
        units,
        data_blocks,
        system,
        system_span: ast.system_blocks.first().map(|b| b.span),
    });
    out
}

impl Checker<'_> {
    /// Whether a name reads as a direct address (see [`reads_as_address`]).
    pub(crate) fn looks_like_address(&self, name: &str) -> bool {
        reads_as_address(self.target, name)
    }
}

/// Whether a name reads as a direct address of `target` or any stdlib target: an area
/// name, an optional width letter, digits, an optional `.bit` (`M0`, `VB100`). `Pump1`
/// is a name, not an address. Such names cannot be symbols (E0212).
pub fn reads_as_address(target: &Target, name: &str) -> bool {
    {
        if !gutta_catalog::is_address_shaped(name) {
            return false;
        }
        let letters = name
            .chars()
            .take_while(char::is_ascii_alphabetic)
            .collect::<String>()
            .to_ascii_uppercase();
        let fits = |area: &str| {
            letters == area
                || (letters.len() == area.len() + 1
                    && letters.starts_with(area)
                    && letters.ends_with(['B', 'W', 'D']))
        };
        target.memory.areas.iter().any(|a| fits(&a.name))
            || address::stdlib_memory_maps()
                .iter()
                .flat_map(|(_, m)| m)
                .any(|m| m.areas.iter().any(|a| fits(&a.name)))
    }
}
