//! The live view's power flow (docs/ladder.md, "Live view"): which elements of a rung
//! pass power out, given one snapshot of its operands' raw values, and which operands a
//! ladder needs read. Pure: the values come in as a map, nothing here talks to a PLC.
//!
//! A snapshot cannot see what happened between two scans, so edges (`EU`, `ED`) never
//! pass power, and a timer or counter's done output is judged from its current value and
//! preset only (the rules are on each function below).

use std::collections::{BTreeMap, BTreeSet};

use gutta_catalog::{CompareOp, Target, TimerCounterKind, Width};
use gutta_format::SymbolTable;

use crate::model::{BoxElement, Branch, BranchEnd, Contact, ContactKind, Ladder, Node, Operand};

/// One snapshot: raw values by canonical address (as `Operand::address` spells it),
/// already cut to the address's width (a bit is 0 or 1).
#[derive(Debug)]
pub struct Snapshot<'a> {
    pub target: &'a Target,
    /// Names a timer or counter box's title may use (its number is its title, not a pin).
    pub symbols: &'a SymbolTable,
    pub values: &'a BTreeMap<String, u32>,
}

/// The power of one rung in a snapshot.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct RungPower {
    /// The ids of the elements that pass power out: contacts whose output is on, coils
    /// that are powered, boxes whose power output (ENO, Q) is on, and boxes without a
    /// power output (`JMP`, `CALL` at a branch end) whose input is powered. A wire is on
    /// when `rail` or one of these powers it (its `data-after`).
    pub energized: BTreeSet<u32>,
}

/// The power of `rung` in `snapshot`. An operand missing from the snapshot, or a constant
/// that does not parse, counts as 0.
pub fn rung_power(rung: &crate::model::Rung, snapshot: &Snapshot<'_>) -> RungPower {
    let mut power = RungPower::default();
    let eval = Evaluator { snapshot };
    let at_outputs = match &rung.input {
        Some(node) => eval.node(node, true, &mut power.energized),
        None => true,
    };
    for branch in &rung.outputs {
        eval.branch(branch, at_outputs, &mut power.energized);
    }
    power
}

pub(crate) struct Evaluator<'a, 's> {
    pub(crate) snapshot: &'a Snapshot<'s>,
}

impl Evaluator<'_, '_> {
    /// The power out of `node` with `power` in; records what passes power.
    fn node(&self, node: &Node, power: bool, on: &mut BTreeSet<u32>) -> bool {
        let out = match node {
            Node::Contact(c) => {
                let out = self.contact(c, power);
                if out {
                    on.insert(c.id);
                }
                out
            }
            Node::Box(b) => self.boxed(b, power, on),
            Node::Series(nodes) => nodes.iter().fold(power, |p, n| self.node(n, p, on)),
            // Every branch is evaluated (each lights its own elements); the block passes
            // power when any branch does.
            Node::Parallel(nodes) => nodes
                .iter()
                .map(|n| self.node(n, power, on))
                .fold(false, |a, b| a | b),
        };
        out
    }

    fn branch(&self, branch: &Branch, power: bool, on: &mut BTreeSet<u32>) {
        let power = branch.path.iter().fold(power, |p, n| self.node(n, p, on));
        match &branch.end {
            BranchEnd::Coil(c) => {
                if power {
                    on.insert(c.id);
                }
            }
            BranchEnd::Box(b) => {
                self.boxed(b, power, on);
            }
            BranchEnd::Split(branches) => {
                for b in branches {
                    self.branch(b, power, on);
                }
            }
        }
    }

    /// A contact's output: NO and NC test their bit, a compare its relation, NOT inverts
    /// its input, EU/ED pass nothing (a snapshot has no edges).
    fn contact(&self, c: &Contact, power: bool) -> bool {
        match c.kind {
            ContactKind::NormallyOpen => power && self.bit(c.operands.first()),
            ContactKind::NormallyClosed => power && !self.bit(c.operands.first()),
            ContactKind::Not => !power,
            ContactKind::PositiveEdge | ContactKind::NegativeEdge => false,
            ContactKind::Compare => power && self.compare(c),
        }
    }

    pub(crate) fn bit(&self, operand: Option<&Operand>) -> bool {
        operand.and_then(|o| self.raw(o)).unwrap_or(0) & 1 != 0
    }

    /// `>=W`, `=B`, `<>D`, `<R`: B unsigned, W and D signed, R a REAL, as the VM compares.
    pub(crate) fn compare(&self, c: &Contact) -> bool {
        let (Some(relation), [a, b, ..]) = (&c.relation, c.operands.as_slice()) else {
            return false;
        };
        let ty = relation.chars().last().unwrap_or('W');
        let op = &relation[..relation.len() - ty.len_utf8()];
        let op = CompareOp::from_symbol(op).unwrap_or(CompareOp::Ge);
        self.compare_operands(op, ty, a, b).unwrap_or(false)
    }

    /// `a op b` compared as the type letter says (`B`, `W`, `D`, `R`); `None` when an
    /// operand has no value.
    pub(crate) fn compare_operands(
        &self,
        op: CompareOp,
        ty: char,
        a: &Operand,
        b: &Operand,
    ) -> Option<bool> {
        let holds = |o: std::cmp::Ordering| op.holds(o);
        let width = match ty {
            'B' => Width::Byte,
            'D' | 'R' => Width::Dword,
            _ => Width::Word,
        };
        let (x, y) = (self.number(a, width)?, self.number(b, width)?);
        Some(match ty {
            'B' => holds((x as u8).cmp(&(y as u8))),
            'R' => f32::from_bits(x)
                .partial_cmp(&f32::from_bits(y))
                .is_some_and(holds),
            'D' => holds((x as i32).cmp(&(y as i32))),
            _ => holds((x as i16).cmp(&(y as i16))),
        })
    }

    /// A box's power output with `power` at EN (IN, CU). Its extra power inputs (R, LD,
    /// CD) are evaluated for their own elements; they do not change the done output,
    /// which the current value already shows.
    fn boxed(&self, b: &BoxElement, power: bool, on: &mut BTreeSet<u32>) -> bool {
        for (_, path) in &b.power_inputs {
            self.node(path, true, on);
        }
        let out = match (&b.output, timer_counter_kind(b, self.snapshot.target)) {
            (Some(_), Some(kind)) => self.done(b, kind, power),
            _ => power,
        };
        if out {
            on.insert(b.id);
        }
        out && b.output.is_some()
    }

    /// A timer's or counter's done output, from its current value (the box's title) and
    /// its preset (the first pin): TON `IN && T >= PT` (or PT <= 0), TONR `T >= PT`, TOF
    /// `IN || 0 < T < PT`, CTU and CTUD `C >= PV`, CTD `C == 0`.
    fn done(&self, b: &BoxElement, kind: TimerCounterKind, power: bool) -> bool {
        let current = counted_address(b, self.snapshot.target, self.snapshot.symbols)
            .and_then(|a| self.snapshot.values.get(&a).copied())
            .map(|raw| i64::from(raw as u16 as i16));
        let preset = b
            .pins
            .first()
            .and_then(|p| self.number(&p.operand, Width::Word))
            .map(|raw| i64::from(raw as u16 as i16));
        done_output(kind, power, current, preset)
    }

    /// The raw value of an operand with an address.
    pub(crate) fn raw(&self, o: &Operand) -> Option<u32> {
        self.snapshot.values.get(o.address.as_ref()?).copied()
    }

    /// An operand's raw bits: its read value, else a constant as written (`100`, `-3`,
    /// `16#FF`, `2#101`, `1.5` as a REAL), cut to `width`.
    pub(crate) fn number(&self, o: &Operand, width: Width) -> Option<u32> {
        if o.address.is_some() {
            return self.raw(o);
        }
        let raw = constant(&o.written)?;
        Some(match width {
            Width::Bit => raw & 1,
            Width::Byte => raw & 0xFF,
            Width::Word => raw & 0xFFFF,
            Width::Dword => raw,
        })
    }
}

/// A timer's or counter's done output from its power in, its current value and its
/// preset (both signed words): TON `IN && T >= PT` (or PT <= 0), TONR `T >= PT`, TOF
/// `IN || 0 < T < PT`, CTU and CTUD `C >= PV`, CTD `C == 0`; without a value or a
/// preset only TOF's `IN` is known.
pub(crate) fn done_output(
    kind: TimerCounterKind,
    power: bool,
    current: Option<i64>,
    preset: Option<i64>,
) -> bool {
    let (Some(value), Some(preset)) = (current, preset) else {
        return kind == TimerCounterKind::OffDelay && power;
    };
    match kind {
        TimerCounterKind::OnDelay => power && (preset <= 0 || value >= preset),
        TimerCounterKind::RetentiveOnDelay => value >= preset,
        TimerCounterKind::OffDelay => power || (0 < value && value < preset),
        TimerCounterKind::CountDown => value == 0,
        TimerCounterKind::CountUp | TimerCounterKind::CountUpDown => value >= preset,
    }
}

/// A literal's 32 bits: decimal (signed), `16#`, `8#`, `2#` radix forms, a REAL with a
/// dot or an exponent.
fn constant(text: &str) -> Option<u32> {
    let t = text.trim().replace('_', "");
    for (prefix, radix) in [("16#", 16), ("8#", 8), ("2#", 2)] {
        if let Some(digits) = t.strip_prefix(prefix) {
            return u32::from_str_radix(digits, radix).ok();
        }
    }
    if let Ok(n) = t.parse::<i64>() {
        return Some(n as u32);
    }
    if t.contains(['.', 'e', 'E']) {
        return t.parse::<f32>().ok().map(f32::to_bits);
    }
    None
}

/// The timer or counter a box is, as the catalog says of its instruction.
fn timer_counter_kind(b: &BoxElement, target: &Target) -> Option<TimerCounterKind> {
    let id = target.instructions.lookup(&b.mnemonic)?;
    target.instructions.get(id).kind
}

/// The canonical address of a timer's or counter's number (its title: `T37`, or a
/// symbol naming it).
pub fn counted_address(b: &BoxElement, target: &Target, symbols: &SymbolTable) -> Option<String> {
    timer_counter_kind(b, target)?;
    let title = b.title.trim();
    let address = match symbols.get(title) {
        Some(s) => target.memory.parse_address(&s.address).ok()?,
        None => target.memory.parse_address(title).ok()?,
    };
    Some(target.memory.format_address(&address))
}

/// Every readable operand of the drawn networks, deduplicated, in drawing order:
/// contacts' and coils' bits, compare operands, box pins with an address, the timers'
/// and counters' numbers, and every addressed operand of a network shown as STL.
pub fn operands(ladder: &Ladder, target: &Target, symbols: &SymbolTable) -> Vec<String> {
    let mut seen = BTreeSet::new();
    let mut out = Vec::new();
    let mut add = |a: &str| {
        if seen.insert(a.to_string()) {
            out.push(a.to_string());
        }
    };
    for network in ladder.blocks.iter().flat_map(|b| &b.networks) {
        for ins in &network.stl_code {
            ins.operands
                .iter()
                .filter_map(|o| o.address.as_deref())
                .for_each(&mut add);
        }
        if let crate::model::Body::Rung(rung) = &network.body {
            let mut visit = OperandVisitor {
                target,
                symbols,
                add: &mut add,
            };
            if let Some(node) = &rung.input {
                visit.node(node);
            }
            for b in &rung.outputs {
                visit.branch(b);
            }
        }
    }
    out
}

struct OperandVisitor<'a, F: FnMut(&str)> {
    target: &'a Target,
    symbols: &'a SymbolTable,
    add: &'a mut F,
}

impl<F: FnMut(&str)> OperandVisitor<'_, F> {
    fn operand(&mut self, o: &Operand) {
        if let Some(a) = &o.address {
            (self.add)(a);
        }
    }

    fn node(&mut self, node: &Node) {
        match node {
            Node::Contact(c) => c.operands.iter().for_each(|o| self.operand(o)),
            Node::Box(b) => self.boxed(b),
            Node::Series(nodes) | Node::Parallel(nodes) => nodes.iter().for_each(|n| self.node(n)),
        }
    }

    fn boxed(&mut self, b: &BoxElement) {
        for (_, path) in &b.power_inputs {
            self.node(path);
        }
        if let Some(a) = counted_address(b, self.target, self.symbols) {
            (self.add)(&a);
        }
        b.pins.iter().for_each(|p| self.operand(&p.operand));
    }

    fn branch(&mut self, branch: &Branch) {
        branch.path.iter().for_each(|n| self.node(n));
        match &branch.end {
            BranchEnd::Coil(c) => {
                self.operand(&c.operand);
                if let Some(n) = &c.count {
                    self.operand(n);
                }
            }
            BranchEnd::Box(b) => self.boxed(b),
            BranchEnd::Split(branches) => branches.iter().for_each(|b| self.branch(b)),
        }
    }
}

mod stl;
pub use stl::{stl_status, StlLineStatus};

#[cfg(test)]
mod tests;
