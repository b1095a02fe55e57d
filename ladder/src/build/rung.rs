//! One network's elements into one rung, by simulating the logic stack on power paths
//! (docs/ladder.md, "Which networks are ladder"), or the reason they are not one rung.
//! Each stack level is either a path from the left rail that feeds nothing yet (free to
//! be combined by `A`, `O`, `ALD`, `OLD`) or a point of the drawn rung where outputs
//! hang (a junction), followed by the series elements since. Knows nothing of the
//! source: elements come in with their instruction's text and line.

use crate::model::{BoxElement, Branch, BranchEnd, ContactKind, Node, Rung};

use super::element::{Element, Join, StackOp};

/// The instruction an element came from, for refusal reasons: "`LD I0.2` at line 14".
#[derive(Debug, Clone)]
pub(super) struct Origin {
    pub text: String,
    pub line: u32,
}

impl Origin {
    /// "`LD I0.2` at line 14".
    pub(super) fn at(&self) -> String {
        format!("`{}` at line {}", self.text, self.line)
    }
}

/// One level of the logic stack.
#[derive(Debug, Clone)]
enum Level {
    /// A path from the left rail that feeds no output yet; `origin` started it.
    /// `acting` is its first element that acts on the power it is given (see
    /// `acts_on_power`): such a path cannot be drawn in series after another.
    Free {
        path: Node,
        origin: Origin,
        acting: Option<Origin>,
    },
    /// The power at `junction` of the rung, then `tail` in series (started by
    /// `tail_origin`).
    Anchored {
        junction: usize,
        tail: Vec<Node>,
        tail_origin: Option<Origin>,
    },
}

/// A branch while the rung is built: a split names a junction.
#[derive(Debug)]
struct DraftBranch {
    path: Vec<Node>,
    end: DraftEnd,
}

#[derive(Debug)]
enum DraftEnd {
    End(Box<BranchEnd>),
    Split(usize),
}

/// The rung being built.
#[derive(Debug, Default)]
pub(super) struct RungBuilder {
    stack: Vec<Level>,
    /// The branches hanging at each junction, top to bottom.
    junctions: Vec<Vec<DraftBranch>>,
    /// The path from the left rail to the first junction, once an output needs it.
    root: Option<(Node, usize)>,
    /// `LPS` (and `LDS 0`) not yet popped by `LPP`.
    open_pushes: Vec<Origin>,
}

type Refusal = String;

impl RungBuilder {
    /// Place one element (from the instruction `origin`).
    pub(super) fn push(&mut self, element: Element, origin: Origin) -> Result<(), Refusal> {
        match element {
            Element::Contact(Join::Load, c) => {
                self.stack.push(Level::Free {
                    path: Node::Contact(c),
                    origin,
                    acting: None,
                });
                Ok(())
            }
            Element::Contact(Join::Series, c) => self.series(Node::Contact(c), origin),
            Element::Contact(Join::Parallel, c) => self.parallel(Node::Contact(c), origin),
            Element::SeriesBox(b) => self.series(Node::Box(b), origin),
            Element::Counter(mut b, inputs) => {
                self.need(inputs.len() + 1, &origin)?;
                let levels = self.stack.split_off(self.stack.len() - inputs.len());
                for (name, level) in inputs.iter().zip(levels) {
                    match level {
                        Level::Free { path, .. } => b.power_inputs.push((name.to_string(), path)),
                        Level::Anchored { .. } => {
                            return Err(format!(
                            "{} takes its {name} input from a path that already feeds an output",
                            origin.at()
                        ))
                        }
                    }
                }
                self.series(Node::Box(b), origin)
            }
            Element::Coil(c) => self.output(BranchEnd::Coil(c), &origin),
            Element::EndBox(b, _) => self.output(BranchEnd::Box(b), &origin),
            Element::Stack(op) => self.stack_op(op, origin),
            Element::Always(_) => Err(format!(
                "{} runs without power flow, and the network has power flow",
                origin.at()
            )),
            Element::Unknown => Err(format!("{} has no ladder element", origin.at())),
        }
    }

    /// The rung, once every element is placed.
    pub(super) fn finish(mut self) -> Result<Rung, Refusal> {
        if let Some(open) = self.open_pushes.first() {
            return Err(format!("{} has no matching `LPP`", open.at()));
        }
        while let Some(level) = self.stack.pop() {
            self.close(level)?;
        }
        let Some((input, junction)) = self.root.take() else {
            return Err("the network has no output".to_string());
        };
        let mut junctions: Vec<Option<Vec<DraftBranch>>> =
            self.junctions.into_iter().map(Some).collect();
        let outputs = branches(&mut junctions, junction)?;
        Ok(Rung {
            input: Some(input),
            outputs,
        })
    }

    fn need(&self, levels: usize, origin: &Origin) -> Result<(), Refusal> {
        if self.stack.len() < levels {
            return Err(format!(
                "{} needs {levels} {} of the logic stack; {} {} loaded",
                origin.at(),
                if levels == 1 { "level" } else { "levels" },
                self.stack.len(),
                if self.stack.len() == 1 { "is" } else { "are" }
            ));
        }
        Ok(())
    }

    fn top(&mut self, origin: &Origin) -> Result<&mut Level, Refusal> {
        self.need(1, origin)?;
        let last = self.stack.len() - 1;
        Ok(&mut self.stack[last])
    }

    fn series(&mut self, node: Node, origin: Origin) -> Result<(), Refusal> {
        match self.top(&origin)? {
            Level::Free { path, acting, .. } => {
                if acting.is_none() && acts_on_power(&node) {
                    *acting = Some(origin);
                }
                let left = std::mem::replace(path, Node::Series(Vec::new()));
                *path = series(left, node);
            }
            Level::Anchored {
                tail, tail_origin, ..
            } => {
                if tail.is_empty() {
                    *tail_origin = Some(origin);
                }
                tail.push(node);
            }
        }
        Ok(())
    }

    fn parallel(&mut self, node: Node, origin: Origin) -> Result<(), Refusal> {
        match self.top(&origin)? {
            Level::Free { path, .. } => {
                let top = std::mem::replace(path, Node::Series(Vec::new()));
                *path = parallel(top, node);
                Ok(())
            }
            Level::Anchored { .. } => Err(format!(
                "{} puts a contact in parallel with a path that already feeds an output",
                origin.at()
            )),
        }
    }

    fn stack_op(&mut self, op: StackOp, origin: Origin) -> Result<(), Refusal> {
        match op {
            StackOp::Ald | StackOp::Old => {
                self.need(2, &origin)?;
                let (Some(top), Some(below)) = (self.stack.pop(), self.stack.pop()) else {
                    return Err(format!("{} lacks levels", origin.at()));
                };
                // A path in series after another takes its power through it: an
                // element acting on its power would act on the path before too.
                if let (
                    StackOp::Ald,
                    Level::Free {
                        acting: Some(x), ..
                    },
                ) = (op, &top)
                {
                    let after = match &below {
                        Level::Free { origin: o, .. } => format!("the path of {}", o.at()),
                        Level::Anchored { .. } => "a path that already feeds an output".to_string(),
                    };
                    return Err(format!(
                        "{} puts the path of {} in series after {after}: `{}` would take its power through that path too",
                        origin.at(),
                        x.at(),
                        x.text
                    ));
                }
                let joined = match (below, top, op) {
                    (
                        Level::Free {
                            path: a,
                            origin: o,
                            acting,
                        },
                        Level::Free { path: b, .. },
                        StackOp::Ald,
                    ) => Level::Free {
                        path: series(a, b),
                        origin: o,
                        acting,
                    },
                    // A path in parallel starts at the left rail, as it did on its own.
                    (
                        Level::Free {
                            path: a,
                            origin: o,
                            acting,
                        },
                        Level::Free {
                            path: b,
                            acting: acting_b,
                            ..
                        },
                        _,
                    ) => Level::Free {
                        path: parallel(a, b),
                        origin: o,
                        acting: acting.or(acting_b),
                    },
                    (
                        Level::Anchored {
                            junction,
                            mut tail,
                            tail_origin,
                        },
                        Level::Free {
                            path, origin: o, ..
                        },
                        StackOp::Ald,
                    ) => {
                        let tail_origin = tail_origin.or(Some(o));
                        match path {
                            Node::Series(v) => tail.extend(v),
                            other => tail.push(other),
                        }
                        Level::Anchored {
                            junction,
                            tail,
                            tail_origin,
                        }
                    }
                    (Level::Anchored { .. }, Level::Free { .. }, _) => {
                        return Err(format!(
                            "{} puts a path in parallel with one that already feeds an output",
                            origin.at()
                        ))
                    }
                    (_, Level::Anchored { .. }, _) => {
                        return Err(format!(
                            "{} combines a path that already feeds an output",
                            origin.at()
                        ))
                    }
                };
                self.stack.push(joined);
                Ok(())
            }
            StackOp::Lps | StackOp::Lds(0) => {
                self.duplicate(&origin)?;
                self.open_pushes.push(origin);
                Ok(())
            }
            StackOp::Lrd => {
                self.need(2, &origin)?;
                if let Some(level) = self.stack.pop() {
                    self.close(level)?;
                }
                self.duplicate(&origin)
            }
            StackOp::Lpp => {
                self.need(2, &origin)?;
                if let Some(level) = self.stack.pop() {
                    self.close(level)?;
                }
                self.open_pushes.pop();
                Ok(())
            }
            StackOp::Lds(_) => Err(format!(
                "{} copies a lower level of the logic stack, which ladder cannot draw",
                origin.at()
            )),
        }
    }

    /// LPS: the top becomes a junction (splitting its tail off), used twice.
    fn duplicate(&mut self, origin: &Origin) -> Result<(), Refusal> {
        let level = self.stack.pop().ok_or_else(|| {
            format!(
                "{} needs 1 level of the logic stack; 0 are loaded",
                origin.at()
            )
        })?;
        let junction = self.junction_of(level)?;
        for _ in 0..2 {
            self.stack.push(Level::Anchored {
                junction,
                tail: Vec::new(),
                tail_origin: None,
            });
        }
        Ok(())
    }

    /// A coil or an ending box at the end of the top's path; the top stays where it was.
    fn output(&mut self, end: BranchEnd, origin: &Origin) -> Result<(), Refusal> {
        self.need(1, origin)?;
        let level = self.stack.pop().ok_or_else(|| origin.at())?;
        let junction = self.junction_of(level)?;
        self.junctions[junction].push(DraftBranch {
            path: Vec::new(),
            end: DraftEnd::End(Box::new(end)),
        });
        self.stack.push(Level::Anchored {
            junction,
            tail: Vec::new(),
            tail_origin: None,
        });
        Ok(())
    }

    /// The junction at the end of a level's path: a free path becomes the rung's input
    /// (there is one), an anchored tail a branch splitting at a new junction.
    fn junction_of(&mut self, level: Level) -> Result<usize, Refusal> {
        match level {
            Level::Free { path, origin, .. } => {
                if self.root.is_some() {
                    return Err(format!("{} starts a second power path", origin.at()));
                }
                let j = self.new_junction();
                self.root = Some((path, j));
                Ok(j)
            }
            Level::Anchored { junction, tail, .. } if tail.is_empty() => Ok(junction),
            Level::Anchored { junction, tail, .. } => {
                let j = self.new_junction();
                self.junctions[junction].push(DraftBranch {
                    path: tail,
                    end: DraftEnd::Split(j),
                });
                Ok(j)
            }
        }
    }

    fn new_junction(&mut self) -> usize {
        self.junctions.push(Vec::new());
        self.junctions.len() - 1
    }

    /// A level that is popped or left at the end: its path must end in an output, or
    /// in a box (which then ends it).
    fn close(&mut self, level: Level) -> Result<(), Refusal> {
        match level {
            Level::Anchored { tail, .. } if tail.is_empty() => Ok(()),
            Level::Anchored {
                junction,
                mut tail,
                tail_origin,
            } => match tail.pop() {
                Some(Node::Box(b)) => {
                    let j = self.junction_of(Level::Anchored {
                        junction,
                        tail,
                        tail_origin,
                    })?;
                    self.junctions[j].push(DraftBranch {
                        path: Vec::new(),
                        end: DraftEnd::End(Box::new(BranchEnd::Box(b))),
                    });
                    Ok(())
                }
                _ => Err(format!(
                    "{} leads to no output",
                    tail_origin.map(|o| o.at()).unwrap_or_default()
                )),
            },
            Level::Free { path, origin, .. } => {
                let (rest, last) = split_last(path);
                match (rest, last) {
                    (Some(rest), Node::Box(b)) => {
                        let j = self.junction_of(Level::Free {
                            path: rest,
                            origin,
                            acting: None,
                        })?;
                        self.junctions[j].push(DraftBranch {
                            path: Vec::new(),
                            end: DraftEnd::End(Box::new(BranchEnd::Box(b))),
                        });
                        Ok(())
                    }
                    _ if self.root.is_some() => {
                        Err(format!("{} starts a second power path", origin.at()))
                    }
                    _ => Err(format!(
                        "{} starts a power path that reaches no output",
                        origin.at()
                    )),
                }
            }
        }
    }
}

/// The branches at a junction, single-branch splits merged into their branch.
fn branches(
    junctions: &mut [Option<Vec<DraftBranch>>],
    junction: usize,
) -> Result<Vec<Branch>, Refusal> {
    let drafts = junctions
        .get_mut(junction)
        .and_then(Option::take)
        .unwrap_or_default();
    let mut out = Vec::with_capacity(drafts.len());
    for draft in drafts {
        let mut path = draft.path;
        let end = match draft.end {
            DraftEnd::End(end) => *end,
            DraftEnd::Split(j) => {
                let mut inner = branches(junctions, j)?;
                match inner.len() {
                    0 => return Err("a branch leads to no output".to_string()),
                    1 => {
                        let only = inner.remove(0);
                        path.extend(only.path);
                        only.end
                    }
                    _ => BranchEnd::Split(inner),
                }
            }
        };
        out.push(Branch { path, end });
    }
    if out.is_empty() {
        return Err("the network has no output".to_string());
    }
    Ok(out)
}

/// Whether a path holds an element that acts on the power it is given, not only passes
/// it or not: a box (its power input runs it: a timer times it, a counter counts it)
/// and `NOT`, `EU`, `ED` (the contacts of the catalog's `Not`, `RisingEdge` and
/// `FallingEdge`). Ladder gives such an element the power of everything before it in
/// series, so a path holding one cannot be drawn after another path.
fn acts_on_power(node: &Node) -> bool {
    match node {
        Node::Box(_) => true,
        Node::Contact(c) => matches!(
            c.kind,
            ContactKind::Not | ContactKind::PositiveEdge | ContactKind::NegativeEdge
        ),
        Node::Series(v) | Node::Parallel(v) => v.iter().any(acts_on_power),
    }
}

/// `a` then `b` in series, flattened.
fn series(a: Node, b: Node) -> Node {
    let mut items = match a {
        Node::Series(v) => v,
        other => vec![other],
    };
    match b {
        Node::Series(v) => items.extend(v),
        other => items.push(other),
    }
    Node::Series(items)
}

/// `a` over `b` in parallel, flattened.
fn parallel(a: Node, b: Node) -> Node {
    let mut items = match a {
        Node::Parallel(v) => v,
        other => vec![other],
    };
    match b {
        Node::Parallel(v) => items.extend(v),
        other => items.push(other),
    }
    Node::Parallel(items)
}

/// A path without its last series element, and that element.
fn split_last(path: Node) -> (Option<Node>, Node) {
    match path {
        Node::Series(mut v) => {
            let last = v.pop().unwrap_or(Node::Series(Vec::new()));
            let rest = match v.len() {
                0 => None,
                1 => v.pop(),
                _ => Some(Node::Series(v)),
            };
            (rest, last)
        }
        other => (None, other),
    }
}

/// A box drawn on the left rail: an instruction without power flow alone in its
/// network.
pub(super) fn rail_rung(b: BoxElement) -> Rung {
    Rung {
        input: None,
        outputs: vec![Branch {
            path: Vec::new(),
            end: BranchEnd::Box(b),
        }],
    }
}

/// Number the rung's contacts, coils and boxes 0, 1, 2... in drawing order: left to
/// right, top to bottom (a box's extra power inputs before the box).
pub(super) fn number(rung: &mut Rung) {
    let mut next = 0;
    if let Some(input) = &mut rung.input {
        number_node(input, &mut next);
    }
    for b in &mut rung.outputs {
        number_branch(b, &mut next);
    }
}

fn take(next: &mut u32) -> u32 {
    *next += 1;
    *next - 1
}

fn number_node(node: &mut Node, next: &mut u32) {
    match node {
        Node::Contact(c) => c.id = take(next),
        Node::Box(b) => number_box(b, next),
        Node::Series(v) | Node::Parallel(v) => v.iter_mut().for_each(|n| number_node(n, next)),
    }
}

fn number_box(b: &mut BoxElement, next: &mut u32) {
    for (_, path) in &mut b.power_inputs {
        number_node(path, next);
    }
    b.id = take(next);
}

fn number_branch(branch: &mut Branch, next: &mut u32) {
    for n in &mut branch.path {
        number_node(n, next);
    }
    match &mut branch.end {
        BranchEnd::Coil(c) => c.id = take(next),
        BranchEnd::Box(b) => number_box(b, next),
        BranchEnd::Split(v) => v.iter_mut().for_each(|b| number_branch(b, next)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Contact;

    fn c(n: u32) -> Node {
        Node::Contact(Contact {
            id: n,
            kind: ContactKind::NormallyOpen,
            mnemonic: "LD".to_string(),
            immediate: false,
            operands: Vec::new(),
            relation: None,
            line: n,
        })
    }

    #[test]
    fn series_and_parallel_flatten_their_own_kind_only() {
        let s = series(series(c(0), c(1)), series(c(2), c(3)));
        assert!(matches!(&s, Node::Series(v) if v.len() == 4));
        let p = parallel(parallel(c(0), c(1)), s.clone());
        assert!(matches!(&p, Node::Parallel(v) if v.len() == 3 && v[2] == s));
    }

    #[test]
    fn split_last_leaves_one_element_bare() {
        let (rest, last) = split_last(series(c(0), c(1)));
        assert_eq!((rest, last), (Some(c(0)), c(1)));
        let (rest, last) = split_last(c(5));
        assert_eq!((rest, last), (None, c(5)));
    }

    #[test]
    fn an_open_branch_point_is_refused_at_the_end() {
        let mut b = RungBuilder::default();
        let at = |line| Origin {
            text: "X".to_string(),
            line,
        };
        let Node::Contact(first) = c(0) else { panic!() };
        b.push(Element::Contact(Join::Load, first), at(1)).unwrap();
        b.push(Element::Stack(StackOp::Lps), at(2)).unwrap();
        assert_eq!(
            b.finish().unwrap_err(),
            "`X` at line 2 has no matching `LPP`"
        );
    }
}
