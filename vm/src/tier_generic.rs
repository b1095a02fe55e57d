//! The compiled tier's steps for instructions the interpreter runs through `ops/`
//! (`Op::Generic`): conversions, shifts, word logic, INC/DEC, ... decoded here from the
//! record's operands into `gutta_jit::Step`s with exactly the semantics of their
//! handler in `ops/` (docs/vm-jit.md, "Generic families compiled"). A record takes a
//! step only when every operand is a plain variable of the width its handler reads
//! and writes (a flat index `check.rs` then bounds), a literal (LDS) or an address
//! (`&VB100` as a MOVx source); a pointer operand, or anything else, keeps it
//! interpreted (None).

use gutta_catalog::Width;
use gutta_format::{Operand, PackedOperand, Pointer};
use gutta_jit::{Combine, Convert, Logic, RealOp, Rel, Shift, Step};

use crate::decode::Unit;
use crate::memory::Memory;
use crate::op::{self, Op};

/// The step of generic record `pc` of `unit`, if the tier compiles it (it then counts
/// 1 instruction and makes no CALL). The target is `unit.target`.
pub(crate) fn generic_step(unit: &Unit, pc: usize, memory: &Memory) -> Option<Step> {
    let (id, _, operands) = unit.instruction(pc)?;
    let Some(Op::Generic { boxed, .. }) = unit.plain_op(pc) else {
        return None;
    };
    let step = decode(unit.mnemonic(id), operands, memory)?;
    // The step runs with the power flow its record has (ManagerFun.xml Flow): a box
    // only with power flow, the others whatever it is.
    (boxed == step.is_box()).then_some(step)
}

/// What a mnemonic with these operands becomes, if anything.
fn decode(mnemonic: &str, operands: &[PackedOperand], memory: &Memory) -> Option<Step> {
    // Operand `k` as a plain variable of `width`: its flat index.
    let var = |k: usize, width: Width| -> Option<u32> {
        match operands.get(k)?.decode().ok()? {
            Operand::Value(a) if a.width == width => {
                memory.index_of(a).and_then(|i| u32::try_from(i).ok())
            }
            _ => None,
        }
    };
    let sized = |letter: u8| match letter {
        b'B' => Some((Width::Byte, 1u8)),
        b'W' => Some((Width::Word, 2)),
        b'D' => Some((Width::Dword, 4)),
        _ => None,
    };
    let last = *mnemonic.as_bytes().last()?;
    let stem = &mnemonic[..mnemonic.len() - 1];
    Some(match mnemonic {
        "ANDB" | "ANDW" | "ANDD" | "ORB" | "ORW" | "ORD" | "XORB" | "XORW" | "XORD" => {
            let (w, width) = sized(last)?;
            Step::Logic {
                op: match stem {
                    "AND" => Logic::And,
                    "OR" => Logic::Or,
                    _ => Logic::Xor,
                },
                src: var(0, w)?,
                dst: var(1, w)?,
                width,
            }
        }
        "INVB" | "INVW" | "INVD" => {
            let (w, width) = sized(last)?;
            Step::Invert {
                at: var(0, w)?,
                width,
            }
        }
        "INCB" | "INCW" | "INCD" | "DECB" | "DECW" | "DECD" => {
            let (w, width) = sized(last)?;
            Step::IncDec {
                at: var(0, w)?,
                width,
                up: stem == "INC",
            }
        }
        "/I" | "/D" => {
            let (w, width) = if last == b'I' {
                (Width::Word, 2)
            } else {
                (Width::Dword, 4)
            };
            Step::Divide {
                src: var(0, w)?,
                dst: var(1, w)?,
                width,
            }
        }
        "MUL" | "DIV" => {
            let (src, dst) = (var(0, Width::Word)?, var(1, Width::Dword)?);
            if mnemonic == "MUL" {
                Step::MulWide { src, dst }
            } else {
                Step::DivWide { src, dst }
            }
        }
        "SRB" | "SRW" | "SRD" | "SLB" | "SLW" | "SLD" | "RRB" | "RRW" | "RRD" | "RLB" | "RLW"
        | "RLD" => {
            let (w, width) = sized(last)?;
            Step::Shift {
                op: match stem {
                    "SR" => Shift::Right,
                    "SL" => Shift::Left,
                    "RR" => Shift::RotateRight,
                    _ => Shift::RotateLeft,
                },
                at: var(0, w)?,
                width,
                count: var(1, Width::Byte)?,
            }
        }
        "BTI" | "ITB" | "ITD" | "DTI" | "DTR" | "ROUND" | "TRUNC" | "BCDI" | "IBCD" | "SEG"
        | "DECO" | "ENCO" => {
            let op = match mnemonic {
                "BTI" => Convert::Bti,
                "ITB" => Convert::Itb,
                "ITD" => Convert::Itd,
                "DTI" => Convert::Dti,
                "DTR" => Convert::Dtr,
                "ROUND" => Convert::Round,
                "TRUNC" => Convert::Trunc,
                "BCDI" => Convert::Bcdi,
                "IBCD" => Convert::Ibcd,
                "SEG" => Convert::Seg,
                "DECO" => Convert::Deco,
                _ => Convert::Enco,
            };
            let (from, to) = op.widths();
            let (from, to) = (sized_width(from)?, sized_width(to)?);
            if matches!(op, Convert::Bcdi | Convert::Ibcd) {
                // OUT is operand 0, read and written in place.
                let at = var(0, from)?;
                Step::Convert {
                    op,
                    src: at,
                    dst: at,
                }
            } else {
                Step::Convert {
                    op,
                    src: var(0, from)?,
                    dst: var(1, to)?,
                }
            }
        }
        "+R" | "-R" | "*R" | "/R" => Step::RealMath {
            op: match mnemonic {
                "+R" => RealOp::Add,
                "-R" => RealOp::Sub,
                "*R" => RealOp::Mul,
                _ => RealOp::Div,
            },
            src: var(0, Width::Dword)?,
            dst: var(1, Width::Dword)?,
        },
        "SQRT" => Step::Sqrt {
            src: var(0, Width::Dword)?,
            dst: var(1, Width::Dword)?,
        },
        "SWAP" => Step::Swap {
            at: var(0, Width::Word)?,
        },
        "MOVB" | "MOVW" | "MOVD" | "MOVR" => {
            // A plain source is the fast path's Move; here only an address source.
            let Operand::AddressOf { byte, .. } = operands.first()?.decode().ok()? else {
                return None;
            };
            let w = match operands.get(1)?.decode().ok()? {
                Operand::Value(a) => a.width,
                _ => return None,
            };
            let width = match w {
                Width::Byte => 1,
                Width::Word => 2,
                Width::Dword => 4,
                Width::Bit => return None,
            };
            Step::Const {
                value: Pointer::to(byte).0,
                dst: var(1, w)?,
                width,
            }
        }
        "LDS" => match operands.first()?.decode().ok()? {
            Operand::Literal(n) => Step::Lds { n },
            _ => return None,
        },
        "NOP" => Step::Nop,
        // The interrupt enable is a byte of the flat memory (`Memory::enable_at`).
        "ENI" | "DISI" if operands.is_empty() => Step::Store {
            at: u32::try_from(memory.enable_at()).ok()?,
            value: u8::from(mnemonic == "ENI"),
        },
        _ => {
            // LDR/AR/OR with a relation (`ops/compare.rs`): the REAL compares.
            let (combine, 'R', rel) = crate::decode::decode_compare(mnemonic)? else {
                return None;
            };
            Step::CompareReal {
                combine: jit_combine(combine),
                rel: jit_rel(rel),
                a: var(0, Width::Dword)?,
                b: var(1, Width::Dword)?,
            }
        }
    })
}

fn sized_width(bytes: u8) -> Option<Width> {
    match bytes {
        1 => Some(Width::Byte),
        2 => Some(Width::Word),
        4 => Some(Width::Dword),
        _ => None,
    }
}

/// The interpreter's combine as gutta-jit's.
pub(crate) fn jit_combine(c: op::Combine) -> Combine {
    match c {
        op::Combine::Load => Combine::Load,
        op::Combine::And => Combine::And,
        op::Combine::Or => Combine::Or,
    }
}

/// The interpreter's relation as gutta-jit's.
pub(crate) fn jit_rel(r: op::Rel) -> Rel {
    match r {
        op::Rel::Eq => Rel::Eq,
        op::Rel::Ne => Rel::Ne,
        op::Rel::Lt => Rel::Lt,
        op::Rel::Le => Rel::Le,
        op::Rel::Gt => Rel::Gt,
        op::Rel::Ge => Rel::Ge,
    }
}
