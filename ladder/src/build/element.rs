//! One STL instruction as a ladder element (docs/ladder.md, "Which networks are
//! ladder"): what it does to the power path (a contact loaded, in series or in
//! parallel; a stack operation; a coil or a box) and the element as drawn, its operands
//! resolved through the program's symbols and the target's address syntax. Knows
//! nothing of the logic stack: `rung.rs` places the elements.

use std::collections::HashMap;

use gutta_catalog::{Flow, Instruction};
use gutta_compiler::syntax::ast::{self, OperandKind, Prefix, VarSection};
use gutta_compiler::CheckedFile;
use gutta_format::SymbolTable;

use crate::model::{BoxElement, Coil, CoilKind, Contact, ContactKind, Operand, Pin};

/// How a contact joins the power path on top of the logic stack.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Join {
    /// `LD...`: a new path from the left rail.
    Load,
    /// `A...`, `NOT`, `EU`, `ED`: in series with the top.
    Series,
    /// `O...`: in parallel with the top.
    Parallel,
}

/// A logic stack instruction without an element of its own.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum StackOp {
    Ald,
    Old,
    Lps,
    Lrd,
    Lpp,
    /// `LDS n`.
    Lds(i64),
}

/// What an instruction is in a rung.
#[derive(Debug, Clone)]
pub(super) enum Element {
    Contact(Join, Contact),
    Stack(StackOp),
    /// Ends a branch: a coil.
    Coil(Coil),
    /// A box whose power output continues the path (`MOVW`, `CALL`, a GUTTA timer).
    SeriesBox(BoxElement),
    /// A box that ends the branch and leaves the power where it was (`JMP`, `FOR`, an
    /// S7-200 timer of a Micro/WIN export).
    EndBox(BoxElement),
    /// A counter: its inputs besides the main one are the lower levels of the stack,
    /// named by `power_inputs` (deepest first), taken by `rung.rs`.
    Counter(BoxElement, &'static [&'static str]),
    /// Runs without power flow (`LBL`, `NEXT`, `RET`): only alone in a network.
    Always(BoxElement),
    /// No ladder drawing (an instruction of a kind this builder does not know).
    Unknown,
}

/// A counter's main power input, its further inputs (lower stack levels, deepest
/// first) and its output: the stack order of docs/instructions.md ("Timer and
/// counter"), as `vm/src/ops/timers.rs` pops them.
const COUNTERS: [(&str, &str, &[&str]); 3] = [
    ("CTU", "CU", &["R"]),
    ("CTD", "CD", &["LD"]),
    ("CTUD", "CU", &["CD", "R"]),
];

/// Box-flow instructions that end the power path: nothing is drawn after them.
const ENDING_BOXES: [&str; 6] = ["JMP", "FOR", "END", "STOP", "CRET", "CRETI"];

/// What the builder reads of the program besides one instruction.
pub(super) struct Resolver<'a> {
    checked: &'a CheckedFile,
    symbols: SymbolTable,
    /// Subroutine name (and numbered name), upper case -> its name and its parameters
    /// in call order (name, drawn as an output pin).
    subroutines: HashMap<String, (String, Vec<(String, bool)>)>,
}

impl<'a> Resolver<'a> {
    pub(super) fn new(checked: &'a CheckedFile) -> Resolver<'a> {
        let text = &checked.file.text;
        let slice = |s: gutta_compiler::source::Span| text.get(s.range()).unwrap_or("");
        let mut subroutines = HashMap::new();
        for unit in &checked.ast.units {
            let mut params: Vec<&ast::VarDecl> = unit
                .vars
                .iter()
                .filter(|v| v.section != VarSection::Temp)
                .collect();
            // Arguments follow the sections' order (VAR_INPUT, VAR_IN_OUT, VAR_OUTPUT).
            params.sort_by_key(|v| v.section);
            let pins: Vec<(String, bool)> = params
                .iter()
                .map(|v| (slice(v.name).to_string(), v.section == VarSection::Output))
                .collect();
            let name = slice(unit.header.name).trim().to_string();
            if let Some((_, span)) = unit.header.number {
                subroutines.insert(
                    slice(span).trim().to_ascii_uppercase(),
                    (name.clone(), pins.clone()),
                );
            }
            subroutines.insert(name.to_ascii_uppercase(), (name, pins));
        }
        Resolver {
            checked,
            symbols: checked.symbols(),
            subroutines,
        }
    }

    fn text(&self, span: gutta_compiler::source::Span) -> &'a str {
        self.checked.file.slice(span)
    }

    /// 1-based line of `offset` in its file.
    pub(super) fn line(&self, offset: u32) -> u32 {
        self.checked
            .file
            .locate(&self.checked.index, offset as usize)
            .line
    }

    /// An operand as drawn: as written, its canonical address and its symbol.
    pub(super) fn operand(&self, op: &ast::Operand) -> Operand {
        let written = self.text(op.span).trim().to_string();
        let (address, symbol) = match op.kind {
            OperandKind::Name {
                prefix: Prefix::None,
                local: false,
                name,
            } => self.address_of(self.text(name)),
            _ => (None, None),
        };
        Operand {
            written,
            address,
            symbol,
        }
    }

    /// A name's canonical address: a symbol's, in a Micro/WIN export a system
    /// symbol's (`Always_On`; user symbols win, as in the checker), or a direct address
    /// normalised.
    fn address_of(&self, name: &str) -> (Option<String>, Option<String>) {
        if let Some(symbol) = self.symbols.get(name) {
            return (Some(symbol.address.clone()), Some(symbol.name.clone()));
        }
        let memory = &self.checked.target.memory;
        if self.checked.microwin.is_some() {
            if let Some(bit) = memory.microwin_system_bit(name) {
                let address = memory.parse_address(&bit.address).ok();
                let symbol = bit.microwin.clone();
                return (address.map(|a| memory.format_address(&a)), symbol);
            }
        }
        match memory.parse_address(name) {
            Ok(address) => (Some(memory.format_address(&address)), None),
            Err(_) => (None, None),
        }
    }

    /// The element of one instruction of a network; `None` for an unknown mnemonic.
    pub(super) fn element(&self, net: &ast::Network, ins: &ast::Instruction) -> Option<Element> {
        let target = &self.checked.target;
        let id = target.instructions.lookup(self.text(ins.mnemonic).trim())?;
        let spec = target.instructions.get(id);
        let ops: Vec<Operand> = net
            .operands_of(ins)
            .iter()
            .map(|o| self.operand(o))
            .collect();
        let line = self.line(ins.span.start);
        let m = spec.mnemonic.as_str();
        Some(match spec.flow {
            Flow::Load | Flow::Combine => {
                let join = match (spec.flow, m.as_bytes().first()) {
                    (Flow::Load, _) => Join::Load,
                    (_, Some(b'O')) => Join::Parallel,
                    _ => Join::Series,
                };
                Element::Contact(join, contact(spec, ops, line))
            }
            Flow::Stack => self.stack_element(spec, ops, line),
            Flow::Output => match coil_kind(m) {
                Some(kind) => {
                    let mut ops = ops.into_iter();
                    let Some(operand) = ops.next() else {
                        return Some(Element::Unknown);
                    };
                    Element::Coil(Coil {
                        id: 0,
                        kind,
                        mnemonic: m.to_string(),
                        operand,
                        count: ops.next(),
                        line,
                    })
                }
                None => Element::Unknown,
            },
            Flow::Box => {
                let ends = ENDING_BOXES.contains(&m);
                let b = if m == "CALL" {
                    self.call_box(ops, line)
                } else {
                    box_element(spec, ops, line, "EN", (!ends).then_some("ENO"))
                };
                if ends {
                    Element::EndBox(b)
                } else {
                    Element::SeriesBox(b)
                }
            }
            Flow::Always => Element::Always(box_element(spec, ops, line, "EN", None)),
        })
    }

    fn stack_element(&self, spec: &Instruction, ops: Vec<Operand>, line: u32) -> Element {
        let m = spec.mnemonic.as_str();
        let contact_kind = match m {
            "NOT" => Some(ContactKind::Not),
            "EU" => Some(ContactKind::PositiveEdge),
            "ED" => Some(ContactKind::NegativeEdge),
            _ => None,
        };
        if let Some(kind) = contact_kind {
            let c = Contact {
                id: 0,
                kind,
                mnemonic: m.to_string(),
                immediate: false,
                operands: Vec::new(),
                relation: None,
                line,
            };
            return Element::Contact(Join::Series, c);
        }
        match m {
            "ALD" => return Element::Stack(StackOp::Ald),
            "OLD" => return Element::Stack(StackOp::Old),
            "LPS" => return Element::Stack(StackOp::Lps),
            "LRD" => return Element::Stack(StackOp::Lrd),
            "LPP" => return Element::Stack(StackOp::Lpp),
            "LDS" => {
                let n = ops
                    .first()
                    .and_then(|o| o.written.parse().ok())
                    .unwrap_or(-1);
                return Element::Stack(StackOp::Lds(n));
            }
            _ => {}
        }
        if let Some((_, enable, inputs)) = COUNTERS.iter().find(|(c, ..)| *c == m) {
            let mut b = box_element(spec, ops, line, enable, Some("Q"));
            title_from_first_pin(&mut b);
            return Element::Counter(b, inputs);
        }
        if spec.stack_needs == 1 && spec.stack_delta == 0 && spec.family == "Timer and counter" {
            // A timer. In a Micro/WIN export (without GUTTA's timer boxes) it leaves its
            // input on the stack, as on an S7-200: a box at the end of its branch.
            let s7200 = self
                .checked
                .microwin
                .as_ref()
                .is_some_and(|m| !m.gutta_boxes);
            let mut b = box_element(spec, ops, line, "IN", (!s7200).then_some("Q"));
            title_from_first_pin(&mut b);
            return if s7200 {
                Element::EndBox(b)
            } else {
                Element::SeriesBox(b)
            };
        }
        Element::Unknown
    }

    /// `CALL SBR, args...`: titled by the subroutine, a pin per parameter.
    fn call_box(&self, ops: Vec<Operand>, line: u32) -> BoxElement {
        let mut ops = ops.into_iter();
        let block = ops.next();
        let written = block.map(|b| b.written).unwrap_or_default();
        let (title, params) = self
            .subroutines
            .get(&written.to_ascii_uppercase())
            .cloned()
            .unwrap_or((written, Vec::new()));
        let pins = ops
            .enumerate()
            .map(|(i, operand)| {
                let (name, output) = params
                    .get(i)
                    .cloned()
                    .unwrap_or_else(|| (format!("#{}", i + 1), false));
                Pin {
                    name,
                    output,
                    operand,
                }
            })
            .collect();
        BoxElement {
            id: 0,
            mnemonic: "CALL".to_string(),
            title,
            pins,
            power_inputs: Vec::new(),
            enable: "EN".to_string(),
            output: Some("ENO".to_string()),
            line,
        }
    }
}

/// A contact of a Load or Combine instruction.
fn contact(spec: &Instruction, operands: Vec<Operand>, line: u32) -> Contact {
    let m = spec.mnemonic.as_str();
    let (kind, immediate, relation) = if spec.family == "Compare" {
        (ContactKind::Compare, false, compare_relation(m))
    } else {
        let base = m
            .strip_prefix("LD")
            .or_else(|| m.strip_prefix('A'))
            .or_else(|| m.strip_prefix('O'))
            .unwrap_or(m);
        let negated = base.starts_with('N');
        let immediate = base.ends_with('I');
        let kind = if negated {
            ContactKind::NormallyClosed
        } else {
            ContactKind::NormallyOpen
        };
        (kind, immediate, None)
    };
    Contact {
        id: 0,
        kind,
        mnemonic: m.to_string(),
        immediate,
        operands,
        relation,
        line,
    }
}

/// `LDW>=` -> `>=W`, `AB=` -> `=B`, `OR<` -> `<R`: the relation, then the type letter.
fn compare_relation(mnemonic: &str) -> Option<String> {
    let rest = mnemonic
        .strip_prefix("LD")
        .or_else(|| mnemonic.strip_prefix('A'))
        .or_else(|| mnemonic.strip_prefix('O'))?;
    let mut chars = rest.chars();
    let ty = chars.next()?;
    Some(format!("{}{ty}", chars.as_str()))
}

fn coil_kind(mnemonic: &str) -> Option<CoilKind> {
    Some(match mnemonic {
        "=" => CoilKind::Out,
        "S" => CoilKind::Set,
        "R" => CoilKind::Reset,
        "=I" => CoilKind::OutImmediate,
        "SI" => CoilKind::SetImmediate,
        "RI" => CoilKind::ResetImmediate,
        _ => return None,
    })
}

/// A box with a pin per operand, named by the catalog.
fn box_element(
    spec: &Instruction,
    operands: Vec<Operand>,
    line: u32,
    enable: &str,
    output: Option<&str>,
) -> BoxElement {
    let pins = operands
        .into_iter()
        .enumerate()
        .map(|(i, operand)| {
            let (name, output) = spec
                .operands
                .get(i)
                .map(|o| (o.name.clone(), o.role.writes()))
                .unwrap_or_else(|| (format!("#{}", i + 1), false));
            Pin {
                name,
                output,
                operand,
            }
        })
        .collect();
    BoxElement {
        id: 0,
        mnemonic: spec.mnemonic.clone(),
        title: spec.mnemonic.clone(),
        pins,
        power_inputs: Vec::new(),
        enable: enable.to_string(),
        output: output.map(str::to_string),
        line,
    }
}

/// A timer's or counter's number is its title (`T37`), not a pin.
fn title_from_first_pin(b: &mut BoxElement) {
    if !b.pins.is_empty() {
        let pin = b.pins.remove(0);
        b.title = pin.operand.written;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compare_relations_put_the_type_after_the_relation() {
        assert_eq!(compare_relation("LDW>=").as_deref(), Some(">=W"));
        assert_eq!(compare_relation("AB=").as_deref(), Some("=B"));
        assert_eq!(compare_relation("OR<").as_deref(), Some("<R"));
        assert_eq!(compare_relation("OD<>").as_deref(), Some("<>D"));
    }
}
