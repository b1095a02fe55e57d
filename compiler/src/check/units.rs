//! Program units: numbering (MAIN = INT0, INTn, SBRn), duplicate names, PlcType
//! limits on counts and numbers, and the locals of each unit laid out in L.

use gutta_catalog::{Address, AreaKind, BlockKind, DataType, Width};

use super::{Checker, DefKind, Local, UnitInfo};
use crate::diagnostics::{Code, Diagnostic};
use crate::source::Span;
use crate::syntax::ast::{BlockPrefix, VarSection};

impl Checker<'_> {
    pub(super) fn units(&mut self) {
        let ast = self.ast;
        let plc = &self.target.plc;
        // Pass 1: numbers written in headers.
        let mut numbers: Vec<Option<u32>> = Vec::with_capacity(ast.units.len());
        for u in &ast.units {
            let name = self.slice(u.header.name);
            let written = match (u.kind, u.header.number) {
                (_, None)
                    if u.kind == BlockKind::Interrupt && name.eq_ignore_ascii_case("MAIN") =>
                {
                    Some(0)
                }
                (_, None) => None,
                (BlockKind::Interrupt, Some((n, _)))
                    if n.prefix == BlockPrefix::Ob && n.number == 1 =>
                {
                    Some(0)
                }
                (BlockKind::Interrupt, Some((n, _))) if n.prefix == BlockPrefix::Int => {
                    Some(n.number)
                }
                (BlockKind::Subroutine, Some((n, _))) if n.prefix == BlockPrefix::Sbr => {
                    Some(n.number)
                }
                (kind, Some((n, span))) => {
                    let want = if kind == BlockKind::Subroutine {
                        "SBRn"
                    } else {
                        "OB1, INT0 (MAIN) or INTn"
                    };
                    self.report(
                        Diagnostic::new(
                            Code::BadBlockHeader,
                            span,
                            format!(
                                "`{}{}` does not fit this block",
                                n.prefix.as_str(),
                                n.number
                            ),
                        )
                        .help(format!("this block's numbered name is {want}")),
                    );
                    None
                }
            };
            numbers.push(written);
        }
        // Pass 2: unnumbered units take the next free number, in file order.
        let next_free =
            |kind: BlockKind, numbers: &[Option<u32>], ast: &crate::syntax::ast::Program| {
                let first = if kind == BlockKind::Interrupt { 1 } else { 0 };
                (first..)
                    .find(|n| {
                        !numbers
                            .iter()
                            .zip(&ast.units)
                            .any(|(m, u)| u.kind == kind && *m == Some(*n))
                    })
                    .unwrap_or(first)
            };
        for i in 0..ast.units.len() {
            if numbers[i].is_none() {
                numbers[i] = Some(next_free(ast.units[i].kind, &numbers, ast));
            }
        }
        let mut counts = [0u32; 2];
        for (i, u) in ast.units.iter().enumerate() {
            let number = numbers[i].unwrap_or(0);
            let name_text = self.slice(u.header.name).to_string();
            let name = if name_text.is_empty() {
                match u.kind {
                    BlockKind::Interrupt if number == 0 => "MAIN".to_string(),
                    BlockKind::Interrupt => format!("INT{number}"),
                    BlockKind::Subroutine => format!("SBR{number}"),
                }
            } else {
                name_text
            };
            let numbered = match (u.kind, number) {
                (BlockKind::Interrupt, 0) => "INT0".to_string(),
                (BlockKind::Interrupt, n) => format!("INT{n}"),
                (BlockKind::Subroutine, n) => format!("SBR{n}"),
            };
            let name_span = if u.header.name.is_empty() {
                u.header.span
            } else {
                u.header.name
            };
            // Limits by number.
            let (limit, limit_name) = match u.kind {
                BlockKind::Interrupt => {
                    (plc.program_block_page_int_size, "ProgramBlockPageIntSize")
                }
                BlockKind::Subroutine => {
                    (plc.program_block_page_sbr_size, "ProgramBlockPageSbrSize")
                }
            };
            let kind_ix = usize::from(u.kind == BlockKind::Subroutine);
            counts[kind_ix] += 1;
            if counts[kind_ix] > limit {
                let (code, what) = match u.kind {
                    BlockKind::Interrupt => (
                        Code::TooManyInterrupts,
                        "interrupt routines (MAIN included)",
                    ),
                    BlockKind::Subroutine => (Code::TooManySubroutines, "subroutines"),
                };
                self.report(
                    Diagnostic::new(
                        code,
                        u.header.span,
                        format!(
                            "too many {what}: {} allows {limit} ({limit_name})",
                            plc.name
                        ),
                    )
                    .label(format!("number {} of its kind", counts[kind_ix])),
                );
            } else if number >= limit {
                let span = u.header.number.map(|(_, s)| s).unwrap_or(name_span);
                self.report(
                    Diagnostic::new(
                        Code::BlockNumberRange,
                        span,
                        format!(
                            "{numbered} is out of range: {} allows {} numbers 0..{} ({limit_name})",
                            plc.name,
                            if u.kind == BlockKind::Subroutine {
                                "SBR"
                            } else {
                                "INT"
                            },
                            limit.saturating_sub(1)
                        ),
                    )
                    .label("number too large"),
                );
            }
            let detail = match u.kind {
                BlockKind::Interrupt if number == 0 => format!("MAIN (INT0) {name}"),
                _ => format!("{numbered} {name}"),
            };
            let def = self.define(name.clone(), DefKind::Unit, name_span, detail, None);
            let index = self.units.len();
            // Duplicate names: symbolic and numbered.
            let mut keys = vec![name.to_ascii_uppercase(), numbered.clone()];
            if number == 0 && u.kind == BlockKind::Interrupt {
                keys.push("MAIN".into());
                keys.push("OB1".into());
            }
            keys.sort();
            keys.dedup();
            for key in keys {
                if let Some(&other) = self.unit_names.get(&key) {
                    let first = self.out.definitions[self.units[other].definition].span;
                    self.report(
                        Diagnostic::new(
                            Code::DuplicateBlock,
                            name_span,
                            format!("block `{key}` is defined twice"),
                        )
                        .with_secondary(first, "first defined here"),
                    );
                    break;
                }
                self.unit_names.insert(key, index);
            }
            let (locals, local_defs) = self.locals(i, index, u.kind);
            self.units.push(UnitInfo {
                kind: u.kind,
                number,
                name,
                ast_index: i,
                locals,
                local_defs,
                definition: def,
            });
        }
        if !self
            .units
            .iter()
            .any(|u| u.kind == BlockKind::Interrupt && u.number == 0)
        {
            self.report(
                Diagnostic::new(
                    Code::MissingMain,
                    Span::default(),
                    "the program has no MAIN",
                )
                .help("add `ORGANIZATION_BLOCK MAIN:OB1` ... `BEGIN` ... `END_ORGANIZATION_BLOCK`"),
            );
        }
    }

    /// Types, duplicates and L layout of a unit's locals.
    fn locals(
        &mut self,
        ast_index: usize,
        unit_index: usize,
        kind: BlockKind,
    ) -> (Vec<Local>, Vec<usize>) {
        let ast = self.ast;
        let u = &ast.units[ast_index];
        let Some(l_area) = self.target.memory.area_of_kind(AreaKind::Local) else {
            return (Vec::new(), Vec::new());
        };
        let (l_slot, l_size) = (l_area.slot, l_area.size);
        let plc = &self.target.plc;
        let (max_args, max_name) = match kind {
            BlockKind::Interrupt => (
                plc.program_block_page_arg_int_size,
                "ProgramBlockPageArgIntSize",
            ),
            BlockKind::Subroutine => (
                plc.program_block_page_arg_sbr_size,
                "ProgramBlockPageArgSbrSize",
            ),
        };
        // Order in L: inputs, in-outs, outputs, temporaries (stable within a section).
        let mut order: Vec<usize> = (0..u.vars.len()).collect();
        order.sort_by_key(|&i| u.vars[i].section);
        let mut seen: std::collections::HashMap<String, Span> = std::collections::HashMap::new();
        let mut locals = Vec::new();
        let mut defs = Vec::new();
        let (mut byte, mut bit) = (0u32, 0u8);
        let mut reported_size = false;
        for (count, i) in order.into_iter().enumerate() {
            let v = &u.vars[i];
            let name = self.slice(v.name).to_string();
            if kind == BlockKind::Interrupt && v.section != VarSection::Temp {
                self.report(
                    Diagnostic::new(
                        Code::InterruptArguments,
                        v.name,
                        format!(
                            "interrupt routines take no {} parameters",
                            v.section.keyword()
                        ),
                    )
                    .help("declare temporaries in a `VAR` section"),
                );
                continue;
            }
            let ty_text = self.slice(v.ty);
            let Ok(ty) = ty_text.parse::<DataType>() else {
                let known: Vec<&str> = DataType::ALL.iter().map(|t| t.keyword()).collect();
                let hint = super::suggest::closest(ty_text, known.iter().copied());
                self.report(
                    Diagnostic::new(
                        Code::UnknownDataType,
                        v.ty,
                        format!("unknown data type `{ty_text}`"),
                    )
                    .maybe_help(hint.map(|h| format!("did you mean `{h}`?"))),
                );
                continue;
            };
            let key = name.to_ascii_uppercase();
            if let Some(first) = seen.get(&key) {
                let first = *first;
                self.report(
                    Diagnostic::new(
                        Code::DuplicateLocal,
                        v.name,
                        format!("local `{name}` is declared twice"),
                    )
                    .with_secondary(first, "first declared here"),
                );
                continue;
            }
            seen.insert(key, v.name);
            if count as u32 >= max_args {
                self.report(Diagnostic::new(
                    Code::TooManyArguments,
                    v.name,
                    format!(
                        "too many locals: {} allows {max_args} per {} ({max_name})",
                        plc.name,
                        if kind == BlockKind::Subroutine {
                            "subroutine"
                        } else {
                            "interrupt routine"
                        }
                    ),
                ));
            }
            let width = ty.width();
            let address = if width == Width::Bit {
                if bit == 8 {
                    byte += 1;
                    bit = 0;
                }
                let a = Address {
                    slot: l_slot,
                    width,
                    offset: byte,
                    bit,
                };
                bit += 1;
                a
            } else {
                if bit > 0 {
                    byte += 1;
                    bit = 0;
                }
                let a = Address {
                    slot: l_slot,
                    width,
                    offset: byte,
                    bit: 0,
                };
                byte += width.bytes();
                a
            };
            let end = address.offset + width.bytes();
            if end > l_size && !reported_size {
                reported_size = true;
                self.report(
                    Diagnostic::new(
                        Code::LocalsTooLarge,
                        v.name,
                        format!("locals need {end} bytes of L; {} has {l_size}", plc.name),
                    )
                    .label("does not fit"),
                );
            }
            let at = self.target.memory.format_address(&address);
            let detail = format!("#{name} : {ty} ({}, {at})", v.section.keyword());
            let def = self.define(
                name.clone(),
                DefKind::Local,
                v.name,
                detail,
                Some(unit_index),
            );
            locals.push(Local {
                name,
                section: v.section,
                ty,
                address,
                span: v.name,
            });
            defs.push(def);
        }
        (locals, defs)
    }
}
