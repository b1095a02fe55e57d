//! CALL: the arguments against the callee's VAR_INPUT, VAR_IN_OUT and VAR_OUTPUT
//! (each an operand spec made by `gutta_catalog::rules::parameter_spec`, the one the
//! verifier uses), and the call graph: recursion, nesting depth, unused subroutines.

use gutta_catalog::{rules, BlockKind, Role};

use super::{CheckedOperand, Checker};
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
use crate::syntax::ast::{Operand, VarSection};

/// A CALL site, for the call graph.
pub(super) struct CallSite {
    pub caller: usize,
    pub callee: usize,
    pub span: Span,
}

impl Checker<'_> {
    /// Arguments of `CALL` against the callee's VAR_INPUT, VAR_IN_OUT, VAR_OUTPUT.
    pub(super) fn call_arguments(
        &mut self,
        caller: usize,
        callee: usize,
        args: &[Operand],
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
            let spec = rules::parameter_spec(p.name.clone(), role, p.ty);
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

    /// Recursion, call depth from each interrupt routine, subroutines never called.
    pub(super) fn call_graph(&mut self, calls: &[CallSite]) {
        let mut edges: Vec<Vec<(usize, Span)>> = vec![Vec::new(); self.units.len()];
        for c in calls {
            edges[c.caller].push((c.callee, c.span));
        }
        // Depths only mean something without cycles.
        if !self.recursion(&edges) {
            self.call_depths(&edges);
        }
        self.unused_subroutines(calls);
    }

    /// Report each unit that reaches itself through CALLs; whether there was one.
    fn recursion(&mut self, edges: &[Vec<(usize, Span)>]) -> bool {
        let n = edges.len();
        let mut reported = vec![false; n];
        for start in 0..n {
            let mut stack = vec![(start, 0usize)];
            let mut on_path = vec![false; n];
            on_path[start] = true;
            while let Some(&mut (node, ref mut next)) = stack.last_mut() {
                let Some(&(to, span)) = edges[node].get(*next) else {
                    on_path[node] = false;
                    stack.pop();
                    continue;
                };
                *next += 1;
                if to == start && !reported[start] {
                    reported[start] = true;
                    let name = self.units[start].name.clone();
                    self.report(
                        Diagnostic::new(
                            Code::CallCycle,
                            span,
                            format!("{name} calls itself (directly or through other subroutines)"),
                        )
                        .help("the PLC cannot run recursive subroutines"),
                    );
                } else if !on_path[to] && stack.len() < n {
                    on_path[to] = true;
                    stack.push((to, 0));
                }
            }
        }
        reported.contains(&true)
    }

    /// Calls from each interrupt routine nest at most `CallDepth` deep (the graph has
    /// no cycles).
    fn call_depths(&mut self, edges: &[Vec<(usize, Span)>]) {
        fn depth(u: usize, edges: &[Vec<(usize, Span)>], memo: &mut Vec<Option<usize>>) -> usize {
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
        let limit = self.target.instructions.call_depth as usize;
        let mut memo = vec![None; edges.len()];
        for u in 0..edges.len() {
            if self.units[u].kind != BlockKind::Interrupt {
                continue;
            }
            let d = depth(u, edges, &mut memo);
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

    /// W-code: a subroutine no other unit calls.
    fn unused_subroutines(&mut self, calls: &[CallSite]) {
        for u in 0..self.units.len() {
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
