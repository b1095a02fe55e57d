//! The outline of one file of a program: SYMBOLS sections with their symbols (or a
//! symbol table's rows), program blocks with their locals and networks (titled), data
//! blocks and the system block. Plain data over `&CheckedFile` and byte spans; no LSP
//! types, no I/O.

use std::ops::Range;

use gutta_catalog::BlockKind;

use gutta_compiler::source::{PartKind, Span};
use gutta_compiler::syntax::ast::{BlockHeader, BlockNumber, BlockPrefix, SymbolDecl};
use gutta_compiler::CheckedFile;

use super::navigation::unit_extent;

/// What an outline entry is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutlineKind {
    /// A `SYMBOLS` section.
    Symbols,
    Symbol,
    /// The main program (`ORGANIZATION_BLOCK`, INT0).
    Main,
    Interrupt,
    Subroutine,
    Local,
    Network,
    DataBlock,
    SystemBlock,
    /// An entry of the system block (`PORT0.BAUD`).
    Setting,
}

/// One entry of the outline.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct OutlineItem {
    pub name: String,
    /// A short description: an address, a type, a title.
    pub detail: Option<String>,
    pub kind: OutlineKind,
    /// All the entry's text.
    pub span: Span,
    /// The name to select (inside `span`).
    pub selection: Span,
    pub children: Vec<OutlineItem>,
}

/// The outline of the file `part` (index into `checked.file.parts()`), in text order.
pub fn outline(checked: &CheckedFile, part: usize) -> Vec<OutlineItem> {
    let Some(file) = checked.file.parts().into_iter().nth(part) else {
        return Vec::new();
    };
    let range = file.start..file.end + 1;
    let inside = |s: Span| range.contains(&(s.start as usize));
    let text = &checked.file.text;
    let slice = |s: Span| text.get(s.range()).unwrap_or("").trim().to_string();
    let mut items = Vec::new();

    let symbols: Vec<OutlineItem> = checked
        .ast
        .symbols
        .iter()
        .filter(|d| inside(d.name))
        .map(|d| symbol_item(checked, d))
        .collect();
    if file.kind == PartKind::SymbolTable {
        return symbols;
    }
    items.extend(symbol_sections(text, symbols, &range));

    for unit in checked.ast.units.iter().filter(|u| inside(u.header.span)) {
        let (kind, fallback) = match unit.kind {
            BlockKind::Subroutine => (OutlineKind::Subroutine, "SUBROUTINE_BLOCK"),
            BlockKind::Interrupt if is_main(&slice, &unit.header) => (OutlineKind::Main, "MAIN"),
            BlockKind::Interrupt => (OutlineKind::Interrupt, "INTERRUPT_BLOCK"),
        };
        let mut children: Vec<OutlineItem> = unit
            .vars
            .iter()
            .map(|v| OutlineItem {
                name: format!("#{}", slice(v.name)),
                detail: Some(format!("{} ({})", slice(v.ty), v.section.keyword())),
                kind: OutlineKind::Local,
                span: v.name.to(v.ty),
                selection: v.name,
                children: Vec::new(),
            })
            .collect();
        for (i, n) in unit.networks.iter().enumerate() {
            let mut span = n.span;
            if let Some(last) = n.instructions.last() {
                span = span.to(last.span);
            }
            let number = n.number.unwrap_or(i as u32 + 1);
            children.push(OutlineItem {
                name: format!("Network {number}"),
                detail: n.title.map(slice).filter(|t| !t.is_empty()),
                kind: OutlineKind::Network,
                span,
                selection: n.header.unwrap_or(n.span),
                children: Vec::new(),
            });
        }
        items.push(OutlineItem {
            name: block_name(&slice, &unit.header, fallback),
            detail: unit.title.map(slice).filter(|t| !t.is_empty()),
            kind,
            span: unit_extent(unit),
            selection: selection(&unit.header),
            children,
        });
    }

    for d in checked
        .ast
        .data_blocks
        .iter()
        .filter(|d| inside(d.header.span))
    {
        let mut span = d.header.span;
        if let Some(last) = d.rows.last() {
            span = span.to(last.span);
        }
        if let Some(end) = d.end {
            span = span.to(end);
        }
        items.push(OutlineItem {
            name: block_name(&slice, &d.header, "DATA_BLOCK"),
            detail: Some(match d.rows.len() {
                1 => "1 row".to_string(),
                n => format!("{n} rows"),
            }),
            kind: OutlineKind::DataBlock,
            span,
            selection: selection(&d.header),
            children: Vec::new(),
        });
    }

    for s in checked.ast.system_blocks.iter().filter(|s| inside(s.span)) {
        let mut span = s.span;
        if let Some(end) = s.end {
            span = span.to(end);
        }
        let children = s
            .entries
            .iter()
            .map(|e| OutlineItem {
                name: slice(e.key),
                detail: Some(
                    slice(e.span)
                        .split_once('=')
                        .map(|(_, v)| v.trim().to_string())
                        .unwrap_or_default(),
                ),
                kind: OutlineKind::Setting,
                span: e.span,
                selection: e.key,
                children: Vec::new(),
            })
            .collect();
        items.push(OutlineItem {
            name: "SYSTEM_BLOCK".into(),
            detail: None,
            kind: OutlineKind::SystemBlock,
            span,
            selection: Span::new(
                s.span.start as usize,
                s.span.start as usize + "SYSTEM_BLOCK".len(),
            ),
            children,
        });
    }
    items.sort_by_key(|i| i.span.start);
    items
}

fn symbol_item(checked: &CheckedFile, d: &SymbolDecl) -> OutlineItem {
    let text = &checked.file.text;
    let slice = |s: Span| text.get(s.range()).unwrap_or("").trim().to_string();
    let mut detail = slice(d.address);
    if let Some(t) = d.data_type {
        detail = format!("{detail} : {}", slice(t));
    }
    if let Some(c) = d.comment_text(text).filter(|c| !c.is_empty()) {
        detail = format!("{detail}  // {c}");
    }
    let mut span = d.name.to(d.address);
    if let Some(c) = d.comment {
        span = span.to(c);
    }
    OutlineItem {
        name: slice(d.name),
        detail: Some(detail),
        kind: OutlineKind::Symbol,
        span,
        selection: d.name,
        children: Vec::new(),
    }
}

/// Symbols of a source grouped into SYMBOLS sections: a section is the symbols between
/// one `SYMBOLS` keyword and its `END_SYMBOLS`.
fn symbol_sections(
    text: &str,
    symbols: Vec<OutlineItem>,
    range: &Range<usize>,
) -> Vec<OutlineItem> {
    let mut sections: Vec<OutlineItem> = Vec::new();
    for item in symbols {
        let start = item.span.start as usize;
        // The section keyword is the last `SYMBOLS` line before the symbol.
        let head = text
            .get(range.start..start)
            .and_then(|before| {
                before
                    .match_indices("SYMBOLS")
                    .filter(|(i, _)| {
                        let line_start = before[..*i].rfind('\n').map(|n| n + 1).unwrap_or(0);
                        before[line_start..*i].trim().is_empty()
                    })
                    .last()
                    .map(|(i, _)| range.start + i)
            })
            .unwrap_or(start);
        match sections.last_mut() {
            Some(s) if s.selection.start as usize == head => {
                s.span = s.span.to(item.span);
                s.children.push(item);
            }
            _ => sections.push(OutlineItem {
                name: "SYMBOLS".into(),
                detail: None,
                kind: OutlineKind::Symbols,
                span: Span::new(head, head).to(item.span),
                selection: Span::new(head, head + if head == start { 0 } else { 7 }),
                children: vec![item],
            }),
        }
    }
    for s in &mut sections {
        let n = s.children.len();
        s.detail = Some(format!("{n} symbol{}", if n == 1 { "" } else { "s" }));
    }
    sections
}

/// MAIN is INT0: named MAIN, numbered OBn, or INT0.
fn is_main(slice: &dyn Fn(Span) -> String, header: &BlockHeader) -> bool {
    slice(header.name).eq_ignore_ascii_case("MAIN")
        || matches!(
            header.number,
            Some((
                BlockNumber {
                    prefix: BlockPrefix::Ob,
                    ..
                },
                _
            )) | Some((
                BlockNumber {
                    prefix: BlockPrefix::Int,
                    number: 0
                },
                _
            ))
        )
}

/// `ADD3 (SBR0)`, `MAIN (OB1)`, or the numbered name alone.
fn block_name(slice: &dyn Fn(Span) -> String, header: &BlockHeader, fallback: &str) -> String {
    let name = slice(header.name);
    let numbered = header.number.map(|(_, s)| slice(s));
    match (name.is_empty(), numbered) {
        (false, Some(n)) if !n.eq_ignore_ascii_case(&name) => format!("{name} ({n})"),
        (false, _) => name,
        (true, Some(n)) => n,
        (true, None) => fallback.to_string(),
    }
}

fn selection(header: &BlockHeader) -> Span {
    if header.name.is_empty() {
        header.span
    } else {
        header.name
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gutta_compiler::source::SourceFile;
    use gutta_compiler::{check_program, ProgramSources};

    fn render(checked: &CheckedFile, items: &[OutlineItem], depth: usize, out: &mut String) {
        for i in items {
            let sel = checked.file.slice(i.selection);
            out.push_str(&format!(
                "{}{:?} {} [{}]{}\n",
                "  ".repeat(depth),
                i.kind,
                i.name,
                sel,
                i.detail
                    .as_ref()
                    .map(|d| format!(" - {d}"))
                    .unwrap_or_default()
            ));
            render(checked, &i.children, depth + 1, out);
        }
    }

    #[test]
    fn blocks_hold_locals_and_titled_networks_and_tables_list_rows() {
        let main = "PLC_TYPE CPU-EC20\nSYMBOLS\n  Start : I0.0 // push button\n  Speed : MW0 : INT\nEND_SYMBOLS\nORGANIZATION_BLOCK MAIN:OB1\nTITLE=Main program\nBEGIN\nNetwork 1 // latch\nLD     Start\n=      Q0.0\nNetwork 2\nLD     SM0.0\nCALL   ADD3, 1, 2, MW12\nEND_ORGANIZATION_BLOCK\nSUBROUTINE_BLOCK ADD3:SBR0\nVAR_INPUT\n  a : INT;\n  b : INT;\nEND_VAR\nVAR_OUTPUT\n  r : INT;\nEND_VAR\nBEGIN\nNetwork 1 // add\nLD     SM0.0\nMOVW   #a, #r\n+I     #b, #r\nEND_SUBROUTINE_BLOCK\nDATA_BLOCK INIT:DAT0\nMW22 UINT 6\nEND_DATA_BLOCK\nSYSTEM_BLOCK\nPORT0.BAUD = 9600\nEND_SYSTEM_BLOCK\n";
        let table = "Symbol,Address,Comment\nLamp,Q0.1,the lamp\n";
        let c = check_program(
            ProgramSources {
                sources: vec![SourceFile::new("main.lad", main)],
                symbol_tables: vec![SourceFile::new("s.csv", table)],
                ..Default::default()
            },
            None,
        );
        assert_eq!(c.diagnostics(), &[]);
        let mut out = String::new();
        render(&c, &outline(&c, 0), 0, &mut out);
        out.push_str("--- s.csv\n");
        render(&c, &outline(&c, 1), 0, &mut out);
        insta::assert_snapshot!(out);
        assert_eq!(outline(&c, 7), Vec::new());
    }
}
