//! The edit operations on a block's networks as a list (insert, delete, move,
//! duplicate) and on a block's title: positions checked (L0017), network numbers kept
//! equal to positions where the block has them, and what undoes each (the block's
//! networks as they were). A new network is checked as any edited one (`check.rs`).

use gutta_catalog::InstructionSet;

use super::check::check_network;
use super::{normalise, Applied, Change, NetworkPath, Undo};
use crate::json::{
    comment_lines, BlockJson, Element, Model, ModelError, ModelErrorCode as Code, NetworkBody,
    NetworkJson,
};

type Edited<T> = Result<T, ModelError>;

/// `network` (normalised and checked) at position `at`.
pub(super) fn insert(
    model: &mut Model,
    set: &InstructionSet,
    at: NetworkPath,
    network: &NetworkJson,
) -> Edited<Applied> {
    let block = block_mut(model, at.block)?;
    if at.network > block.networks.len() {
        return Err(out_of_range(
            &at.to_string(),
            format!(
                "a network is inserted at a position from 0 to {}",
                block.networks.len()
            ),
        ));
    }
    let mut new = network.clone();
    new.title = title_as_read(&new.title);
    new.comment = comment_as_read(&new.comment);
    match &mut new.body {
        NetworkBody::Rung { rung } => {
            *rung = normalise(std::mem::replace(rung, Element::Series { series: vec![] }));
        }
        NetworkBody::Stl { stl, .. } => {
            *stl = stl
                .iter()
                .map(|l| l.trim().to_string())
                .filter(|l| !l.is_empty())
                .collect();
        }
    }
    check_network(set, &new, at.block, at.network)?;
    let before = block.networks.clone();
    block.networks.insert(at.network, new);
    renumber(&mut block.networks);
    Ok((vec![Change::Inserted(at)], Undo::Networks(at.block, before)))
}

pub(super) fn delete(model: &mut Model, at: NetworkPath) -> Edited<Applied> {
    let block = block_mut(model, at.block)?;
    existing(block, at)?;
    let before = block.networks.clone();
    block.networks.remove(at.network);
    renumber(&mut block.networks);
    Ok((vec![Change::Deleted(at)], Undo::Networks(at.block, before)))
}

/// The network at `at` to position `to` (counted after it is taken out).
pub(super) fn move_to(model: &mut Model, at: NetworkPath, to: usize) -> Edited<Applied> {
    let block = block_mut(model, at.block)?;
    existing(block, at)?;
    if to >= block.networks.len() {
        return Err(out_of_range(
            &at.to_string(),
            format!(
                "a network moves to a position from 0 to {}, not {to}",
                block.networks.len() - 1
            ),
        ));
    }
    let before = block.networks.clone();
    let moved = block.networks.remove(at.network);
    block.networks.insert(to, moved);
    renumber(&mut block.networks);
    let change = Change::Moved {
        block: at.block,
        from: at.network,
        to,
    };
    Ok((vec![change], Undo::Networks(at.block, before)))
}

/// A copy of the network right after it.
pub(super) fn duplicate(model: &mut Model, at: NetworkPath) -> Edited<Applied> {
    let block = block_mut(model, at.block)?;
    existing(block, at)?;
    let before = block.networks.clone();
    let copy = block.networks[at.network].clone();
    block.networks.insert(at.network + 1, copy);
    renumber(&mut block.networks);
    let new = NetworkPath {
        block: at.block,
        network: at.network + 1,
    };
    Ok((
        vec![Change::Inserted(new)],
        Undo::Networks(at.block, before),
    ))
}

/// The block's `TITLE=` (one line of the program: L0002 with a line break).
pub(super) fn set_block_title(
    model: &mut Model,
    b: usize,
    title: &Option<String>,
) -> Edited<Applied> {
    let block = block_mut(model, b)?;
    if title.as_deref().is_some_and(|t| t.contains(['\n', '\r'])) {
        return Err(ModelError::new(
            Code::Shape,
            &format!("blocks[{b}].title"),
            "a line break in a field that is one line of the program",
        ));
    }
    let title = title
        .as_deref()
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .map(str::to_string);
    let before = std::mem::replace(&mut block.title, title);
    Ok((vec![Change::Block(b)], Undo::BlockTitle(b, before)))
}

fn block_mut(model: &mut Model, b: usize) -> Edited<&mut BlockJson> {
    let count = model.blocks.len();
    model.blocks.get_mut(b).ok_or_else(|| {
        out_of_range(
            &format!("blocks[{b}]"),
            format!(
                "the model has {count} block{}",
                if count == 1 { "" } else { "s" }
            ),
        )
    })
}

fn existing(block: &BlockJson, at: NetworkPath) -> Edited<()> {
    if at.network < block.networks.len() {
        return Ok(());
    }
    Err(out_of_range(
        &at.to_string(),
        format!("the block has {} networks", block.networks.len()),
    ))
}

fn out_of_range(path: &str, message: String) -> ModelError {
    ModelError::new(Code::OutOfRange, path, message)
}

/// A block's networks numbered by position when any carries a number (a model read
/// from a program does); a block written without numbers stays without.
fn renumber(networks: &mut [NetworkJson]) {
    if networks.iter().any(|n| n.number.is_some()) {
        for (i, n) in networks.iter_mut().enumerate() {
            n.number = u32::try_from(i + 1).ok();
        }
    }
}

/// A network title as the program reads it back: without blanks around it (the
/// writer and the text edits write `NETWORK n // title` trimmed).
pub(super) fn title_as_read(title: &str) -> String {
    title.trim().to_string()
}

/// Network comment lines as the program reads them back: each without blanks around it,
/// no empty lines at the end (a `//` line at the end would read back as one line
/// fewer once joined).
pub(super) fn comment_as_read(comment: &str) -> String {
    let mut lines: Vec<&str> = comment_lines(comment).map(str::trim).collect();
    while lines.last().is_some_and(|l| l.is_empty()) {
        lines.pop();
    }
    lines.join("\n")
}
