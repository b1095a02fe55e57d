//! Program code: mnemonics, operand counts, the logic stack of every network, labels
//! and jumps, CALL arguments against the callee's VAR sections, FOR/NEXT pairing, the
//! call graph (recursion, depth, unused subroutines) and double-coil/timer warnings.

use std::collections::{BTreeMap, HashMap};

use gutta_catalog::{
    BlockKind, DataType, Flow, InstrId, OperandKind as SpecKind, OperandSpec, Role, Width,
};

use super::{
    CheckedInstruction, CheckedNetwork, CheckedOperand, CheckedUnit, Checker, DefKind, Use,
};
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
use crate::syntax::ast::{OperandKind, VarSection};

/// A CALL site, for the call graph.
struct CallSite {
    caller: usize,
    callee: usize,
    span: Span,
}

impl Checker<'_> {
    pub(super) fn code(&mut self) -> Vec<CheckedUnit> {
        let mut calls = Vec::new();
        let mut checked = Vec::new();
        let mut coils: HashMap<(u8, u32, u8), Span> = HashMap::new();
        let mut timers: HashMap<(u8, u32), Span> = HashMap::new();
        // Labels of every unit first, so jumps can be checked in one pass.
        let labels = self.labels();
        for ui in 0..self.units.len() {
            let unit = self.unit_code(ui, &labels, &mut calls, &mut coils, &mut timers);
            checked.push(unit);
        }
        self.call_graph(&calls);
        // Order: interrupts by number (MAIN first), then subroutines by number.
        checked.sort_by_key(|u: &CheckedUnit| (u.kind == BlockKind::Subroutine, u.number));
        checked
    }

    /// `LBL n` of every unit: unit -> label -> span.
    fn labels(&mut self) -> Vec<BTreeMap<u16, Span>> {
        let ast = self.ast;
        let lbl = self.target.instructions.lookup("LBL");
        let mut all = Vec::new();
        for ui in 0..self.units.len() {
            let mut map: BTreeMap<u16, Span> = BTreeMap::new();
            let u = &ast.units[self.units[ui].ast_index];
            for net in &u.networks {
                for ins in &net.instructions {
                    if self.target.instructions.lookup(self.slice(ins.mnemonic)) != lbl
                        || lbl.is_none()
                    {
                        continue;
                    }
                    let ops = net.operands_of(ins);
                    let Some(op) = ops.first() else { continue };
                    let OperandKind::Integer(n) = op.kind else {
                        continue;
                    };
                    if !(0..=255).contains(&n) {
                        continue;
                    }
                    if let Some(first) = map.get(&(n as u16)) {
                        let first = *first;
                        self.report(
                            Diagnostic::new(
                                Code::DuplicateLabel,
                                op.span,
                                format!("label {n} is defined twice in this block"),
                            )
                            .with_secondary(first, "first defined here"),
                        );
                    } else {
                        map.insert(n as u16, op.span);
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
            all.push(map);
        }
        all
    }

    fn unit_code(
        &mut self,
        ui: usize,
        labels: &[BTreeMap<u16, Span>],
        calls: &mut Vec<CallSite>,
        coils: &mut HashMap<(u8, u32, u8), Span>,
        timers: &mut HashMap<(u8, u32), Span>,
    ) -> CheckedUnit {
        let ast = self.ast;
        let info = self.units[ui].clone();
        let u = &ast.units[info.ast_index];
        let set = &self.target.instructions;
        let max_stack = set.logic_stack_depth as i32;
        let for_depth = set.for_depth as usize;
        let (for_id, next_id) = (set.lookup("FOR"), set.lookup("NEXT"));
        let mut for_stack: Vec<Span> = Vec::new();
        let mut networks = Vec::new();
        let mut last_number: Option<(u32, Span)> = None;
        for net in &u.networks {
            let number = match (net.number, last_number) {
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
                (Some(n), _) => n,
                (None, Some((prev, _))) => prev + 1,
                (None, None) => u32::from(net.header.is_some()),
            };
            if net.header.is_some() {
                last_number = Some((number, net.header.unwrap_or(net.span)));
            }
            if net.instructions.is_empty() {
                self.report(Diagnostic::new(
                    Code::EmptyNetwork,
                    net.header.unwrap_or(net.span),
                    format!("network {number} is empty"),
                ));
            }
            let mut depth: i32 = 0;
            let mut stack_ok = true;
            let mut instructions = Vec::new();
            for ins in &net.instructions {
                let text = self.slice(ins.mnemonic);
                let Some(id) = set.lookup(text) else {
                    stack_ok = false;
                    if ins.syntax_error {
                        continue;
                    }
                    let hint = super::suggest::closest(text, set.names().map(|(n, _)| n))
                        .map(|s| format!("did you mean `{s}`?"));
                    self.report(
                        Diagnostic::new(
                            Code::UnknownMnemonic,
                            ins.mnemonic,
                            format!("unknown instruction `{text}`"),
                        )
                        .label(format!("not in {}'s instruction set", self.target.name()))
                        .maybe_help(hint),
                    );
                    stack_ok = false;
                    continue;
                };
                self.out.mnemonics.push((ins.mnemonic, id));
                let spec = set.get(id);
                let ops = net.operands_of(ins);
                let parse_error = ops.iter().any(|o| o.kind == OperandKind::Error);
                // Logic stack.
                if stack_ok {
                    // `LDS n` copies level n to the top: it needs n + 1 levels.
                    let lds_extra = match (spec.mnemonic.as_str(), ops.first().map(|o| o.kind)) {
                        ("LDS", Some(OperandKind::Integer(n))) if (0..=31).contains(&n) => n as i32,
                        _ => 0,
                    };
                    let needs = spec.stack_needs as i32 + lds_extra;
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
                        self.report(Diagnostic::new(Code::StackUnderflow, ins.mnemonic, msg).help("start the logic with a load such as `LD I0.0` (or `LD SM0.0` to run always)"));
                        stack_ok = false;
                    } else {
                        depth += spec.stack_delta as i32;
                        if spec.stack_delta > 0 && depth > max_stack {
                            self.report(Diagnostic::new(Code::StackOverflow, ins.mnemonic, format!("the logic stack holds {max_stack} levels; this load would make {depth}")).help("combine branches with ALD or OLD before loading more"));
                            stack_ok = false;
                        }
                    }
                }
                if parse_error {
                    continue;
                }
                // The kinds of block the instruction belongs to.
                let scope = spec.units;
                let allowed = match info.kind {
                    BlockKind::Interrupt if info.number == 0 => scope.main,
                    BlockKind::Interrupt => scope.interrupt,
                    BlockKind::Subroutine => scope.subroutine,
                };
                if !allowed {
                    self.report(
                        Diagnostic::new(
                            Code::WrongUnitKind,
                            ins.mnemonic,
                            format!("`{}` is not allowed in {}", spec.mnemonic, info.name),
                        )
                        .label(format!("only in {}", scope.describe()))
                        .help(
                            match (scope.main, scope.interrupt, scope.subroutine) {
                                (false, false, true) => "a subroutine returns with RET or CRET",
                                (false, true, false) => {
                                    "an interrupt routine returns with RETI or CRETI"
                                }
                                _ => "END ends the scan in MAIN; other blocks return",
                            },
                        ),
                    );
                }
                // FOR/NEXT pairing.
                if Some(id) == for_id {
                    for_stack.push(ins.mnemonic);
                    if for_stack.len() > for_depth {
                        self.report(Diagnostic::new(
                            Code::ForNext,
                            ins.mnemonic,
                            format!("FOR loops nest at most {for_depth} deep"),
                        ));
                    }
                } else if Some(id) == next_id && for_stack.pop().is_none() {
                    self.report(
                        Diagnostic::new(Code::ForNext, ins.mnemonic, "NEXT without FOR")
                            .label("no open FOR loop in this block"),
                    );
                }
                if let Some(ci) = self.instruction(
                    ui,
                    id,
                    ins.mnemonic,
                    ops,
                    ins.span,
                    labels,
                    calls,
                    coils,
                    timers,
                ) {
                    instructions.push(ci);
                }
            }
            let title = net.title.map(|t| self.slice(t).to_string());
            networks.push(CheckedNetwork {
                number,
                title,
                span: net.header.unwrap_or(net.span),
                instructions,
            });
        }
        for open in for_stack {
            self.report(
                Diagnostic::new(Code::ForNext, open, "FOR without NEXT")
                    .label("this loop is never closed in its block"),
            );
        }
        let title = u.title.map(|t| self.slice(t).to_string());
        CheckedUnit {
            kind: info.kind,
            number: info.number,
            name: info.name.clone(),
            title,
            span: u.header.span,
            locals: info.locals.clone(),
            networks,
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn instruction(
        &mut self,
        ui: usize,
        id: InstrId,
        mnemonic_span: Span,
        ops: &[crate::syntax::ast::Operand],
        span: Span,
        labels: &[BTreeMap<u16, Span>],
        calls: &mut Vec<CallSite>,
        coils: &mut HashMap<(u8, u32, u8), Span>,
        timers: &mut HashMap<(u8, u32), Span>,
    ) -> Option<CheckedInstruction> {
        // Borrowed from the target, not from `self` (no clone per instruction).
        let target = self.target;
        let spec = target.instructions.get(id);
        let m = spec.mnemonic.as_str();
        let fixed = spec.operands.len();
        let count_ok = if spec.call_arguments {
            ops.len() >= fixed
        } else {
            ops.len() == fixed
        };
        if !count_ok {
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
            let at = if ops.is_empty() {
                mnemonic_span
            } else {
                ops[0].span.to(ops[ops.len() - 1].span)
            };
            self.report(
                Diagnostic::new(
                    Code::OperandCount,
                    at,
                    format!("`{m}` takes {want}, found {}", ops.len()),
                )
                .help(if spec.example.is_empty() {
                    spec.summary.clone()
                } else {
                    format!("for example: {}", spec.example.lines().next().unwrap_or(""))
                }),
            );
            return None;
        }
        let mut out = Vec::with_capacity(ops.len());
        let mut ok = true;
        for (op, os) in ops.iter().zip(&spec.operands) {
            match self.operand(ui, op, os, m) {
                Some(c) => {
                    if let CheckedOperand::Label(n) = c {
                        if spec.flow != Flow::Always && !labels[ui].contains_key(&n) {
                            self.missing_label(ui, n, op.span, labels);
                            ok = false;
                        }
                    }
                    self.warnings(&spec.mnemonic, os, &c, op.span, coils, timers);
                    out.push(c);
                }
                None => ok = false,
            }
        }
        if spec.call_arguments {
            let callee = match out.first() {
                Some(CheckedOperand::Unit {
                    kind: BlockKind::Subroutine,
                    number,
                }) => self
                    .units
                    .iter()
                    .position(|u| u.kind == BlockKind::Subroutine && u.number == *number),
                _ => None,
            };
            if let Some(callee) = callee {
                calls.push(CallSite {
                    caller: ui,
                    callee,
                    span: ops[0].span,
                });
                match self.call_arguments(ui, callee, &ops[fixed..], ops[0].span) {
                    Some(args) => out.extend(args),
                    None => ok = false,
                }
            } else {
                ok = false;
            }
        }
        ok.then_some(CheckedInstruction {
            id,
            operands: out,
            span,
        })
    }

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

    fn warnings(
        &mut self,
        mnemonic: &str,
        spec: &OperandSpec,
        c: &CheckedOperand,
        span: Span,
        coils: &mut HashMap<(u8, u32, u8), Span>,
        timers: &mut HashMap<(u8, u32), Span>,
    ) {
        let CheckedOperand::Memory {
            address,
            use_: Use::Value,
            ..
        } = *c
        else {
            return;
        };
        if mnemonic == "=" && address.width == Width::Bit {
            let key = (address.slot, address.offset, address.bit);
            if let Some(first) = coils.insert(key, span) {
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
            if let Some(first) = timers.insert(key, span) {
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

    /// Arguments of `CALL` against the callee's VAR_INPUT, VAR_IN_OUT, VAR_OUTPUT.
    fn call_arguments(
        &mut self,
        caller: usize,
        callee: usize,
        args: &[crate::syntax::ast::Operand],
        callee_span: Span,
    ) -> Option<Vec<CheckedOperand>> {
        let params: Vec<super::Local> = self.units[callee]
            .locals
            .iter()
            .filter(|l| l.section != VarSection::Temp)
            .cloned()
            .collect();
        let name = self.units[callee].name.clone();
        if args.len() != params.len() {
            let list: Vec<String> = params
                .iter()
                .map(|p| format!("{} : {}", p.name, p.ty))
                .collect();
            let at = if args.is_empty() {
                callee_span
            } else {
                args[0].span.to(args[args.len() - 1].span)
            };
            self.report(
                Diagnostic::new(
                    Code::ArgumentCount,
                    at,
                    format!(
                        "{name} takes {} argument{}, found {}",
                        params.len(),
                        if params.len() == 1 { "" } else { "s" },
                        args.len()
                    ),
                )
                .help(if list.is_empty() {
                    format!("call it as `CALL {name}`")
                } else {
                    format!("parameters in order: {}", list.join(", "))
                }),
            );
            return None;
        }
        let mut out = Vec::new();
        let mut ok = true;
        for (arg, p) in args.iter().zip(&params) {
            let role = match p.section {
                VarSection::Input => Role::In,
                VarSection::InOut => Role::InOut,
                _ => Role::Out,
            };
            let types = if p.ty.width() == Width::Bit {
                vec![DataType::Bool]
            } else {
                vec![p.ty]
            };
            let spec = OperandSpec {
                name: p.name.clone(),
                role,
                kind: SpecKind::Data,
                types,
                areas: None,
                constant: role == Role::In,
                pointer: p.ty != DataType::Bool,
                address_of: p.ty == DataType::Dword || p.ty == DataType::Udint,
                min: None,
                max: None,
                block: None,
            };
            let before = self.diags.len();
            match self.operand(caller, arg, &spec, &format!("CALL {name}")) {
                Some(c) => out.push(c),
                None => {
                    ok = false;
                    // Argument problems carry the argument code, with the parameter named.
                    for d in &mut self.diags[before..] {
                        if matches!(
                            d.code,
                            Code::WidthMismatch
                                | Code::TypeMismatch
                                | Code::WriteToReadOnly
                                | Code::ConstantNotAllowed
                        ) {
                            d.code = Code::ArgumentMismatch;
                            d.severity = Code::ArgumentMismatch.severity();
                        }
                    }
                }
            }
        }
        ok.then_some(out)
    }

    fn call_graph(&mut self, calls: &[CallSite]) {
        let n = self.units.len();
        let mut edges: Vec<Vec<(usize, Span)>> = vec![Vec::new(); n];
        for c in calls {
            edges[c.caller].push((c.callee, c.span));
        }
        // Recursion: a cycle through the call graph.
        let mut reported = vec![false; n];
        for start in 0..n {
            let mut stack = vec![(start, 0usize)];
            let mut on_path = vec![false; n];
            on_path[start] = true;
            while let Some(&mut (node, ref mut next)) = stack.last_mut() {
                if *next < edges[node].len() {
                    let (to, span) = edges[node][*next];
                    *next += 1;
                    if to == start && !reported[start] {
                        reported[start] = true;
                        let name = self.units[start].name.clone();
                        self.report(
                            Diagnostic::new(
                                Code::CallCycle,
                                span,
                                format!(
                                    "{name} calls itself (directly or through other subroutines)"
                                ),
                            )
                            .help("the PLC cannot run recursive subroutines"),
                        );
                    } else if !on_path[to] && stack.len() < n {
                        on_path[to] = true;
                        stack.push((to, 0));
                    }
                } else {
                    on_path[node] = false;
                    stack.pop();
                }
            }
        }
        // Depth from each interrupt routine (only without cycles).
        if !reported.iter().any(|r| *r) {
            let limit = self.target.instructions.call_depth as usize;
            fn depth(
                u: usize,
                edges: &[Vec<(usize, Span)>],
                memo: &mut Vec<Option<usize>>,
            ) -> usize {
                if let Some(d) = memo[u] {
                    return d;
                }
                memo[u] = Some(0);
                let d = edges[u]
                    .iter()
                    .map(|(v, _)| 1 + depth(*v, edges, memo))
                    .max()
                    .unwrap_or(0);
                memo[u] = Some(d);
                d
            }
            let mut memo = vec![None; n];
            for u in 0..n {
                if self.units[u].kind == BlockKind::Interrupt {
                    let d = depth(u, &edges, &mut memo);
                    if d > limit {
                        let span = self.out.definitions[self.units[u].definition].span;
                        let name = self.units[u].name.clone();
                        self.report(Diagnostic::new(
                            Code::CallCycle,
                            span,
                            format!("calls from {name} nest {d} deep; the PLC allows {limit}"),
                        ));
                    }
                }
            }
        }
        for u in 0..n {
            if self.units[u].kind == BlockKind::Subroutine
                && !calls.iter().any(|c| c.callee == u && c.caller != u)
            {
                let span = self.out.definitions[self.units[u].definition].span;
                let name = self.units[u].name.clone();
                self.report(Diagnostic::new(
                    Code::UnusedSubroutine,
                    span,
                    format!("subroutine {name} is never called"),
                ));
            }
        }
    }
}
