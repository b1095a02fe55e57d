//! The live status of a network shown as STL (docs/ladder.md, "Live view"), as TIA's STL
//! status shows it: per line, the logic result (RLO, the top of the logic stack) after
//! its instruction and the operands whose values go beside it. One snapshot, a logic
//! stack over the catalog's instruction kinds (`LadderClass`, `Join`, stack effects),
//! never over mnemonics. Pure: no PLC, no drawing.
//!
//! What a snapshot cannot tell is `None` (`null` in `/state`): an operand without a
//! value, a level below the bottom of the stack, an instruction the catalog does not
//! know. EU and ED pass nothing (a snapshot has no edges, as in `rung_power`); a box
//! passes its RLO to ENO; a timer's or counter's output is its done bit, judged from its
//! current value and preset as `rung_power` judges it.

use gutta_catalog::{DataType, Join, LadderClass, Target, TimerCounterKind, Width};

use super::{done_output, Evaluator, Snapshot};
use crate::model::{Operand, StlInstruction};

/// One STL line's status.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StlLineStatus {
    /// The line's index in `Network::stl` (`data-index`).
    pub index: usize,
    /// The RLO after the line's (last) instruction; `None` when the snapshot cannot tell
    /// or the stack is empty.
    pub rlo: Option<bool>,
    /// The canonical addresses of the line's operands, whose values the line shows.
    pub operands: Vec<String>,
}

/// The status of every line holding an instruction, in line order.
pub fn stl_status(code: &[StlInstruction], snapshot: &Snapshot<'_>) -> Vec<StlLineStatus> {
    let eval = Evaluator { snapshot };
    let mut stack: Vec<Option<bool>> = Vec::new();
    let mut lines: Vec<StlLineStatus> = Vec::new();
    for ins in code {
        step(&eval, snapshot.target, ins, &mut stack);
        let rlo = stack.last().copied().flatten();
        let operands = ins.operands.iter().filter_map(|o| o.address.clone());
        match lines.last_mut() {
            Some(line) if line.index == ins.index => {
                line.rlo = rlo;
                line.operands.extend(operands);
            }
            _ => lines.push(StlLineStatus {
                index: ins.index,
                rlo,
                operands: operands.collect(),
            }),
        }
    }
    lines
}

/// Three-valued AND: false wins over unknown.
fn and(a: Option<bool>, b: Option<bool>) -> Option<bool> {
    match (a, b) {
        (Some(false), _) | (_, Some(false)) => Some(false),
        (Some(true), Some(true)) => Some(true),
        _ => None,
    }
}

/// Three-valued OR: true wins over unknown.
fn or(a: Option<bool>, b: Option<bool>) -> Option<bool> {
    match (a, b) {
        (Some(true), _) | (_, Some(true)) => Some(true),
        (Some(false), Some(false)) => Some(false),
        _ => None,
    }
}

/// The stack after one instruction.
fn step(
    eval: &Evaluator<'_, '_>,
    target: &Target,
    ins: &StlInstruction,
    stack: &mut Vec<Option<bool>>,
) {
    let set = target
        .instructions
        .lookup(&ins.mnemonic)
        .map(|id| target.instructions.get(id));
    let Some(spec) = set else {
        // Unknown: the top is no longer known.
        if let Some(top) = stack.last_mut() {
            *top = None;
        }
        return;
    };
    let top = stack.last().copied().flatten();
    let pop = |stack: &mut Vec<Option<bool>>| stack.pop().flatten();
    match spec.ladder {
        LadderClass::Contact | LadderClass::ClosedContact | LadderClass::Compare => {
            let value = match spec.ladder {
                LadderClass::Compare => compare(eval, spec, &ins.operands),
                LadderClass::ClosedContact => bit(eval, ins.operands.first()).map(|b| !b),
                _ => bit(eval, ins.operands.first()),
            };
            match spec.join() {
                Some(Join::And) => set_top(stack, and(top, value)),
                Some(Join::Or) => set_top(stack, or(top, value)),
                Some(Join::Load) | None => stack.push(value),
            }
        }
        LadderClass::Not => set_top(stack, top.map(|b| !b)),
        LadderClass::RisingEdge | LadderClass::FallingEdge => set_top(stack, Some(false)),
        LadderClass::AndBlock => {
            let b = pop(stack);
            let a = stack.last().copied().flatten();
            set_top(stack, and(a, b));
        }
        LadderClass::OrBlock => {
            let b = pop(stack);
            let a = stack.last().copied().flatten();
            set_top(stack, or(a, b));
        }
        LadderClass::Push => stack.push(top),
        LadderClass::Read => {
            let below = stack.len().checked_sub(2).and_then(|i| stack[i]);
            set_top(stack, below);
        }
        LadderClass::Pop => {
            stack.pop();
        }
        LadderClass::LoadStack => {
            let n: Option<usize> = ins
                .operands
                .first()
                .and_then(|o| o.written.trim().parse().ok());
            let copied = n
                .and_then(|n| stack.len().checked_sub(n + 1))
                .and_then(|i| stack[i]);
            stack.push(copied);
        }
        LadderClass::Coil | LadderClass::SetCoil | LadderClass::ResetCoil => {}
        LadderClass::Box => {
            // The levels the box takes besides its main input go (a counter's R, CD).
            for _ in 0..(-i32::from(spec.stack_delta)).max(0) {
                stack.pop();
            }
            if spec.power_output.is_some() {
                let out = match spec.kind {
                    Some(kind) => counted_done(eval, kind, top, &ins.operands),
                    None => top,
                };
                set_top(stack, out);
            }
        }
    }
}

fn set_top(stack: &mut Vec<Option<bool>>, value: Option<bool>) {
    match stack.last_mut() {
        Some(top) => *top = value,
        None => stack.push(value),
    }
}

fn bit(eval: &Evaluator<'_, '_>, operand: Option<&Operand>) -> Option<bool> {
    operand.and_then(|o| eval.raw(o)).map(|v| v & 1 != 0)
}

/// A compare instruction's relation on its two operands, typed by its first operand's
/// type as the catalog declares it.
fn compare(
    eval: &Evaluator<'_, '_>,
    spec: &gutta_catalog::Instruction,
    operands: &[Operand],
) -> Option<bool> {
    let op = spec.compare?;
    let ty = match spec.operands.first()?.types.first()? {
        DataType::Byte | DataType::Sint | DataType::Usint => 'B',
        DataType::Real => 'R',
        DataType::Dint | DataType::Dword | DataType::Udint => 'D',
        _ => 'W',
    };
    let [a, b, ..] = operands else {
        return None;
    };
    eval.compare_operands(op, ty, a, b)
}

/// A timer's or counter's done bit: its number is the first operand, its preset the
/// second. A timer's with an unknown power in is unknown (a counter's does not depend
/// on it).
fn counted_done(
    eval: &Evaluator<'_, '_>,
    kind: TimerCounterKind,
    power: Option<bool>,
    operands: &[Operand],
) -> Option<bool> {
    let word = |o: Option<&Operand>| {
        o.and_then(|o| eval.number(o, Width::Word))
            .map(|raw| i64::from(raw as u16 as i16))
    };
    let current = word(operands.first());
    let preset = word(operands.get(1));
    current?;
    let power = match power {
        Some(p) => p,
        None if kind.is_timer() => return None,
        None => false,
    };
    Some(done_output(kind, power, current, preset))
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use gutta_catalog::stdlib;
    use gutta_format::SymbolTable;

    use super::*;

    fn ins(index: usize, mnemonic: &str, operands: &[&str]) -> StlInstruction {
        StlInstruction {
            index,
            mnemonic: mnemonic.to_string(),
            operands: operands
                .iter()
                .map(|w| Operand {
                    written: w.to_string(),
                    address: w
                        .chars()
                        .next()
                        .filter(char::is_ascii_alphabetic)
                        .map(|_| w.to_string()),
                    symbol: None,
                    comment: None,
                    data_type: None,
                })
                .collect(),
        }
    }

    /// The RLO of every line of `code` with `values`.
    fn rlos(code: &[StlInstruction], values: &[(&str, u32)]) -> Vec<Option<bool>> {
        let target = stdlib::default_target().expect("stdlib");
        let symbols = SymbolTable::default();
        let values: BTreeMap<String, u32> =
            values.iter().map(|(a, v)| (a.to_string(), *v)).collect();
        let snapshot = Snapshot {
            target: &target,
            symbols: &symbols,
            values: &values,
        };
        stl_status(code, &snapshot)
            .into_iter()
            .map(|l| l.rlo)
            .collect()
    }

    const T: Option<bool> = Some(true);
    const F: Option<bool> = Some(false);

    #[test]
    fn loads_and_combines_follow_their_bits() {
        let code = [
            ins(0, "LD", &["I0.0"]),
            ins(1, "AN", &["I0.1"]),
            ins(2, "O", &["M0.0"]),
            ins(3, "=", &["Q0.0"]),
        ];
        let v = [("I0.0", 1), ("I0.1", 1), ("M0.0", 0), ("Q0.0", 0)];
        assert_eq!(rlos(&code, &v), [T, F, F, F]);
        let v = [("I0.0", 1), ("I0.1", 0), ("M0.0", 0), ("Q0.0", 1)];
        assert_eq!(rlos(&code, &v), [T, T, T, T]);
    }

    #[test]
    fn blocks_and_the_output_stack_combine_levels() {
        // (I0.0 AND I0.1) OR (I0.2 AND I0.3), then LPS/LRD/LPP branches.
        let code = [
            ins(0, "LD", &["I0.0"]),
            ins(1, "A", &["I0.1"]),
            ins(2, "LD", &["I0.2"]),
            ins(3, "A", &["I0.3"]),
            ins(4, "OLD", &[]),
            ins(5, "LPS", &[]),
            ins(6, "A", &["M0.0"]),
            ins(7, "=", &["Q0.0"]),
            ins(8, "LPP", &[]),
            ins(9, "AN", &["M0.0"]),
            ins(10, "=", &["Q0.1"]),
        ];
        let v = [
            ("I0.0", 0),
            ("I0.1", 1),
            ("I0.2", 1),
            ("I0.3", 1),
            ("M0.0", 0),
        ];
        assert_eq!(rlos(&code, &v), [F, F, T, T, T, T, F, F, T, T, T]);
        let code = [
            ins(0, "LD", &["I0.0"]),
            ins(1, "LD", &["I0.1"]),
            ins(2, "O", &["I0.2"]),
            ins(3, "ALD", &[]),
            ins(4, "NOT", &[]),
        ];
        let v = [("I0.0", 1), ("I0.1", 0), ("I0.2", 1)];
        assert_eq!(rlos(&code, &v), [T, F, T, T, F]);
    }

    #[test]
    fn compares_edges_and_boxes() {
        let code = [
            ins(0, "LDW>=", &["MW0", "100"]),
            ins(1, "EU", &[]),
            ins(2, "LDB=", &["MB2", "MB3"]),
            ins(3, "MOVW", &["MW0", "MW4"]),
        ];
        let v = [("MW0", 100), ("MB2", 7), ("MB3", 7), ("MW4", 100)];
        assert_eq!(rlos(&code, &v), [T, F, T, T]);
        // A signed word: 16#FFFF is -1, less than 100.
        let v = [("MW0", 0xFFFF), ("MB2", 7), ("MB3", 8), ("MW4", 0)];
        assert_eq!(rlos(&code, &v), [F, F, F, F]);
    }

    #[test]
    fn what_the_snapshot_cannot_tell_is_none() {
        // I0.5 was not read; ANDed with false it is still false, with true unknown.
        let code = [
            ins(0, "LD", &["I0.5"]),
            ins(1, "A", &["I0.0"]),
            ins(2, "O", &["I0.1"]),
        ];
        assert_eq!(rlos(&code, &[("I0.0", 0), ("I0.1", 0)]), [None, F, F]);
        assert_eq!(rlos(&code, &[("I0.0", 1), ("I0.1", 0)]), [None, None, None]);
        assert_eq!(rlos(&code, &[("I0.0", 1), ("I0.1", 1)]), [None, None, T]);
        // An unknown instruction makes the top unknown.
        let code = [ins(0, "LD", &["I0.0"]), ins(1, "FROB", &[])];
        assert_eq!(rlos(&code, &[("I0.0", 1)]), [T, None]);
    }

    #[test]
    fn a_timer_box_gives_its_done_bit_and_a_line_collects_its_operands() {
        let code = [ins(0, "LD", &["I0.0"]), ins(1, "TON", &["T37", "100"])];
        assert_eq!(rlos(&code, &[("I0.0", 1), ("T37", 100)]), [T, T]);
        assert_eq!(rlos(&code, &[("I0.0", 1), ("T37", 40)]), [T, F]);
        let target = stdlib::default_target().expect("stdlib");
        let symbols = SymbolTable::default();
        let values = BTreeMap::from([("I0.0".to_string(), 1), ("T37".to_string(), 3)]);
        let snapshot = Snapshot {
            target: &target,
            symbols: &symbols,
            values: &values,
        };
        // Two instructions on one line: one status, the last RLO, both operands.
        let code = [ins(0, "LD", &["I0.0"]), ins(0, "TON", &["T37", "100"])];
        assert_eq!(
            stl_status(&code, &snapshot),
            [StlLineStatus {
                index: 0,
                rlo: F,
                operands: vec!["I0.0".into(), "T37".into()],
            }]
        );
    }
}
