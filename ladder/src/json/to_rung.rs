//! A JSON rung back into the ladder model's `Rung` for the writer (`crate::write`),
//! remembering the JSON path of every part by the writer's `Place` of that part: the
//! source map `to_program.rs` gives each written line. The last element of a rung's
//! `series` is its outputs (one branch, or a `parallel` of them), everything before it
//! the path from the left rail. What each mnemonic is (contact, coil, box, its power
//! inputs and output) comes from the catalog, never from its spelling. No I/O.

use std::collections::BTreeMap;

use gutta_catalog::{Instruction, InstructionSet, LadderClass};

use super::codes::{ModelError, ModelErrorCode as Code};
use super::{Element, NetworkBody, NetworkJson};
use crate::model::{
    Body, BoxElement, Branch, BranchEnd, Coil, CoilKind, Contact, ContactKind, Network, Node,
    Operand, Pin, Rung,
};
use crate::write::{Place, Step};

type Made<T> = Result<T, ModelError>;

/// A JSON network turned into the Rust model's network, remembering the JSON path of
/// every part of its rung by the writer's `Place` of that part.
pub(super) struct Places<'a> {
    set: &'a InstructionSet,
    paths: BTreeMap<Place, String>,
}

impl<'a> Places<'a> {
    pub(super) fn new(set: &'a InstructionSet) -> Places<'a> {
        Places {
            set,
            paths: BTreeMap::new(),
        }
    }

    /// The JSON path of the part at `place` (or of the nearest part around it; the
    /// network's for none).
    pub(super) fn path_of(&self, place: &[Step], network: &str) -> String {
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
    pub(super) fn network(&mut self, net: &NetworkJson, n: usize, path: &str) -> Made<Network> {
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
            super::comment_lines(&net.comment)
                .map(str::to_string)
                .collect()
        };
        Ok(Network {
            number: net.number.unwrap_or(n as u32 + 1),
            title: Some(net.title.clone()).filter(|t| !t.is_empty()),
            comment,
            stl,
            line: 0,
            body,
            stl_code: Vec::new(),
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
        let sides = crate::names::pin_sides(spec);
        let pins = pins
            .iter()
            .enumerate()
            .map(|(i, o)| {
                let side = sides.get(i + usize::from(titled));
                Pin {
                    name: side.map_or_else(|| format!("{}", i + 1), |p| p.name.clone()),
                    output: side.is_some_and(|p| p.output),
                    operand: operand(o),
                    input: side.and_then(|p| p.input.clone()),
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
            pins,
            power_inputs,
            enable: spec.power_inputs.first().cloned().unwrap_or_default(),
            output: spec.power_output.clone(),
            line: 0,
            counted: spec.kind.map(|_| Box::new(operand(&title))),
            resolution_ms: None,
            shape: crate::build::box_shape(spec),
            title,
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

fn spec<'a>(set: &'a InstructionSet, mnemonic: &str, path: &str) -> Made<&'a Instruction> {
    set.lookup(mnemonic).map(|id| set.get(id)).ok_or_else(|| {
        ModelError::new(
            Code::UnknownMnemonic,
            path,
            format!("`{mnemonic}` is not an instruction of this PLC type"),
        )
    })
}

/// An operand as the program reads it back: without blanks around it.
fn operand(written: &str) -> Operand {
    Operand {
        written: written.trim().to_string(),
        address: None,
        symbol: None,
        comment: None,
        data_type: None,
    }
}
