//! The ladder model back into STL (docs/ladder.md, "From ladder to STL"): a rung as the
//! canonical instruction lines Micro/WIN writes for it, a network shown as STL as its
//! stored lines. The inverse of `build/`: building the written lines gives the same
//! rung. Which STL form a contact takes (`LD`, `A`, `O`...) and which instructions
//! combine paths and split outputs (`ALD`, `OLD`, `LPS`, `LRD`, `LPP`) come from the
//! catalog, never from a mnemonic spelled here. Every line can come with its origin
//! (`network_lines`, `rung_lines`): the `Place` in the rung (or the part of the network)
//! it was written for, the source map `json::check` maps diagnostics back with; the
//! text is the same either way. Writes text only: no I/O, no compiling.

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

/// One step from a part of a rung to a part inside it: a written line's [`Place`] is
/// the steps from the [`Rung`] to the part it was written for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Step {
    /// The rung's `input`.
    Input,
    /// The rung's `outputs`.
    Outputs,
    /// The n-th branch of a list of branches (`outputs`, a `Split`).
    Branch(usize),
    /// The n-th node of a branch's `path`.
    Path(usize),
    /// A branch's `end`.
    End,
    /// The n-th node of a `Series` or a `Parallel`.
    Child(usize),
    /// The n-th of a box's `power_inputs`.
    PowerInput(usize),
}

/// Where in a rung a line was written for: a contact's, a coil's or a box's line is at
/// that element; `ALD` at the `Parallel` it puts in series, `OLD` at the `Parallel`
/// whose branch it joins, `LPS`/`LRD`/`LPP` at the list of branches they split.
pub type Place = Vec<Step>;

/// What part of a network a written line says.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum NetworkPart {
    /// `NETWORK n // title`.
    Heading,
    /// Its n-th comment line.
    Comment(usize),
    /// The n-th of its stored STL lines (a network shown as STL).
    Stl(usize),
    /// A line of its rung, at this place.
    Rung(Place),
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
    Ok(network_lines(set, net)?
        .into_iter()
        .map(|(line, _)| line)
        .collect())
}

/// [`network_text`]'s lines, each with the part of the network it says.
pub fn network_lines(
    set: &InstructionSet,
    net: &Network,
) -> Result<Vec<(String, NetworkPart)>, WriteError> {
    // Title and comment lines trimmed, as the program reads them back.
    let heading = match net
        .title
        .as_deref()
        .map(str::trim)
        .filter(|t| !t.is_empty())
    {
        Some(title) => format!("NETWORK {} // {title}", net.number),
        None => format!("NETWORK {}", net.number),
    };
    let mut lines = vec![(heading, NetworkPart::Heading)];
    lines.extend(net.comment.iter().enumerate().map(|(i, c)| {
        let line = format!("// {}", c.trim());
        (line.trim_end().to_string(), NetworkPart::Comment(i))
    }));
    match &net.body {
        Body::Rung(r) => lines.extend(
            rung_lines(set, r)?
                .into_iter()
                .map(|(line, place)| (line, NetworkPart::Rung(place))),
        ),
        Body::Stl { .. } => lines.extend(
            net.stl
                .iter()
                .enumerate()
                .map(|(i, l)| (l.clone(), NetworkPart::Stl(i))),
        ),
    }
    Ok(lines)
}

/// A rung's canonical STL lines (`LD     I0.0`, `=      Q0.0`).
pub fn rung(set: &InstructionSet, rung: &Rung) -> Result<Vec<String>, WriteError> {
    Ok(rung_lines(set, rung)?
        .into_iter()
        .map(|(line, _)| line)
        .collect())
}

/// [`rung`]'s lines, each with the [`Place`] it was written for.
pub fn rung_lines(set: &InstructionSet, rung: &Rung) -> Result<Vec<(String, Place)>, WriteError> {
    let mut w = Writer {
        set,
        lines: Vec::new(),
        place: Vec::new(),
    };
    if let Some(input) = &rung.input {
        w.within(Step::Input, |w| w.load(input))?;
    }
    if rung.outputs.is_empty() {
        return refuse("the rung has no output".to_string());
    }
    w.within(Step::Outputs, |w| w.branches(&rung.outputs))?;
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
    lines: Vec<(String, Place)>,
    /// The place of the part being written.
    place: Place,
}

impl Writer<'_> {
    /// `write` with `step` added to the place, for the part inside.
    fn within<T>(
        &mut self,
        step: Step,
        write: impl FnOnce(&mut Self) -> Result<T, WriteError>,
    ) -> Result<T, WriteError> {
        self.place.push(step);
        let done = write(self);
        self.place.pop();
        done
    }

    /// A line written for the part at the current place.
    fn push(&mut self, line: String) {
        self.lines.push((line, self.place.clone()));
    }

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
        let mnemonic = self.set.get(id).mnemonic.clone();
        self.push(mnemonic);
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
        let text = line(mnemonic, &ops);
        self.push(text);
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
                self.within(Step::Child(0), |w| w.load(&v[0]))?;
                (1..v.len()).try_for_each(|i| self.within(Step::Child(i), |w| w.and(&v[i])))
            }
            Node::Parallel(v) => {
                self.within(Step::Child(0), |w| w.load(&v[0]))?;
                for (i, n) in v.iter().enumerate().skip(1) {
                    if self.within(Step::Child(i), |w| w.or(n))? {
                        self.stack(LadderClass::OrBlock)?;
                    }
                }
                Ok(())
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
            Node::Series(v) => v
                .iter()
                .enumerate()
                .try_for_each(|(i, n)| self.within(Step::Child(i), |w| w.and(n))),
            Node::Parallel(_) => {
                self.load(node)?;
                self.stack(LadderClass::AndBlock)
            }
            Node::Box(b) => self.boxed(b),
        }
    }

    /// In parallel with the top of the stack: `O...`, or a path loaded; true when it
    /// was loaded, for the caller to write `OLD` at the parallel's place.
    fn or(&mut self, node: &Node) -> Result<bool, WriteError> {
        if let Node::Contact(c) = node {
            if self.contact(c, Join::Or)? {
                return Ok(false);
            }
        }
        self.load(node)?;
        Ok(true)
    }

    /// A box: its extra power inputs loaded in STL order, then the box with its
    /// operands in STL order (a timer's or counter's number and a CALL's block first:
    /// the box's title).
    fn boxed(&mut self, b: &BoxElement) -> Result<(), WriteError> {
        for (i, (_, path)) in b.power_inputs.iter().enumerate() {
            self.within(Step::PowerInput(i), |w| w.load(path))?;
        }
        if crate::model::is_scr(&b.mnemonic) {
            // A sequence control relay of a Micro/WIN export (no catalog instruction):
            // its STL line as Micro/WIN writes it, the S bit its only operand.
            let ops: Vec<&str> = b.pins.iter().map(|p| p.operand.written.as_str()).collect();
            let text = line(&b.mnemonic, &ops);
            self.push(text);
            return Ok(());
        }
        let spec = self.spec(&b.mnemonic)?;
        let mut ops: Vec<&str> = Vec::with_capacity(b.pins.len() + 1);
        if spec.kind.is_some() || spec.call_arguments {
            ops.push(&b.title);
        }
        ops.extend(b.pins.iter().map(|p| p.operand.written.as_str()));
        let text = line(&spec.mnemonic, &ops);
        self.push(text);
        Ok(())
    }

    fn coil(&mut self, c: &Coil) -> Result<(), WriteError> {
        let spec = self.spec(&c.mnemonic)?;
        let mut ops = vec![c.operand.written.as_str()];
        ops.extend(c.count.iter().map(|n| n.written.as_str()));
        let text = line(&spec.mnemonic, &ops);
        self.push(text);
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
            self.within(Step::Branch(i), |w| w.branch(b))?;
            if changing.last() == Some(&i) {
                self.stack(LadderClass::Pop)?;
            } else if changing.contains(&i) {
                self.stack(LadderClass::Read)?;
            }
        }
        Ok(())
    }

    fn branch(&mut self, b: &Branch) -> Result<(), WriteError> {
        for (i, n) in b.path.iter().enumerate() {
            self.within(Step::Path(i), |w| w.and(n))?;
        }
        self.within(Step::End, |w| match &b.end {
            BranchEnd::Coil(c) => w.coil(c),
            BranchEnd::Box(x) => w.boxed(x),
            BranchEnd::Split(v) if v.is_empty() => refuse("a split without branches".to_string()),
            BranchEnd::Split(v) => w.branches(v),
        })
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
