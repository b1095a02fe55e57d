//! Lines that use a timer's or counter's bit (`LD T37`, `R T37, 1`), where an earlier
//! stage asks for them (`Conventions::timer_bit_lines`, by instruction: in a Micro/WIN
//! export). GUTTA's T and C areas hold only current values, so such a line has no
//! instruction of its own here: the checker resolves its timer or counter, leaves a
//! placeholder instruction where it stood and records it ([`BitUse`]), with every timer
//! and counter box that checked ([`TimerBox`]). That stage's pass after checking
//! (`crate::microwin`, "Timer and counter bits") gives each placeholder its
//! instructions. The checker reports nothing here: what such a line means, and every
//! refusal, is that pass's.

use gutta_catalog::{Address, AreaKind, InstrId, Join};

use super::names::Variable;
use super::Checker;
use crate::source::Span;
use crate::syntax::ast::{Operand, OperandKind, Prefix};

/// What a line does with a timer's or counter's bit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BitOp {
    /// `LD`/`A`/`O` (how the compare that replaces it joins the logic stack), negated
    /// for `LDN`/`AN`/`ON`.
    Read { join: Join, negated: bool },
    /// `R T37, count` (the count is the line's).
    Reset { count: u32 },
    /// `S T37, count`, which has no counterpart on GUTTA.
    Set { count: u32 },
}

/// A timer or counter bit used on a line; its placeholder instruction is at
/// `units[unit].networks[network].instructions[index]` of the checked program.
#[derive(Debug, Clone)]
pub struct BitUse {
    pub unit: usize,
    pub network: usize,
    pub index: usize,
    pub op: BitOp,
    /// The first (or only) timer or counter, as a word address.
    pub address: Address,
    /// The operand naming it, the name in it, the operands as a whole, and the line.
    pub operand: Span,
    pub name: Span,
    pub operands: Span,
    pub span: Span,
}

/// A timer or counter instruction (`TON T37, 100`) that checked, at
/// `units[unit].networks[network].instructions[index]`.
#[derive(Debug, Clone)]
pub struct TimerBox {
    pub unit: usize,
    pub network: usize,
    pub index: usize,
    /// Logic stack levels before it, when known.
    pub depth: Option<i32>,
    pub preset: Span,
    pub span: Span,
}

/// Every bit line and timer box of the program, in the order they were checked.
#[derive(Debug, Clone, Default)]
pub struct BitLines {
    pub uses: Vec<BitUse>,
    pub boxes: Vec<TimerBox>,
}

impl BitLines {
    /// After the checked units were sorted: `position[old]` is a unit's new index.
    pub(super) fn renumber_units(&mut self, position: &[usize]) {
        for u in &mut self.uses {
            u.unit = position[u.unit];
        }
        for b in &mut self.boxes {
            b.unit = position[b.unit];
        }
    }
}

impl Checker<'_> {
    /// The line as a bit use when it uses a timer's or counter's bit, `at` being where its
    /// placeholder goes (unit, network, instruction index); `None` when it does not (the
    /// ordinary check goes on).
    pub(super) fn bit_line(
        &mut self,
        at: (usize, usize, usize),
        id: InstrId,
        ops: &[Operand],
        span: Span,
    ) -> Option<BitUse> {
        let op = *self.conventions.timer_bit_lines.as_ref()?.get(&id)?;
        let (ui, network, index) = at;
        let first = ops.first()?;
        let OperandKind::Name {
            prefix: Prefix::None,
            local: false,
            name,
        } = first.kind
        else {
            return None;
        };
        self.peek_timer_or_counter(name)?;
        let Variable { address, .. } = self.variable(ui, false, name)?;
        let op = match op {
            BitOp::Reset { .. } | BitOp::Set { .. } => {
                let count = match ops.get(1).map(|o| o.kind) {
                    Some(OperandKind::Integer(n)) if ops.len() == 2 && (1..=255).contains(&n) => {
                        n as u32
                    }
                    _ => return None,
                };
                match op {
                    BitOp::Set { .. } => BitOp::Set { count },
                    _ => BitOp::Reset { count },
                }
            }
            read => {
                if ops.len() != 1 {
                    return None;
                }
                read
            }
        };
        Some(BitUse {
            unit: ui,
            network,
            index,
            op,
            address,
            operand: first.span,
            name,
            operands: ops.last().map_or(first.span, |l| first.span.to(l.span)),
            span,
        })
    }

    /// The word address a name stands for when it is a timer or counter of the target
    /// (a symbol or a direct address), without reporting anything.
    fn peek_timer_or_counter(&self, name: Span) -> Option<Address> {
        let text = self.slice(name);
        let address = match self.symbols.get(&text.to_ascii_uppercase()) {
            Some(&(a, _)) => a,
            None if self.looks_like_address(text) => self.target.memory.parse_address(text).ok()?,
            None => return None,
        };
        let area = self.target.memory.area_by_slot(address.slot)?;
        matches!(area.kind, AreaKind::Timer | AreaKind::Counter).then_some(address)
    }
}
