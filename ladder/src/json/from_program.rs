//! A checked program's ladder (`crate::model::Ladder`, from `build.rs`) as the JSON
//! model: its symbols and the blocks' variable sections from the checked program, each
//! rung as series and parallel elements, contacts in their load form (the catalog's
//! `with_join`), operands in STL order. Reads only; draws nothing.

use gutta_catalog::{InstructionSet, Join};
use gutta_compiler::syntax::ast::{self, VarSection};
use gutta_compiler::CheckedFile;

use super::{BlockJson, Element, Model, NetworkBody, NetworkJson, SymbolJson, VarJson};
use crate::model::{BoxElement, Branch, BranchEnd, Contact, Ladder, Network, Node, Rung};

/// A symbol declared at an S address (`Step1 : S0.1`, in a Micro/WIN export) keeps the
/// S address as written: the program written from the model is an export again.
fn written_s_address(checked: &CheckedFile, name: &str) -> Option<String> {
    checked.microwin.as_ref()?;
    let text = &checked.file.text;
    let d = checked
        .ast
        .symbols
        .iter()
        .find(|d| text.get(d.name.range()) == Some(name))?;
    let written = text.get(d.address.range())?.trim();
    gutta_catalog::s7200::s_operand(written).map(|_| written.to_ascii_uppercase())
}

/// The JSON model of `checked`, whose ladder `build` made.
pub fn model_of(checked: &CheckedFile, ladder: &Ladder) -> Model {
    let set = &checked.target.instructions;
    let symbols = checked
        .symbols()
        .symbols
        .into_iter()
        .map(|s| SymbolJson {
            address: written_s_address(checked, &s.name).unwrap_or(s.address),
            name: s.name,
            data_type: s.data_type,
            comment: Some(s.comment).filter(|c| !c.is_empty()),
        })
        .collect();
    let blocks = ladder
        .blocks
        .iter()
        .zip(&checked.ast.units)
        .map(|(block, unit)| {
            let sections = |section: VarSection| vars(checked, unit, section);
            BlockJson {
                kind: keyword(checked, unit),
                name: block.name.clone(),
                id: block.numbered.clone(),
                title: block.title.clone(),
                var_input: sections(VarSection::Input),
                var_in_out: sections(VarSection::InOut),
                var_output: sections(VarSection::Output),
                var: sections(VarSection::Temp),
                networks: block.networks.iter().map(|n| network(set, n)).collect(),
            }
        })
        .collect();
    Model {
        format: super::FORMAT.to_string(),
        version: super::VERSION,
        plc: ladder.plc.clone(),
        symbols,
        blocks,
    }
}

/// The block's keyword as the source writes it: the header line's first word.
fn keyword(checked: &CheckedFile, unit: &ast::Unit) -> String {
    checked
        .file
        .slice(unit.header.span)
        .split_whitespace()
        .next()
        .unwrap_or("")
        .to_ascii_uppercase()
}

fn vars(checked: &CheckedFile, unit: &ast::Unit, section: VarSection) -> Vec<VarJson> {
    let text = |s| checked.file.slice(s).trim().to_string();
    unit.vars
        .iter()
        .filter(|v| v.section == section)
        .map(|v| VarJson {
            name: text(v.name),
            data_type: text(v.ty),
            comment: v.comment.map(|c| {
                let c = text(c);
                c.strip_prefix("//")
                    .map_or(c.clone(), |c| c.trim().to_string())
            }),
        })
        .collect()
}

fn network(set: &InstructionSet, net: &Network) -> NetworkJson {
    let body = match &net.body {
        // The JSON model's boxes are the catalog's instructions: a network with a
        // sequence control relay (drawn with the label and jump shapes, no catalog
        // instruction) is kept as its STL lines, which build the same drawing again.
        crate::model::Body::Rung(rung) if rung_has_scr(rung) => NetworkBody::Stl {
            stl: net.stl.clone(),
            reason: format!(
                "network {} holds a sequence control relay, which the JSON model keeps as STL",
                net.number
            ),
        },
        crate::model::Body::Rung(rung) => NetworkBody::Rung {
            rung: rung_element(set, rung),
        },
        crate::model::Body::Stl { reason } => NetworkBody::Stl {
            stl: net.stl.clone(),
            reason: reason.clone(),
        },
    };
    NetworkJson {
        number: Some(net.number),
        title: net.title.clone().unwrap_or_default(),
        comment: net.comment.join("\n"),
        body,
    }
}

/// The rung: its input path in series with its outputs (in a `parallel` when several).
/// Whether a rung holds an `LSCR`, `SCRT`, `SCRE` or `CSCRE` box.
fn rung_has_scr(rung: &Rung) -> bool {
    fn node(n: &Node) -> bool {
        match n {
            Node::Contact(_) => false,
            Node::Box(b) => boxed(b),
            Node::Series(v) | Node::Parallel(v) => v.iter().any(node),
        }
    }
    fn boxed(b: &BoxElement) -> bool {
        crate::model::is_scr(&b.mnemonic) || b.power_inputs.iter().any(|(_, n)| node(n))
    }
    fn branch(b: &Branch) -> bool {
        b.path.iter().any(node)
            || match &b.end {
                BranchEnd::Coil(_) => false,
                BranchEnd::Box(x) => boxed(x),
                BranchEnd::Split(v) => v.iter().any(branch),
            }
    }
    rung.input.as_ref().is_some_and(node) || rung.outputs.iter().any(branch)
}

fn rung_element(set: &InstructionSet, rung: &Rung) -> Element {
    let mut parts = Vec::new();
    if let Some(input) = &rung.input {
        parts.push(node(set, input));
    }
    parts.push(outputs(set, &rung.outputs));
    series(parts)
}

fn outputs(set: &InstructionSet, branches: &[Branch]) -> Element {
    match branches {
        [one] => branch(set, one),
        _ => Element::Parallel {
            parallel: branches.iter().map(|b| branch(set, b)).collect(),
        },
    }
}

fn branch(set: &InstructionSet, b: &Branch) -> Element {
    let mut parts: Vec<Element> = b.path.iter().map(|n| node(set, n)).collect();
    parts.push(match &b.end {
        BranchEnd::Coil(c) => {
            let mut operands = vec![c.operand.written.clone()];
            operands.extend(c.count.iter().map(|n| n.written.clone()));
            Element::Coil {
                coil: c.mnemonic.clone(),
                operands,
            }
        }
        BranchEnd::Box(b) => box_element(set, b),
        BranchEnd::Split(branches) => outputs(set, branches),
    });
    series(parts)
}

/// One element for one part, a `series` for several (nested series flattened).
fn series(parts: Vec<Element>) -> Element {
    let mut flat = Vec::with_capacity(parts.len());
    for p in parts {
        match p {
            Element::Series { series } => flat.extend(series),
            other => flat.push(other),
        }
    }
    if flat.len() == 1 {
        flat.remove(0)
    } else {
        Element::Series { series: flat }
    }
}

fn node(set: &InstructionSet, n: &Node) -> Element {
    match n {
        Node::Contact(c) => contact(set, c),
        Node::Box(b) => box_element(set, b),
        Node::Series(nodes) => series(nodes.iter().map(|n| node(set, n)).collect()),
        Node::Parallel(nodes) => Element::Parallel {
            parallel: nodes.iter().map(|n| node(set, n)).collect(),
        },
    }
}

/// A contact in its load form (`AN` is `LDN`, `OW>=` is `LDW>=`); `EU`, `ED`, `NOT`
/// have no load form and stay as they are.
fn contact(set: &InstructionSet, c: &Contact) -> Element {
    let mnemonic = set
        .lookup(&c.mnemonic)
        .and_then(|id| set.with_join(id, Join::Load))
        .map_or_else(|| c.mnemonic.clone(), |id| set.get(id).mnemonic.clone());
    Element::Contact {
        contact: mnemonic,
        operands: c.operands.iter().map(|o| o.written.clone()).collect(),
    }
}

/// A box's operands in STL order: a timer's or counter's number and a CALL's
/// subroutine are its title, before the pins.
fn box_element(set: &InstructionSet, b: &BoxElement) -> Element {
    let spec = set.lookup(&b.mnemonic).map(|id| set.get(id));
    let titled = spec.is_some_and(|s| s.kind.is_some() || s.call_arguments);
    let mut operands = Vec::with_capacity(b.pins.len() + 1);
    if titled {
        operands.push(b.title.clone());
    }
    operands.extend(b.pins.iter().map(|p| p.operand.written.clone()));
    Element::Box {
        mnemonic: b.mnemonic.clone(),
        operands,
        inputs: b.power_inputs.iter().map(|(_, n)| node(set, n)).collect(),
    }
}
