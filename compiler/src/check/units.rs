//! Program units: numbering (MAIN = INT0, INTn, SBRn), duplicate names, PlcType
//! limits on counts and numbers (`gutta_catalog::rules`, as the verifier), and the
//! locals of each unit laid out in L (`rules::LocalLayout`).

use std::collections::HashMap;

use gutta_catalog::rules::{self, LocalLayout};
use gutta_catalog::{Address, AreaKind, BlockKind, DataType};

use super::{Checker, DefKind, Local, UnitInfo};
use crate::diagnostics::{Code, Diagnostic, Suggestion};
use crate::source::Span;
use crate::syntax::ast::{self, BlockPrefix, VarSection};

/// Where a unit's locals go in L.
struct LocalPlacement {
    slot: u8,
    size: u32,
    layout: LocalLayout,
    /// Locals past the end of L are reported once.
    reported_size: bool,
}

/// `INT0`, `INT3`, `SBR0`: the numbered name (MAIN's is INT0).
fn numbered_name(kind: BlockKind, number: u32) -> String {
    match kind {
        BlockKind::Interrupt => format!("INT{number}"),
        BlockKind::Subroutine => format!("SBR{number}"),
    }
}

impl Checker<'_> {
    pub(super) fn units(&mut self) {
        let numbers = self.unit_numbers();
        // Units of each kind so far: interrupt routines, subroutines.
        let mut counts = [0u32; 2];
        for (i, number) in numbers.into_iter().enumerate() {
            self.unit(i, number, &mut counts);
        }
        if !self
            .units
            .iter()
            .any(|u| u.kind == BlockKind::Interrupt && u.number == 0)
        {
            let help = self.conventions.missing_main_help.as_deref().unwrap_or(
                "add `ORGANIZATION_BLOCK MAIN:OB1` ... `BEGIN` ... `END_ORGANIZATION_BLOCK`",
            );
            self.report(
                Diagnostic::new(
                    Code::MissingMain,
                    Span::default(),
                    "the program has no MAIN",
                )
                .help(help),
            );
        }
    }

    /// Every unit's number: as its header writes it, else the next free number of its
    /// kind (from 1 for interrupt routines, 0 for subroutines), in file order.
    fn unit_numbers(&mut self) -> Vec<u32> {
        let ast = self.ast;
        let numbers: Vec<Option<u32>> = ast.units.iter().map(|u| self.written_number(u)).collect();
        let taken = |kind: BlockKind, n: u32, numbers: &[Option<u32>]| {
            numbers
                .iter()
                .zip(&ast.units)
                .any(|(m, u)| u.kind == kind && *m == Some(n))
        };
        let mut numbers = numbers;
        for i in 0..ast.units.len() {
            if numbers[i].is_none() {
                let kind = ast.units[i].kind;
                let first = if kind == BlockKind::Interrupt { 1 } else { 0 };
                numbers[i] = (first..).find(|n| !taken(kind, *n, &numbers));
            }
        }
        numbers.into_iter().map(|n| n.unwrap_or(0)).collect()
    }

    /// The number a unit's header writes (`MAIN`, `OB1`, `INTn`, `SBRn`), if any.
    fn written_number(&mut self, u: &ast::Unit) -> Option<u32> {
        let name = self.slice(u.header.name);
        match (u.kind, u.header.number) {
            (BlockKind::Interrupt, None) if name.eq_ignore_ascii_case("MAIN") => Some(0),
            (_, None) => None,
            (BlockKind::Interrupt, Some((n, _)))
                if n.prefix == BlockPrefix::Ob && n.number == 1 =>
            {
                Some(0)
            }
            (BlockKind::Interrupt, Some((n, _))) if n.prefix == BlockPrefix::Int => Some(n.number),
            (BlockKind::Subroutine, Some((n, _))) if n.prefix == BlockPrefix::Sbr => Some(n.number),
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
        }
    }

    /// Unit `i` of the file with its number: limits, definition, names, locals.
    fn unit(&mut self, i: usize, number: u32, counts: &mut [u32; 2]) {
        let u = &self.ast.units[i];
        let name_text = self.slice(u.header.name).to_string();
        let name = match (name_text.is_empty(), u.kind) {
            (false, _) => name_text,
            (true, BlockKind::Interrupt) if number == 0 => "MAIN".to_string(),
            (true, kind) => numbered_name(kind, number),
        };
        let numbered = numbered_name(u.kind, number);
        let name_span = if u.header.name.is_empty() {
            u.header.span
        } else {
            u.header.name
        };
        self.unit_limits(u, number, &numbered, name_span, counts);
        let detail = match u.kind {
            BlockKind::Interrupt if number == 0 => format!("MAIN (INT0) {name}"),
            _ => format!("{numbered} {name}"),
        };
        let def = self.define(name.clone(), DefKind::Unit, name_span, detail, None);
        let index = self.units.len();
        let number_span = u.header.number.map(|(_, s)| s);
        self.unit_names(
            index,
            &name,
            numbered,
            u.kind,
            number,
            HeaderSpans {
                name: name_span,
                number: number_span,
            },
        );
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

    /// The PlcType limits: how many units of a kind, and which numbers.
    fn unit_limits(
        &mut self,
        u: &ast::Unit,
        number: u32,
        numbered: &str,
        name_span: Span,
        counts: &mut [u32; 2],
    ) {
        let plc = &self.target.plc;
        let (limit, limit_name) = rules::unit_limit(plc, u.kind);
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
        } else if !rules::unit_exists(plc, u.kind, number) {
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
    }

    /// Register a unit's names (symbolic and numbered; MAIN also as MAIN and OB1),
    /// reporting the first one another unit has already.
    fn unit_names(
        &mut self,
        index: usize,
        name: &str,
        numbered: String,
        kind: BlockKind,
        number: u32,
        spans: HeaderSpans,
    ) {
        let HeaderSpans {
            name: name_span,
            number: number_span,
        } = spans;
        let mut keys = vec![name.to_ascii_uppercase(), numbered];
        if number == 0 && kind == BlockKind::Interrupt {
            keys.push("MAIN".into());
            keys.push("OB1".into());
        }
        keys.sort();
        keys.dedup();
        let symbolic = name.to_ascii_uppercase();
        for key in keys {
            if let Some(&other) = self.unit_names.get(&key) {
                // A numbered name (or MAIN's other names) collides: point at the
                // numbered part of both headers (`INT0` of `INT_0:INT0`), not the name.
                let by_number = key != symbolic;
                let numbered_span = |u: &ast::Unit| u.header.number.map(|(_, s)| s);
                let at = match number_span {
                    Some(s) if by_number => s,
                    _ => name_span,
                };
                let other_unit = &self.ast.units[self.units[other].ast_index];
                let first = match numbered_span(other_unit) {
                    Some(s) if by_number => s,
                    _ => self.out.definitions[self.units[other].definition].span,
                };
                let d = if by_number && number == 0 && kind == BlockKind::Interrupt {
                    Diagnostic::new(
                        Code::DuplicateBlock,
                        at,
                        format!(
                            "block `{key}` is defined twice: GUTTA's MAIN is INT0 (also written OB1), so an interrupt routine INT0 collides with MAIN"
                        ),
                    )
                    .label("MAIN is INT0")
                    .help("an S7-200 program's own INT0 needs another number here (INT1 and up)")
                } else {
                    Diagnostic::new(
                        Code::DuplicateBlock,
                        at,
                        format!("block `{key}` is defined twice"),
                    )
                };
                self.report(d.with_secondary(first, "first defined here"));
                break;
            }
            self.unit_names.insert(key, index);
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
        let mut place = LocalPlacement {
            slot: l_area.slot,
            size: l_area.size,
            layout: LocalLayout::new(),
            reported_size: false,
        };
        let (max_args, max_name) = rules::locals_limit(&self.target.plc, kind);
        // Order in L: inputs, in-outs, outputs, temporaries (stable within a section).
        let mut order: Vec<usize> = (0..u.vars.len()).collect();
        order.sort_by_key(|&i| u.vars[i].section);
        let mut seen: HashMap<String, Span> = HashMap::new();
        let mut locals = Vec::new();
        let mut defs = Vec::new();
        for (count, i) in order.into_iter().enumerate() {
            let v = &u.vars[i];
            let Some(ty) = self.local_type(v, kind) else {
                continue;
            };
            let name = self.slice(v.name).to_string();
            let key = name.to_ascii_uppercase();
            if let Some(&first) = seen.get(&key) {
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
                let plc = &self.target.plc;
                let per = match kind {
                    BlockKind::Subroutine => "subroutine",
                    BlockKind::Interrupt => "interrupt routine",
                };
                self.report(Diagnostic::new(
                    Code::TooManyArguments,
                    v.name,
                    format!(
                        "too many locals: {} allows {max_args} per {per} ({max_name})",
                        plc.name
                    ),
                ));
            }
            let address = self.place_local(v, ty, &mut place);
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

    /// The local's place in L; the first local past the end of L is reported.
    fn place_local(
        &mut self,
        v: &ast::VarDecl,
        ty: DataType,
        place: &mut LocalPlacement,
    ) -> Address {
        let width = ty.width();
        let (offset, bit) = place.layout.place(width);
        let address = Address {
            slot: place.slot,
            width,
            offset,
            bit,
        };
        let end = offset + width.bytes();
        if end > place.size && !place.reported_size {
            place.reported_size = true;
            let (plc, size) = (&self.target.plc.name, place.size);
            self.report(
                Diagnostic::new(
                    Code::LocalsTooLarge,
                    v.name,
                    format!("locals need {end} bytes of L; {plc} has {size}"),
                )
                .label("does not fit"),
            );
        }
        address
    }

    /// A local's type, if its section is one the unit may have and the type exists.
    fn local_type(&mut self, v: &ast::VarDecl, kind: BlockKind) -> Option<DataType> {
        if !rules::takes_parameters(kind) && v.section != VarSection::Temp {
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
            return None;
        }
        let ty_text = self.slice(v.ty);
        let Ok(ty) = ty_text.parse::<DataType>() else {
            let known: Vec<&str> = DataType::ALL.iter().map(|t| t.keyword()).collect();
            let hint = crate::suggest::closest(ty_text, known.iter().copied());
            self.report(
                Diagnostic::new(
                    Code::UnknownDataType,
                    v.ty,
                    format!("unknown data type `{ty_text}`"),
                )
                .maybe_suggest(hint.map(|h| Suggestion::new(v.ty, h))),
            );
            return None;
        };
        Some(ty)
    }
}

/// Where a block header names its block: the symbolic name (or the whole header when
/// there is none) and the numbered name (`INT0` of `INT_0:INT0`) if written.
#[derive(Debug, Clone, Copy)]
struct HeaderSpans {
    name: Span,
    number: Option<Span>,
}
