//! The ladder model back into STL (docs/ladder.md, "From ladder to STL"): a rung as the
//! canonical instruction lines Micro/WIN writes for it, a network shown as STL as its
//! stored lines. The inverse of `build/`: building the written lines gives the same
//! rung. Which STL form a contact takes (`LD`, `A`, `O`...) and which instructions
//! combine paths and split outputs (`ALD`, `OLD`, `LPS`, `LRD`, `LPP`) come from the
//! catalog, never from a mnemonic spelled here. Writes text only: no I/O, no compiling.

use std::fmt;

use gutta_catalog::{Instruction, InstructionSet, Join, LadderClass};

use crate::model::{Body, BoxElement, Branch, BranchEnd, Coil, Contact, Network, Node, Rung};

/// Why a rung cannot be written as STL: an element the catalog does not know, or a
/// shape STL cannot say (a path starting with `NOT`, a box without power input).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WriteError {
    pub message: String,
}

impl fmt::Display for WriteError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for WriteError {}

fn refuse<T>(message: String) -> Result<T, WriteError> {
    Err(WriteError { message })
}

/// A network's instruction lines: its rung written, or its STL as stored.
pub fn network(set: &InstructionSet, net: &Network) -> Result<Vec<String>, WriteError> {
    match &net.body {
        Body::Rung(r) => rung(set, r),
        Body::Stl { .. } => Ok(net.stl.clone()),
    }
}

/// A whole network as text: `NETWORK n // title`, its comment lines, then its
/// instruction lines ([`network`]).
pub fn network_text(set: &InstructionSet, net: &Network) -> Result<Vec<String>, WriteError> {
    let mut lines = vec![match &net.title {
        Some(title) => format!("NETWORK {} // {title}", net.number),
        None => format!("NETWORK {}", net.number),
    }];
    lines.extend(net.comment.iter().map(|c| format!("// {c}")));
    lines.extend(network(set, net)?);
    Ok(lines)
}

/// A rung's canonical STL lines (`LD     I0.0`, `=      Q0.0`).
pub fn rung(set: &InstructionSet, rung: &Rung) -> Result<Vec<String>, WriteError> {
    let mut w = Writer {
        set,
        lines: Vec::new(),
    };
    if let Some(input) = &rung.input {
        w.load(input)?;
    }
    if rung.outputs.is_empty() {
        return refuse("the rung has no output".to_string());
    }
    w.branches(&rung.outputs)?;
    Ok(w.lines)
}

/// One instruction line: the mnemonic in a column of seven, then the operands.
fn line(mnemonic: &str, operands: &[&str]) -> String {
    if operands.is_empty() {
        return mnemonic.to_string();
    }
    format!("{mnemonic:<6} {}", operands.join(", "))
}

struct Writer<'a> {
    set: &'a InstructionSet,
    lines: Vec<String>,
}

impl Writer<'_> {
    fn spec(&self, mnemonic: &str) -> Result<&Instruction, WriteError> {
        match self.set.lookup(mnemonic) {
            Some(id) => Ok(self.set.get(id)),
            None => refuse(format!("`{mnemonic}` is not an instruction")),
        }
    }

    /// An instruction without operands of a ladder class (`ALD`, `LPS`...).
    fn stack(&mut self, class: LadderClass) -> Result<(), WriteError> {
        let Some(id) = self.set.plain(class, None) else {
            return refuse(format!("the instruction set has no {class:?} instruction"));
        };
        self.lines.push(self.set.get(id).mnemonic.clone());
        Ok(())
    }

    /// A contact in the STL form of `join`; `None` for one that has no such form
    /// (`NOT`, `EU`, `ED` only go in series, as they are).
    fn contact(&mut self, c: &Contact, join: Join) -> Result<bool, WriteError> {
        let Some(id) = self.set.lookup(&c.mnemonic) else {
            return refuse(format!("`{}` is not an instruction", c.mnemonic));
        };
        let spec = self.set.get(id);
        if !spec.ladder.is_contact() && !is_series_only(spec.ladder) {
            return refuse(format!("`{}` is not a contact", c.mnemonic));
        }
        let mnemonic = match (spec.join(), join) {
            (None, Join::And) => spec.mnemonic.as_str(),
            (None, _) => return Ok(false),
            (Some(_), _) => match self.set.with_join(id, join) {
                Some(to) => self.set.get(to).mnemonic.as_str(),
                None => return Ok(false),
            },
        };
        let ops: Vec<&str> = c.operands.iter().map(|o| o.written.as_str()).collect();
        self.lines.push(line(mnemonic, &ops));
        Ok(true)
    }

    /// A new path from the left rail: one more level of the logic stack.
    fn load(&mut self, node: &Node) -> Result<(), WriteError> {
        match node {
            Node::Contact(c) => {
                if !self.contact(c, Join::Load)? {
                    return refuse(format!("`{}` cannot start a power path", c.mnemonic));
                }
                Ok(())
            }
            Node::Series(v) | Node::Parallel(v) if v.is_empty() => {
                refuse("an empty series or parallel".to_string())
            }
            Node::Series(v) => {
                self.load(&v[0])?;
                v[1..].iter().try_for_each(|n| self.and(n))
            }
            Node::Parallel(v) => {
                self.load(&v[0])?;
                v[1..].iter().try_for_each(|n| self.or(n))
            }
            Node::Box(b) => refuse(format!("the box {} has no power path into it", b.mnemonic)),
        }
    }

    /// In series with the top of the stack: `A...`, or a path loaded and `ALD`.
    fn and(&mut self, node: &Node) -> Result<(), WriteError> {
        match node {
            Node::Contact(c) => {
                if !self.contact(c, Join::And)? {
                    return refuse(format!("`{}` cannot go in series", c.mnemonic));
                }
                Ok(())
            }
            Node::Series(v) => v.iter().try_for_each(|n| self.and(n)),
            Node::Parallel(_) => {
                self.load(node)?;
                self.stack(LadderClass::AndBlock)
            }
            Node::Box(b) => self.boxed(b),
        }
    }

    /// In parallel with the top of the stack: `O...`, or a path loaded and `OLD`.
    fn or(&mut self, node: &Node) -> Result<(), WriteError> {
        if let Node::Contact(c) = node {
            if self.contact(c, Join::Or)? {
                return Ok(());
            }
        }
        self.load(node)?;
        self.stack(LadderClass::OrBlock)
    }

    /// A box: its extra power inputs loaded in STL order, then the box with its
    /// operands in STL order (a timer's or counter's number and a CALL's block first:
    /// the box's title).
    fn boxed(&mut self, b: &BoxElement) -> Result<(), WriteError> {
        for (_, path) in &b.power_inputs {
            self.load(path)?;
        }
        let spec = self.spec(&b.mnemonic)?;
        let mut ops: Vec<&str> = Vec::with_capacity(b.pins.len() + 1);
        if spec.kind.is_some() || spec.call_arguments {
            ops.push(&b.title);
        }
        ops.extend(b.pins.iter().map(|p| p.operand.written.as_str()));
        self.lines.push(line(&spec.mnemonic, &ops));
        Ok(())
    }

    fn coil(&mut self, c: &Coil) -> Result<(), WriteError> {
        let spec = self.spec(&c.mnemonic)?;
        let mut ops = vec![c.operand.written.as_str()];
        ops.extend(c.count.iter().map(|n| n.written.as_str()));
        self.lines.push(line(&spec.mnemonic, &ops));
        Ok(())
    }

    /// Branches hanging at the power on top of the stack. A branch that leaves the top
    /// as it was (a coil, a box ending power) needs no copy; before the first branch
    /// that changes it and has branches after it comes `LPS`, after each such branch
    /// `LRD`, after the last one `LPP`.
    fn branches(&mut self, list: &[Branch]) -> Result<(), WriteError> {
        let changing: Vec<usize> = (0..list.len().saturating_sub(1))
            .filter(|&i| !keeps_top(&list[i]))
            .collect();
        for (i, b) in list.iter().enumerate() {
            if changing.first() == Some(&i) {
                self.stack(LadderClass::Push)?;
            }
            self.branch(b)?;
            if changing.last() == Some(&i) {
                self.stack(LadderClass::Pop)?;
            } else if changing.contains(&i) {
                self.stack(LadderClass::Read)?;
            }
        }
        Ok(())
    }

    fn branch(&mut self, b: &Branch) -> Result<(), WriteError> {
        for n in &b.path {
            self.and(n)?;
        }
        match &b.end {
            BranchEnd::Coil(c) => self.coil(c),
            BranchEnd::Box(x) => self.boxed(x),
            BranchEnd::Split(v) if v.is_empty() => refuse("a split without branches".to_string()),
            BranchEnd::Split(v) => self.branches(v),
        }
    }
}

/// `NOT`, `EU`, `ED`: contacts with only a series form.
fn is_series_only(class: LadderClass) -> bool {
    matches!(
        class,
        LadderClass::Not | LadderClass::RisingEdge | LadderClass::FallingEdge
    )
}

/// Whether writing the branch leaves the top of the logic stack as it found it.
fn keeps_top(b: &Branch) -> bool {
    b.path.is_empty()
        && match &b.end {
            BranchEnd::Coil(_) => true,
            BranchEnd::Box(x) => x.output.is_none(),
            BranchEnd::Split(v) => v.iter().all(keeps_top),
        }
}
