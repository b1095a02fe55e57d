//! A validated JSON model back into a program's source text (docs/ladder.md, "The model
//! as JSON"): the inverse of `from_program.rs`. `PLC_TYPE`, the SYMBOLS block, then each
//! block with its keyword, `name:id`, `TITLE=`, variable sections and networks. A rung
//! element becomes the Rust `Rung` again and `crate::write` writes its STL: there is no
//! second STL writer here. `written_program` adds the source map: the JSON path behind
//! each line (the writer's `Place`s of a rung mapped back to the model's elements),
//! which `check.rs` maps diagnostics with. What each mnemonic is (contact, coil, box, its power inputs
//! and output) comes from the catalog, never from its spelling. Text only: no I/O.

use std::collections::BTreeMap;

use gutta_catalog::{Instruction, InstructionSet, LadderClass, Role};

use super::codes::{ModelError, ModelErrorCode as Code};
use super::{BlockJson, Element, Model, NetworkBody, NetworkJson, VarJson};
use crate::model::{
    Body, BoxElement, Branch, BranchEnd, Coil, CoilKind, Contact, ContactKind, Network, Node,
    Operand, Pin, Rung,
};
use crate::write::{self, NetworkPart, Place, Step};

type Made<T> = Result<T, ModelError>;

/// The block keywords of docs/ladder-model.schema.json's `kind`.
const KINDS: [&str; 3] = ["ORGANIZATION_BLOCK", "SUBROUTINE_BLOCK", "INTERRUPT_BLOCK"];

/// A model's program text and its source map: for each line of `text`, the JSON path
/// of the part of the model it was written for (`""`: the whole model).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WrittenProgram {
    pub text: String,
    /// One path per line of `text`, in order.
    pub paths: Vec<String>,
}

impl WrittenProgram {
    /// The path behind the 0-based line `line` (`""` past the end).
    pub fn path_of_line(&self, line: usize) -> &str {
        self.paths.get(line).map_or("", String::as_str)
    }
}

/// The program text of `model` (validated against `set`), ending in a newline. A rung
/// the writer cannot say as STL is L0013 at its JSON path; a block `kind` the schema
/// does not name, or a line break in a field that is one line of source, is L0002.
pub fn program_of(model: &Model, set: &InstructionSet) -> Made<String> {
    Ok(written_program(model, set)?.text)
}

/// [`program_of`]'s text with the JSON path behind each line: `plc` for `PLC_TYPE`,
/// `symbols` and `symbols[i]` for the SYMBOLS block and its rows, `blocks[b]` for a
/// block's keyword, `TITLE=`, section, `BEGIN` and `END_` lines, `blocks[b].VAR[i]` (the
/// section's JSON name) for a variable, `blocks[b].networks[n]` for a `NETWORK` line and
/// its comment, `...stl[i]` for a stored STL line, and the element of the rung for each
/// rung line (the writer's `Place`s mapped back: a contact, coil or box at itself,
/// `ALD`/`OLD`/`LPS`/`LRD`/`LPP` at the `parallel` they write); `""` for blank lines.
pub fn written_program(model: &Model, set: &InstructionSet) -> Made<WrittenProgram> {
    one_line_fields(model)?;
    let mut out = Lines::default();
    out.push(format!("PLC_TYPE {}", model.plc), "plc");
    out.push(String::new(), "");
    if !model.symbols.is_empty() {
        out.push("SYMBOLS".to_string(), "symbols");
        let width = model.symbols.iter().map(|s| s.name.chars().count()).max();
        for (i, s) in model.symbols.iter().enumerate() {
            let mut row = format!("  {:<w$} : {}", s.name, s.address, w = width.unwrap_or(0));
            if let Some(ty) = &s.data_type {
                row.push_str(&format!(" : {ty}"));
            }
            if let Some(c) = &s.comment {
                row.push_str(&format!(" // {c}"));
            }
            out.push(row, &format!("symbols[{i}]"));
        }
        out.push("END_SYMBOLS".to_string(), "symbols");
        out.push(String::new(), "");
    }
    for (b, block) in model.blocks.iter().enumerate() {
        block_text(set, block, b, &mut out)?;
        out.push(String::new(), "");
    }
    while out.lines.last().is_some_and(|(l, _)| l.is_empty()) {
        out.lines.pop();
    }
    let (lines, paths): (Vec<String>, Vec<String>) = out.lines.into_iter().unzip();
    let mut text = lines.join("\n");
    text.push('\n');
    Ok(WrittenProgram { text, paths })
}

/// Program lines with the JSON path behind each.
#[derive(Default)]
struct Lines {
    lines: Vec<(String, String)>,
}

impl Lines {
    fn push(&mut self, line: String, path: &str) {
        self.lines.push((line, path.to_string()));
    }
}

fn block_text(set: &InstructionSet, block: &BlockJson, b: usize, out: &mut Lines) -> Made<()> {
    if !KINDS.contains(&block.kind.as_str()) {
        return Err(ModelError::new(
            Code::Shape,
            &format!("blocks[{b}].kind"),
            format!(
                "`{}` is not a block kind: one of {}",
                block.kind,
                KINDS.join(", ")
            ),
        ));
    }
    let at = format!("blocks[{b}]");
    out.push(format!("{} {}:{}", block.kind, block.name, block.id), &at);
    if let Some(title) = &block.title {
        out.push(format!("TITLE={title}"), &at);
    }
    let sections: [(&str, &[VarJson]); 4] = [
        ("VAR_INPUT", &block.var_input),
        ("VAR_IN_OUT", &block.var_in_out),
        ("VAR_OUTPUT", &block.var_output),
        ("VAR", &block.var),
    ];
    for (keyword, vars) in sections {
        if vars.is_empty() {
            continue;
        }
        out.push(keyword.to_string(), &at);
        for (i, v) in vars.iter().enumerate() {
            let mut row = format!("  {} : {};", v.name, v.data_type);
            if let Some(c) = &v.comment {
                row.push_str(&format!(" // {c}"));
            }
            out.push(row, &format!("{at}.{keyword}[{i}]"));
        }
        out.push("END_VAR".to_string(), &at);
    }
    out.push("BEGIN".to_string(), &at);
    for (n, net) in block.networks.iter().enumerate() {
        let path = format!("{at}.networks[{n}]");
        let mut places = Places {
            set,
            paths: BTreeMap::new(),
        };
        let network = places.network(net, n, &path)?;
        let lines = write::network_lines(set, &network)
            .map_err(|e| ModelError::new(Code::Unwritable, &format!("{path}.rung"), e.message))?;
        for (line, part) in lines {
            let origin = match part {
                NetworkPart::Heading | NetworkPart::Comment(_) => path.clone(),
                NetworkPart::Stl(i) => format!("{path}.stl[{i}]"),
                NetworkPart::Rung(place) => places.path_of(&place, &path),
            };
            out.push(line, &origin);
        }
    }
    out.push(format!("END_{}", block.kind), &at);
    Ok(())
}

/// A JSON network turned into the Rust model's network, remembering the JSON path of
/// every part of its rung by the writer's `Place` of that part.
struct Places<'a> {
    set: &'a InstructionSet,
    paths: BTreeMap<Place, String>,
}

impl Places<'_> {
    /// The JSON path of the part at `place` (or of the nearest part around it; the
    /// network's for none).
    fn path_of(&self, place: &[Step], network: &str) -> String {
        (0..=place.len())
            .rev()
            .find_map(|n| self.paths.get(&place[..n]))
            .cloned()
            .unwrap_or_else(|| network.to_string())
    }

    fn at(&mut self, place: &[Step], path: &str) {
        self.paths.insert(place.to_vec(), path.to_string());
    }

    /// The JSON network as the Rust model's network (its `line` and ids are not used
    /// by the writer and stay 0).
    fn network(&mut self, net: &NetworkJson, n: usize, path: &str) -> Made<Network> {
        let (body, stl) = match &net.body {
            NetworkBody::Rung { rung } => (
                Body::Rung(self.rung(rung, &format!("{path}.rung"))?),
                Vec::new(),
            ),
            NetworkBody::Stl { stl, reason } => (
                Body::Stl {
                    reason: reason.clone(),
                },
                stl.clone(),
            ),
        };
        let comment = if net.comment.is_empty() {
            Vec::new()
        } else {
            net.comment.lines().map(str::to_string).collect()
        };
        Ok(Network {
            number: net.number.unwrap_or(n as u32 + 1),
            title: Some(net.title.clone()).filter(|t| !t.is_empty()),
            comment,
            stl,
            line: 0,
            body,
        })
    }

    /// A rung element: its last part is the outputs (one branch, or a `parallel` of
    /// branches), everything before it the input path.
    fn rung(&mut self, e: &Element, path: &str) -> Made<Rung> {
        self.at(&[], path);
        let (parts, at): (&[Element], String) = match e {
            Element::Series { series } => (series, format!("{path}.series")),
            other => (std::slice::from_ref(other), path.to_string()),
        };
        let Some((last, before)) = parts.split_last() else {
            return Err(ModelError::new(Code::Unwritable, path, "an empty rung"));
        };
        let step = |i: usize| {
            if matches!(e, Element::Series { .. }) {
                format!("{at}[{i}]")
            } else {
                at.clone()
            }
        };
        let input = match before {
            [] => None,
            [one] => Some(self.node(one, &step(0), vec![Step::Input])?),
            many => {
                // The path from the rail is the rung's series without its last part.
                self.at(&[Step::Input], path);
                Some(Node::Series(
                    many.iter()
                        .enumerate()
                        .map(|(i, p)| self.node(p, &step(i), vec![Step::Input, Step::Child(i)]))
                        .collect::<Made<_>>()?,
                ))
            }
        };
        let outputs = self.branches(last, &step(before.len()), vec![Step::Outputs])?;
        Ok(Rung { input, outputs })
    }

    /// Outputs: a `parallel` of branches, or one branch.
    fn branches(&mut self, e: &Element, path: &str, place: Place) -> Made<Vec<Branch>> {
        self.at(&place, path);
        match e {
            Element::Parallel { parallel } => parallel
                .iter()
                .enumerate()
                .map(|(i, b)| {
                    self.branch(
                        b,
                        &format!("{path}.parallel[{i}]"),
                        with(&place, Step::Branch(i)),
                    )
                })
                .collect(),
            other => Ok(vec![self.branch(
                other,
                path,
                with(&place, Step::Branch(0)),
            )?]),
        }
    }

    /// A branch: its series path, then its end (a coil, a box, a further split).
    fn branch(&mut self, e: &Element, path: &str, place: Place) -> Made<Branch> {
        self.at(&place, path);
        let (parts, at): (&[Element], Option<String>) = match e {
            Element::Series { series } => (series, Some(format!("{path}.series"))),
            other => (std::slice::from_ref(other), None),
        };
        let step = |i: usize| {
            at.as_ref()
                .map_or(path.to_string(), |a| format!("{a}[{i}]"))
        };
        let Some((last, before)) = parts.split_last() else {
            return Err(ModelError::new(Code::Unwritable, path, "an empty branch"));
        };
        let path_nodes = before
            .iter()
            .enumerate()
            .map(|(i, p)| self.node(p, &step(i), with(&place, Step::Path(i))))
            .collect::<Made<_>>()?;
        let here = step(before.len());
        let end_place = with(&place, Step::End);
        let end = match last {
            Element::Coil { coil, operands } => {
                self.at(&end_place, &here);
                BranchEnd::Coil(coil_of(self.set, coil, operands, &here)?)
            }
            Element::Box { .. } => BranchEnd::Box(self.boxed(last, &here, end_place)?),
            Element::Parallel { .. } => BranchEnd::Split(self.branches(last, &here, end_place)?),
            _ => {
                return Err(ModelError::new(
                    Code::Unwritable,
                    &here,
                    "an output branch that does not end in a coil, a box or outputs in parallel",
                ))
            }
        };
        Ok(Branch {
            path: path_nodes,
            end,
        })
    }

    /// A piece of input path.
    fn node(&mut self, e: &Element, path: &str, place: Place) -> Made<Node> {
        self.at(&place, path);
        match e {
            Element::Series { series } => Ok(Node::Series(self.children(
                series,
                &format!("{path}.series"),
                &place,
            )?)),
            Element::Parallel { parallel } => Ok(Node::Parallel(self.children(
                parallel,
                &format!("{path}.parallel"),
                &place,
            )?)),
            Element::Contact { contact, operands } => {
                let spec = spec(self.set, contact, path)?;
                let kind = match spec.ladder {
                    LadderClass::ClosedContact => ContactKind::NormallyClosed,
                    LadderClass::Compare => ContactKind::Compare,
                    LadderClass::Not => ContactKind::Not,
                    LadderClass::RisingEdge => ContactKind::PositiveEdge,
                    LadderClass::FallingEdge => ContactKind::NegativeEdge,
                    _ => ContactKind::NormallyOpen,
                };
                Ok(Node::Contact(Contact {
                    id: 0,
                    kind,
                    mnemonic: spec.mnemonic.clone(),
                    immediate: spec.immediate,
                    operands: operands.iter().map(|o| operand(o)).collect(),
                    relation: None,
                    line: 0,
                }))
            }
            Element::Box { .. } => Ok(Node::Box(self.boxed(e, path, place)?)),
            Element::Coil { .. } => Err(ModelError::new(
                Code::Unwritable,
                path,
                "a coil inside a power path: a coil ends a branch",
            )),
        }
    }

    /// The nodes of a series or parallel at `place`, whose JSON list is `at`.
    fn children(&mut self, v: &[Element], at: &str, place: &[Step]) -> Made<Vec<Node>> {
        v.iter()
            .enumerate()
            .map(|(i, p)| self.node(p, &format!("{at}[{i}]"), with(place, Step::Child(i))))
            .collect()
    }

    /// A box: a timer's or counter's number and a CALL's subroutine (its first operand)
    /// are its title, the rest its pins named as the catalog names them.
    fn boxed(&mut self, e: &Element, path: &str, place: Place) -> Made<BoxElement> {
        self.at(&place, path);
        let Element::Box {
            mnemonic,
            operands,
            inputs,
        } = e
        else {
            return Err(ModelError::new(Code::Unwritable, path, "not a box"));
        };
        let spec = spec(self.set, mnemonic, path)?;
        let titled = spec.kind.is_some() || spec.call_arguments;
        let (title, pins) = match operands.split_first() {
            Some((first, rest)) if titled => (first.clone(), rest),
            _ => (spec.mnemonic.clone(), operands.as_slice()),
        };
        let specs = spec.operands.iter().skip(usize::from(titled));
        let pins = pins
            .iter()
            .enumerate()
            .map(|(i, o)| {
                let pin = specs.clone().nth(i);
                Pin {
                    name: pin.map_or_else(|| format!("{}", i + 1), |p| p.name.clone()),
                    output: pin.is_some_and(|p| p.role == Role::Out),
                    operand: operand(o),
                }
            })
            .collect();
        let power_inputs = inputs
            .iter()
            .enumerate()
            .map(|(i, input)| {
                let name = spec.power_inputs.get(i + 1).cloned().unwrap_or_default();
                let node = self.node(
                    input,
                    &format!("{path}.inputs[{i}]"),
                    with(&place, Step::PowerInput(i)),
                )?;
                Ok((name, node))
            })
            .collect::<Made<_>>()?;
        Ok(BoxElement {
            id: 0,
            mnemonic: spec.mnemonic.clone(),
            title,
            pins,
            power_inputs,
            enable: spec.power_inputs.first().cloned().unwrap_or_default(),
            output: spec.power_output.clone(),
            line: 0,
        })
    }
}

/// `place` and one more step.
fn with(place: &[Step], step: Step) -> Place {
    let mut inner = place.to_vec();
    inner.push(step);
    inner
}

fn coil_of(set: &InstructionSet, mnemonic: &str, operands: &[String], path: &str) -> Made<Coil> {
    let spec = spec(set, mnemonic, path)?;
    let kind = match (spec.ladder, spec.immediate) {
        (LadderClass::SetCoil, false) => CoilKind::Set,
        (LadderClass::SetCoil, true) => CoilKind::SetImmediate,
        (LadderClass::ResetCoil, false) => CoilKind::Reset,
        (LadderClass::ResetCoil, true) => CoilKind::ResetImmediate,
        (_, true) => CoilKind::OutImmediate,
        (_, false) => CoilKind::Out,
    };
    let Some((bit, count)) = operands.split_first() else {
        return Err(ModelError::new(
            Code::OperandCount,
            path,
            format!("`{mnemonic}` takes its bit"),
        ));
    };
    Ok(Coil {
        id: 0,
        kind,
        mnemonic: spec.mnemonic.clone(),
        operand: operand(bit),
        count: count.first().map(|c| operand(c)),
        line: 0,
    })
}

/// Every field written as (part of) one source line holds no line break: the network
/// comment is the only text of several lines.
fn one_line_fields(model: &Model) -> Made<()> {
    let mut fields: Vec<(String, &str)> = vec![("plc".to_string(), model.plc.as_str())];
    for (i, s) in model.symbols.iter().enumerate() {
        let at = |f: &str| format!("symbols[{i}].{f}");
        fields.push((at("name"), &s.name));
        fields.push((at("address"), &s.address));
        fields.extend(s.data_type.as_deref().map(|t| (at("type"), t)));
        fields.extend(s.comment.as_deref().map(|c| (at("comment"), c)));
    }
    for (b, block) in model.blocks.iter().enumerate() {
        let at = |f: &str| format!("blocks[{b}].{f}");
        fields.push((at("name"), &block.name));
        fields.push((at("id"), &block.id));
        fields.extend(block.title.as_deref().map(|t| (at("title"), t)));
        let sections: [(&str, &[VarJson]); 4] = [
            ("VAR_INPUT", &block.var_input),
            ("VAR_IN_OUT", &block.var_in_out),
            ("VAR_OUTPUT", &block.var_output),
            ("VAR", &block.var),
        ];
        for (section, vars) in sections {
            for (i, v) in vars.iter().enumerate() {
                let at = |f: &str| format!("blocks[{b}].{section}[{i}].{f}");
                fields.push((at("name"), &v.name));
                fields.push((at("type"), &v.data_type));
                fields.extend(v.comment.as_deref().map(|c| (at("comment"), c)));
            }
        }
        for (n, net) in block.networks.iter().enumerate() {
            let at = format!("blocks[{b}].networks[{n}]");
            fields.push((format!("{at}.title"), &net.title));
            match &net.body {
                NetworkBody::Stl { stl, .. } => fields.extend(
                    stl.iter()
                        .enumerate()
                        .map(|(i, l)| (format!("{at}.stl[{i}]"), l.as_str())),
                ),
                NetworkBody::Rung { rung } => operands(rung, &format!("{at}.rung"), &mut fields),
            }
        }
    }
    match fields
        .into_iter()
        .find(|(_, text)| text.contains(['\n', '\r']))
    {
        Some((path, _)) => Err(ModelError::new(
            Code::Shape,
            &path,
            "a line break in a field that is one line of the program",
        )),
        None => Ok(()),
    }
}

/// The operands of every element of `e`, with their JSON paths.
fn operands<'a>(e: &'a Element, path: &str, out: &mut Vec<(String, &'a str)>) {
    let list = |v: &'a [Element], at: String, out: &mut Vec<(String, &'a str)>| {
        for (i, x) in v.iter().enumerate() {
            operands(x, &format!("{at}[{i}]"), out);
        }
    };
    match e {
        Element::Series { series } => list(series, format!("{path}.series"), out),
        Element::Parallel { parallel } => list(parallel, format!("{path}.parallel"), out),
        Element::Contact { operands: ops, .. } | Element::Coil { operands: ops, .. } => out.extend(
            ops.iter()
                .enumerate()
                .map(|(i, o)| (format!("{path}.operands[{i}]"), o.as_str())),
        ),
        Element::Box {
            operands: ops,
            inputs,
            ..
        } => {
            out.extend(
                ops.iter()
                    .enumerate()
                    .map(|(i, o)| (format!("{path}.operands[{i}]"), o.as_str())),
            );
            list(inputs, format!("{path}.inputs"), out);
        }
    }
}

fn spec<'a>(set: &'a InstructionSet, mnemonic: &str, path: &str) -> Made<&'a Instruction> {
    set.lookup(mnemonic).map(|id| set.get(id)).ok_or_else(|| {
        ModelError::new(
            Code::UnknownMnemonic,
            path,
            format!("`{mnemonic}` is not an instruction of this PLC type"),
        )
    })
}

fn operand(written: &str) -> Operand {
    Operand {
        written: written.to_string(),
        address: None,
        symbol: None,
    }
}
