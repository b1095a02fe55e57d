//! The rules a program must meet on a target that both the checker (gutta-compiler's
//! `check/`) and the verifier (gutta-format's `verify/`) apply: literal and label
//! ranges, unit numbers, where an instruction may stand, locals, CALL parameters and
//! the areas a memory operand may name and how. One home, so the two cannot drift;
//! each caller turns a refusal into its own diagnostic or error. Pure functions of the
//! target's tables: no messages, no I/O.

use std::ops::RangeInclusive;

use crate::{
    Area, AreaKind, BlockKind, DataType, InstructionSet, MemoryMap, OperandKind, OperandSpec,
    PlcType, Role, UnitScope, Width,
};

/// Whether FOR loops may be open `depth` deep at once (ForDepth of ManagerFun.xml).
pub fn for_depth_allowed(set: &InstructionSet, depth: usize) -> bool {
    depth <= usize::from(set.for_depth)
}

/// Whether an operand has the given name (names compare case-insensitively).
fn is_named(spec: &OperandSpec, name: &str) -> bool {
    spec.name.eq_ignore_ascii_case(name)
}

/// Whether a literal operand is an interrupt event number (`EVNT` of `ATCH`, `DTCH`,
/// `CEVNT`).
pub fn is_event_operand(spec: &OperandSpec) -> bool {
    spec.kind == OperandKind::Literal && is_named(spec, "EVNT")
}

/// Why a literal operand's value is refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LiteralRefusal {
    /// An `EVNT` operand: the target raises no interrupt event with that number.
    NoSuchEvent,
    /// Outside [`literal_range`].
    OutOfRange { min: i64, max: i64 },
}

/// The values a literal operand takes on a target: its spec's `Min..Max` (a literal
/// is stored in the 16-bit OFFSET field), a `PORT` narrowed to the target's serial
/// ports.
pub fn literal_range(spec: &OperandSpec, memory: &MemoryMap) -> RangeInclusive<i64> {
    let min = spec.min.unwrap_or(0);
    let mut max = spec.max.unwrap_or(i64::from(u16::MAX));
    if is_named(spec, "PORT") {
        max = max.min(i64::from(memory.serial_ports) - 1);
    }
    min..=max
}

/// Check a literal operand's value: an `EVNT` must be one of the target's interrupt
/// events (checked first: the events are the narrower set), then every literal lies
/// in its [`literal_range`].
pub fn check_literal(
    spec: &OperandSpec,
    memory: &MemoryMap,
    value: i64,
) -> Result<(), LiteralRefusal> {
    if is_event_operand(spec) && !memory.events.iter().any(|e| i64::from(e.number) == value) {
        return Err(LiteralRefusal::NoSuchEvent);
    }
    let range = literal_range(spec, memory);
    if range.contains(&value) {
        Ok(())
    } else {
        Err(LiteralRefusal::OutOfRange {
            min: *range.start(),
            max: *range.end(),
        })
    }
}

/// The numbers a label operand takes: its spec's `Min..Max` within 0..255, the
/// numbers an `LBL` can have.
pub fn label_range(spec: &OperandSpec) -> RangeInclusive<i64> {
    spec.min.unwrap_or(0).max(0)..=spec.max.unwrap_or(255).min(255)
}

/// How many units of a kind a target can have (numbers `0..limit`; MAIN is INT0) and
/// the PlcType attribute that says so.
pub fn unit_limit(plc: &PlcType, kind: BlockKind) -> (u32, &'static str) {
    match kind {
        BlockKind::Interrupt => (plc.program_block_page_int_size, "ProgramBlockPageIntSize"),
        BlockKind::Subroutine => (plc.program_block_page_sbr_size, "ProgramBlockPageSbrSize"),
    }
}

/// Whether the target can have INTn / SBRn.
pub fn unit_exists(plc: &PlcType, kind: BlockKind, number: u32) -> bool {
    number < unit_limit(plc, kind).0
}

/// Whether a unit operand (`CALL`, `ATCH`) may name the unit `kind` `number`: the
/// kind its spec names (`Block`), and never MAIN, which is neither attached nor called.
pub fn unit_operand_accepts(spec: &OperandSpec, kind: BlockKind, number: u32) -> bool {
    let expected = unit_operand_kind(spec);
    kind == expected && !(expected == BlockKind::Interrupt && number == 0)
}

/// The kind of unit a unit operand names (a spec without `Block` names subroutines).
pub fn unit_operand_kind(spec: &OperandSpec) -> BlockKind {
    spec.block.unwrap_or(BlockKind::Subroutine)
}

/// Whether an instruction of that scope (ManagerFun.xml `Units`) may stand in the
/// unit `kind` `number`: MAIN is INT0, its own scope.
pub fn placement_allowed(scope: UnitScope, kind: BlockKind, number: u32) -> bool {
    match kind {
        BlockKind::Interrupt if number == 0 => scope.main,
        BlockKind::Interrupt => scope.interrupt,
        BlockKind::Subroutine => scope.subroutine,
    }
}

/// How many locals a unit of a kind may declare, and the PlcType attribute.
pub fn locals_limit(plc: &PlcType, kind: BlockKind) -> (u32, &'static str) {
    match kind {
        BlockKind::Interrupt => (
            plc.program_block_page_arg_int_size,
            "ProgramBlockPageArgIntSize",
        ),
        BlockKind::Subroutine => (
            plc.program_block_page_arg_sbr_size,
            "ProgramBlockPageArgSbrSize",
        ),
    }
}

/// Whether a unit of that kind takes parameters (VAR_INPUT, VAR_IN_OUT, VAR_OUTPUT):
/// subroutines do; interrupt routines have temporaries only.
pub fn takes_parameters(kind: BlockKind) -> bool {
    kind == BlockKind::Subroutine
}

/// The operand spec a CALL argument meets: the callee's local `name` of type `ty`,
/// passed in (`Role::In`, a constant may stand there), in-out or out. Any area; `*`
/// for every type but BOOL; `&` for a DWORD or UDINT input.
pub fn parameter_spec(name: String, role: Role, ty: DataType) -> OperandSpec {
    OperandSpec {
        name,
        role,
        kind: OperandKind::Data,
        types: vec![ty],
        areas: None,
        constant: role == Role::In,
        pointer: ty.width() != Width::Bit,
        address_of: matches!(ty, DataType::Dword | DataType::Udint),
        min: None,
        max: None,
        block: None,
    }
}

/// The areas a data block may initialise (docs/language.md section 10): not inputs
/// (the terminals fill them), not K (the compiler's), not L (exists only in a call).
pub const INITIALISABLE: &[AreaKind] = &[
    AreaKind::Memory,
    AreaKind::DigitalOutput,
    AreaKind::AnalogOutput,
    AreaKind::Timer,
    AreaKind::Counter,
];

/// Which areas a memory operand may name (directly, as a value).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AreaRule<'a> {
    Any,
    /// Area names from an operand spec; K as well when the operand takes constants.
    Listed(&'a [String]),
    Kinds(&'static [AreaKind]),
}

/// What a memory operand must be: the data part of an operand spec, or the rules of a
/// local or a data item.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DataRules<'a> {
    /// Access width of the value.
    pub width: Width,
    /// The instruction writes the operand.
    pub writes: bool,
    /// A constant (a variable in K) may stand here.
    pub constant: bool,
    /// `*pointer` is accepted.
    pub pointer: bool,
    /// `&byte` is accepted (see [`DataRules::takes_address_of`]).
    pub address_of: bool,
    pub areas: AreaRule<'a>,
}

impl<'a> DataRules<'a> {
    pub fn from_spec(spec: &'a OperandSpec) -> DataRules<'a> {
        DataRules {
            width: access_width(spec),
            writes: spec.role.writes(),
            constant: spec.constant,
            pointer: spec.pointer,
            address_of: spec.address_of,
            areas: match &spec.areas {
                None => AreaRule::Any,
                Some(list) => AreaRule::Listed(list),
            },
        }
    }

    /// A local of a unit's argument page: in L, of its type's width.
    pub fn local(width: Width) -> DataRules<'static> {
        DataRules {
            width,
            writes: false,
            constant: false,
            pointer: false,
            address_of: false,
            areas: AreaRule::Kinds(&[AreaKind::Local]),
        }
    }

    /// A data item: written at download, in an [`INITIALISABLE`] area.
    pub fn data_item(width: Width) -> DataRules<'static> {
        DataRules {
            width,
            writes: true,
            constant: false,
            pointer: false,
            address_of: false,
            areas: AreaRule::Kinds(INITIALISABLE),
        }
    }

    /// `&byte` stands only where a DWORD is read: a pointer value is a DWORD.
    pub fn takes_address_of(&self) -> bool {
        self.address_of && !self.writes && self.width == Width::Dword
    }

    /// Whether the operand may name a variable of this area directly.
    pub fn accepts_area(&self, area: &Area) -> bool {
        match self.areas {
            AreaRule::Any => true,
            AreaRule::Listed(list) => {
                (self.constant && area.kind == AreaKind::Constant)
                    || list.iter().any(|a| a.eq_ignore_ascii_case(&area.name))
            }
            AreaRule::Kinds(kinds) => kinds.contains(&area.kind),
        }
    }

    /// Whether the operand may be in this area as far as writing goes: an operand
    /// the instruction writes needs a `Writable` area.
    pub fn may_write(&self, area: &Area) -> bool {
        !self.writes || area.writable
    }
}

/// The access width of a data operand: its first type's (DWORD when it lists none).
pub fn access_width(spec: &OperandSpec) -> Width {
    spec.types.first().map_or(Width::Dword, |t| t.width())
}

/// Why a variable cannot stand behind `&` or `*`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IndirectRefusal {
    /// The area does not allow it (`AddressOf`, `HoldsPointer` of ManagerVar.xml).
    Area,
    /// The variable has the wrong width: `&` takes a BYTE, `*` reads a DWORD pointer.
    Width,
}

/// `&variable`: the area allows taking addresses and the variable is a byte.
pub fn address_of_target(area: &Area, width: Width) -> Result<(), IndirectRefusal> {
    if !area.address_of {
        Err(IndirectRefusal::Area)
    } else if width != Width::Byte || !area.allows(Width::Byte) {
        Err(IndirectRefusal::Width)
    } else {
        Ok(())
    }
}

/// `*holder`: the area holds pointers and the holder is a DWORD.
pub fn pointer_holder(area: &Area, width: Width) -> Result<(), IndirectRefusal> {
    if !area.holds_pointer {
        Err(IndirectRefusal::Area)
    } else if width != Width::Dword || !area.allows(Width::Dword) {
        Err(IndirectRefusal::Width)
    } else {
        Ok(())
    }
}

/// Where locals go in L (docs/language.md): one after another in declaration order
/// (VAR_INPUT, VAR_IN_OUT, VAR_OUTPUT, VAR), BOOLs packed into bytes from bit 0, every
/// other type at the next whole byte, without alignment. The checker places locals
/// with it and the disassembler checks argument pages against it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LocalLayout {
    /// The byte being filled.
    byte: u32,
    /// Bits of `byte` already taken by BOOLs (0 when none).
    bit: u8,
}

impl LocalLayout {
    pub fn new() -> LocalLayout {
        LocalLayout::default()
    }

    /// The place of the next local of `width`: its byte offset in L and its bit (0
    /// unless it is a BOOL).
    pub fn place(&mut self, width: Width) -> (u32, u8) {
        if width == Width::Bit {
            if self.bit == 8 {
                self.byte += 1;
                self.bit = 0;
            }
            self.bit += 1;
            (self.byte, self.bit - 1)
        } else {
            if self.bit > 0 {
                self.byte += 1;
                self.bit = 0;
            }
            let at = self.byte;
            self.byte += width.bytes();
            (at, 0)
        }
    }
}

/// Serial port settings of a system block (docs/language.md section 11), as the
/// vendor's editor allows them: 8 data bits (RTU), 1 or 2 stop bits, a response
/// timeout of 1..255 x 100 ms and a frame gap of 1..255 x 1 ms.
pub mod port {
    use std::ops::RangeInclusive;

    pub const DATA_BITS: u8 = 8;
    pub const STOP_BITS: RangeInclusive<u8> = 1..=2;
    pub const TIMEOUT: RangeInclusive<u8> = 1..=255;
    pub const FRAME_GAP: RangeInclusive<u8> = 1..=255;
}

/// Whether a login password may be these bytes: 1..16 ASCII characters, none of
/// them NUL (the system page pads the password with zeros).
pub fn password_allowed(password: &[u8]) -> bool {
    (1..=16).contains(&password.len()) && password.iter().all(|b| (1..=0x7F).contains(b))
}
