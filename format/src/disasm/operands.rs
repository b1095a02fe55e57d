//! Operands as source text: direct addresses by the target's names, `#local`, `&`,
//! `*`, constants read back from the const page and spelled for the instruction's
//! operand types, labels, units and literals. An operand whose bits no text
//! reproduces is an error string, never a guess.

use gutta_catalog::{plural, rules};
use gutta_catalog::{
    Address, Area, AreaKind, BlockKind, DataType, Instruction, OperandKind, OperandSpec, Role,
    Width,
};

use super::units::Local;
use super::{Disassembler, Format};
use crate::{LocalSection, Operand, PackedOperand, UnitRef};

/// Where an instruction fails to print: the operand's index (if one is to blame) and why.
pub(super) type InstructionError = (Option<usize>, String);

/// What a decoded operand is, for messages.
pub(super) fn operand_name(op: &Operand) -> &'static str {
    match op {
        Operand::Value(_) => "a variable or constant",
        Operand::AddressOf { .. } => "an address (&)",
        Operand::Pointer { .. } => "a pointer access (*)",
        Operand::Label(_) => "a label",
        Operand::Unit(_) => "a program unit",
        Operand::Literal(_) => "a literal",
    }
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
    let any_bits = spec.types.iter().any(|t| t.is_bit_string());
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

/// The spec a CALL argument meets (the checker's and the verifier's).
fn parameter_spec(p: &Local) -> OperandSpec {
    let role = match p.section {
        LocalSection::Input => Role::In,
        LocalSection::InOut => Role::InOut,
        _ => Role::Out,
    };
    rules::parameter_spec(p.name.clone(), role, p.data_type)
}

impl<'a> Disassembler<'a> {
    /// A decoded variable, if the text `format_address` prints for it reads back as it.
    pub(super) fn address(&self, at: Address) -> Result<(Address, &'a Area), String> {
        let target = self.target;
        let area = target
            .memory
            .area_by_slot(at.slot)
            .ok_or_else(|| format!("SLOT {} is no memory area of {}", at.slot, target.name()))?;
        if !area.allows(at.width) {
            return Err(format!("area {} has no {} access", area.name, at.width));
        }
        if area.fixed_width().is_some() && !at.offset.is_multiple_of(area.unit.bytes()) {
            return Err(format!(
                "byte offset {} is not a whole {} of area {}",
                at.offset, area.unit, area.name
            ));
        }
        Ok((at, area))
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
                    "{} takes {}{}, the record has {}",
                    ins.mnemonic,
                    if ins.call_arguments { "at least " } else { "" },
                    plural::count(fixed, "operand"),
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
        let Some(Ok(Operand::Unit(
            unit @ UnitRef {
                kind: BlockKind::Subroutine,
                ..
            },
        ))) = unit.map(PackedOperand::decode)
        else {
            return Err((Some(0), "a CALL that names no subroutine".to_string()));
        };
        let params: Vec<Local> = unit
            .page(&self.target.plc)
            .and_then(|page| self.decoded_locals(page))
            .ok_or_else(|| {
                (
                    Some(0),
                    format!("CALL of {unit}, whose argument page is missing or does not decode"),
                )
            })?
            .into_iter()
            .filter(|l| l.section != LocalSection::Temp)
            .collect();
        if params.len() != passed {
            return Err((
                None,
                format!(
                    "{unit} takes {}, the record passes {passed}",
                    plural::count(params.len(), "argument")
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
        let operand = op.decode().map_err(|e| e.to_string())?;
        match (spec.kind, operand) {
            (OperandKind::Literal, Operand::Literal(n))
                if self.format == Format::Awl && rules::is_event_operand(spec) =>
            {
                self.s7200_event(n)
            }
            (OperandKind::Label, Operand::Label(n))
            | (OperandKind::Literal, Operand::Literal(n)) => Ok(n.to_string()),
            (OperandKind::Block, Operand::Unit(unit)) => Ok(self.unit_name(unit)),
            (OperandKind::Data, operand) => self.data_operand(operand, spec, locals, marks),
            (kind, other) => {
                let what = match kind {
                    OperandKind::Label => "a label",
                    OperandKind::Literal => "a literal",
                    _ => "a program unit",
                };
                Err(format!("{} where {what} belongs", operand_name(&other)))
            }
        }
    }

    fn data_operand(
        &self,
        operand: Operand,
        spec: &OperandSpec,
        locals: &[Local],
        marks: &mut Vec<(usize, usize)>,
    ) -> Result<String, String> {
        let memory = &self.target.memory;
        let want = rules::access_width(spec);
        let width_is = |w: Width| {
            if w == want {
                Ok(())
            } else {
                Err(format!("a {w} access where the instruction takes a {want}"))
            }
        };
        match operand {
            Operand::Value(variable) => {
                width_is(variable.width)?;
                let (address, area) = self.address(variable)?;
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
            Operand::AddressOf { byte, width } => {
                if width != Width::Dword {
                    return Err(format!(
                        "an address (&) read as a {width} (must be a DWORD)"
                    ));
                }
                let (address, _) = self.address(byte)?;
                Ok(format!("&{}", memory.format_address(&address)))
            }
            Operand::Pointer { holder, width } => {
                width_is(width)?;
                let (address, _) = self.address(holder)?;
                Ok(match locals.iter().find(|l| l.address == address) {
                    Some(l) => format!("*#{}", l.name),
                    None => format!("*{}", memory.format_address(&address)),
                })
            }
            other => Err(format!("{} where a variable belongs", operand_name(&other))),
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
