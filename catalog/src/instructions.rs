//! `ManagerFun.xml`: the instruction set of a PLC type: mnemonics, opcodes, operand
//! roles, allowed data types, areas and uses, power-flow behaviour, what each
//! instruction is (timer or counter kind, ladder element, pins) and descriptions.
//! Schema: docs/instruction-schema.md.

use std::collections::BTreeSet;
use std::str::FromStr;

use serde::Deserialize;

mod nature;

use crate::instruction_kinds::{CompareOp, Join, LadderClass, Logic, LoopRole, TimerCounterKind};
use crate::text::decode_xml_text;
use crate::xml_util::{attr_bool, attr_int, from_xml};
use crate::{CatalogError, CatalogErrorCode, DataType, MemoryMap};

const FILE: &str = "ManagerFun.xml";

/// Which kinds of program unit may contain an instruction (`Units` attribute).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct UnitScope {
    /// MAIN (INT0).
    pub main: bool,
    /// Interrupt routines other than MAIN.
    pub interrupt: bool,
    pub subroutine: bool,
}

impl UnitScope {
    pub const ALL: UnitScope = UnitScope {
        main: true,
        interrupt: true,
        subroutine: true,
    };

    /// `MAIN`, `INT`, `SBR` separated by spaces.
    fn parse(text: &str) -> Option<UnitScope> {
        let mut scope = UnitScope {
            main: false,
            interrupt: false,
            subroutine: false,
        };
        for word in text.split_whitespace() {
            match word.to_ascii_uppercase().as_str() {
                "MAIN" => scope.main = true,
                "INT" => scope.interrupt = true,
                "SBR" => scope.subroutine = true,
                _ => return None,
            }
        }
        (scope.main || scope.interrupt || scope.subroutine).then_some(scope)
    }

    /// The allowed kinds as words, for messages and docs.
    pub fn describe(self) -> String {
        let mut words = Vec::new();
        if self.main {
            words.push("MAIN");
        }
        if self.interrupt {
            words.push("interrupt routines");
        }
        if self.subroutine {
            words.push("subroutines");
        }
        words.join(", ")
    }
}

/// Index of an instruction in its [`InstructionSet`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct InstrId(pub u16);

/// How an instruction relates to the logic stack (power flow).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Flow {
    /// Pushes a new value (`LD`, `LDN`, `LDW>=`): needs 0 levels, +1.
    Load,
    /// Combines the top of stack with its operand (`A`, `ON`, `AW=`): needs 1, +0.
    Combine,
    /// Rearranges the stack (`ALD`, `LPS`, `NOT`, `EU`); effect given by `StackNeeds`/`StackDelta`.
    Stack,
    /// Writes from the top of stack without consuming it (`=`, `S`, `R`): needs 1, +0.
    Output,
    /// Runs only while the top of stack is 1 (`MOVW`, `+I`, `JMP`, `CALL`): needs 1, +0.
    Box,
    /// Runs regardless of the stack (`LBL`, `NEXT`, `RET`): needs 0, +0.
    Always,
}

impl Flow {
    const NAMES: [(&'static str, Flow); 6] = [
        ("Load", Flow::Load),
        ("Combine", Flow::Combine),
        ("Stack", Flow::Stack),
        ("Output", Flow::Output),
        ("Box", Flow::Box),
        ("Always", Flow::Always),
    ];

    pub fn keyword(self) -> &'static str {
        Self::NAMES
            .iter()
            .find(|(_, f)| *f == self)
            .map(|(n, _)| *n)
            .unwrap_or("?")
    }

    /// Default (needs, delta) of the logic stack.
    fn default_stack_effect(self) -> Option<(u8, i8)> {
        match self {
            Flow::Load => Some((0, 1)),
            Flow::Combine | Flow::Output | Flow::Box => Some((1, 0)),
            Flow::Always => Some((0, 0)),
            Flow::Stack => None,
        }
    }
}

impl FromStr for Flow {
    type Err = ();
    fn from_str(s: &str) -> Result<Self, ()> {
        Self::NAMES
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(s))
            .map(|(_, f)| *f)
            .ok_or(())
    }
}

/// Direction of an operand.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Role {
    In,
    Out,
    InOut,
}

impl Role {
    pub fn keyword(self) -> &'static str {
        match self {
            Role::In => "In",
            Role::Out => "Out",
            Role::InOut => "InOut",
        }
    }

    /// Whether the instruction writes the operand.
    pub fn writes(self) -> bool {
        !matches!(self, Role::In)
    }
}

/// What sort of thing an operand is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum OperandKind {
    /// A variable (direct, `*` pointer, `&` address-of, `#local`, symbol) or a constant.
    Data,
    /// A label number (`JMP 3`, `LBL 3`).
    Label,
    /// A program unit (`CALL ADD3`, `ATCH TICK, 10`).
    Block,
    /// A literal number only, checked against `Min`..`Max` (`LDS 1`, `EXCH ..., 0`).
    Literal,
}

/// Kind of program unit a `Block` operand names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BlockKind {
    Subroutine,
    Interrupt,
}

/// One operand of an instruction, in source order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct OperandSpec {
    pub name: String,
    pub role: Role,
    pub kind: OperandKind,
    /// Allowed data types (their widths give the access width).
    pub types: Vec<DataType>,
    /// Allowed areas by name; `None` = every area that allows the width.
    pub areas: Option<Vec<String>>,
    /// Whether a constant may stand here.
    pub constant: bool,
    /// Whether `*pointer` access is allowed.
    pub pointer: bool,
    /// Whether `&address` is allowed.
    pub address_of: bool,
    /// Range of a literal or constant, when narrower than the type's.
    pub min: Option<i64>,
    pub max: Option<i64>,
    pub block: Option<BlockKind>,
}

impl OperandSpec {
    /// Whether the operand accepts the named area (by its name).
    pub fn allows_area(&self, area: &str) -> bool {
        match &self.areas {
            None => true,
            Some(list) => list.iter().any(|a| a.eq_ignore_ascii_case(area)),
        }
    }
}

/// One instruction.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Instruction {
    /// Canonical upper-case mnemonic (`LD`, `+I`, `LDW>=`).
    pub mnemonic: String,
    pub aliases: Vec<String>,
    pub opcode: u16,
    pub family: String,
    pub flow: Flow,
    /// Logic-stack levels the instruction reads.
    pub stack_needs: u8,
    /// Change of logic-stack depth.
    pub stack_delta: i8,
    /// Further operands after the declared ones are call arguments (`CALL`).
    pub call_arguments: bool,
    /// Kinds of unit the instruction may appear in.
    pub units: UnitScope,
    pub operands: Vec<OperandSpec>,
    /// One line for hover and tables.
    pub summary: String,
    /// Full semantics, as the VM implements them.
    pub description: String,
    /// STL example lines.
    pub example: String,
    /// The timer or counter it is (`Kind`), for the six timer and counter instructions.
    pub kind: Option<TimerCounterKind>,
    /// The ladder element it is drawn as (`Ladder`).
    pub ladder: LadderClass,
    /// Reads or writes the physical I/O at once (`LDI`, `=I`; `Immediate`).
    pub immediate: bool,
    /// How a `Combine` instruction joins (`Logic`); `None` for the other flows.
    pub logic: Option<Logic>,
    /// A compare contact's relation (`Compare`).
    pub compare: Option<CompareOp>,
    /// The box's power inputs, in the order STL loads them: the first is the one on
    /// the series path (`EN`, a timer's `IN`, a counter's `CU`), the rest are lower
    /// levels of the logic stack with paths of their own (`R`; `CD`, `R`).
    /// Empty for contacts, coils and stack operations (`PowerInputs`).
    pub power_inputs: Vec<String>,
    /// The box's power output (`ENO`, a timer's `Q`); `None` for a box that ends the
    /// power path (`JMP`, `FOR`, `END`) and for everything not a box (`PowerOutput`).
    pub power_output: Option<String>,
    /// Its part in a FOR/NEXT loop (`Loop`).
    pub loop_role: Option<LoopRole>,
    /// It defines the label its operand names, the target of jumps (`LBL`;
    /// `DefinesLabel`).
    pub defines_label: bool,
}

impl Instruction {
    /// How a contact instruction starts or joins its path: `Load` for `Flow="Load"`,
    /// `And`/`Or` for `Flow="Combine"` (its `Logic`), `None` otherwise.
    pub fn join(&self) -> Option<Join> {
        match (self.flow, self.logic) {
            (Flow::Load, _) => Some(Join::Load),
            (Flow::Combine, Some(Logic::And)) => Some(Join::And),
            (Flow::Combine, Some(Logic::Or)) => Some(Join::Or),
            _ => None,
        }
    }
}

/// The instruction set with case-insensitive lookup.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InstructionSet {
    /// Levels of the logic stack.
    pub logic_stack_depth: u8,
    /// Nesting of subroutine calls.
    pub call_depth: u8,
    /// Nesting of FOR loops.
    pub for_depth: u8,
    pub instructions: Vec<Instruction>,
    /// Upper-case mnemonics and aliases, sorted, for lookup.
    index: Vec<(String, InstrId)>,
}

#[derive(Deserialize)]
struct Raw {
    #[serde(rename = "@LogicStackDepth")]
    logic_stack_depth: String,
    #[serde(rename = "@CallDepth")]
    call_depth: String,
    #[serde(rename = "@ForDepth")]
    for_depth: String,
    #[serde(rename = "Instruction", default)]
    instructions: Vec<RawInstruction>,
}

#[derive(Deserialize)]
struct RawInstruction {
    #[serde(rename = "@Mnemonic")]
    mnemonic: String,
    #[serde(rename = "@Aliases")]
    aliases: Option<String>,
    #[serde(rename = "@Opcode")]
    opcode: String,
    #[serde(rename = "@Family")]
    family: String,
    #[serde(rename = "@Flow")]
    flow: String,
    #[serde(rename = "@StackNeeds")]
    stack_needs: Option<String>,
    #[serde(rename = "@StackDelta")]
    stack_delta: Option<String>,
    #[serde(rename = "@CallArguments")]
    call_arguments: Option<String>,
    #[serde(rename = "@Units")]
    units: Option<String>,
    #[serde(rename = "@Summary")]
    summary: String,
    #[serde(rename = "@Kind")]
    kind: Option<String>,
    #[serde(rename = "@Ladder")]
    ladder: Option<String>,
    #[serde(rename = "@Immediate")]
    immediate: Option<String>,
    #[serde(rename = "@Logic")]
    logic: Option<String>,
    #[serde(rename = "@Compare")]
    compare: Option<String>,
    #[serde(rename = "@PowerInputs")]
    power_inputs: Option<String>,
    #[serde(rename = "@PowerOutput")]
    power_output: Option<String>,
    #[serde(rename = "@Loop")]
    loop_role: Option<String>,
    #[serde(rename = "@DefinesLabel")]
    defines_label: Option<String>,
    #[serde(rename = "Operand", default)]
    operands: Vec<RawOperand>,
    #[serde(rename = "Description", default)]
    description: Option<String>,
    #[serde(rename = "Example", default)]
    example: Option<String>,
}

#[derive(Deserialize)]
struct RawOperand {
    #[serde(rename = "@Name")]
    name: String,
    #[serde(rename = "@Role")]
    role: Option<String>,
    #[serde(rename = "@Kind")]
    kind: Option<String>,
    #[serde(rename = "@Types")]
    types: Option<String>,
    #[serde(rename = "@Areas")]
    areas: Option<String>,
    #[serde(rename = "@Constant")]
    constant: Option<String>,
    #[serde(rename = "@Pointer")]
    pointer: Option<String>,
    #[serde(rename = "@AddressOf")]
    address_of: Option<String>,
    #[serde(rename = "@Min")]
    min: Option<String>,
    #[serde(rename = "@Max")]
    max: Option<String>,
    #[serde(rename = "@Block")]
    block: Option<String>,
}

fn err(code: CatalogErrorCode, msg: String) -> CatalogError {
    CatalogError::new(code, FILE, msg)
}

fn dedent(text: Option<String>) -> String {
    let text = text.unwrap_or_default();
    let lines: Vec<&str> = text.lines().collect();
    let indent = lines
        .iter()
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.len() - l.trim_start().len())
        .min()
        .unwrap_or(0);
    let body: Vec<&str> = lines
        .iter()
        .map(|l| {
            if l.len() >= indent {
                &l[indent..]
            } else {
                l.trim_start()
            }
        })
        .collect();
    body.join("\n").trim_matches('\n').trim_end().to_string()
}

fn parse_operand(m: &str, raw: RawOperand) -> Result<OperandSpec, CatalogError> {
    let ctx = |attr: &str| format!("{attr} of operand {} of {m}", raw.name);
    let role = match raw.role.as_deref().map(str::trim) {
        None | Some("In") => Role::In,
        Some("Out") => Role::Out,
        Some("InOut") => Role::InOut,
        Some(other) => {
            return Err(err(
                CatalogErrorCode::Value,
                format!("{}: unknown Role `{other}`", ctx("Role")),
            ))
        }
    };
    let kind = match raw.kind.as_deref().map(str::trim) {
        None | Some("Data") => OperandKind::Data,
        Some("Label") => OperandKind::Label,
        Some("Block") => OperandKind::Block,
        Some("Literal") => OperandKind::Literal,
        Some(other) => {
            return Err(err(
                CatalogErrorCode::Value,
                format!("{}: unknown Kind `{other}`", ctx("Kind")),
            ))
        }
    };
    let mut types = Vec::new();
    for word in raw.types.as_deref().unwrap_or("").split_whitespace() {
        let t = word.parse::<DataType>().map_err(|_| {
            err(
                CatalogErrorCode::Value,
                format!("{}: unknown data type `{word}`", ctx("Types")),
            )
        })?;
        if !types.contains(&t) {
            types.push(t);
        }
    }
    if matches!(kind, OperandKind::Data | OperandKind::Literal) {
        if types.is_empty() {
            return Err(err(
                CatalogErrorCode::Syntax,
                format!("{}: a data operand needs Types", ctx("Types")),
            ));
        }
        let w = types[0].width();
        if types.iter().any(|t| t.width() != w) {
            return Err(err(
                CatalogErrorCode::Value,
                format!(
                    "{}: all types of one operand must have the same width",
                    ctx("Types")
                ),
            ));
        }
    }
    let areas = raw.areas.map(|a| {
        a.split_whitespace()
            .map(|s| s.to_ascii_uppercase())
            .collect::<Vec<_>>()
    });
    let is_bool = types.first() == Some(&DataType::Bool);
    let data = kind == OperandKind::Data;
    let constant = attr_bool(
        FILE,
        &ctx("Constant"),
        raw.constant.as_deref(),
        data && role == Role::In && !is_bool,
    )?;
    let pointer = attr_bool(
        FILE,
        &ctx("Pointer"),
        raw.pointer.as_deref(),
        data && !is_bool,
    )?;
    let address_of = attr_bool(FILE, &ctx("AddressOf"), raw.address_of.as_deref(), false)?;
    if constant && role != Role::In {
        return Err(err(
            CatalogErrorCode::Value,
            format!("{}: only In operands may be constants", ctx("Constant")),
        ));
    }
    let min = raw
        .min
        .as_deref()
        .map(|v| attr_int(FILE, &ctx("Min"), v, i64::MIN, i64::MAX))
        .transpose()?;
    let max = raw
        .max
        .as_deref()
        .map(|v| attr_int(FILE, &ctx("Max"), v, i64::MIN, i64::MAX))
        .transpose()?;
    if kind == OperandKind::Literal && (min.is_none() || max.is_none()) {
        return Err(err(
            CatalogErrorCode::Syntax,
            format!("{}: a Literal operand needs Min and Max", ctx("Min")),
        ));
    }
    let block = match raw.block.as_deref().map(str::trim) {
        None => None,
        Some("SBR") => Some(BlockKind::Subroutine),
        Some("INT") => Some(BlockKind::Interrupt),
        Some(other) => {
            return Err(err(
                CatalogErrorCode::Value,
                format!("{}: Block must be SBR or INT, not `{other}`", ctx("Block")),
            ))
        }
    };
    if (kind == OperandKind::Block) != block.is_some() {
        return Err(err(
            CatalogErrorCode::Syntax,
            format!(
                "{}: Block goes with Kind=\"Block\" and only there",
                ctx("Block")
            ),
        ));
    }
    Ok(OperandSpec {
        name: raw.name,
        role,
        kind,
        types,
        areas,
        constant,
        pointer,
        address_of,
        min,
        max,
        block,
    })
}

fn parse_instruction(raw: RawInstruction) -> Result<Instruction, CatalogError> {
    let mnemonic = raw.mnemonic.trim().to_ascii_uppercase();
    if mnemonic.is_empty() || mnemonic.chars().any(char::is_whitespace) {
        return Err(err(
            CatalogErrorCode::Value,
            format!("bad mnemonic `{}`", raw.mnemonic),
        ));
    }
    let m = mnemonic.as_str();
    let opcode = attr_int(FILE, &format!("Opcode of {m}"), &raw.opcode, 1, 0xFFFF)? as u16;
    let flow = raw.flow.parse::<Flow>().map_err(|_| {
        err(
            CatalogErrorCode::Value,
            format!("unknown Flow `{}` of {m}", raw.flow),
        )
    })?;
    let needs = raw
        .stack_needs
        .as_deref()
        .map(|v| attr_int(FILE, &format!("StackNeeds of {m}"), v, 0, 32))
        .transpose()?;
    let delta = raw
        .stack_delta
        .as_deref()
        .map(|v| attr_int(FILE, &format!("StackDelta of {m}"), v, -32, 32))
        .transpose()?;
    let (stack_needs, stack_delta) = match (needs, delta, flow.default_stack_effect()) {
        (Some(n), Some(d), _) => (n as u8, d as i8),
        (None, None, Some(def)) => def,
        (n, d, Some((dn, dd))) => (
            n.map(|v| v as u8).unwrap_or(dn),
            d.map(|v| v as i8).unwrap_or(dd),
        ),
        _ => {
            return Err(err(
                CatalogErrorCode::Syntax,
                format!("{m} has Flow=\"Stack\" and needs StackNeeds and StackDelta"),
            ))
        }
    };
    if (stack_needs as i32) + (stack_delta as i32) < 0 {
        return Err(err(
            CatalogErrorCode::Value,
            format!("{m} pops more levels than it needs"),
        ));
    }
    let nature = nature::parse(m, flow, stack_needs, &raw)?;
    let operands = raw
        .operands
        .into_iter()
        .map(|o| parse_operand(m, o))
        .collect::<Result<Vec<_>, _>>()?;
    let aliases = raw
        .aliases
        .map(|a| {
            a.split_whitespace()
                .map(|s| s.to_ascii_uppercase())
                .collect()
        })
        .unwrap_or_default();
    let units = match raw.units.as_deref() {
        None => UnitScope::ALL,
        Some(text) => UnitScope::parse(text).ok_or_else(|| {
            err(
                CatalogErrorCode::Value,
                format!("Units of {m} must list MAIN, INT or SBR, not `{text}`"),
            )
        })?,
    };
    Ok(Instruction {
        kind: nature.kind,
        ladder: nature.ladder,
        immediate: nature.immediate,
        logic: nature.logic,
        compare: nature.compare,
        power_inputs: nature.power_inputs,
        power_output: nature.power_output,
        loop_role: nature.loop_role,
        defines_label: nature.defines_label,
        aliases,
        opcode,
        family: raw.family.trim().to_string(),
        flow,
        stack_needs,
        stack_delta,
        call_arguments: attr_bool(
            FILE,
            &format!("CallArguments of {m}"),
            raw.call_arguments.as_deref(),
            false,
        )?,
        units,
        operands,
        summary: raw.summary.trim().to_string(),
        description: dedent(raw.description),
        example: dedent(raw.example),
        mnemonic,
    })
}

impl InstructionSet {
    pub fn parse(bytes: &[u8]) -> Result<InstructionSet, CatalogError> {
        let text = decode_xml_text(bytes, FILE)?;
        let raw: Raw = from_xml(&text, FILE)?;
        let instructions = raw
            .instructions
            .into_iter()
            .map(parse_instruction)
            .collect::<Result<Vec<_>, _>>()?;
        if instructions.len() > u16::MAX as usize {
            return Err(err(CatalogErrorCode::Value, "too many instructions".into()));
        }
        let mut index = Vec::new();
        let mut opcodes = BTreeSet::new();
        for (i, ins) in instructions.iter().enumerate() {
            if !opcodes.insert(ins.opcode) {
                return Err(err(
                    CatalogErrorCode::Duplicate,
                    format!(
                        "opcode 0x{:04X} of {} is used twice",
                        ins.opcode, ins.mnemonic
                    ),
                ));
            }
            for name in std::iter::once(&ins.mnemonic).chain(&ins.aliases) {
                index.push((name.clone(), InstrId(i as u16)));
            }
        }
        index.sort();
        for pair in index.windows(2) {
            if pair[0].0 == pair[1].0 {
                return Err(err(
                    CatalogErrorCode::Duplicate,
                    format!("mnemonic {} is described twice", pair[0].0),
                ));
            }
        }
        Ok(InstructionSet {
            logic_stack_depth: attr_int(FILE, "LogicStackDepth", &raw.logic_stack_depth, 1, 32)?
                as u8,
            call_depth: attr_int(FILE, "CallDepth", &raw.call_depth, 1, 255)? as u8,
            for_depth: attr_int(FILE, "ForDepth", &raw.for_depth, 1, 255)? as u8,
            instructions,
            index,
        })
    }

    /// Check references into the memory map that one file alone cannot check.
    pub(crate) fn validate_against(&self, memory: &MemoryMap) -> Result<(), CatalogError> {
        let _ = memory; // Areas named by operands may be absent on a given target (V, HC).
        for ins in &self.instructions {
            for op in &ins.operands {
                if let Some(areas) = &op.areas {
                    if let Some(bad) = areas
                        .iter()
                        .find(|a| !a.chars().all(|c| c.is_ascii_uppercase()))
                    {
                        return Err(CatalogError::new(
                            CatalogErrorCode::Mismatch,
                            FILE,
                            format!("operand {} of {} names area `{bad}`", op.name, ins.mnemonic),
                        ));
                    }
                }
            }
        }
        Ok(())
    }

    /// Look an instruction up by mnemonic or alias, case-insensitively.
    pub fn lookup(&self, mnemonic: &str) -> Option<InstrId> {
        let mut buf = [0u8; 32];
        let bytes = mnemonic.as_bytes();
        if bytes.len() > buf.len() {
            return None;
        }
        for (d, s) in buf.iter_mut().zip(bytes) {
            *d = s.to_ascii_uppercase();
        }
        let key = std::str::from_utf8(&buf[..bytes.len()]).ok()?;
        self.index
            .binary_search_by(|(name, _)| name.as_str().cmp(key))
            .ok()
            .map(|i| self.index[i].1)
    }

    pub fn get(&self, id: InstrId) -> &Instruction {
        &self.instructions[id.0 as usize]
    }

    pub fn by_opcode(&self, opcode: u16) -> Option<InstrId> {
        self.instructions
            .iter()
            .position(|i| i.opcode == opcode)
            .map(|i| InstrId(i as u16))
    }

    /// The instruction of a timer or counter kind.
    pub fn by_kind(&self, kind: TimerCounterKind) -> Option<InstrId> {
        self.position(|i| i.kind == Some(kind))
    }

    /// The instruction that defines a label (`LBL`).
    pub fn label_definition(&self) -> Option<InstrId> {
        self.position(|i| i.defines_label)
    }

    /// The instruction with a part in FOR/NEXT loops (`FOR`, `NEXT`).
    pub fn by_loop_role(&self, role: LoopRole) -> Option<InstrId> {
        self.position(|i| i.loop_role == Some(role))
    }

    /// The compare contact that loads (`Join::Load`) or combines a relation of two
    /// operands of type `ty`, not immediate: `(Join::And, CompareOp::Ge, INT)` is `AW>=`.
    pub fn compare(&self, join: Join, op: CompareOp, ty: DataType) -> Option<InstrId> {
        self.position(|i| {
            i.compare == Some(op)
                && i.join() == Some(join)
                && i.operands.first().and_then(|o| o.types.first()) == Some(&ty)
        })
    }

    /// The same contact in another STL form: `LD` -> `A` -> `O`, `LDNI` -> `ONI`,
    /// `AW>=` -> `LDW>=` (same ladder element, immediacy, relation and operand types).
    /// `None` for an instruction that is not a contact.
    pub fn with_join(&self, id: InstrId, join: Join) -> Option<InstrId> {
        let from = self.get(id);
        if !from.ladder.is_contact() {
            return None;
        }
        let types = |i: &Instruction| -> Vec<Vec<DataType>> {
            i.operands.iter().map(|o| o.types.clone()).collect()
        };
        self.position(|i| {
            i.join() == Some(join)
                && i.ladder == from.ladder
                && i.immediate == from.immediate
                && i.compare == from.compare
                && types(i) == types(from)
        })
    }

    /// The bit contact or coil of a ladder class and join, not immediate: the plain
    /// form an S7-200 timer bit's `LD`/`AN`/`R` line has (`(ClosedContact, Or)` is `ON`).
    pub fn plain(&self, ladder: LadderClass, join: Option<Join>) -> Option<InstrId> {
        self.position(|i| i.ladder == ladder && i.join() == join && !i.immediate)
    }

    fn position(&self, test: impl Fn(&Instruction) -> bool) -> Option<InstrId> {
        self.instructions
            .iter()
            .position(test)
            .map(|i| InstrId(i as u16))
    }

    /// All mnemonics and aliases (upper case), for suggestions and completion.
    pub fn names(&self) -> impl Iterator<Item = (&str, InstrId)> {
        self.index.iter().map(|(n, id)| (n.as_str(), *id))
    }
}
