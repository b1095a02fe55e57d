//! A validated JSON model back into a program's source text (docs/ladder.md, "The model
//! as JSON"): the inverse of `from_program.rs`. `PLC_TYPE`, the SYMBOLS block, then each
//! block with its keyword, `name:id`, `TITLE=`, variable sections and networks. A rung
//! element becomes the Rust `Rung` again and `crate::write` writes its STL: there is no
//! second STL writer here. What each mnemonic is (contact, coil, box, its power inputs
//! and output) comes from the catalog, never from its spelling. Text only: no I/O.

use gutta_catalog::{Instruction, InstructionSet, LadderClass, Role};

use super::codes::{ModelError, ModelErrorCode as Code};
use super::{BlockJson, Element, Model, NetworkBody, NetworkJson, VarJson};
use crate::model::{
    Body, BoxElement, Branch, BranchEnd, Coil, CoilKind, Contact, ContactKind, Network, Node,
    Operand, Pin, Rung,
};
use crate::write;

type Made<T> = Result<T, ModelError>;

/// The block keywords of docs/ladder-model.schema.json's `kind`.
const KINDS: [&str; 3] = ["ORGANIZATION_BLOCK", "SUBROUTINE_BLOCK", "INTERRUPT_BLOCK"];

/// The program text of `model` (validated against `set`), ending in a newline. A rung
/// the writer cannot say as STL is L0013 at its JSON path; a block `kind` the schema
/// does not name, or a line break in a field that is one line of source, is L0002.
pub fn program_of(model: &Model, set: &InstructionSet) -> Made<String> {
    one_line_fields(model)?;
    let mut out = vec![format!("PLC_TYPE {}", model.plc), String::new()];
    if !model.symbols.is_empty() {
        out.push("SYMBOLS".to_string());
        let width = model.symbols.iter().map(|s| s.name.chars().count()).max();
        for s in &model.symbols {
            let mut row = format!("  {:<w$} : {}", s.name, s.address, w = width.unwrap_or(0));
            if let Some(ty) = &s.data_type {
                row.push_str(&format!(" : {ty}"));
            }
            if let Some(c) = &s.comment {
                row.push_str(&format!(" // {c}"));
            }
            out.push(row);
        }
        out.push("END_SYMBOLS".to_string());
        out.push(String::new());
    }
    for (b, block) in model.blocks.iter().enumerate() {
        out.extend(block_text(set, block, b)?);
        out.push(String::new());
    }
    while out.last().is_some_and(String::is_empty) {
        out.pop();
    }
    let mut text = out.join("\n");
    text.push('\n');
    Ok(text)
}

fn block_text(set: &InstructionSet, block: &BlockJson, b: usize) -> Made<Vec<String>> {
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
    let mut out = vec![format!("{} {}:{}", block.kind, block.name, block.id)];
    if let Some(title) = &block.title {
        out.push(format!("TITLE={title}"));
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
        out.push(keyword.to_string());
        for v in vars {
            let mut row = format!("  {} : {};", v.name, v.data_type);
            if let Some(c) = &v.comment {
                row.push_str(&format!(" // {c}"));
            }
            out.push(row);
        }
        out.push("END_VAR".to_string());
    }
    out.push("BEGIN".to_string());
    for (n, net) in block.networks.iter().enumerate() {
        out.extend(network_lines(set, net, b, n)?);
    }
    out.push(format!("END_{}", block.kind));
    Ok(out)
}

/// The lines of network `n` of block `b`, its `NETWORK` line and comment lines first;
/// L0013 when the writer cannot say its rung.
fn network_lines(set: &InstructionSet, net: &NetworkJson, b: usize, n: usize) -> Made<Vec<String>> {
    written(set, net, b, n, write::network_text)
}

/// The instruction lines of network `n` of block `b` (what follows its comment lines,
/// as `network_lines` writes it; what `gutta_analysis::network_edit::replace_network`
/// takes); L0013 when the writer cannot say its rung. The edit operations check the
/// networks they change with it (and `network_fields_one_line` first).
pub(crate) fn network_instructions(
    set: &InstructionSet,
    net: &NetworkJson,
    b: usize,
    n: usize,
) -> Made<Vec<String>> {
    written(set, net, b, n, write::network)
}

/// A network as the Rust model's, written by `writer`.
fn written(
    set: &InstructionSet,
    net: &NetworkJson,
    b: usize,
    n: usize,
    writer: fn(&InstructionSet, &Network) -> Result<Vec<String>, write::WriteError>,
) -> Made<Vec<String>> {
    let path = format!("blocks[{b}].networks[{n}]");
    let network = network_of(set, net, n, &path)?;
    writer(set, &network)
        .map_err(|e| ModelError::new(Code::Unwritable, &format!("{path}.rung"), e.message))
}

/// The JSON network as the Rust model's network (its `line` and ids are not used by
/// the writer and stay 0).
fn network_of(set: &InstructionSet, net: &NetworkJson, n: usize, path: &str) -> Made<Network> {
    let (body, stl) = match &net.body {
        NetworkBody::Rung { rung } => (
            Body::Rung(rung_of(set, rung, &format!("{path}.rung"))?),
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
fn rung_of(set: &InstructionSet, e: &Element, path: &str) -> Made<Rung> {
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
        [one] => Some(node(set, one, &step(0))?),
        many => Some(Node::Series(
            many.iter()
                .enumerate()
                .map(|(i, p)| node(set, p, &step(i)))
                .collect::<Made<_>>()?,
        )),
    };
    let outputs = branches(set, last, &step(before.len()))?;
    Ok(Rung { input, outputs })
}

/// Outputs: a `parallel` of branches, or one branch.
fn branches(set: &InstructionSet, e: &Element, path: &str) -> Made<Vec<Branch>> {
    match e {
        Element::Parallel { parallel } => parallel
            .iter()
            .enumerate()
            .map(|(i, b)| branch(set, b, &format!("{path}.parallel[{i}]")))
            .collect(),
        other => Ok(vec![branch(set, other, path)?]),
    }
}

/// A branch: its series path, then its end (a coil, a box, a further split).
fn branch(set: &InstructionSet, e: &Element, path: &str) -> Made<Branch> {
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
        .map(|(i, p)| node(set, p, &step(i)))
        .collect::<Made<_>>()?;
    let here = step(before.len());
    let end = match last {
        Element::Coil { coil, operands } => BranchEnd::Coil(coil_of(set, coil, operands, &here)?),
        Element::Box { .. } => BranchEnd::Box(box_of(set, last, &here)?),
        Element::Parallel { .. } => BranchEnd::Split(branches(set, last, &here)?),
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
fn node(set: &InstructionSet, e: &Element, path: &str) -> Made<Node> {
    let many = |v: &[Element], at: String| -> Made<Vec<Node>> {
        v.iter()
            .enumerate()
            .map(|(i, p)| node(set, p, &format!("{at}[{i}]")))
            .collect()
    };
    match e {
        Element::Series { series } => Ok(Node::Series(many(series, format!("{path}.series"))?)),
        Element::Parallel { parallel } => {
            Ok(Node::Parallel(many(parallel, format!("{path}.parallel"))?))
        }
        Element::Contact { contact, operands } => {
            let spec = spec(set, contact, path)?;
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
        Element::Box { .. } => Ok(Node::Box(box_of(set, e, path)?)),
        Element::Coil { .. } => Err(ModelError::new(
            Code::Unwritable,
            path,
            "a coil inside a power path: a coil ends a branch",
        )),
    }
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

/// A box: a timer's or counter's number and a CALL's subroutine (its first operand)
/// are its title, the rest its pins named as the catalog names them.
fn box_of(set: &InstructionSet, e: &Element, path: &str) -> Made<BoxElement> {
    let Element::Box {
        mnemonic,
        operands,
        inputs,
    } = e
    else {
        return Err(ModelError::new(Code::Unwritable, path, "not a box"));
    };
    let spec = spec(set, mnemonic, path)?;
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
            Ok((name, node(set, input, &format!("{path}.inputs[{i}]"))?))
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
            network_fields(net, &format!("blocks[{b}].networks[{n}]"), &mut fields);
        }
    }
    no_line_break(fields)
}

/// L0002 when a field of network `n` of block `b` that is one line of source holds a
/// line break (`one_line_fields` for one network).
pub(crate) fn network_fields_one_line(net: &NetworkJson, b: usize, n: usize) -> Made<()> {
    let mut fields = Vec::new();
    network_fields(net, &format!("blocks[{b}].networks[{n}]"), &mut fields);
    no_line_break(fields)
}

/// A network's one-line fields with their JSON paths: its title, its STL lines or the
/// operands of its rung.
fn network_fields<'a>(net: &'a NetworkJson, at: &str, fields: &mut Vec<(String, &'a str)>) {
    fields.push((format!("{at}.title"), &net.title));
    match &net.body {
        NetworkBody::Stl { stl, .. } => fields.extend(
            stl.iter()
                .enumerate()
                .map(|(i, l)| (format!("{at}.stl[{i}]"), l.as_str())),
        ),
        NetworkBody::Rung { rung } => operands(rung, &format!("{at}.rung"), fields),
    }
}

/// L0002 at the first field holding a line break.
fn no_line_break(fields: Vec<(String, &str)>) -> Made<()> {
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
