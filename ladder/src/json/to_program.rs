//! A validated JSON model back into a program's source text (docs/ladder.md, "The model
//! as JSON"): the inverse of `from_program.rs`. `PLC_TYPE`, the SYMBOLS block, then each
//! block with its keyword, `name:id`, `TITLE=`, variable sections and networks. A rung
//! element becomes the Rust `Rung` again (`to_rung.rs`) and `crate::write` writes its
//! STL: there is no second STL writer here. `written_program` adds the source map: the
//! JSON path behind each line (the writer's `Place`s of a rung mapped back to the
//! model's elements), which `check.rs` maps diagnostics with. Text only: no I/O.

use gutta_catalog::InstructionSet;

use super::codes::{ModelError, ModelErrorCode as Code};
use super::to_rung::Places;
use super::{BlockJson, Element, Model, NetworkBody, NetworkJson, VarJson};
use crate::write::{self, NetworkPart};

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
        let mut places = Places::new(set);
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

/// The instruction lines of network `n` of block `b` (what follows its `NETWORK` line
/// and comment lines, as `written_program` writes them; what
/// `gutta_analysis::network_edit::replace_network` takes); L0013 when the writer cannot
/// say its rung. The edit operations check the networks they change with it (and
/// `network_fields_one_line` first).
pub(crate) fn network_instructions(
    set: &InstructionSet,
    net: &NetworkJson,
    b: usize,
    n: usize,
) -> Made<Vec<String>> {
    let path = format!("blocks[{b}].networks[{n}]");
    let network = Places::new(set).network(net, n, &path)?;
    write::network(set, &network)
        .map_err(|e| ModelError::new(Code::Unwritable, &format!("{path}.rung"), e.message))
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
