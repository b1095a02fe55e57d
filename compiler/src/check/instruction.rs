//! One instruction against its entry in the instruction set: the operand count, each
//! operand against its spec (`operands.rs`), jump targets in the same unit, CALL
//! arguments (`calls.rs`), and the double-coil and timer-reuse warnings.

use std::collections::BTreeMap;

use gutta_catalog::{
    AreaKind, BlockKind, Flow, InstrId, Instruction, LadderClass, OperandSpec, Role, Width,
};

use super::calls::CallSite;
use super::code::CodeContext;
use super::{CheckedInstruction, CheckedOperand, Checker, Use};
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
use crate::syntax::ast::{Operand, OperandKind};

impl Checker<'_> {
    /// One instruction's operands against its operand specs (count, each operand,
    /// jump targets, CALL arguments); `None` when any is refused.
    pub(super) fn instruction(
        &mut self,
        ui: usize,
        id: InstrId,
        mnemonic_span: Span,
        ops: &[Operand],
        span: Span,
        cx: &mut CodeContext,
    ) -> Option<CheckedInstruction> {
        // Borrowed from the target, not from `self` (no clone per instruction).
        let target = self.target;
        let spec = target.instructions.get(id);
        if !self.operand_count(spec, ops, mnemonic_span) {
            return None;
        }
        let mut out = Vec::with_capacity(ops.len());
        let mut ok = true;
        for (op, os) in ops.iter().zip(&spec.operands) {
            match self.operand(ui, op, os, &spec.mnemonic) {
                Some(c) => {
                    if let CheckedOperand::Label(n) = c {
                        if spec.flow != Flow::Always && !cx.labels[ui].contains_key(&n) {
                            self.missing_label(ui, n, op.span, &cx.labels);
                            ok = false;
                        }
                    }
                    self.warnings(spec, os, &c, op.span, cx);
                    out.push(c);
                }
                None => {
                    ok = false;
                    if let OperandKind::Real(v) = op.kind {
                        self.timer_unit_note(&out, v, op.span);
                    }
                }
            }
        }
        if spec.call_arguments {
            let callee_span = ops.first().map_or(mnemonic_span, |o| o.span);
            let args = ops.get(spec.operands.len()..).unwrap_or_default();
            match self.call(ui, &out, args, callee_span, cx) {
                Some(args) => out.extend(args),
                None => ok = false,
            }
        }
        ok.then_some(CheckedInstruction {
            id,
            operands: out,
            span,
        })
    }

    /// The record has the instruction's operands (at least, before CALL arguments).
    fn operand_count(&mut self, spec: &Instruction, ops: &[Operand], mnemonic_span: Span) -> bool {
        let fixed = spec.operands.len();
        let count_ok = if spec.call_arguments {
            ops.len() >= fixed
        } else {
            ops.len() == fixed
        };
        if count_ok {
            return true;
        }
        let names: Vec<&str> = spec.operands.iter().map(|o| o.name.as_str()).collect();
        let want = if names.is_empty() {
            "no operands".to_string()
        } else {
            format!(
                "{} operand{} ({})",
                fixed,
                if fixed == 1 { "" } else { "s" },
                names.join(", ")
            )
        };
        let at = match (ops.first(), ops.last()) {
            (Some(first), Some(last)) => first.span.to(last.span),
            _ => mnemonic_span,
        };
        self.report(
            Diagnostic::new(
                Code::OperandCount,
                at,
                format!("`{}` takes {want}, found {}", spec.mnemonic, ops.len()),
            )
            .help(example_use(spec).unwrap_or_else(|| spec.summary.clone())),
        );
        false
    }

    /// E0312 on a timer's preset (`TON T4, 2.5`): a second help line with the timer's
    /// unit on this target (its `<Timers>` row) and, read as seconds, the preset that
    /// means the time written (`T4 counts in 100 ms units on CPU-EC20: 25 for 2.5 s`).
    fn timer_unit_note(&mut self, before: &[CheckedOperand], seconds: f64, span: Span) {
        let memory = &self.target.memory;
        let Some((timer, ms)) = before.iter().find_map(|c| match c {
            CheckedOperand::Memory { address, .. } => {
                let area = memory.area_by_slot(address.slot)?;
                if area.kind != AreaKind::Timer {
                    return None;
                }
                let ms = memory.timer_resolution(address.offset / area.unit.bytes())?;
                Some((memory.format_address(address), ms))
            }
            _ => None,
        }) else {
            return;
        };
        let units = seconds * 1000.0 / f64::from(ms);
        let mut note = format!("{timer} counts in {ms} ms units on {}", self.target.name());
        if units.fract() == 0.0 && (1.0..=32767.0).contains(&units) {
            note.push_str(&format!(": {units} for {} s", self.slice(span)));
        }
        let Some(d) = self
            .diags
            .iter_mut()
            .rev()
            .find(|d| d.code == Code::RealNotAllowed && d.primary.span == span)
        else {
            return;
        };
        d.help = Some(match d.help.take() {
            Some(h) => format!("{h}\n{note}"),
            None => note,
        });
    }

    /// A CALL of the subroutine its first checked operand names: a call-graph edge and
    /// the checked arguments; `None` when the callee or an argument is refused.
    fn call(
        &mut self,
        ui: usize,
        checked: &[CheckedOperand],
        args: &[Operand],
        callee_span: Span,
        cx: &mut CodeContext,
    ) -> Option<Vec<CheckedOperand>> {
        let Some(CheckedOperand::Unit {
            kind: BlockKind::Subroutine,
            number,
        }) = checked.first()
        else {
            return None;
        };
        let callee = self
            .units
            .iter()
            .position(|u| u.kind == BlockKind::Subroutine && u.number == *number)?;
        cx.calls.push(CallSite {
            caller: ui,
            callee,
            span: callee_span,
        });
        self.call_arguments(ui, callee, args, callee_span)
    }

    /// A jump to a label its unit does not have (perhaps another unit has it).
    fn missing_label(&mut self, ui: usize, n: u16, span: Span, labels: &[BTreeMap<u16, Span>]) {
        let elsewhere = labels
            .iter()
            .enumerate()
            .find(|(i, l)| *i != ui && l.contains_key(&n))
            .map(|(i, _)| i);
        let d = match elsewhere {
            Some(other) => {
                let name = self.units[other].name.clone();
                let at = labels[other][&n];
                Diagnostic::new(
                    Code::JumpAcrossBlocks,
                    span,
                    format!("label {n} is in {name}, not in this block"),
                )
                .with_secondary(at, "defined here")
                .help("jumps stay inside their block; CALL a subroutine instead")
            }
            None => Diagnostic::new(
                Code::UndefinedLabel,
                span,
                format!("no `LBL {n}` in this block"),
            )
            .label("jump target missing"),
        };
        self.report(d);
    }

    /// W-codes: a bit assigned with `=` twice, a timer or counter driven twice.
    fn warnings(
        &mut self,
        instruction: &Instruction,
        spec: &OperandSpec,
        c: &CheckedOperand,
        span: Span,
        cx: &mut CodeContext,
    ) {
        let CheckedOperand::Memory {
            address,
            use_: Use::Value,
            ..
        } = *c
        else {
            return;
        };
        let plain_coil = instruction.ladder == LadderClass::Coil && !instruction.immediate;
        // Micro/WIN's temporaries (`l_temporaries.rs`) are meant to be assigned anew in
        // every network that uses them.
        let temporary = self.l_temporary_uses.contains(&span);
        if plain_coil && address.width == Width::Bit && !temporary {
            let key = (address.slot, address.offset, address.bit);
            if let Some(first) = cx.coils.insert(key, span) {
                self.report(
                    Diagnostic::new(
                        Code::DoubleCoil,
                        span,
                        format!("`{}` is also assigned with `=` elsewhere", self.slice(span)),
                    )
                    .with_secondary(first, "first assignment"),
                );
            }
        }
        let timer_like =
            spec.role == Role::InOut && spec.areas.as_ref().is_some_and(|a| a.len() == 1);
        if timer_like {
            let key = (address.slot, address.offset);
            if let Some(first) = cx.timers.insert(key, span) {
                self.report(
                    Diagnostic::new(
                        Code::TimerReused,
                        span,
                        format!("`{}` is driven by two instructions", self.slice(span)),
                    )
                    .with_secondary(first, "also driven here"),
                );
            }
        }
    }
}

/// The help of E0301: the line of the instruction's example that uses the instruction
/// itself (not the `LD` before it), as `for example `TON T4, 20` (2 s with a 100 ms
/// timer)`: the mnemonic and its operands one blank apart, the line's comment in
/// parentheses. None when no example line starts with the mnemonic.
fn example_use(spec: &Instruction) -> Option<String> {
    spec.example.lines().find_map(|line| {
        let (code, comment) = match line.split_once("//") {
            Some((code, comment)) => (code.trim(), Some(comment.trim())),
            None => (line.trim(), None),
        };
        let (first, operands) = code
            .split_once(char::is_whitespace)
            .map_or((code, ""), |(m, rest)| (m, rest.trim()));
        if !first.eq_ignore_ascii_case(&spec.mnemonic) {
            return None;
        }
        let shown = if operands.is_empty() {
            first.to_string()
        } else {
            format!("{first} {operands}")
        };
        Some(match comment.filter(|c| !c.is_empty()) {
            Some(c) => format!("for example `{shown}` ({c})"),
            None => format!("for example `{shown}`"),
        })
    })
}

#[cfg(test)]
mod tests {
    use super::example_use;

    #[test]
    fn the_example_shown_uses_the_instruction_itself() {
        let target = gutta_catalog::stdlib::default_target().expect("stdlib");
        let ton = target
            .instructions
            .by_kind(gutta_catalog::TimerCounterKind::OnDelay)
            .expect("an on-delay timer");
        assert_eq!(
            example_use(target.instructions.get(ton)).as_deref(),
            Some("for example `TON T4, 20` (2 s with a 100 ms timer)")
        );
        // Every instruction's example has a line that uses it: the help never falls
        // back to the summary for the stdlib set.
        for spec in &target.instructions.instructions {
            let help = example_use(spec).unwrap_or_default();
            assert!(
                help.starts_with(&format!("for example `{}", spec.mnemonic)),
                "{}: {help:?}",
                spec.mnemonic
            );
        }
    }
}
