//! Completion: what may be written at the cursor, from its place in the grammar
//! (`place.rs`) and the target's tables: mnemonics that fit the block, what fits an
//! operand's spec (addresses of the allowed areas, symbols, locals, blocks, labels, a
//! constant's range), system block keys and values, declaration types, block keywords.
//! Items are plain data, sorted by relevance; insert texts are plain (no snippets).
//! Nothing here edits text or knows LSP types.

use gutta_catalog::rules::{self, DataRules};
use gutta_catalog::{
    Area, BlockKind, DataType, Instruction, OperandKind, OperandSpec, Target, Width,
};

use super::place::{cursor_at, Block, Cursor, Place};
use super::signature::operand_specs;
use gutta_compiler::check::DefKind;
use gutta_compiler::source::Span;
use gutta_compiler::syntax::ast::{self, VarSection};
use gutta_compiler::CheckedFile;

/// What a completion item is (an editor shows an icon for it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CompletionKind {
    Keyword,
    Mnemonic,
    Local,
    Symbol,
    Block,
    Label,
    Address,
    Constant,
    Type,
    /// A system block key or value, an interrupt event, a PLC type name.
    Value,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CompletionItem {
    pub label: String,
    pub kind: CompletionKind,
    /// One line beside the label: a signature, an address, a range.
    pub detail: Option<String>,
    /// Markdown.
    pub documentation: Option<String>,
    /// The text that replaces [`Completions::replace`].
    pub insert: String,
}

/// The items for one position, best first, and the span they replace (the word being
/// typed, possibly empty).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Completions {
    pub replace: Span,
    pub items: Vec<CompletionItem>,
}

/// Items of one relevance group (0 first).
struct Items {
    list: Vec<(u8, CompletionItem)>,
}

impl Items {
    fn add(
        &mut self,
        group: u8,
        kind: CompletionKind,
        label: impl Into<String>,
    ) -> &mut CompletionItem {
        let label = label.into();
        self.list.push((
            group,
            CompletionItem {
                insert: label.clone(),
                label,
                kind,
                detail: None,
                documentation: None,
            },
        ));
        &mut self.list.last_mut().expect("just pushed").1
    }
}

impl CompletionItem {
    fn detail(&mut self, detail: impl Into<String>) -> &mut CompletionItem {
        self.detail = Some(detail.into());
        self
    }

    fn documentation(&mut self, doc: impl Into<String>) -> &mut CompletionItem {
        self.documentation = Some(doc.into());
        self
    }
}

/// Top-level keywords that open a block or name the PLC type.
const TOP_KEYWORDS: [(&str, &str); 7] = [
    (
        "ORGANIZATION_BLOCK",
        "MAIN program: `ORGANIZATION_BLOCK MAIN:OB1`",
    ),
    (
        "SUBROUTINE_BLOCK",
        "subroutine: `SUBROUTINE_BLOCK NAME:SBRn`",
    ),
    (
        "INTERRUPT_BLOCK",
        "interrupt routine: `INTERRUPT_BLOCK NAME:INTn`",
    ),
    ("SYMBOLS", "symbol declarations `Name : ADDRESS`"),
    ("DATA_BLOCK", "initial values: `DATA_BLOCK NAME:DATn`"),
    ("SYSTEM_BLOCK", "serial ports and password"),
    (
        "PLC_TYPE",
        "the PLC type the program is written for (first line)",
    ),
];

/// Completions at `offset` of the checked text.
pub fn completions(checked: &CheckedFile, offset: usize) -> Completions {
    let cursor = cursor_at(checked, offset);
    let mut items = Items { list: Vec::new() };
    let target = &*checked.target;
    match &cursor.place {
        Place::Comment => {}
        Place::TopKeyword => {
            for (k, doc) in TOP_KEYWORDS {
                items.add(0, CompletionKind::Keyword, k).detail(doc);
            }
        }
        Place::PlcTypeName => {
            for name in gutta_catalog::stdlib::names() {
                items.add(0, CompletionKind::Value, name);
            }
        }
        Place::LineStart(Block::Symbols) => {
            items.add(1, CompletionKind::Keyword, "END_SYMBOLS");
        }
        Place::LineStart(Block::Vars) => {
            items.add(1, CompletionKind::Keyword, "END_VAR");
        }
        Place::LineStart(_) => unit_head(checked, &cursor, &mut items),
        Place::AfterColon(Block::Symbols, 1) => {
            addresses(target, &AddressFilter::Any, &mut items);
        }
        Place::AfterColon(..) => types(&mut items),
        Place::Mnemonic => mnemonics(checked, &cursor, &mut items),
        Place::Operand { mnemonic, index } => {
            operand(checked, &cursor, *mnemonic, *index, offset, &mut items)
        }
        Place::DataField(0) => {
            let filter = AddressFilter::Kinds(rules::INITIALISABLE);
            symbols(checked, &filter, &mut items);
            addresses(target, &filter, &mut items);
        }
        Place::DataField(1) => types(&mut items),
        Place::DataField(_) => {}
        Place::SystemKey => system_keys(target, &mut items),
        Place::SystemValue(key) => system_values(key, &mut items),
    }
    // Within a group, labels that start with the word typed so far come first.
    let typed = checked
        .file
        .text
        .get(cursor.word.range())
        .unwrap_or("")
        .to_uppercase();
    let mut list: Vec<(u8, bool, CompletionItem)> = items
        .list
        .into_iter()
        .map(|(g, i)| (g, !i.label.to_uppercase().starts_with(&typed), i))
        .collect();
    list.sort_by(|a, b| (a.0, a.1, &a.2.label).cmp(&(b.0, b.1, &b.2.label)));
    Completions {
        replace: cursor.word,
        items: list.into_iter().map(|(_, _, i)| i).collect(),
    }
}

/// Before `BEGIN`: VAR sections (parameters only in subroutines), `TITLE=`, `BEGIN`.
fn unit_head(checked: &CheckedFile, cursor: &Cursor, items: &mut Items) {
    let kind = cursor.unit.map(|u| checked.ast.units[u].kind);
    let parameters = kind.is_some_and(rules::takes_parameters);
    for (section, takes) in [
        (VarSection::Input, true),
        (VarSection::InOut, true),
        (VarSection::Output, true),
        (VarSection::Temp, false),
    ] {
        if parameters || !takes {
            items.add(1, CompletionKind::Keyword, section.keyword());
        }
    }
    items.add(0, CompletionKind::Keyword, "BEGIN");
    items.add(2, CompletionKind::Keyword, "TITLE=");
}

fn types(items: &mut Items) {
    for t in DataType::ALL {
        items
            .add(0, CompletionKind::Type, t.keyword())
            .detail(format!("{} bits", t.width().bits()));
    }
}

/// Whether unit `u` is MAIN (INT0).
fn is_main(checked: &CheckedFile, u: &ast::Unit) -> bool {
    let text = &checked.file.text;
    let name = text.get(u.header.name.range()).unwrap_or("");
    u.kind == BlockKind::Interrupt
        && (name.eq_ignore_ascii_case("MAIN")
            || u.header.number.is_some_and(|(n, _)| n.number == 0)
            || text
                .get(u.header.span.range())
                .is_some_and(|h| h.to_ascii_uppercase().starts_with("ORGANIZATION_BLOCK")))
}

/// At the start of a code line: the mnemonics the block may hold, `NETWORK` and the
/// block's END_ keyword.
fn mnemonics(checked: &CheckedFile, cursor: &Cursor, items: &mut Items) {
    let unit = cursor.unit.map(|u| &checked.ast.units[u]);
    let allowed = |ins: &Instruction| match unit {
        None => true,
        Some(u) if u.kind == BlockKind::Subroutine => ins.units.subroutine,
        Some(u) if is_main(checked, u) => ins.units.main,
        Some(_) => ins.units.interrupt,
    };
    for ins in checked
        .target
        .instructions
        .instructions
        .iter()
        .filter(|i| allowed(i))
    {
        let signature: Vec<String> = ins
            .operands
            .iter()
            .map(|o| format!("{}: {}", o.name, operand_types(o)))
            .collect();
        let doc = format!("{}\n\n{}", ins.summary, ins.description);
        items
            .add(1, CompletionKind::Mnemonic, ins.mnemonic.clone())
            .detail(
                format!("{} {}", ins.mnemonic, signature.join(", "))
                    .trim_end()
                    .to_string(),
            )
            .documentation(doc);
    }
    items.add(1, CompletionKind::Keyword, "NETWORK");
    let end = match unit.map(|u| (u.kind, is_main(checked, u))) {
        Some((BlockKind::Subroutine, _)) => "END_SUBROUTINE_BLOCK",
        Some((_, true)) => "END_ORGANIZATION_BLOCK",
        _ => "END_INTERRUPT_BLOCK",
    };
    items.add(2, CompletionKind::Keyword, end);
}

fn operand_types(o: &OperandSpec) -> String {
    match o.kind {
        OperandKind::Data => o
            .types
            .iter()
            .map(|t| t.keyword())
            .collect::<Vec<_>>()
            .join("|"),
        OperandKind::Label => "label".into(),
        OperandKind::Block => "block".into(),
        OperandKind::Literal => "literal".into(),
    }
}

/// In operand `index` of the instruction at `mnemonic`.
fn operand(
    checked: &CheckedFile,
    cursor: &Cursor,
    mnemonic: Span,
    index: usize,
    offset: usize,
    items: &mut Items,
) {
    let Some((ins, specs)) = operand_specs(checked, mnemonic, offset) else {
        return;
    };
    let Some(spec) = specs.get(index) else {
        return;
    };
    match spec.kind {
        OperandKind::Data => data_operand(checked, cursor, spec, items),
        OperandKind::Label => labels(checked, cursor, ins, items),
        OperandKind::Block => blocks(checked, spec, items),
        OperandKind::Literal => literal(checked, spec, items),
    }
}

/// How an operand is written: plainly, after `&`, or after `*`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Access {
    Direct,
    AddressOf,
    Pointer,
}

/// Which addresses fit.
enum AddressFilter<'a> {
    /// Every area and width (a symbol declaration).
    Any,
    /// Areas of these kinds, any width (a data block row).
    Kinds(&'static [gutta_catalog::AreaKind]),
    /// An operand's rules, as written with `access`.
    Operand(DataRules<'a>, Access),
}

impl AddressFilter<'_> {
    /// The widths of `area` that fit.
    fn widths(&self, area: &Area) -> Vec<Width> {
        let all = || area.widths.iter().copied().collect::<Vec<_>>();
        match self {
            AddressFilter::Any => all(),
            AddressFilter::Kinds(kinds) if kinds.contains(&area.kind) => all(),
            AddressFilter::Kinds(_) => Vec::new(),
            AddressFilter::Operand(r, Access::Direct) => {
                let fits = area.allows(r.width) && r.accepts_area(area) && r.may_write(area);
                if fits {
                    vec![r.width]
                } else {
                    Vec::new()
                }
            }
            AddressFilter::Operand(_, Access::AddressOf) => {
                match rules::address_of_target(area, Width::Byte) {
                    Ok(()) => vec![Width::Byte],
                    Err(_) => Vec::new(),
                }
            }
            AddressFilter::Operand(_, Access::Pointer) => {
                match rules::pointer_holder(area, Width::Dword) {
                    Ok(()) => vec![Width::Dword],
                    Err(_) => Vec::new(),
                }
            }
        }
    }

    fn fits(&self, area: &Area, width: Width) -> bool {
        self.widths(area).contains(&width)
    }
}

fn data_operand(checked: &CheckedFile, cursor: &Cursor, spec: &OperandSpec, items: &mut Items) {
    let text = &checked.file.text;
    let access = match text[..cursor.word.start as usize].chars().next_back() {
        Some('&') => Access::AddressOf,
        Some('*') => Access::Pointer,
        _ => Access::Direct,
    };
    let rules = DataRules::from_spec(spec);
    if (access == Access::AddressOf && !rules.takes_address_of())
        || (access == Access::Pointer && !rules.pointer)
    {
        return;
    }
    let filter = AddressFilter::Operand(rules, access);
    locals(checked, cursor, spec, access, items);
    if text
        .get(cursor.word.range())
        .is_some_and(|w| w.starts_with('#'))
    {
        return;
    }
    symbols(checked, &filter, items);
    addresses(&checked.target, &filter, items);
    if access == Access::Direct && rules.constant {
        let real = spec.types.contains(&DataType::Real);
        let range = DataType::union_range(&spec.types)
            .map(|(lo, hi)| format!(" {lo}..{hi}"))
            .unwrap_or_default();
        let what = operand_types(spec);
        items
            .add(4, CompletionKind::Constant, if real { "0.0" } else { "0" })
            .detail(format!("constant {what}{range}"))
            .documentation("A constant: decimal, `16#FF`, `2#1010`, `1.5` (REAL), `1_000`");
    }
}

/// `#name` locals of the cursor's unit whose type the operand accepts.
fn locals(
    checked: &CheckedFile,
    cursor: &Cursor,
    spec: &OperandSpec,
    access: Access,
    items: &mut Items,
) {
    let Some(ui) = cursor.unit else { return };
    let text = &checked.file.text;
    let memory = &checked.target.memory;
    let local_area = memory.area_of_kind(gutta_catalog::AreaKind::Local);
    let rules = DataRules::from_spec(spec);
    if access == Access::Direct && !local_area.is_some_and(|a| rules.accepts_area(a)) {
        return;
    }
    for v in &checked.ast.units[ui].vars {
        let Some(ty) = text
            .get(v.ty.range())
            .and_then(|t| t.parse::<DataType>().ok())
        else {
            continue;
        };
        let fits = match access {
            Access::Direct => ty.accepted_by(&spec.types),
            Access::AddressOf => false,
            Access::Pointer => ty.width() == Width::Dword && ty != DataType::Real,
        };
        if !fits {
            continue;
        }
        let name = text.get(v.name.range()).unwrap_or("");
        let detail = checked
            .output
            .definitions
            .iter()
            .find(|d| d.kind == DefKind::Local && d.span == v.name)
            .map_or_else(|| format!("#{name} : {ty}"), |d| d.detail.clone());
        items
            .add(0, CompletionKind::Local, format!("#{name}"))
            .detail(detail);
    }
}

/// Symbols whose address fits, with their address and comment.
fn symbols(checked: &CheckedFile, filter: &AddressFilter, items: &mut Items) {
    let text = &checked.file.text;
    let memory = &checked.target.memory;
    for d in &checked.ast.symbols {
        let (Some(name), Some(address)) = (text.get(d.name.range()), text.get(d.address.range()))
        else {
            continue;
        };
        let Ok(a) = memory.parse_address(address.trim()) else {
            continue;
        };
        if !memory
            .area_by_slot(a.slot)
            .is_some_and(|area| filter.fits(area, a.width))
        {
            continue;
        }
        let item = items
            .add(1, CompletionKind::Symbol, name)
            .detail(memory.format_address(&a));
        if let Some(comment) = d.comment_text(text).filter(|c| !c.is_empty()) {
            item.documentation(comment);
        }
    }
}

/// Area prefixes with their width letter (`MW`, `VD`, `T`, `M` for bits), with the
/// range the target has; and the named system bits where a bit fits.
fn addresses(target: &Target, filter: &AddressFilter, items: &mut Items) {
    let memory = &target.memory;
    // K is the compiler's constant pool: programs write constants, not K addresses.
    let offered = |a: &&Area| a.size > 0 && a.kind != gutta_catalog::AreaKind::Constant;
    for area in memory.areas.iter().filter(offered) {
        for width in filter.widths(area) {
            let name = &area.name;
            let (label, range) = if area.fixed_width().is_some() {
                (
                    name.clone(),
                    format!("{name}0..{name}{}", area.unit_count().saturating_sub(1)),
                )
            } else if width == Width::Bit {
                (
                    name.clone(),
                    format!("{name}0.0..{name}{}.7", area.size - 1),
                )
            } else {
                let letter = width.letter().map(String::from).unwrap_or_default();
                let last = area.size.saturating_sub(width.bytes());
                (
                    format!("{name}{letter}"),
                    format!("{name}{letter}0..{name}{letter}{last}"),
                )
            };
            items.add(2, CompletionKind::Address, label).detail(format!(
                "{} {}: {range}",
                area.description,
                width.keyword()
            ));
        }
    }
    let bits_fit = memory
        .areas
        .iter()
        .any(|a| a.kind == gutta_catalog::AreaKind::System && filter.fits(a, Width::Bit));
    if bits_fit {
        for bit in &memory.system_bits {
            items
                .add(3, CompletionKind::Address, bit.address.clone())
                .detail(bit.name.clone())
                .documentation(bit.description.clone());
        }
    }
}

/// Labels of the cursor's unit for a jump; for `LBL`, the lowest number its block does
/// not use yet.
fn labels(checked: &CheckedFile, cursor: &Cursor, ins: &Instruction, items: &mut Items) {
    let Some(ui) = cursor.unit else { return };
    let set = &checked.target.instructions;
    let defines = set
        .label_definition()
        .is_some_and(|id| std::ptr::eq(set.get(id), ins));
    let defined: Vec<u16> = checked
        .output
        .definitions
        .iter()
        .filter(|d| d.kind == DefKind::Label && d.unit == Some(ui))
        .filter_map(|d| d.name.strip_prefix("LBL ")?.parse().ok())
        .collect();
    if defines {
        if let Some(free) = (0..=255u16).find(|n| !defined.contains(n)) {
            items
                .add(0, CompletionKind::Label, free.to_string())
                .detail("the lowest label number this block does not use");
        }
        return;
    }
    for n in defined {
        items
            .add(0, CompletionKind::Label, n.to_string())
            .detail("label of this block");
    }
}

/// Blocks of the kind the operand names, by their symbolic name.
fn blocks(checked: &CheckedFile, spec: &OperandSpec, items: &mut Items) {
    let want = rules::unit_operand_kind(spec);
    let defs = &checked.output.definitions;
    for (i, u) in checked.ast.units.iter().enumerate() {
        if u.kind != want || is_main(checked, u) {
            continue;
        }
        let Some(d) = defs
            .iter()
            .find(|d| d.kind == DefKind::Unit && d.span == unit_name_span(u))
        else {
            continue;
        };
        let params = super::signature::parameter_labels(checked, i);
        let item = items.add(0, CompletionKind::Block, d.name.clone());
        item.detail(d.detail.clone());
        if !params.is_empty() {
            item.documentation(format!("parameters: {}", params.join(", ")));
        }
    }
}

/// The span the checker defines a unit at (its name, or the header without one).
fn unit_name_span(u: &ast::Unit) -> Span {
    if u.header.name.is_empty() {
        u.header.span
    } else {
        u.header.name
    }
}

/// A literal: interrupt events for `EVNT` (by S7-200 number in a Micro/WIN export),
/// else the numbers of its range.
fn literal(checked: &CheckedFile, spec: &OperandSpec, items: &mut Items) {
    let memory = &checked.target.memory;
    let events: Vec<_> = memory
        .events
        .iter()
        .filter(|e| rules::check_literal(spec, memory, i64::from(e.number)).is_ok())
        .collect();
    if rules::is_event_operand(spec) {
        for e in events {
            // A Micro/WIN export names events by their S7-200 numbers
            // (docs/microwin.md, "Interrupt events").
            let number = match (checked.microwin.is_some(), e.microwin) {
                (false, _) => e.number,
                (true, Some(s7)) => s7,
                (true, None) => continue,
            };
            items
                .add(0, CompletionKind::Value, number.to_string())
                .detail(e.name.clone())
                .documentation(e.description.clone());
        }
        return;
    }
    let range = rules::literal_range(spec, memory);
    if range.end() - range.start() < 16 {
        for n in range {
            items.add(0, CompletionKind::Value, n.to_string());
        }
    } else {
        items
            .add(0, CompletionKind::Constant, range.start().to_string())
            .detail(format!("{}..{}", range.start(), range.end()));
    }
}

/// `PORTn.FIELD` for each serial port of the target, and `PASSWORD`.
fn system_keys(target: &Target, items: &mut Items) {
    for port in 0..target.memory.serial_ports {
        for field in gutta_compiler::check::PORT_KEYS {
            items.add(0, CompletionKind::Value, format!("PORT{port}.{field}"));
        }
    }
    items
        .add(1, CompletionKind::Value, "PASSWORD")
        .detail("string of 1..16 ASCII characters");
    items.add(2, CompletionKind::Keyword, "END_SYSTEM_BLOCK");
}

/// The values a system key allows (docs/language.md section 11).
fn system_values(key: &str, items: &mut Items) {
    let field = key.split_once('.').map_or(key, |(_, f)| f);
    let words: Vec<String> = match field {
        "PROTOCOL" => vec!["MODBUS".into()],
        "BAUD" => gutta_format::BAUD_RATES
            .iter()
            .map(u32::to_string)
            .collect(),
        "DATA_BITS" => vec![rules::port::DATA_BITS.to_string()],
        "PARITY" => vec!["NONE".into(), "EVEN".into(), "ODD".into()],
        "STOP_BITS" => rules::port::STOP_BITS.map(|b| b.to_string()).collect(),
        _ => Vec::new(),
    };
    for w in words {
        items.add(0, CompletionKind::Value, w);
    }
    let range = match field {
        "ADDRESS" => Some("station address 0..255"),
        "TIMEOUT" => Some("1..255 (x 100 ms)"),
        "FRAME_GAP" => Some("1..255 (x 1 ms)"),
        _ => None,
    };
    if let Some(r) = range {
        items.add(0, CompletionKind::Constant, "1").detail(r);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gutta_compiler::source::SourceFile;

    const PROGRAM: &str =
        "SYMBOLS\n  Start : I0.0 // go\n  Speed : MW10\n  Ptr : MD20\nEND_SYMBOLS\n\
        ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\nNETWORK 1\nLD Start\nJMP 2\nNETWORK 2\nLBL 2\n\
        @MAIN\nEND_ORGANIZATION_BLOCK\n\
        SUBROUTINE_BLOCK ADD3:SBR0\nVAR_INPUT\n  a : INT;\n  f : BOOL;\n  p : DWORD;\nEND_VAR\n\
        BEGIN\nNETWORK 1\nLD SM0.0\n@SBR\nEND_SUBROUTINE_BLOCK\n\
        INTERRUPT_BLOCK TICK:INT1\nBEGIN\nNETWORK 1\nLD SM0.0\nEND_INTERRUPT_BLOCK\n\
        SYSTEM_BLOCK\n@SYS\nEND_SYSTEM_BLOCK\n@TOP";

    /// Completions with `line` (holding `|`, the cursor) in place of `@slot`.
    fn complete(slot: &str, line: &str) -> Completions {
        let text = PROGRAM.replacen(slot, line, 1);
        let offset = text.find('|').expect("a cursor");
        let text = text.replacen('|', "", 1);
        let checked = gutta_compiler::check_source(SourceFile::new("t.lad", text), None);
        completions(&checked, offset)
    }

    fn labels(c: &Completions) -> Vec<String> {
        c.items.iter().map(|i| i.label.clone()).collect()
    }

    fn has(labels: &[String], label: &str) -> bool {
        labels.iter().any(|l| l == label)
    }

    #[test]
    fn mnemonics_fit_the_block() {
        let main = complete("@MAIN", "MO|");
        let l = labels(&main);
        assert_eq!(l[0], "MOVB");
        assert!(has(&l, "MOVW") && !has(&l, "RET"), "{l:?}");
        assert_eq!(main.replace.end - main.replace.start, 2);
        let movw = main.items.iter().find(|i| i.label == "MOVW").expect("MOVW");
        assert!(movw
            .detail
            .as_deref()
            .is_some_and(|d| d.starts_with("MOVW IN: ")));
        assert!(movw.documentation.is_some());
        assert!(has(&labels(&complete("@SBR", "|")), "RET"));
    }

    #[test]
    fn operands_fit_the_spec() {
        let c = complete("@SBR", "MOVW |");
        let l = labels(&c);
        assert_eq!(l[0], "#a", "{l:?}");
        assert!(has(&l, "Speed") && !has(&l, "Start") && !has(&l, "#f"));
        assert!(has(&l, "MW") && !has(&l, "MB") && has(&l, "T"), "{l:?}");
        assert!(has(&l, "0"), "a constant hint");
        let out = labels(&complete("@SBR", "MOVW 1, |"));
        assert!(!has(&out, "0") && !has(&out, "IW"), "{out:?}");
        let bits = labels(&complete("@MAIN", "LD |"));
        assert!(has(&bits, "Start") && has(&bits, "SM0.0") && has(&bits, "I"));
        let ptr = labels(&complete("@SBR", "MOVW 1, *|"));
        assert!(
            has(&ptr, "Ptr") && has(&ptr, "#p") && has(&ptr, "MD"),
            "{ptr:?}"
        );
        assert!(!has(&ptr, "Speed"));
        let addr = labels(&complete("@SBR", "MOVD &|"));
        assert!(has(&addr, "MB") && !has(&addr, "IB"), "{addr:?}");
    }

    #[test]
    fn blocks_labels_events() {
        assert_eq!(labels(&complete("@MAIN", "CALL |")), ["ADD3"]);
        assert_eq!(labels(&complete("@MAIN", "ATCH |")), ["TICK"]);
        assert_eq!(labels(&complete("@MAIN", "JMP |")), ["2"]);
        assert_eq!(labels(&complete("@MAIN", "LBL |")), ["0"]);
        assert!(has(&labels(&complete("@MAIN", "ATCH TICK, |")), "10"));
        let args = labels(&complete("@MAIN", "CALL ADD3, MW0, |"));
        assert!(has(&args, "M") && !has(&args, "MW"), "{args:?}");
    }

    #[test]
    fn keys_values_keywords_types() {
        let keys = labels(&complete("@SYS", "  PO|"));
        assert!(has(&keys, "PORT0.BAUD") && has(&keys, "PASSWORD"));
        let baud = labels(&complete("@SYS", "  PORT0.BAUD = |"));
        assert!(has(&baud, "38400"));
        let top = labels(&complete("@TOP", "SU|"));
        assert!(has(&top, "SUBROUTINE_BLOCK"));
        let ty = labels(&complete("@TOP", "SUBROUTINE_BLOCK X\nVAR\n  x : |"));
        assert!(has(&ty, "INT") && has(&ty, "REAL"));
        let head = labels(&complete("@TOP", "INTERRUPT_BLOCK X\n|"));
        assert!(has(&head, "BEGIN") && !has(&head, "VAR_INPUT"));
        assert!(complete("@MAIN", "LD Start // |").items.is_empty());
    }

    #[test]
    fn a_large_file_completes_at_its_end() {
        let mut text = String::from("ORGANIZATION_BLOCK MAIN:OB1\nBEGIN\n");
        for i in 0..2_500 {
            text.push_str(&format!("NETWORK {i}\nLD I0.0\nMOVW MW0, MW2\n= Q0.0\n"));
        }
        let offset = text.len() - 3;
        text.push_str("END_ORGANIZATION_BLOCK\n");
        let checked = gutta_compiler::check_source(SourceFile::new("t.lad", text), None);
        let c = completions(&checked, offset);
        assert!(has(&labels(&c), "Q") && !has(&labels(&c), "I"));
    }
}
