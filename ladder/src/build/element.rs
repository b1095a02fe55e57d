//! One STL instruction as a ladder element (docs/ladder.md, "Which networks are
//! ladder"): what it does to the power path (a contact loaded, in series or in
//! parallel; a stack operation; a coil or a box) and the element as drawn, its operands
//! resolved through the program's symbols and the target's address syntax. What an
//! instruction is comes from the catalog (`Ladder`, `Kind`, `PowerInputs`... of
//! ManagerFun.xml), never from its mnemonic. Knows nothing of the logic stack:
//! `rung.rs` places the elements.

use std::collections::HashMap;

use gutta_catalog::{DataType, Flow, Instruction, LadderClass, LoopRole};
use gutta_compiler::syntax::ast::{self, OperandKind, Prefix, VarSection};
use gutta_compiler::CheckedFile;
use gutta_format::SymbolTable;

use crate::model::{BoxElement, BoxShape, Coil, CoilKind, Contact, ContactKind, Operand, Pin};

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
    /// S7-200 timer of a Micro/WIN export); with whether it opens a loop (`FOR`).
    EndBox(BoxElement, bool),
    /// A counter: its inputs besides the main one are the lower levels of the stack,
    /// named by the catalog's `PowerInputs` after the first (deepest first), taken by
    /// `rung.rs`.
    Counter(BoxElement, Vec<String>),
    /// Runs without power flow (`LBL`, `NEXT`, `RET`): only alone in a network.
    Always(BoxElement),
    /// No ladder drawing (an instruction of a kind this builder does not know).
    Unknown,
}

/// What names an operand: its canonical address, the symbol (or system name) drawn
/// above it, with that name's comment and type.
#[derive(Debug, Default)]
struct Named {
    address: Option<String>,
    symbol: Option<String>,
    comment: Option<String>,
    data_type: Option<String>,
}

/// A system bit or byte named `shown` (none: drawn by its address alone).
fn system_name(
    bit: &gutta_catalog::SystemBit,
    shown: Option<String>,
    address: &gutta_catalog::Address,
    memory: &gutta_catalog::MemoryMap,
) -> Named {
    let named = shown.is_some();
    Named {
        address: Some(memory.format_address(address)),
        symbol: shown,
        comment: named
            .then(|| bit.description.trim().to_string())
            .filter(|d| !d.is_empty()),
        data_type: named.then(|| width_type(address.width).to_string()),
    }
}

/// The type the symbol information shows for an address without a declared type.
fn width_type(width: gutta_catalog::Width) -> &'static str {
    match width {
        gutta_catalog::Width::Bit => "BOOL",
        gutta_catalog::Width::Byte => "BYTE",
        gutta_catalog::Width::Word => "WORD",
        gutta_catalog::Width::Dword => "DWORD",
    }
}

/// What the builder reads of the program besides one instruction.
pub(super) struct Resolver<'a> {
    checked: &'a CheckedFile,
    symbols: SymbolTable,
    /// Subroutine name (and numbered name), upper case -> its name and its parameters
    /// in call order (name, drawn as an output pin).
    subroutines: HashMap<String, (String, Vec<(String, bool)>)>,
    /// The target's system bits and bytes by canonical address -> index in
    /// `memory.system_bits`.
    system: HashMap<String, usize>,
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
        let memory = &checked.target.memory;
        let system = memory
            .system_bits
            .iter()
            .enumerate()
            .filter_map(|(i, b)| {
                let address = memory.parse_address(&b.address).ok()?;
                Some((memory.format_address(&address), i))
            })
            .collect();
        Resolver {
            checked,
            symbols: checked.symbols(),
            subroutines,
            system,
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

    /// An operand as drawn: as written, its canonical address, its symbol (or the
    /// system name of its address) with the symbol's comment and type.
    pub(super) fn operand(&self, op: &ast::Operand) -> Operand {
        let written = self.text(op.span).trim().to_string();
        let named = match op.kind {
            OperandKind::Name {
                prefix: Prefix::None,
                local: false,
                name,
            } => {
                let named = self.address_of(self.text(name));
                match named.address {
                    None => self.s_operand(name).unwrap_or(named),
                    Some(_) => named,
                }
            }
            _ => Named::default(),
        };
        Operand {
            written,
            address: named.address,
            symbol: named.symbol,
            comment: named.comment,
            data_type: named.data_type,
        }
    }

    /// A name's canonical address and what names it: a symbol's, in a Micro/WIN export
    /// a system symbol's (`Always_On`; user symbols win, as in the checker), or a direct
    /// address normalised, named by a user symbol or the target's name when it is a
    /// system bit or byte (`SM0.0` as `Always_On`, docs/ladder.md "System names").
    fn address_of(&self, name: &str) -> Named {
        let memory = &self.checked.target.memory;
        if let Some(symbol) = self.symbols.get(name) {
            return self.user_symbol(symbol);
        }
        if self.checked.microwin.is_some() {
            if let Some(bit) = memory.microwin_system_bit(name) {
                if let Ok(address) = memory.parse_address(&bit.address) {
                    return system_name(bit, bit.microwin.clone(), &address, memory);
                }
            }
        }
        let Ok(address) = memory.parse_address(name) else {
            return Named::default();
        };
        let canonical = memory.format_address(&address);
        if let Some(bit) = self.system.get(&canonical).map(|&i| &memory.system_bits[i]) {
            if let Some(symbol) = self.symbols.for_address(&canonical) {
                return self.user_symbol(symbol);
            }
            let shown = bit.microwin.clone().unwrap_or_else(|| bit.name.clone());
            return system_name(bit, Some(shown), &address, memory);
        }
        Named {
            address: Some(canonical),
            ..Named::default()
        }
    }

    /// An S operand of a Micro/WIN export (`S0.1`): its S name drawn over the GUTTA
    /// address it went to (`Export::s_operands`, docs/microwin.md "Sequence control
    /// relays").
    fn s_operand(&self, name: gutta_compiler::source::Span) -> Option<Named> {
        let export = self.checked.microwin.as_ref()?;
        let (_, s_name, address) = export.s_operands.iter().find(|s| s.0 == name)?;
        Some(Named {
            address: Some(self.checked.target.memory.format_address(address)),
            symbol: Some(s_name.clone()),
            comment: None,
            data_type: Some(width_type(address.width).to_string()),
        })
    }

    fn user_symbol(&self, symbol: &gutta_format::Symbol) -> Named {
        let memory = &self.checked.target.memory;
        let width = memory.parse_address(&symbol.address).ok().map(|a| a.width);
        Named {
            address: Some(symbol.address.clone()),
            symbol: Some(symbol.name.clone()),
            comment: Some(symbol.comment.trim().to_string()).filter(|c| !c.is_empty()),
            data_type: symbol
                .data_type
                .clone()
                .or_else(|| width.map(|w| width_type(w).to_string())),
        }
    }

    /// The element of one instruction of a network; `None` for an unknown mnemonic.
    pub(super) fn element(&self, net: &ast::Network, ins: &ast::Instruction) -> Option<Element> {
        let target = &self.checked.target;
        let ops = || -> Vec<Operand> {
            net.operands_of(ins)
                .iter()
                .map(|o| self.operand(o))
                .collect()
        };
        let line = self.line(ins.span.start);
        let written = self.text(ins.mnemonic).trim();
        let Some(id) = target.instructions.lookup(written) else {
            return self
                .checked
                .microwin
                .as_ref()
                .and_then(|_| scr_element(written, ops(), line));
        };
        let spec = target.instructions.get(id);
        let ops = ops();
        Some(match spec.ladder {
            LadderClass::Contact | LadderClass::ClosedContact | LadderClass::Compare => {
                let join = match spec.join() {
                    Some(gutta_catalog::Join::Load) | None => Join::Load,
                    Some(gutta_catalog::Join::And) => Join::Series,
                    Some(gutta_catalog::Join::Or) => Join::Parallel,
                };
                Element::Contact(join, contact(spec, ops, line))
            }
            LadderClass::Not => series_contact(spec, ContactKind::Not, line),
            LadderClass::RisingEdge => series_contact(spec, ContactKind::PositiveEdge, line),
            LadderClass::FallingEdge => series_contact(spec, ContactKind::NegativeEdge, line),
            LadderClass::AndBlock => Element::Stack(StackOp::Ald),
            LadderClass::OrBlock => Element::Stack(StackOp::Old),
            LadderClass::Push => Element::Stack(StackOp::Lps),
            LadderClass::Read => Element::Stack(StackOp::Lrd),
            LadderClass::Pop => Element::Stack(StackOp::Lpp),
            LadderClass::LoadStack => {
                let n = ops
                    .first()
                    .and_then(|o| o.written.parse().ok())
                    .unwrap_or(-1);
                Element::Stack(StackOp::Lds(n))
            }
            LadderClass::Coil | LadderClass::SetCoil | LadderClass::ResetCoil => {
                let mut ops = ops.into_iter();
                let Some(operand) = ops.next() else {
                    return Some(Element::Unknown);
                };
                Element::Coil(Coil {
                    id: 0,
                    kind: coil_kind(spec),
                    mnemonic: spec.mnemonic.clone(),
                    operand,
                    count: ops.next(),
                    line,
                })
            }
            LadderClass::Box => self.box_of(spec, ops, line),
        })
    }

    /// A box: a timer, a counter, a CALL, a box that ends the power path, one that
    /// continues it, or one that runs without power flow.
    fn box_of(&self, spec: &Instruction, ops: Vec<Operand>, line: u32) -> Element {
        let enable = spec.power_inputs.first().map_or("EN", String::as_str);
        let output = spec.power_output.as_deref();
        match spec.kind {
            Some(kind) if kind.is_timer() => {
                // In a Micro/WIN export (without GUTTA's timer boxes) a timer leaves its
                // input on the stack, as on an S7-200: a box at the end of its branch.
                let s7200 = self
                    .checked
                    .microwin
                    .as_ref()
                    .is_some_and(|m| !m.gutta_boxes);
                let mut b = box_element(spec, ops, line, enable, output.filter(|_| !s7200));
                title_from_first_pin(&mut b);
                b.resolution_ms = b
                    .counted
                    .as_ref()
                    .and_then(|c| c.address.as_deref())
                    .and_then(counted_number)
                    .and_then(|n| self.checked.target.timer_resolution(kind, n));
                return if s7200 {
                    Element::EndBox(b, false)
                } else {
                    Element::SeriesBox(b)
                };
            }
            Some(_) => {
                let mut b = box_element(spec, ops, line, enable, output);
                title_from_first_pin(&mut b);
                return Element::Counter(b, spec.power_inputs[1..].to_vec());
            }
            None => {}
        }
        match spec.flow {
            Flow::Box => {
                let b = if spec.call_arguments {
                    self.call_box(spec, ops, line)
                } else {
                    box_element(spec, ops, line, enable, output)
                };
                if output.is_none() {
                    Element::EndBox(b, spec.loop_role == Some(LoopRole::Start))
                } else {
                    Element::SeriesBox(b)
                }
            }
            Flow::Always => Element::Always(box_element(spec, ops, line, enable, None)),
            Flow::Load | Flow::Combine | Flow::Output | Flow::Stack => Element::Unknown,
        }
    }

    /// `CALL SBR, args...`: titled by the subroutine, a pin per parameter.
    fn call_box(&self, spec: &Instruction, ops: Vec<Operand>, line: u32) -> BoxElement {
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
                    input: None,
                }
            })
            .collect();
        BoxElement {
            id: 0,
            mnemonic: spec.mnemonic.clone(),
            title,
            pins,
            power_inputs: Vec::new(),
            enable: spec.power_inputs.first().cloned().unwrap_or_default(),
            output: spec.power_output.clone(),
            line,
            counted: None,
            resolution_ms: None,
            shape: BoxShape::Box,
        }
    }
}

/// A sequence control relay line of a Micro/WIN export (docs/microwin.md, "Sequence
/// control relays") as Micro/WIN's LAD draws it, with the shapes of the label and jump
/// boxes: `LSCR` the `SCR` box on the rail, its S bit above; `SCRT` a coil `(SCRT)` at
/// the end of its branch, its S bit above; `CSCRE` a coil `(SCRE)` at the end of its
/// branch; `SCRE` the coil `(SCRE)` on the rail. The mnemonic stays the STL one, which
/// the writer writes back (`write.rs`); `None` for any other mnemonic.
pub(super) fn scr_element(written: &str, ops: Vec<Operand>, line: u32) -> Option<Element> {
    let mnemonic = written.to_ascii_uppercase();
    let (title, shape) = match mnemonic.as_str() {
        "LSCR" => ("SCR", BoxShape::Label),
        "SCRT" => ("SCRT", BoxShape::Jump),
        "SCRE" | "CSCRE" => ("SCRE", BoxShape::Jump),
        _ => return None,
    };
    let pins = ops
        .into_iter()
        .map(|operand| Pin {
            name: "S_bit".to_string(),
            output: false,
            operand,
            input: None,
        })
        .collect();
    let b = BoxElement {
        id: 0,
        title: title.to_string(),
        pins,
        power_inputs: Vec::new(),
        enable: "EN".to_string(),
        output: None,
        line,
        counted: None,
        resolution_ms: None,
        shape,
        mnemonic,
    };
    // LSCR and SCRE stand on the rail alone in their network (Micro/WIN's SCR box and
    // SCRE coil); SCRT and CSCRE end the branch whose power they take.
    Some(match b.mnemonic.as_str() {
        "LSCR" | "SCRE" => Element::Always(b),
        _ => Element::EndBox(b, false),
    })
}

/// A contact of a Load or Combine instruction.
fn contact(spec: &Instruction, operands: Vec<Operand>, line: u32) -> Contact {
    let kind = match spec.ladder {
        LadderClass::Compare => ContactKind::Compare,
        LadderClass::ClosedContact => ContactKind::NormallyClosed,
        _ => ContactKind::NormallyOpen,
    };
    Contact {
        id: 0,
        kind,
        mnemonic: spec.mnemonic.clone(),
        immediate: spec.immediate,
        operands,
        relation: compare_relation(spec),
        line,
    }
}

/// `NOT`, `EU`, `ED`: a contact without operands in series with the top.
fn series_contact(spec: &Instruction, kind: ContactKind, line: u32) -> Element {
    let c = Contact {
        id: 0,
        kind,
        mnemonic: spec.mnemonic.clone(),
        immediate: false,
        operands: Vec::new(),
        relation: None,
        line,
    };
    Element::Contact(Join::Series, c)
}

/// A compare's relation as drawn inside the contact: the relation, then the letter of
/// the type compared (`>=W`, `=B`, `<>D`, `<R`), as S7-200 STL names the compares.
fn compare_relation(spec: &Instruction) -> Option<String> {
    let op = spec.compare?;
    let letter = match spec.operands.first()?.types.first()? {
        DataType::Byte | DataType::Sint | DataType::Usint => 'B',
        DataType::Real => 'R',
        DataType::Dint | DataType::Dword | DataType::Udint => 'D',
        _ => 'W',
    };
    Some(format!("{}{letter}", op.symbol()))
}

fn coil_kind(spec: &Instruction) -> CoilKind {
    match (spec.ladder, spec.immediate) {
        (LadderClass::SetCoil, false) => CoilKind::Set,
        (LadderClass::SetCoil, true) => CoilKind::SetImmediate,
        (LadderClass::ResetCoil, false) => CoilKind::Reset,
        (LadderClass::ResetCoil, true) => CoilKind::ResetImmediate,
        (_, false) => CoilKind::Out,
        (_, true) => CoilKind::OutImmediate,
    }
}

/// A box with a pin per operand, named by the catalog.
fn box_element(
    spec: &Instruction,
    operands: Vec<Operand>,
    line: u32,
    enable: &str,
    output: Option<&str>,
) -> BoxElement {
    let sides = crate::names::pin_sides(spec);
    let pins = operands
        .into_iter()
        .enumerate()
        .map(|(i, operand)| {
            let side = sides.get(i).cloned().unwrap_or(crate::names::PinSide {
                name: format!("#{}", i + 1),
                output: false,
                input: None,
            });
            Pin {
                name: side.name,
                output: side.output,
                operand,
                input: side.input,
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
        counted: None,
        resolution_ms: None,
        shape: box_shape(spec),
    }
}

/// How the catalog's instruction is drawn: a label definition as a label box, a box
/// that ends the power path at a label operand as a jump coil.
pub fn box_shape(spec: &Instruction) -> BoxShape {
    let to_label = spec
        .operands
        .iter()
        .any(|o| o.kind == gutta_catalog::OperandKind::Label);
    if spec.defines_label {
        BoxShape::Label
    } else if to_label && spec.power_output.is_none() && spec.flow == Flow::Box {
        BoxShape::Jump
    } else {
        BoxShape::Box
    }
}

/// A timer's or counter's number is its title (`T37`) and its counted operand, drawn
/// above the box, not a pin.
fn title_from_first_pin(b: &mut BoxElement) {
    if !b.pins.is_empty() {
        let pin = b.pins.remove(0);
        b.title = pin.operand.written.clone();
        b.counted = Some(Box::new(pin.operand));
    }
}

/// The number of a canonical timer or counter address (`T37` -> 37).
fn counted_number(address: &str) -> Option<u32> {
    address
        .trim_start_matches(|c: char| c.is_ascii_alphabetic())
        .parse()
        .ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compare_relations_put_the_type_after_the_relation() {
        let set = gutta_catalog::stdlib::default_target()
            .expect("stdlib")
            .instructions;
        let relation = |m: &str| compare_relation(set.get(set.lookup(m).expect(m)));
        assert_eq!(relation("LDW>=").as_deref(), Some(">=W"));
        assert_eq!(relation("AB=").as_deref(), Some("=B"));
        assert_eq!(relation("OR<").as_deref(), Some("<R"));
        assert_eq!(relation("OD<>").as_deref(), Some("<>D"));
        assert_eq!(relation("LD"), None);
        // Every compare is drawn with the relation and type its STL name ends with.
        for spec in set.instructions.iter().filter(|i| i.compare.is_some()) {
            let drawn = compare_relation(spec).expect("a relation");
            let (rel, ty) = drawn.split_at(drawn.len() - 1);
            assert!(
                spec.mnemonic.ends_with(&format!("{ty}{rel}")),
                "{}: {drawn}",
                spec.mnemonic
            );
        }
    }
}
