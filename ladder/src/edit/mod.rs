//! Edit operations on the ladder model (docs/ladder.md, "Editing the model"): a plain
//! library API over `json::Model`, no I/O. `path.rs` (where: `ElementPath`,
//! `NetworkPath`, printed and parsed as the L codes' JSON paths), `op.rs` (what: `Edit`
//! and its JSON form), `rung.rs` (the element tree operations and `normalise`),
//! `networks.rs` (a block's networks as a list, its title), `check.rs` (what an edited
//! network must pass: `json/`'s own per-network checks and writer, and the power rules
//! of STL), `history.rs` (`Editor`: a model with undo and redo), `text.rs`
//! (`apply_to_text`: the changes written into the `.lad` text in place). Here: `apply`, which
//! edits a copy of the one network it changes and keeps it only when it checks (the
//! catalog decides what a mnemonic is, the writer what STL can say), and `Change`.

mod check;
mod history;
mod networks;
mod op;
mod path;
mod rung;
mod text;

use gutta_catalog::InstructionSet;

use check::check_network;

pub use history::Editor;
pub use op::{Edit, Place};
pub use path::{ElementPath, NetworkPath, Step};
pub use rung::normalise;
pub use text::apply_to_text;

use crate::json::{
    network_instructions, Element, Model, ModelError, ModelErrorCode as Code, NetworkBody,
    NetworkJson,
};

type Edited<T> = Result<T, ModelError>;

/// What an edit changed, for a caller that rewrites the `.lad` text
/// (`gutta_analysis::network_edit`): positions are the model's after the edit.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Change {
    /// The network's instruction lines changed (an element edit): write them with
    /// [`instruction_lines`] and replace them (`network_edit::replace_network`).
    Lines(NetworkPath),
    /// The network's title or comment changed: its `NETWORK` line or comment lines.
    Heading(NetworkPath),
    /// A network was inserted here (after `network - 1`, or first).
    Inserted(NetworkPath),
    /// The network that was here is deleted.
    Deleted(NetworkPath),
    /// A network moved from position `from` to `to` of `block`.
    Moved {
        block: usize,
        from: usize,
        to: usize,
    },
    /// The block's title changed.
    Block(usize),
}

impl Change {
    /// The change that takes this one back.
    fn inverse(&self) -> Change {
        match *self {
            Change::Lines(at) => Change::Lines(at),
            Change::Heading(at) => Change::Heading(at),
            Change::Inserted(at) => Change::Deleted(at),
            Change::Deleted(at) => Change::Inserted(at),
            Change::Moved { block, from, to } => Change::Moved {
                block,
                from: to,
                to: from,
            },
            Change::Block(b) => Change::Block(b),
        }
    }
}

/// What an applied edit changed, and what takes it back.
type Applied = (Vec<Change>, Undo);

/// What takes an applied edit back.
#[derive(Debug, Clone)]
enum Undo {
    /// The network as it was.
    Network(NetworkPath, NetworkJson),
    /// A block's networks as they were (a network inserted, deleted or moved).
    Networks(usize, Vec<NetworkJson>),
    /// A block's title as it was.
    BlockTitle(usize, Option<String>),
}

impl Undo {
    fn restore(self, model: &mut Model) {
        match self {
            Undo::Network(at, net) => {
                if let Some(slot) = model
                    .blocks
                    .get_mut(at.block)
                    .and_then(|b| b.networks.get_mut(at.network))
                {
                    *slot = net;
                }
            }
            Undo::Networks(b, networks) => {
                if let Some(block) = model.blocks.get_mut(b) {
                    block.networks = networks;
                }
            }
            Undo::BlockTitle(b, title) => {
                if let Some(block) = model.blocks.get_mut(b) {
                    block.title = title;
                }
            }
        }
    }
}

/// `edit` applied to `model`, checked against `set`: what changed, or the refusal with
/// the model unchanged.
pub fn apply(model: &mut Model, set: &InstructionSet, edit: &Edit) -> Edited<Vec<Change>> {
    perform(model, set, edit).map(|(changes, _)| changes)
}

/// The instruction lines of the network at `at` as `json::program_of` writes them
/// (after its `NETWORK` line and comment lines): what a caller puts into the `.lad` text
/// for a `Change::Lines` (`gutta_analysis::network_edit::replace_network`) or a new
/// network's instructions for a `Change::Inserted`.
pub fn instruction_lines(
    model: &Model,
    set: &InstructionSet,
    at: NetworkPath,
) -> Edited<Vec<String>> {
    let net = model
        .blocks
        .get(at.block)
        .and_then(|b| b.networks.get(at.network))
        .ok_or_else(|| no_network(at))?;
    network_instructions(set, net, at.block, at.network)
}

fn perform(model: &mut Model, set: &InstructionSet, edit: &Edit) -> Edited<Applied> {
    match edit {
        Edit::InsertContact {
            at,
            count,
            place,
            contact,
            operands,
        } => {
            let new = Element::Contact {
                contact: contact.clone(),
                operands: operands.clone(),
            };
            edit_rung(model, set, at, false, |r| {
                insert(r, at, *count, *place, new)
            })
        }
        Edit::InsertCoil {
            at,
            count,
            place,
            coil,
            operands,
        } => {
            let new = Element::Coil {
                coil: coil.clone(),
                operands: operands.clone(),
            };
            edit_rung(model, set, at, false, |r| {
                insert(r, at, *count, *place, new)
            })
        }
        Edit::InsertBox {
            at,
            count,
            place,
            mnemonic,
            operands,
            inputs,
        } => {
            let new = Element::Box {
                mnemonic: mnemonic.clone(),
                operands: operands.clone(),
                inputs: inputs.clone(),
            };
            edit_rung(model, set, at, false, |r| {
                insert(r, at, *count, *place, new)
            })
        }
        Edit::WrapParallel { at, count, branch } => edit_rung(model, set, at, false, |r| {
            rung::wrap_parallel(r, at, *count, branch.clone())
        }),
        Edit::Delete { at, count } => {
            edit_rung(model, set, at, true, |r| rung::delete(r, at, *count))
        }
        Edit::SetOperands { at, operands } => {
            edit_rung(model, set, at, false, |r| match rung::at_mut(r, at)? {
                Element::Contact { operands: ops, .. }
                | Element::Coil { operands: ops, .. }
                | Element::Box { operands: ops, .. } => {
                    ops.clone_from(operands);
                    Ok(())
                }
                _ => Err(not_an_instruction(at)),
            })
        }
        Edit::SetMnemonic {
            at,
            mnemonic,
            operands,
            inputs,
        } => edit_rung(model, set, at, false, |r| {
            let e = rung::at_mut(r, at)?;
            if inputs.is_some() && !matches!(e, Element::Box { .. }) {
                return Err(ModelError::new(
                    Code::WrongTarget,
                    &at.to_string(),
                    "only a box has power `inputs`",
                ));
            }
            let (name, ops) = match e {
                Element::Contact { contact, operands } => (contact, operands),
                Element::Coil { coil, operands } => (coil, operands),
                Element::Box {
                    mnemonic,
                    operands,
                    inputs: box_inputs,
                } => {
                    if let Some(new) = inputs {
                        box_inputs.clone_from(new);
                    }
                    (mnemonic, operands)
                }
                _ => return Err(not_an_instruction(at)),
            };
            name.clone_from(mnemonic);
            if let Some(new) = operands {
                ops.clone_from(new);
            }
            Ok(())
        }),
        Edit::InsertNetwork { at, network } => networks::insert(model, set, *at, network),
        Edit::DeleteNetwork { at } => networks::delete(model, *at),
        Edit::MoveNetwork { at, to } => networks::move_to(model, *at, *to),
        Edit::DuplicateNetwork { at } => networks::duplicate(model, *at),
        Edit::SetNetworkTitle { at, title } => {
            edit_network(model, set, *at, Change::Heading, |n| {
                n.title = networks::title_as_read(title);
                Ok(())
            })
        }
        Edit::SetNetworkComment { at, comment } => {
            edit_network(model, set, *at, Change::Heading, |n| {
                n.comment = networks::comment_as_read(comment);
                Ok(())
            })
        }
        Edit::SetBlockTitle { block, title } => networks::set_block_title(model, *block, title),
    }
}

fn insert(
    root: &mut Element,
    at: &ElementPath,
    count: usize,
    place: Place,
    new: Element,
) -> Edited<()> {
    match place {
        Place::Before => rung::insert_beside(root, at, count, new, true),
        Place::After => rung::insert_beside(root, at, count, new, false),
        Place::Parallel => rung::wrap_parallel(root, at, count, new),
    }
}

fn no_network(at: NetworkPath) -> ModelError {
    ModelError::new(
        Code::NoSuchPath,
        &at.to_string(),
        format!("the model has no network at `{at}`"),
    )
}

fn not_an_instruction(at: &ElementPath) -> ModelError {
    ModelError::new(
        Code::WrongTarget,
        &at.to_string(),
        format!("`{at}` is a series or a parallel: operands and mnemonics belong to contacts, coils and boxes"),
    )
}

/// A change of the network at `at` made on a copy, kept only when it checks.
fn edit_network(
    model: &mut Model,
    set: &InstructionSet,
    at: NetworkPath,
    kind: fn(NetworkPath) -> Change,
    change: impl FnOnce(&mut NetworkJson) -> Edited<()>,
) -> Edited<Applied> {
    let slot = model
        .blocks
        .get_mut(at.block)
        .and_then(|b| b.networks.get_mut(at.network))
        .ok_or_else(|| no_network(at))?;
    let mut new = slot.clone();
    change(&mut new)?;
    check_network(set, &new, at.block, at.network)?;
    let before = std::mem::replace(slot, new);
    Ok((vec![kind(at)], Undo::Network(at, before)))
}

/// A change of the rung holding `at`, normalised and checked; `deleting` turns "no
/// output" into L0016.
fn edit_rung(
    model: &mut Model,
    set: &InstructionSet,
    at: &ElementPath,
    deleting: bool,
    change: impl FnOnce(&mut Element) -> Edited<()>,
) -> Edited<Applied> {
    let net = at.network_path();
    let result = edit_network(model, set, net, Change::Lines, |network| {
        let NetworkBody::Rung { rung } = &mut network.body else {
            return Err(ModelError::new(
                Code::NoSuchPath,
                &at.to_string(),
                format!("`{net}` is shown as STL: it has no rung"),
            ));
        };
        change(rung)?;
        *rung = normalise(std::mem::replace(
            rung,
            Element::Series { series: Vec::new() },
        ));
        Ok(())
    });
    result.map_err(|e| match e.code {
        Code::NoOutput if deleting => ModelError::new(
            Code::LastOutput,
            &at.to_string(),
            format!(
                "deleting it leaves a rung or an output branch without an output ({})",
                e.message
            ),
        ),
        _ => e,
    })
}
