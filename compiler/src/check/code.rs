//! Program code, unit by unit and network by network: network numbers, mnemonics, the
//! logic stack, where an instruction may stand, FOR/NEXT pairing and the labels of
//! every unit. Each instruction's operands are `instruction.rs`'s; CALL arguments and
//! the call graph are `calls.rs`'s.

use std::collections::{BTreeMap, HashMap};

use gutta_catalog::{rules, BlockKind, InstrId, Instruction, LoopRole};

use super::aeno_lines::PreviousLine;
use super::bit_lines::{BitLines, TimerBox};
use super::calls::CallSite;
use super::sequence::SequenceLines;
use super::{CheckedInstruction, CheckedNetwork, CheckedUnit, Checker, DefKind, UnitInfo};
use crate::diagnostics::{Code, Diagnostic, Suggestion};
use crate::source::Span;
use crate::syntax::ast::{self, Operand, OperandKind};

/// What the code check gathers across units.
pub(super) struct CodeContext {
    /// `LBL n` of every unit (collected first, so jumps are checked in one pass):
    /// unit -> label -> span.
    pub labels: Vec<BTreeMap<u16, Span>>,
    pub calls: Vec<CallSite>,
    /// Bits assigned with `=`: (slot, offset, bit) -> first assignment.
    pub coils: HashMap<(u8, u32, u8), Span>,
    /// Timers and counters driven: (slot, offset) -> first instruction.
    pub timers: HashMap<(u8, u32), Span>,
    /// Where an earlier stage asks for them: timer and counter bits used and timer and
    /// counter instructions (`bit_lines.rs`); and the network being checked (its index).
    pub bit_lines: BitLines,
    pub network: usize,
    /// SCR lines met (`sequence.rs`), where an earlier stage asks for them.
    pub scr_lines: Vec<super::ScrLine>,
}

/// The logic stack of one network as far as it is known.
struct LogicStack {
    depth: i32,
    /// False after an unknown mnemonic or a reported stack error: the depth is unknown.
    known: bool,
}

/// The open FOR loops of one unit.
struct ForLoops {
    for_id: Option<InstrId>,
    next_id: Option<InstrId>,
    max_depth: usize,
    open: Vec<Span>,
}

impl Checker<'_> {
    /// Every unit's code, sorted (interrupts by number, MAIN first, then subroutines by
    /// number), and the bit lines and timer boxes met, their unit indices into it.
    pub(super) fn code(&mut self) -> (Vec<CheckedUnit>, BitLines) {
        let mut cx = CodeContext {
            labels: self.labels(),
            calls: Vec::new(),
            coils: HashMap::new(),
            timers: HashMap::new(),
            bit_lines: BitLines::default(),
            network: 0,
            scr_lines: Vec::new(),
        };
        let mut checked = Vec::new();
        for ui in 0..self.units.len() {
            let unit = self.unit_code(ui, &mut cx);
            checked.push(unit);
        }
        self.call_graph(&cx.calls);
        // Order: interrupts by number (MAIN first), then subroutines by number.
        let mut indexed: Vec<(usize, CheckedUnit)> = checked.into_iter().enumerate().collect();
        indexed.sort_by_key(|(_, u)| (u.kind == BlockKind::Subroutine, u.number));
        let mut position = vec![0; indexed.len()];
        for (new, (old, _)) in indexed.iter().enumerate() {
            position[*old] = new;
        }
        cx.bit_lines.renumber_units(&position);
        let mut lines = SequenceLines {
            lines: std::mem::take(&mut cx.scr_lines),
            ..SequenceLines::default()
        };
        lines.renumber_units(&position);
        self.sequence.lines = lines.lines;
        (indexed.into_iter().map(|(_, u)| u).collect(), cx.bit_lines)
    }

    /// `LBL n` of every unit: unit -> label -> span.
    fn labels(&mut self) -> Vec<BTreeMap<u16, Span>> {
        let set = &self.target.instructions;
        let lbl = set.label_definition();
        let range = lbl
            .and_then(|id| set.get(id).operands.first())
            .map_or(0..=255, rules::label_range);
        (0..self.units.len())
            .map(|ui| match lbl {
                Some(lbl) => self.unit_labels(ui, lbl, &range),
                None => BTreeMap::new(),
            })
            .collect()
    }

    fn unit_labels(
        &mut self,
        ui: usize,
        lbl: InstrId,
        range: &std::ops::RangeInclusive<i64>,
    ) -> BTreeMap<u16, Span> {
        let ast = self.ast;
        let mut map: BTreeMap<u16, Span> = BTreeMap::new();
        let u = &ast.units[self.units[ui].ast_index];
        for net in &u.networks {
            for ins in &net.instructions {
                if self.target.instructions.lookup(self.slice(ins.mnemonic)) != Some(lbl) {
                    continue;
                }
                let Some(op) = net.operands_of(ins).first() else {
                    continue;
                };
                let OperandKind::Integer(n) = op.kind else {
                    continue;
                };
                if !range.contains(&n) {
                    continue;
                }
                let n = n as u16;
                if let Some(&first) = map.get(&n) {
                    self.report(
                        Diagnostic::new(
                            Code::DuplicateLabel,
                            op.span,
                            format!("label {n} is defined twice in this block"),
                        )
                        .with_secondary(first, "first defined here"),
                    );
                } else {
                    map.insert(n, op.span);
                    let name = self.units[ui].name.clone();
                    self.define(
                        format!("LBL {n}"),
                        DefKind::Label,
                        op.span,
                        format!("label {n} of {name}"),
                        Some(ui),
                    );
                }
            }
        }
        map
    }

    fn unit_code(&mut self, ui: usize, cx: &mut CodeContext) -> CheckedUnit {
        let ast = self.ast;
        let info = self.units[ui].clone();
        let u = &ast.units[info.ast_index];
        let set = &self.target.instructions;
        let mut loops = ForLoops {
            for_id: set.by_loop_role(LoopRole::Start),
            next_id: set.by_loop_role(LoopRole::End),
            max_depth: usize::from(set.for_depth),
            open: Vec::new(),
        };
        let mut networks = Vec::new();
        let mut last_number: Option<(u32, Span)> = None;
        let addresses_from = self.out.addresses.len();
        for net in &u.networks {
            cx.network = networks.len();
            let number = self.network_number(net, &mut last_number);
            networks.push(self.network(ui, &info, net, number, &mut loops, cx));
        }
        self.place_l_temporaries(&info, addresses_from);
        for open in loops.open {
            self.report(
                Diagnostic::new(Code::ForNext, open, "FOR without NEXT")
                    .label("this loop is never closed in its block"),
            );
        }
        let title = u.title.map(|t| self.slice(t).to_string());
        CheckedUnit {
            kind: info.kind,
            number: info.number,
            name: info.name,
            title,
            span: u.header.span,
            locals: info.locals,
            networks,
        }
    }

    /// The network's number: as written (in increasing order), or the previous + 1.
    fn network_number(&mut self, net: &ast::Network, last: &mut Option<(u32, Span)>) -> u32 {
        let number = match (net.number, *last) {
            (Some(n), Some((prev, prev_span))) if n <= prev => {
                let at = net.header.unwrap_or(net.span);
                self.report(
                    Diagnostic::new(
                        Code::NetworkOrder,
                        at,
                        format!("network {n} after network {prev}"),
                    )
                    .with_secondary(prev_span, "previous network")
                    .help("number networks in increasing order"),
                );
                n
            }
            _ => net.number_after(last.map(|(prev, _)| prev)),
        };
        if let Some(header) = net.header {
            *last = Some((number, header));
        }
        number
    }

    fn network(
        &mut self,
        ui: usize,
        info: &UnitInfo,
        net: &ast::Network,
        number: u32,
        loops: &mut ForLoops,
        cx: &mut CodeContext,
    ) -> CheckedNetwork {
        if net.instructions.is_empty() {
            self.report(Diagnostic::new(
                Code::EmptyNetwork,
                net.header.unwrap_or(net.span),
                format!("network {number} is empty"),
            ));
        }
        let mut stack = LogicStack {
            depth: 0,
            known: true,
        };
        let mut instructions = Vec::new();
        let mut previous = None;
        for ins in &net.instructions {
            if self.is_aeno_line(ins) {
                let depth = stack.known.then_some(stack.depth);
                let ops = net.operands_of(ins);
                instructions.extend(self.aeno_line(ins, ops, previous, depth));
                continue;
            }
            let at = (ui, cx.network, instructions.len());
            let ops = net.operands_of(ins);
            let stack_ref = (&mut stack.depth, &mut stack.known);
            if let Some(line) = self.scr_line(at, ins.mnemonic, ops, ins.span, stack_ref) {
                if let Some(id) = self.target.instructions.label_definition() {
                    cx.scr_lines.push(line);
                    // A placeholder: the pass after checking puts the instructions here.
                    instructions.push(CheckedInstruction {
                        id,
                        operands: Vec::new(),
                        span: ins.span,
                    });
                }
                continue;
            }
            let Some(id) = self.mnemonic(ins) else {
                stack.known = false;
                previous = Some(PreviousLine::Unknown(ins.mnemonic));
                continue;
            };
            previous = Some(PreviousLine::Known(id));
            self.out.mnemonics.push((ins.mnemonic, id));
            let spec = self.target.instructions.get(id);
            let ops = net.operands_of(ins);
            let depth = stack.known.then_some(stack.depth);
            self.logic_stack(&mut stack, spec, ops, ins.mnemonic);
            if ops.iter().any(|o| o.kind == OperandKind::Error) {
                continue;
            }
            self.placement(info, spec, ins.mnemonic);
            self.for_next(id, ins.mnemonic, loops);
            let at = (ui, cx.network, instructions.len());
            if let Some(bit_use) = self.bit_line(at, id, ops, ins.span) {
                cx.bit_lines.uses.push(bit_use);
                // A placeholder: the pass after checking puts the instructions here.
                instructions.push(CheckedInstruction {
                    id,
                    operands: Vec::new(),
                    span: ins.span,
                });
                continue;
            }
            if let Some(ci) = self.instruction(ui, id, ins.mnemonic, ops, ins.span, cx) {
                if self.conventions.timer_bit_lines.is_some()
                    && spec.family == "Timer and counter"
                    && ops.len() >= 2
                {
                    cx.bit_lines.boxes.push(TimerBox {
                        unit: ui,
                        network: cx.network,
                        index: instructions.len(),
                        depth,
                        preset: ops[1].span,
                        span: ins.span,
                    });
                }
                instructions.push(ci);
            }
        }
        CheckedNetwork {
            number,
            title: net.title.map(|t| self.slice(t).to_string()),
            span: net.header.unwrap_or(net.span),
            instructions,
        }
    }

    /// The instruction a mnemonic names, or a diagnostic (none for a line that did
    /// not parse: it has one already).
    fn mnemonic(&mut self, ins: &ast::Instruction) -> Option<InstrId> {
        let set = &self.target.instructions;
        let text = self.slice(ins.mnemonic);
        if let Some(id) = set.lookup(text) {
            return Some(id);
        }
        if !ins.syntax_error {
            if let Some(s7) = gutta_catalog::s7200::s7200_instruction(text) {
                let d = Diagnostic::new(
                    Code::S7200Instruction,
                    ins.mnemonic,
                    format!(
                        "`{text}` is an S7-200 instruction ({}) that {} does not have",
                        s7.what,
                        self.target.name()
                    ),
                )
                .label("S7-200 only")
                .help(match s7.instead {
                    Some(alt) => format!("instead: {alt}"),
                    None => "GUTTA has no equivalent; this part of the program must be rewritten"
                        .to_string(),
                });
                self.report(d);
                return None;
            }
            let hint = crate::suggest::closest(text, set.names().map(|(n, _)| n))
                .map(|s| Suggestion::new(ins.mnemonic, s));
            self.report(
                Diagnostic::new(
                    Code::UnknownMnemonic,
                    ins.mnemonic,
                    format!("unknown instruction `{text}`"),
                )
                .label(format!("not in {}'s instruction set", self.target.name()))
                .maybe_suggest(hint),
            );
        }
        None
    }

    /// The levels an instruction needs and leaves on the logic stack.
    fn logic_stack(
        &mut self,
        stack: &mut LogicStack,
        spec: &Instruction,
        ops: &[Operand],
        at: Span,
    ) {
        if !stack.known {
            return;
        }
        // `LDS n` copies level n to the top: it needs n + 1 levels.
        let lds_extra = match (spec.mnemonic.as_str(), ops.first().map(|o| o.kind)) {
            ("LDS", Some(OperandKind::Integer(n))) if (0..=31).contains(&n) => n as i32,
            _ => 0,
        };
        let needs = spec.stack_needs as i32 + lds_extra;
        let depth = stack.depth;
        if depth < needs {
            let msg = if depth == 0 {
                format!(
                    "`{}` needs power flow, but nothing is loaded in this network",
                    spec.mnemonic
                )
            } else {
                format!(
                    "`{}` needs {needs} levels of the logic stack; {depth} are loaded",
                    spec.mnemonic
                )
            };
            self.report(Diagnostic::new(Code::StackUnderflow, at, msg).help(
                "start the logic with a load such as `LD I0.0` (or `LD SM0.0` to run always)",
            ));
            stack.known = false;
            return;
        }
        stack.depth += spec.stack_delta as i32;
        let max = self.target.instructions.logic_stack_depth as i32;
        if spec.stack_delta > 0 && stack.depth > max {
            self.report(
                Diagnostic::new(
                    Code::StackOverflow,
                    at,
                    format!(
                        "the logic stack holds {max} levels; this load would make {}",
                        stack.depth
                    ),
                )
                .help("combine branches with ALD or OLD before loading more"),
            );
            stack.known = false;
        }
    }

    /// Whether the instruction may stand in this unit (`Units` of ManagerFun.xml).
    fn placement(&mut self, info: &UnitInfo, spec: &Instruction, at: Span) {
        let scope = spec.units;
        if rules::placement_allowed(scope, info.kind, info.number) {
            return;
        }
        self.report(
            Diagnostic::new(
                Code::WrongUnitKind,
                at,
                format!("`{}` is not allowed in {}", spec.mnemonic, info.name),
            )
            .label(format!("only in {}", scope.describe()))
            .help(match (scope.main, scope.interrupt, scope.subroutine) {
                (false, false, true) => "a subroutine returns with RET or CRET",
                (false, true, false) => "an interrupt routine returns with RETI or CRETI",
                _ => "END ends the scan in MAIN; other blocks return",
            }),
        );
    }

    /// FOR opens a loop (at most `ForDepth` deep), NEXT closes the innermost.
    fn for_next(&mut self, id: InstrId, at: Span, loops: &mut ForLoops) {
        if Some(id) == loops.for_id {
            loops.open.push(at);
            if !rules::for_depth_allowed(&self.target.instructions, loops.open.len()) {
                self.report(Diagnostic::new(
                    Code::ForNext,
                    at,
                    format!("FOR loops nest at most {} deep", loops.max_depth),
                ));
            }
        } else if Some(id) == loops.next_id && loops.open.pop().is_none() {
            self.report(
                Diagnostic::new(Code::ForNext, at, "NEXT without FOR")
                    .label("no open FOR loop in this block"),
            );
        }
    }
}
