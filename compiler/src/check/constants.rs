//! Constants in operands: where a constant may stand (`Constant` of the operand
//! spec; never where the instruction writes), the range of an integer constant (the
//! spec's Min..Max, else its types'), REAL constants. The constant's place in K is
//! the lowering's business, not this file's.

use gutta_catalog::{rules, DataType, OperandSpec, Width};

use super::operands::types_text;
use super::{CheckedOperand, Checker, ConstValue};
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;

impl Checker<'_> {
    /// A REAL constant: where constants are taken and REAL is one of the types.
    pub(super) fn real_constant(
        &mut self,
        span: Span,
        v: f64,
        spec: &OperandSpec,
        mnemonic: &str,
    ) -> Option<CheckedOperand> {
        if !self.constant_allowed(span, spec, mnemonic) {
            return None;
        }
        if spec.types.contains(&DataType::Real) {
            return Some(CheckedOperand::Constant {
                value: ConstValue::Real(v as f32),
                width: Width::Dword,
            });
        }
        self.report(
            Diagnostic::new(
                Code::RealNotAllowed,
                span,
                format!(
                    "{} of {mnemonic} takes {}, not a REAL constant",
                    spec.name,
                    types_text(&spec.types)
                ),
            )
            .label("has a fraction or exponent"),
        );
        None
    }

    /// Whether a constant may stand here; reports why not.
    fn constant_allowed(&mut self, span: Span, spec: &OperandSpec, mnemonic: &str) -> bool {
        if spec.constant {
            return true;
        }
        if spec.role.writes() {
            self.report(
                Diagnostic::new(
                    Code::WriteToReadOnly,
                    span,
                    format!(
                        "{mnemonic} writes {}; a constant cannot be written",
                        spec.name
                    ),
                )
                .label("constant")
                .help("S7-200 operand order: the destination comes last (`MOVW 5, MW0`)"),
            );
        } else {
            self.report(
                Diagnostic::new(
                    Code::ConstantNotAllowed,
                    span,
                    format!(
                        "{} of {mnemonic} must be a variable, not a constant",
                        spec.name
                    ),
                )
                .label("constant"),
            );
        }
        false
    }

    /// An integer constant: where constants are taken, in range (as a REAL where the
    /// operand is REAL).
    pub(super) fn integer_constant(
        &mut self,
        span: Span,
        v: i64,
        spec: &OperandSpec,
        mnemonic: &str,
    ) -> Option<CheckedOperand> {
        if !self.constant_allowed(span, spec, mnemonic) {
            return None;
        }
        let width = rules::access_width(spec);
        if spec.types.contains(&DataType::Real) {
            return Some(CheckedOperand::Constant {
                value: ConstValue::Real(v as f32),
                width: Width::Dword,
            });
        }
        let (lo, hi) = match (spec.min, spec.max) {
            (Some(lo), Some(hi)) => (lo, hi),
            _ => DataType::union_range(&spec.types).unwrap_or((i64::MAX, i64::MIN)),
        };
        if !(lo..=hi).contains(&v) {
            self.report(
                Diagnostic::new(
                    Code::ConstantOutOfRange,
                    span,
                    format!(
                        "{v} does not fit {} of {mnemonic} ({})",
                        spec.name,
                        types_text(&spec.types)
                    ),
                )
                .label(format!("allowed: {lo}..{hi}")),
            );
            return None;
        }
        Some(CheckedOperand::Constant {
            value: ConstValue::Integer(v),
            width,
        })
    }
}
