//! A checked program's networks into rungs (docs/ladder.md, "Which networks are
//! ladder"): every block of the tree, every network with its number, title, comment and
//! STL lines, and its body: one rung, or the STL with the true reason it is not one.
//! `element.rs` reads one instruction as an element, `rung.rs` places elements by the
//! logic stack. Reads only the tree, the target and the symbols; no I/O.

mod element;
mod rung;

use gutta_compiler::source::Span;
use gutta_compiler::syntax::ast::{self, OperandKind};
use gutta_compiler::CheckedFile;

use crate::model::{Block, Body, Ladder, Network, StlInstruction};
pub use element::box_shape;
use element::{Element, Resolver};
use rung::{Origin, RungBuilder};

/// The ladder of a checked program: every block, every network drawn or refused.
/// Works on programs with errors too: a network the parser could not read is STL.
pub fn build(checked: &CheckedFile) -> Ladder {
    let resolver = Resolver::new(checked);
    let blocks = checked
        .ast
        .units
        .iter()
        .map(|unit| block(checked, &resolver, unit))
        .collect();
    Ladder {
        plc: checked.target.name().to_string(),
        blocks,
    }
}

fn block(checked: &CheckedFile, resolver: &Resolver<'_>, unit: &ast::Unit) -> Block {
    let text = |s: Span| checked.file.slice(s).trim().to_string();
    let name = text(unit.header.name);
    let mut last: Option<u32> = None;
    let networks = unit
        .networks
        .iter()
        .map(|net| {
            let number = network_number(net, &mut last);
            network(checked, resolver, net, number)
        })
        .collect();
    Block {
        numbered: numbered_name(checked, unit, &name),
        name,
        title: unit.title.map(text).filter(|t| !t.is_empty()),
        networks,
    }
}

/// The numbered name: as the header writes it, else the checker's number, else `OB1`
/// for MAIN.
fn numbered_name(checked: &CheckedFile, unit: &ast::Unit, name: &str) -> String {
    if let Some((_, span)) = unit.header.number {
        return checked.file.slice(span).trim().to_string();
    }
    if name.eq_ignore_ascii_case("MAIN") {
        return "OB1".to_string();
    }
    checked
        .output
        .program
        .as_ref()
        .and_then(|p| p.units.iter().find(|u| u.name.eq_ignore_ascii_case(name)))
        .map(|u| u.numbered_name())
        .unwrap_or_else(|| name.to_string())
}

/// The network's number as the checker gives it (`ast::Network::number_after`).
fn network_number(net: &ast::Network, last: &mut Option<u32>) -> u32 {
    let number = net.number_after(*last);
    if net.header.is_some() {
        *last = Some(number);
    }
    number
}

fn network(
    checked: &CheckedFile,
    resolver: &Resolver<'_>,
    net: &ast::Network,
    number: u32,
) -> Network {
    let text = &checked.file.text;
    let body = match rung_of(checked, resolver, net, number) {
        Ok(rung) => Body::Rung(rung),
        Err(reason) => Body::Stl { reason },
    };
    let lines = stl_lines(text, net);
    let stl_code = match body {
        Body::Stl { .. } => stl_code(checked, resolver, net, &lines),
        Body::Rung(_) => Vec::new(),
    };
    Network {
        number,
        title: net
            .title
            .map(|t| checked.file.slice(t).trim().to_string())
            .filter(|t| !t.is_empty()),
        comment: comment_lines(text, net),
        stl: lines.into_iter().map(|(_, l)| l).collect(),
        line: resolver.line(net.span.start),
        body,
        stl_code,
    }
}

/// The instructions of a network shown as STL, each with the index of its line in
/// `lines` (an instruction on a line of its own; two on one line share it).
fn stl_code(
    checked: &CheckedFile,
    resolver: &Resolver<'_>,
    net: &ast::Network,
    lines: &[(usize, String)],
) -> Vec<StlInstruction> {
    let text = &checked.file.text;
    net.instructions
        .iter()
        .filter_map(|ins| {
            let start = line_start(text, ins.span.start as usize);
            let index = lines.iter().position(|(at, _)| *at == start)?;
            let written = checked.file.slice(ins.mnemonic).trim();
            let instructions = &checked.target.instructions;
            let mnemonic = instructions.lookup(written).map_or_else(
                || written.to_string(),
                |id| instructions.get(id).mnemonic.clone(),
            );
            let operands = net
                .operands_of(ins)
                .iter()
                .map(|o| resolver.operand(o))
                .collect();
            Some(StlInstruction {
                index,
                mnemonic,
                operands,
            })
        })
        .collect()
}

/// The rung of a network, or why it is not one.
fn rung_of(
    checked: &CheckedFile,
    resolver: &Resolver<'_>,
    net: &ast::Network,
    number: u32,
) -> Result<crate::model::Rung, String> {
    if net.instructions.is_empty() {
        return Err(format!("network {number} is empty"));
    }
    let mut elements = Vec::with_capacity(net.instructions.len());
    for ins in &net.instructions {
        let origin = Origin {
            text: instruction_text(checked.file.slice(ins.span)),
            line: resolver.line(ins.span.start),
        };
        let broken = ins.syntax_error
            || net
                .operands_of(ins)
                .iter()
                .any(|o| o.kind == OperandKind::Error);
        if broken {
            return Err(format!("{} did not parse", origin.at()));
        }
        let aeno = checked.microwin.is_some()
            && checked
                .file
                .slice(ins.mnemonic)
                .eq_ignore_ascii_case("AENO");
        if aeno {
            // Micro/WIN's chain of boxes by their ENO (docs/microwin.md, "AENO"): the
            // compiler gives it the flags' contacts; the drawing does not chain boxes yet.
            return Err(format!(
                "{} chains the boxes by their ENO, which the drawing does not show yet",
                origin.at()
            ));
        }
        let Some(element) = resolver.element(net, ins) else {
            return Err(format!(
                "{} is not an instruction of {}",
                origin.at(),
                checked.target.name()
            ));
        };
        elements.push((element, origin));
    }
    if let [(Element::Always(b), _)] = elements.as_slice() {
        let mut rung = rung::rail_rung(b.clone());
        rung::number(&mut rung);
        return Ok(rung);
    }
    if elements
        .iter()
        .all(|(e, _)| matches!(e, Element::Always(_)))
    {
        let (_, second) = &elements[1];
        return Err(format!(
            "{} is a second instruction without power flow in the network",
            second.at()
        ));
    }
    let count = elements.len();
    let mut builder = RungBuilder::default();
    for (i, (element, origin)) in elements.into_iter().enumerate() {
        let ends_loop = matches!(&element, Element::EndBox(_, true));
        if ends_loop && i + 1 < count {
            return Err(format!(
                "{} starts a loop whose body is in the same network",
                origin.at()
            ));
        }
        builder.push(element, origin)?;
    }
    let mut rung = builder.finish()?;
    rung::number(&mut rung);
    Ok(rung)
}

/// An instruction's text with its blanks collapsed: `LD I0.2`, `MOVW 0, MW10`.
fn instruction_text(raw: &str) -> String {
    raw.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// Offset of the start of the line holding `offset`.
fn line_start(text: &str, offset: usize) -> usize {
    text.get(..offset)
        .and_then(|t| t.rfind('\n'))
        .map_or(0, |i| i + 1)
}

/// Offset of the end of the line holding `offset` (before its newline).
fn line_end(text: &str, offset: usize) -> usize {
    text.get(offset..)
        .and_then(|t| t.find('\n'))
        .map_or(text.len(), |i| offset + i)
}

/// The comment lines between the NETWORK line and the first instruction, without `//`.
fn comment_lines(text: &str, net: &ast::Network) -> Vec<String> {
    let (Some(header), Some(first)) = (net.header, net.instructions.first()) else {
        return Vec::new();
    };
    let from = line_end(text, header.end as usize);
    let to = line_start(text, first.span.start as usize);
    text.get(from..to.max(from))
        .unwrap_or("")
        .lines()
        .filter_map(|l| l.trim().strip_prefix("//"))
        .map(|c| c.trim().to_string())
        .collect()
}

/// The network's STL lines as written (trimmed, blank lines left out): from the first
/// instruction's line to the last's, each with the offset where its line starts.
fn stl_lines(text: &str, net: &ast::Network) -> Vec<(usize, String)> {
    let (Some(first), Some(last)) = (net.instructions.first(), net.instructions.last()) else {
        return Vec::new();
    };
    let from = line_start(text, first.span.start as usize);
    let to = line_end(text, last.span.end as usize);
    let mut at = from;
    let mut lines = Vec::new();
    for raw in text
        .get(from..to.max(from))
        .unwrap_or("")
        .split_inclusive('\n')
    {
        let line = raw.trim();
        if !line.is_empty() {
            lines.push((at, line.to_string()));
        }
        at += raw.len();
    }
    lines
}
