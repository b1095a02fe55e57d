//! Navigation over a checked program: what is at a byte offset, its definition, its
//! uses (in every file of the program), and the hover text that explains it. Plain data
//! over `&CheckedFile` and byte offsets in the joined text; no LSP types, no I/O.

use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;

use gutta_catalog::{Address, InstrId, OperandKind as SpecKind};

use gutta_compiler::check::{DefKind, Definition, Reference};
use gutta_compiler::source::Span;
use gutta_compiler::syntax::ast::{OperandKind, SymbolDecl, Unit, VarSection};
use gutta_compiler::CheckedFile;

use crate::inlay::symbol_addresses;
use crate::timers;

/// What the text at an offset is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Item {
    /// An instruction's mnemonic.
    Mnemonic(InstrId),
    /// A definition (index into `output.definitions`), at its definition or a use.
    Definition(usize),
    /// A direct address in an operand.
    Address(Address),
}

/// How a use touches its definition, for highlighting.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    /// The definition itself.
    Declaration,
    /// An operand the instruction only reads (or a name that is not an operand).
    Read,
    /// An operand the instruction writes.
    Write,
}

/// The item at `offset` and the span of its text there.
pub fn item_at(checked: &CheckedFile, offset: usize) -> Option<(Span, Item)> {
    let out = &checked.output;
    if let Some((span, id)) = out.mnemonics.iter().find(|(s, _)| s.contains(offset)) {
        return Some((*span, Item::Mnemonic(*id)));
    }
    if let Some((span, def)) = definition_at(checked, offset) {
        return Some((span, Item::Definition(def)));
    }
    out.addresses
        .iter()
        .find(|(s, _)| s.contains(offset))
        .map(|(s, a)| (*s, Item::Address(*a)))
}

/// The definition named at `offset` (a use, or the definition's own name) and the
/// span of that name.
pub fn definition_at(checked: &CheckedFile, offset: usize) -> Option<(Span, usize)> {
    let out = &checked.output;
    uses(checked)
        .into_iter()
        .find(|r| r.span.contains(offset))
        .map(|r| (r.span, r.definition))
        .or_else(|| {
            out.definitions
                .iter()
                .position(|d| d.span.contains(offset) && !d.span.is_empty())
                .map(|i| (out.definitions[i].span, i))
        })
}

/// Every use of every definition: the checker's references, plus `JMP n` naming the
/// `LBL n` of its own block.
pub fn uses(checked: &CheckedFile) -> Vec<Reference> {
    let mut all = checked.output.references.clone();
    all.extend(label_uses(checked));
    all
}

/// The definition and every use of the definition at `offset`, the definition first,
/// then the uses in text order (across every file of the program). For a direct
/// address: every operand naming the same address, in text order.
pub fn references_at(checked: &CheckedFile, offset: usize) -> Vec<(Span, Access)> {
    let writes = written_operands(checked);
    let access = |span: Span| {
        if writes
            .get(&span.end)
            .is_some_and(|start| *start <= span.start)
        {
            Access::Write
        } else {
            Access::Read
        }
    };
    let Some((_, def)) = definition_at(checked, offset) else {
        let addresses = &checked.output.addresses;
        let Some((_, a)) = addresses.iter().find(|(s, _)| s.contains(offset)) else {
            return Vec::new();
        };
        let mut found: Vec<(Span, Access)> = addresses
            .iter()
            .filter(|(_, x)| x == a)
            .map(|(s, _)| (*s, access(*s)))
            .collect();
        found.sort_by_key(|(s, _)| (s.start, s.end));
        found.dedup_by_key(|(s, _)| *s);
        return found;
    };
    let mut found: Vec<(Span, Access)> = uses(checked)
        .into_iter()
        .filter(|r| r.definition == def)
        .map(|r| {
            let written = writes
                .get(&r.span.end)
                .is_some_and(|start| *start <= r.span.start);
            let access = if written { Access::Write } else { Access::Read };
            (r.span, access)
        })
        .collect();
    found.sort_by_key(|(s, _)| (s.start, s.end));
    found.dedup_by_key(|(s, _)| *s);
    let mut all = vec![(checked.output.definitions[def].span, Access::Declaration)];
    all.extend(found);
    all
}

/// Markdown that explains the item at `offset`, and the span it explains. A timer (its
/// address, a symbol naming it, or a constant preset of its box) also gets what its
/// boxes say: kind, resolution, preset as a duration (`timers.rs`).
pub fn hover(checked: &CheckedFile, offset: usize) -> Option<(Span, String)> {
    let Some((span, item)) = item_at(checked, offset) else {
        let preset = timers::preset_at(checked, offset)?;
        return Some((preset, timers::timer_note(checked, offset, None)?));
    };
    let mut text = match item {
        Item::Mnemonic(id) => instruction_hover(checked, id),
        Item::Definition(def) => definition_hover(checked, def),
        Item::Address(a) => address_hover(checked, &a),
    };
    let address = match item {
        Item::Address(a) => Some(a),
        Item::Definition(def) => symbol_addresses(checked).get(&def).copied(),
        Item::Mnemonic(_) => None,
    };
    if let Some(note) = timers::timer_note(checked, offset, address) {
        text = format!("{text}\n\n{note}");
    }
    // An S7-200 timer or counter bit of a Micro/WIN export: what it compiles to.
    if let Some((_, note)) = checked
        .microwin
        .iter()
        .flat_map(|m| &m.bits)
        .find(|(s, _)| s.start as usize <= offset && offset <= s.end as usize)
    {
        text = format!("{text}\n\n{note}");
    }
    Some((span, text))
}

/// Operands an instruction writes, by the end of their span (a name's span ends
/// where its operand's does, after any `#`, `&` or `*`) -> the operand's start. A
/// CALL's arguments are written where the callee's parameter is VAR_OUTPUT or
/// VAR_IN_OUT.
fn written_operands(checked: &CheckedFile) -> HashMap<u32, u32> {
    let set = &checked.target.instructions;
    let defs = &checked.output.definitions;
    // Uses by the end of their span (which is their operand's end).
    let use_at: HashMap<u32, usize> = checked
        .output
        .references
        .iter()
        .map(|r| (r.span.end, r.definition))
        .collect();
    let mut spans = HashMap::new();
    for_each_instruction(checked, |id, operands| {
        let ins = set.get(id);
        for (spec, op) in ins.operands.iter().zip(operands) {
            if spec.role.writes() {
                spans.insert(op.span.end, op.span.start);
            }
        }
        if !ins.call_arguments {
            return;
        }
        // The callee: the block the first operand names.
        let callee = operands.first().and_then(|op| {
            let def = defs.get(*use_at.get(&op.span.end)?)?;
            unit_defined_at(checked, def.span)
        });
        let Some(callee) = callee else { return };
        let params = callee.vars.iter().filter(|v| v.section != VarSection::Temp);
        let args = operands.iter().skip(ins.operands.len());
        for (param, arg) in params.zip(args) {
            if matches!(param.section, VarSection::Output | VarSection::InOut) {
                spans.insert(arg.span.end, arg.span.start);
            }
        }
    });
    spans
}

/// Call `f` with every checked instruction's id and its operands.
fn for_each_instruction(
    checked: &CheckedFile,
    mut f: impl FnMut(InstrId, &[gutta_compiler::syntax::ast::Operand]),
) {
    let mnemonics: HashMap<Span, InstrId> = checked.output.mnemonics.iter().copied().collect();
    for unit in &checked.ast.units {
        for network in &unit.networks {
            for ins in &network.instructions {
                let Some(id) = mnemonics.get(&ins.mnemonic) else {
                    continue;
                };
                let (a, b) = (ins.operands.0 as usize, ins.operands.1 as usize);
                if let Some(ops) = network.operands.get(a..b) {
                    f(*id, ops);
                }
            }
        }
    }
}

/// `JMP n` (any label operand that is not the `LBL n` definition itself) as a use of
/// the `LBL n` in the same block.
fn label_uses(checked: &CheckedFile) -> Vec<Reference> {
    let set = &checked.target.instructions;
    let defs = &checked.output.definitions;
    let extents: Vec<Span> = checked.ast.units.iter().map(unit_extent).collect();
    let unit_of = |offset: u32| extents.iter().position(|s| s.contains(offset as usize));
    // (unit, label name) -> definition, and the LBL operands themselves.
    let mut labels: HashMap<(Option<usize>, &str), usize> = HashMap::new();
    let mut label_defs: HashSet<Span> = HashSet::new();
    for (i, d) in defs.iter().enumerate() {
        if d.kind == DefKind::Label {
            labels.insert((unit_of(d.span.start), d.name.as_str()), i);
            label_defs.insert(d.span);
        }
    }
    let mut found = Vec::new();
    if labels.is_empty() {
        return found;
    }
    for_each_instruction(checked, |id, operands| {
        let ins = set.get(id);
        for (spec, op) in ins.operands.iter().zip(operands) {
            let OperandKind::Integer(n) = op.kind else {
                continue;
            };
            if spec.kind != SpecKind::Label || label_defs.contains(&op.span) {
                continue;
            }
            let name = format!("LBL {n}");
            if let Some(def) = labels.get(&(unit_of(op.span.start), name.as_str())) {
                found.push(Reference {
                    span: op.span,
                    definition: *def,
                });
            }
        }
    });
    found
}

/// The text range of a program unit: its header to its END line (or its last code).
pub fn unit_extent(unit: &Unit) -> Span {
    let mut end = unit.header.span;
    if let Some(t) = unit.title {
        end = end.to(t);
    }
    for v in &unit.vars {
        end = end.to(v.name).to(v.ty);
    }
    for n in &unit.networks {
        end = end.to(n.span);
        if let Some(last) = n.instructions.last() {
            end = end.to(last.span);
        }
    }
    if let Some(e) = unit.end {
        end = end.to(e);
    }
    end
}

/// The unit whose name is defined at `span`.
fn unit_defined_at(checked: &CheckedFile, span: Span) -> Option<&Unit> {
    checked
        .ast
        .units
        .iter()
        .find(|u| u.header.name == span || (u.header.name.is_empty() && u.header.span == span))
}

fn symbol_decl_at(checked: &CheckedFile, span: Span) -> Option<&SymbolDecl> {
    checked.ast.symbols.iter().find(|d| d.name == span)
}

/// Where a definition is: `file:line`.
pub fn declared_where(checked: &CheckedFile, span: Span) -> String {
    let at = checked.file.locate(&checked.index, span.start as usize);
    format!("{}:{}", at.file, at.line)
}

fn instruction_hover(checked: &CheckedFile, id: InstrId) -> String {
    let ins = checked.target.instructions.get(id);
    let names: Vec<&str> = ins.operands.iter().map(|o| o.name.as_str()).collect();
    let mut text = format!("```gutta\n{} {}\n```\n", ins.mnemonic, names.join(", "));
    let _ = write!(text, "\n{}\n", ins.summary.trim());
    if !ins.operands.is_empty() {
        text.push_str("\n| operand | role | types |\n| --- | --- | --- |\n");
        for o in &ins.operands {
            let types = match o.kind {
                SpecKind::Label => "label number".to_string(),
                SpecKind::Block => match o.block {
                    Some(gutta_catalog::BlockKind::Interrupt) => "interrupt routine".into(),
                    _ => "subroutine".into(),
                },
                _ => o
                    .types
                    .iter()
                    .map(|t| t.keyword())
                    .collect::<Vec<_>>()
                    .join(", "),
            };
            let _ = writeln!(text, "| {} | {} | {} |", o.name, o.role.keyword(), types);
        }
    }
    if !ins.description.trim().is_empty() {
        let _ = write!(text, "\n{}\n", ins.description.trim());
    }
    let _ = write!(text, "\nAllowed in: {}.", ins.units.describe());
    text
}

fn definition_hover(checked: &CheckedFile, def: usize) -> String {
    let d = &checked.output.definitions[def];
    let mut text = match d.kind {
        DefKind::Symbol => symbol_hover(checked, d),
        DefKind::Local => format!("local variable `#{}`\n\n`{}`", d.name, d.detail),
        DefKind::Unit => unit_hover(checked, d),
        DefKind::DataBlock => format!("data block `{}`\n\n{}", d.name, d.detail),
        DefKind::Label => format!("`{}`: {}", d.name, d.detail),
    };
    if let (DefKind::Local | DefKind::Label, Some(unit)) = (d.kind, d.unit) {
        let owner = checked
            .output
            .definitions
            .iter()
            .filter(|x| x.kind == DefKind::Unit)
            .nth(unit);
        if let (DefKind::Local, Some(owner)) = (d.kind, owner) {
            let _ = write!(text, "\n\nin `{}`", owner.name);
        }
    }
    let _ = write!(text, "\n\ndeclared at {}", declared_where(checked, d.span));
    text
}

fn symbol_hover(checked: &CheckedFile, d: &Definition) -> String {
    let Some(decl) = symbol_decl_at(checked, d.span) else {
        return format!("symbol `{}`\n\n{}", d.name, d.detail);
    };
    let text = &checked.file.text;
    let memory = &checked.target.memory;
    let written = text.get(decl.address.range()).unwrap_or("").trim();
    let address = memory.parse_address(written).ok();
    let ty = decl
        .data_type
        .and_then(|t| text.get(t.range()))
        .map(str::trim)
        .filter(|t| !t.is_empty());
    let mut out = format!("symbol `{}`", d.name);
    match address {
        Some(a) => {
            let _ = write!(out, "\n\n`{}`", memory.format_address(&a));
            match ty {
                Some(t) => {
                    let _ = write!(out, " : {}", t.to_ascii_uppercase());
                }
                None => {
                    let _ = write!(out, " ({})", a.width.keyword());
                }
            }
            if let Some(m) = memory.modbus_location(&a) {
                let _ = write!(out, "\n\nModbus: {m}");
            }
        }
        None => {
            let _ = write!(out, "\n\n`{written}`");
        }
    }
    if let Some(c) = decl.comment_text(text).filter(|c| !c.is_empty()) {
        let _ = write!(out, "\n\n{c}");
    }
    out
}

fn unit_hover(checked: &CheckedFile, d: &Definition) -> String {
    let Some(unit) = unit_defined_at(checked, d.span) else {
        return format!("program block `{}`\n\n{}", d.name, d.detail);
    };
    let kind = match unit.kind {
        gutta_catalog::BlockKind::Subroutine => "subroutine",
        gutta_catalog::BlockKind::Interrupt => match d.detail.starts_with("MAIN") {
            true => "main program (organization block)",
            false => "interrupt routine",
        },
    };
    let mut out = format!("{kind} `{}`\n\n{}", d.name, d.detail);
    let text = &checked.file.text;
    if let Some(title) = unit.title.and_then(|t| text.get(t.range())) {
        let _ = write!(out, "\n\n{}", title.trim());
    }
    if !unit.vars.is_empty() {
        out.push_str("\n\n```gutta");
        let mut section = None;
        for v in &unit.vars {
            if section != Some(v.section) {
                if section.is_some() {
                    out.push_str("\nEND_VAR");
                }
                let _ = write!(out, "\n{}", v.section.keyword());
                section = Some(v.section);
            }
            let name = text.get(v.name.range()).unwrap_or("");
            let ty = text.get(v.ty.range()).unwrap_or("");
            let _ = write!(out, "\n  {name} : {ty};");
            if let Some(c) = v.comment.and_then(|c| text.get(c.range())) {
                let _ = write!(out, " // {}", c.trim());
            }
        }
        out.push_str("\nEND_VAR\n```");
    }
    let _ = match unit.networks.len() {
        1 => write!(out, "\n\n1 network"),
        n => write!(out, "\n\n{n} networks"),
    };
    out
}

/// Hover for a direct address: canonical name, width, area, Modbus address, and the
/// symbols naming it.
fn address_hover(checked: &CheckedFile, a: &Address) -> String {
    let memory = &checked.target.memory;
    let name = memory.format_address(a);
    let area = memory.area_by_slot(a.slot);
    let mut out = format!("`{name}`: {}", a.width.keyword());
    if let Some(area) = area {
        let _ = write!(out, " in {} ({})", area.name, area.description.trim());
    }
    if let Some(m) = memory.modbus_location(a) {
        let _ = write!(out, "\n\nModbus: {m}");
    }
    let text = &checked.file.text;
    let named: Vec<String> = checked
        .ast
        .symbols
        .iter()
        .filter(|d| {
            text.get(d.address.range())
                .and_then(|t| memory.parse_address(t.trim()).ok())
                .is_some_and(|x| x == *a)
        })
        .filter_map(|d| text.get(d.name.range()).map(|n| format!("`{n}`")))
        .collect();
    if !named.is_empty() {
        let _ = write!(out, "\n\nsymbol: {}", named.join(", "));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use gutta_compiler::source::SourceFile;
    use gutta_compiler::{check_program, ProgramSources};

    const MAIN: &str = "SYMBOLS\n  Start : I0.0 // push button\nEND_SYMBOLS\nORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1 // go\nLD     Start\nJMP    3\nCALL   ADD3, 2, 3, MW12\nLBL    3\nLD     Start\n=      Q0.0\nEND_ORGANIZATION_BLOCK\n";
    const SUB: &str = "SUBROUTINE_BLOCK ADD3:SBR0\nTITLE=r := a + b\nVAR_INPUT\n  a : INT; // first\n  b : INT;\nEND_VAR\nVAR_OUTPUT\n  r : INT;\nEND_VAR\nBEGIN\nNetwork 1\nLD     SM0.0\nMOVW   #a, #r\n+I     #b, #r\nEND_SUBROUTINE_BLOCK\n";
    const TABLE: &str = "Symbol,Address,Comment\nLamp,Q0.0,the lamp\n";

    fn program() -> CheckedFile {
        check_program(
            ProgramSources {
                sources: vec![
                    SourceFile::new("main.lad", MAIN),
                    SourceFile::new("sub.lad", SUB),
                ],
                symbol_tables: vec![SourceFile::new("symbols.csv", TABLE)],
                ..Default::default()
            },
            None,
        )
    }

    /// Offset in the joined text of the `n`th `needle` (plus `shift`).
    fn at(c: &CheckedFile, needle: &str, n: usize, shift: usize) -> usize {
        c.file.text.match_indices(needle).nth(n).unwrap().0 + shift
    }

    fn slices(c: &CheckedFile, spans: &[(Span, Access)]) -> Vec<(String, &'static str, Access)> {
        spans
            .iter()
            .map(|(s, a)| {
                let file = if c.file.file_name_at(s.start as usize) == "main.lad" {
                    "main"
                } else {
                    "other"
                };
                (c.file.slice(*s).to_string(), file, *a)
            })
            .collect()
    }

    #[test]
    fn the_program_checks_cleanly() {
        let c = program();
        assert_eq!(c.diagnostics(), &[]);
    }

    #[test]
    fn references_span_files_and_mark_writes() {
        let c = program();
        let refs = references_at(&c, at(&c, "Start", 1, 2));
        assert_eq!(
            slices(&c, &refs),
            [
                ("Start".into(), "main", Access::Declaration),
                ("Start".into(), "main", Access::Read),
                ("Start".into(), "main", Access::Read)
            ]
        );
        // `#r` is written by MOVW and +I (IN_OUT).
        let r = references_at(&c, at(&c, "#r", 0, 1));
        let kinds: Vec<Access> = r.iter().map(|(_, a)| *a).collect();
        assert_eq!(kinds, [Access::Declaration, Access::Write, Access::Write]);
        // A direct address: its operands (`=` writes it).
        let m = references_at(&c, at(&c, "Q0.0", 0, 1));
        assert_eq!(slices(&c, &m), [("Q0.0".into(), "main", Access::Write)]);
        // A CALL's argument for a VAR_OUTPUT is written, one for a VAR_INPUT read.
        let out = references_at(&c, at(&c, "MW12", 0, 1));
        assert_eq!(slices(&c, &out), [("MW12".into(), "main", Access::Write)]);
        // The call names the subroutine in the other file.
        let (span, def) = definition_at(&c, at(&c, "ADD3", 0, 1)).unwrap();
        assert_eq!(c.file.slice(span), "ADD3");
        assert_eq!(
            c.file
                .file_name_at(c.output.definitions[def].span.start as usize),
            "sub.lad"
        );
    }

    #[test]
    fn a_jump_goes_to_its_label() {
        let c = program();
        let (_, def) = definition_at(&c, at(&c, "JMP    3", 0, 7)).unwrap();
        let d = &c.output.definitions[def];
        assert_eq!(d.kind, DefKind::Label);
        assert_eq!(d.span.start as usize, at(&c, "LBL    3", 0, 7));
        let refs = references_at(&c, d.span.start as usize);
        assert_eq!(refs.len(), 2);
    }

    #[test]
    fn hovers_explain_instructions_symbols_addresses_blocks_and_locals() {
        let c = program();
        let texts = [
            hover(&c, at(&c, "MOVW", 0, 1)),
            hover(&c, at(&c, "Start", 1, 0)),
            hover(&c, at(&c, "Q0.0", 0, 1)),
            hover(&c, at(&c, "ADD3", 0, 0)),
            hover(&c, at(&c, "#a", 0, 1)),
            hover(&c, at(&c, "Lamp", 0, 0)),
            hover(&c, at(&c, "LBL    3", 0, 7)),
        ]
        .map(|h| h.map(|(_, t)| t).unwrap_or_default());
        insta::assert_snapshot!(texts.join("\n\n-----\n\n"));
    }

    #[test]
    fn an_s7_200_timer_bit_hover_says_what_it_compiles_to() {
        let text = "ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNetwork 1\nLD     I0.0\nTON    T33, +50\n\
                    Network 2\nLD     T33\n=      Q0.0\nEND_ORGANIZATION_BLOCK\n";
        let with = |scale| {
            gutta_compiler::check_program(
                ProgramSources {
                    sources: vec![SourceFile::new("main.awl", text)],
                    options: gutta_compiler::CompileOptions {
                        scale_timer_presets: scale,
                        ..Default::default()
                    },
                    ..Default::default()
                },
                Some(&gutta_compiler::ExplicitTarget {
                    target: gutta_catalog::stdlib::shared("CPU-EC20-M3").unwrap(),
                    origin: "--plc CPU-EC20-M3".into(),
                }),
            )
        };
        let c = with(false);
        let (_, h) = hover(&c, at(&c, "T33", 1, 1)).unwrap();
        assert!(
            h.ends_with(
                "S7-200 timer bit: compiled as `LDW>= T33, +50`, the bit of `TON    T33, +50`"
            ),
            "{h}"
        );
        let c = with(true);
        let (_, h) = hover(&c, at(&c, "T33", 1, 1)).unwrap();
        assert!(
            h.ends_with(
                "S7-200 timer bit: compiled as `LDW>= T33, 5`, the bit of `TON    T33, +50` (its preset +50, scaled)"
            ),
            "{h}"
        );
        // Not a bit: the TON's own operand has no such line.
        let (_, h) = hover(&c, at(&c, "T33", 0, 1)).unwrap();
        assert!(!h.contains("S7-200"), "{h}");
    }
}
