//! Constants in operands: where a constant may stand (`Constant` of the operand
//! spec; never where the instruction writes), the range of an integer constant (the
//! spec's Min..Max, else its types'), REAL constants. The constant's place in K is
//! the lowering's business, not this file's.

use gutta_catalog::{rules, DataType, OperandSpec, Width};

use super::memory::width_words;
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
            .label("has a fraction or exponent")
            .help(self.integer_help(spec, mnemonic)),
        );
        None
    }

    /// E0312's help: what an integer operand may be (`PT of TON takes an integer (INT):
    /// a constant such as `20`, a word such as `MW0`, or a symbol declared as one`).
    fn integer_help(&self, spec: &OperandSpec, mnemonic: &str) -> String {
        let width = rules::access_width(spec);
        let variable = self
            .example_place(&rules::DataRules::from_spec(spec), width)
            .map(|at| {
                format!(
                    " {} such as `{at}`, or a symbol declared as one",
                    width_words(width)
                )
            });
        let constant = match (spec.min, spec.max) {
            (Some(lo), Some(hi)) if !(lo..=hi).contains(&20) => lo,
            _ => 20,
        };
        format!(
            "{} of {mnemonic} takes an integer ({}): a constant such as `{constant}`{}",
            spec.name,
            types_text(&spec.types),
            variable.map_or(String::new(), |v| format!(",{v}"))
        )
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
