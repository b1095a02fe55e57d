//! Operands as source text: direct addresses by the target's names, `#local`, `&`,
//! `*`, constants read back from the const page and spelled for the instruction's
//! operand types, labels, units and literals. An operand whose bits no text
//! reproduces is an error string, never a guess.

use gutta_catalog::{
    Address, Area, AreaKind, DataType, Instruction, OperandKind, OperandSpec, Role, Width,
};

use super::units::Local;
use super::Disassembler;
use crate::{LocalSection, PackedOperand, Use};

/// Where an instruction fails to print: the operand's index (if one is to blame) and why.
pub(super) type InstructionError = (Option<usize>, String);

fn use_name(u: Use) -> &'static str {
    match u {
        Use::Value => "a variable or constant",
        Use::AddressOf => "an address (&)",
        Use::Pointer => "a pointer access (*)",
        Use::Label => "a label",
        Use::Unit => "a program unit",
        Use::Literal => "a literal",
    }
}

/// The untyped data type of a width (BOOL, BYTE, WORD, DWORD).
pub(super) fn bit_string_type(w: Width) -> DataType {
    match w {
        Width::Bit => DataType::Bool,
        Width::Byte => DataType::Byte,
        Width::Word => DataType::Word,
        Width::Dword => DataType::Dword,
    }
}

fn is_bit_string(t: DataType) -> bool {
    matches!(t, DataType::Byte | DataType::Word | DataType::Dword)
}

/// `0`..`9` in decimal, anything larger as `16#` and the width's hex digits.
pub(super) fn unsigned_text(value: u64, width: Width) -> String {
    if value < 10 {
        value.to_string()
    } else {
        let digits = 2 * width.bytes() as usize;
        format!("16#{value:0digits$X}")
    }
}

/// An integer constant of `width` with bits `raw`, spelled so that the operand's
/// types accept it and compile it to the same bits: signed decimal when every type is
/// signed, unsigned decimal when every type is an unsigned integer, else decimal below
/// 10 and `16#` hex above; the other reading when the preferred one is out of range.
pub(super) fn integer_text(raw: u32, width: Width, spec: &OperandSpec) -> String {
    let bits = width.bits();
    let unsigned = if bits >= 32 {
        raw as i64
    } else {
        (raw & ((1u32 << bits) - 1)) as i64
    };
    let signed = if bits > 1 && unsigned >= 1i64 << (bits - 1) {
        unsigned - (1i64 << bits)
    } else {
        unsigned
    };
    let (lo, hi) = match (spec.min, spec.max) {
        (Some(lo), Some(hi)) => (lo, hi),
        _ => DataType::union_range(&spec.types).unwrap_or((i64::MAX, i64::MIN)),
    };
    let fits = |v: i64| lo <= v && v <= hi;
    let all_signed = !spec.types.is_empty() && spec.types.iter().all(|t| t.is_signed());
    let any_bits = spec.types.iter().any(|t| is_bit_string(*t));
    let spell_unsigned = |v: i64| {
        if any_bits {
            unsigned_text(v as u64, width)
        } else {
            v.to_string()
        }
    };
    if all_signed && fits(signed) {
        signed.to_string()
    } else if fits(unsigned) {
        spell_unsigned(unsigned)
    } else if fits(signed) {
        signed.to_string()
    } else {
        spell_unsigned(unsigned)
    }
}

/// A REAL literal the compiler reads back to exactly these bits (it parses an f64 and
/// rounds to f32), with digits on both sides of the point; `None` for NaN and infinity.
pub(super) fn real_text(x: f32) -> Option<String> {
    if !x.is_finite() {
        return None;
    }
    let reads_back =
        |s: &str| s.parse::<f64>().ok().map(|v| (v as f32).to_bits()) == Some(x.to_bits());
    let mut s = format!("{x:?}");
    if !reads_back(&s) {
        // Every f32 is an f64, whose shortest form reads back exactly.
        s = format!("{:?}", x as f64);
    }
    let mantissa_end = s.find(['e', 'E']).unwrap_or(s.len());
    if !s[..mantissa_end].contains('.') {
        s.insert_str(mantissa_end, ".0");
    }
    Some(s)
}

/// The spec the checker gives a CALL argument for a parameter.
fn parameter_spec(p: &Local) -> OperandSpec {
    let role = match p.section {
        LocalSection::Input => Role::In,
        LocalSection::InOut => Role::InOut,
        _ => Role::Out,
    };
    let types = if p.data_type.width() == Width::Bit {
        vec![DataType::Bool]
    } else {
        vec![p.data_type]
    };
    OperandSpec {
        name: p.name.clone(),
        role,
        kind: OperandKind::Data,
        types,
        areas: None,
        constant: role == Role::In,
        pointer: p.data_type != DataType::Bool,
        address_of: matches!(p.data_type, DataType::Dword | DataType::Udint),
        min: None,
        max: None,
        block: None,
    }
}

impl<'a> Disassembler<'a> {
    /// A direct address, if the text `format_address` prints for it reads back as it.
    pub(super) fn address(
        &self,
        slot: u8,
        width: Width,
        offset: u16,
        bit: u8,
    ) -> Result<(Address, &'a Area), String> {
        let target = self.target;
        let area = target
            .memory
            .area_by_slot(slot)
            .ok_or_else(|| format!("SLOT {slot} is no memory area of {}", target.name()))?;
        if !area.allows(width) {
            return Err(format!("area {} has no {width} access", area.name));
        }
        if area.fixed_width().is_some() && offset as u32 % area.unit.bytes() != 0 {
            return Err(format!(
                "byte offset {offset} is not a whole {} of area {}",
                area.unit, area.name
            ));
        }
        if width == Width::Bit && bit > 7 {
            return Err(format!("BIT_OFFSET {bit} is not 0..7"));
        }
        if width != Width::Bit && bit != 0 {
            return Err(format!("BIT_OFFSET {bit} in a {width} operand"));
        }
        Ok((
            Address {
                slot,
                width,
                offset: offset as u32,
                bit,
            },
            area,
        ))
    }

    /// One instruction line without its step comment. Constants it prints are marked
    /// in the const page's coverage only when the whole line prints.
    pub(super) fn instruction_text(
        &mut self,
        ins: &Instruction,
        ops: &[PackedOperand],
        locals: &[Local],
    ) -> Result<String, InstructionError> {
        let fixed = ins.operands.len();
        let count_ok = if ins.call_arguments {
            ops.len() >= fixed
        } else {
            ops.len() == fixed
        };
        if !count_ok {
            return Err((
                None,
                format!(
                    "{} takes {}{fixed} operand(s), the record has {}",
                    ins.mnemonic,
                    if ins.call_arguments { "at least " } else { "" },
                    ops.len()
                ),
            ));
        }
        let mut marks = Vec::new();
        let mut texts = Vec::with_capacity(ops.len());
        for (i, (op, spec)) in ops.iter().zip(&ins.operands).enumerate() {
            let text = self
                .operand(*op, spec, locals, &mut marks)
                .map_err(|r| (Some(i), format!("operand {} ({}): {r}", i + 1, spec.name)))?;
            texts.push(text);
        }
        if ins.call_arguments {
            let params = self.parameters(ops.first().copied(), ops.len() - fixed)?;
            let args = ops.get(fixed..).unwrap_or_default();
            for (i, (op, p)) in args.iter().zip(&params).enumerate() {
                let spec = parameter_spec(p);
                let text = self.operand(*op, &spec, locals, &mut marks).map_err(|r| {
                    (
                        Some(fixed + i),
                        format!("argument {} ({}): {r}", i + 1, p.name),
                    )
                })?;
                texts.push(text);
            }
        }
        for (start, len) in marks {
            for used in self.const_used.iter_mut().skip(start).take(len) {
                *used = true;
            }
        }
        Ok(if texts.is_empty() {
            ins.mnemonic.clone()
        } else {
            format!("{:<6} {}", ins.mnemonic, texts.join(", "))
        })
    }

    /// The callee's parameters (VAR_INPUT, VAR_IN_OUT, VAR_OUTPUT in L order), which
    /// must be as many as the arguments passed.
    fn parameters(
        &self,
        unit: Option<PackedOperand>,
        passed: usize,
    ) -> Result<Vec<Local>, InstructionError> {
        let Some(unit) = unit.filter(|u| u.use_() == Some(Use::Unit) && u.slot() == 1) else {
            return Err((Some(0), "a CALL that names no subroutine".to_string()));
        };
        let number = self.target.plc.program_block_page_int_size + unit.offset() as u32;
        let params: Vec<Local> = u8::try_from(number)
            .ok()
            .and_then(|n| self.decoded_locals(n))
            .ok_or_else(|| {
                (
                    Some(0),
                    format!(
                        "CALL of SBR{}, whose argument page is missing or does not decode",
                        unit.offset()
                    ),
                )
            })?
            .into_iter()
            .filter(|l| l.section != LocalSection::Temp)
            .collect();
        if params.len() != passed {
            return Err((
                None,
                format!(
                    "SBR{} takes {} argument(s), the record passes {passed}",
                    unit.offset(),
                    params.len()
                ),
            ));
        }
        Ok(params)
    }

    fn operand(
        &self,
        op: PackedOperand,
        spec: &OperandSpec,
        locals: &[Local],
        marks: &mut Vec<(usize, usize)>,
    ) -> Result<String, String> {
        let Some(use_) = op.use_() else {
            return Err(format!("USE code {} is not 0..5", op.use_code()));
        };
        let special = |want: Use, what: &str| -> Result<u16, String> {
            if use_ != want {
                return Err(format!("{} where {what} belongs", use_name(use_)));
            }
            if op.width_code() != 0 || op.bit() != 0 {
                return Err(format!(
                    "{what} with WIDTH {} and BIT_OFFSET {} (both must be 0)",
                    op.width_code(),
                    op.bit()
                ));
            }
            Ok(op.offset())
        };
        match spec.kind {
            OperandKind::Label | OperandKind::Literal => {
                let (want, what) = if spec.kind == OperandKind::Label {
                    (Use::Label, "a label")
                } else {
                    (Use::Literal, "a literal")
                };
                let value = special(want, what)?;
                if op.slot() != 0 {
                    return Err(format!("{what} with SLOT {} (must be 0)", op.slot()));
                }
                Ok(value.to_string())
            }
            OperandKind::Block => {
                let n = special(Use::Unit, "a program unit")?;
                match op.slot() {
                    0 => Ok(format!("INT{n}")),
                    1 => Ok(format!("SBR{n}")),
                    s => Err(format!(
                        "program unit SLOT {s} is neither 0 (INT) nor 1 (SBR)"
                    )),
                }
            }
            OperandKind::Data => self.data_operand(op, use_, spec, locals, marks),
        }
    }

    fn data_operand(
        &self,
        op: PackedOperand,
        use_: Use,
        spec: &OperandSpec,
        locals: &[Local],
        marks: &mut Vec<(usize, usize)>,
    ) -> Result<String, String> {
        let memory = &self.target.memory;
        let want = spec.types.first().map_or(Width::Dword, |t| t.width());
        let width = || {
            let w = op
                .width()
                .ok_or_else(|| format!("WIDTH code {} is not 0..3", op.width_code()))?;
            if w == want {
                Ok(w)
            } else {
                Err(format!("a {w} access where the instruction takes a {want}"))
            }
        };
        match use_ {
            Use::Value => {
                let (address, area) = self.address(op.slot(), width()?, op.offset(), op.bit())?;
                if area.kind == AreaKind::Constant && spec.constant {
                    if let Some(text) = self.constant(address, spec, marks)? {
                        return Ok(text);
                    }
                }
                let local = locals
                    .iter()
                    .find(|l| l.address == address && l.data_type.accepted_by(&spec.types));
                Ok(match local {
                    Some(l) => format!("#{}", l.name),
                    None => memory.format_address(&address),
                })
            }
            Use::AddressOf => {
                if op.width() != Some(Width::Dword) {
                    return Err(format!(
                        "an address (&) with WIDTH {} (must be 3, DWORD)",
                        op.width_code()
                    ));
                }
                let (address, _) = self.address(op.slot(), Width::Byte, op.offset(), op.bit())?;
                Ok(format!("&{}", memory.format_address(&address)))
            }
            Use::Pointer => {
                width()?;
                if op.bit() != 0 {
                    return Err(format!("BIT_OFFSET {} in a pointer access", op.bit()));
                }
                let (address, _) = self.address(op.slot(), Width::Dword, op.offset(), 0)?;
                Ok(match locals.iter().find(|l| l.address == address) {
                    Some(l) => format!("*#{}", l.name),
                    None => format!("*{}", memory.format_address(&address)),
                })
            }
            other => Err(format!("{} where a variable belongs", use_name(other))),
        }
    }

    /// The value of a constant operand from the const page; `None` when only the
    /// address reproduces it (outside the page, or a bit other than a 0/1 byte's bit 0).
    fn constant(
        &self,
        at: Address,
        spec: &OperandSpec,
        marks: &mut Vec<(usize, usize)>,
    ) -> Result<Option<String>, String> {
        let start = at.offset as usize;
        let len = at.width.bytes() as usize;
        let Some(bytes) = self.consts.get(start..start + len) else {
            return Ok(None);
        };
        let mut le = [0u8; 4];
        le[..len].copy_from_slice(bytes);
        let raw = u32::from_le_bytes(le);
        let text = if at.width == Width::Bit {
            if at.bit != 0 || raw > 1 {
                return Ok(None);
            }
            raw.to_string()
        } else if spec.types.contains(&DataType::Real) {
            let x = f32::from_bits(raw);
            real_text(x).ok_or_else(|| {
                format!(
                    "the REAL constant at {} is {x}, which no literal spells",
                    self.target.memory.format_address(&at)
                )
            })?
        } else {
            integer_text(raw, at.width, spec)
        };
        marks.push((start, len));
        Ok(Some(text))
    }
}
