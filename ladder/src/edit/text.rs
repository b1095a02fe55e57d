//! An edit's changes applied to the program's `.lad` text in place (docs/ladder.md,
//! "Editing the model"): the `.lad` file stays the one source of truth, so a studio
//! that edits the model writes back only what the edit changed, through
//! `gutta_analysis::network_edit`. A changed network gets its new instruction lines
//! (lines that stay the same keep their bytes; its NETWORK line, title and comment lines
//! stay); a new title or comment rewrites only the heading; an inserted, deleted or
//! moved network is that network's text alone; a block title its `TITLE=` line. Every
//! other byte of the file (the SYMBOLS block, comments, blank lines, the other networks
//! as they were written) stays as it was. Text only, no I/O.

use gutta_analysis::network_edit::{self, BlockRef, NetworkRef, NewNetwork};
use gutta_catalog::InstructionSet;

use super::{instruction_lines, Change, NetworkPath};
use crate::json::{comment_lines, Model, ModelError, ModelErrorCode as Code};

/// `text` with `changes` (what `Editor::apply`, `undo` or `redo` returned, in order)
/// applied: each network or heading they name written as `model` (the model after the
/// edit) has it. L0020 when the text does not hold a block or network a change names
/// (the text is not the one the model was read from); nothing is returned half done.
pub fn apply_to_text(
    text: &str,
    model: &Model,
    set: &InstructionSet,
    changes: &[Change],
) -> Result<String, ModelError> {
    let mut text = text.to_string();
    for change in changes {
        text = match *change {
            Change::Lines(at) => {
                let lines = instruction_lines(model, set, at)?;
                let lines: Vec<&str> = lines.iter().map(String::as_str).collect();
                let tree = network_edit::parse(&text, false);
                let edit = network_edit::replace_network(&text, &tree, place(at), &lines)
                    .map_err(|e| out_of_step(at, &e))?;
                network_edit::apply(&text, &[edit])
            }
            Change::Heading(at) => {
                let net = network(model, at)?;
                let comment: Vec<&str> = comment_lines(&net.comment).collect();
                let tree = network_edit::parse(&text, false);
                let edits = network_edit::replace_heading(
                    &text,
                    &tree,
                    place(at),
                    Some(net.title.as_str()),
                    &comment,
                )
                .map_err(|e| out_of_step(at, &e))?;
                network_edit::apply(&text, &edits)
            }
            Change::Inserted(at) => insert(&text, model, set, at)?,
            Change::Deleted(at) => delete(&text, at)?,
            Change::Moved { block, from, to } => {
                let removed = delete(
                    &text,
                    NetworkPath {
                        block,
                        network: from,
                    },
                )?;
                insert(&removed, model, set, NetworkPath { block, network: to })?
            }
            Change::Block(b) => {
                let title = model
                    .blocks
                    .get(b)
                    .ok_or_else(|| {
                        ModelError::new(Code::OutOfRange, &format!("blocks[{b}]"), "no such block")
                    })?
                    .title
                    .as_deref();
                let tree = network_edit::parse(&text, false);
                let edits = network_edit::set_block_title(&text, &tree, BlockRef::Index(b), title)
                    .map_err(|e| {
                        ModelError::new(
                            Code::TextOutOfStep,
                            &format!("blocks[{b}]"),
                            format!("the program text does not take the block's title: {e}"),
                        )
                    })?;
                network_edit::apply(&text, &edits)
            }
        };
    }
    Ok(text)
}

/// Network `at` of the model as it is now (L0014 when it is not there).
fn network(model: &Model, at: NetworkPath) -> Result<&crate::json::NetworkJson, ModelError> {
    model
        .blocks
        .get(at.block)
        .and_then(|b| b.networks.get(at.network))
        .ok_or_else(|| ModelError::new(Code::NoSuchPath, &at.to_string(), "no such network"))
}

/// The model's network `at` written into the text at its place: after the network
/// before it, or first in its block.
fn insert(
    text: &str,
    model: &Model,
    set: &InstructionSet,
    at: NetworkPath,
) -> Result<String, ModelError> {
    let net = network(model, at)?;
    let lines = instruction_lines(model, set, at)?;
    let lines: Vec<&str> = lines.iter().map(String::as_str).collect();
    let comment: Vec<&str> = comment_lines(&net.comment).collect();
    let new = NewNetwork {
        title: Some(net.title.as_str()).filter(|t| !t.is_empty()),
        comment: &comment,
        lines: &lines,
    };
    let tree = network_edit::parse(text, false);
    let edits = match at.network {
        0 => network_edit::insert_network_first(text, &tree, BlockRef::Index(at.block), &new),
        n => network_edit::insert_network_after(
            text,
            &tree,
            place(NetworkPath {
                block: at.block,
                network: n - 1,
            }),
            &new,
        ),
    }
    .map_err(|e| out_of_step(at, &e))?;
    Ok(network_edit::apply(text, &edits))
}

/// The text without network `at`.
fn delete(text: &str, at: NetworkPath) -> Result<String, ModelError> {
    let tree = network_edit::parse(text, false);
    let edit =
        network_edit::delete_network(text, &tree, place(at)).map_err(|e| out_of_step(at, &e))?;
    Ok(network_edit::apply(text, &[edit]))
}

fn place(at: NetworkPath) -> NetworkRef<'static> {
    NetworkRef {
        block: BlockRef::Index(at.block),
        network: at.network,
    }
}

fn out_of_step(at: NetworkPath, e: &network_edit::EditError) -> ModelError {
    ModelError::new(
        Code::TextOutOfStep,
        &at.to_string(),
        format!("the program text does not match the model: {e}"),
    )
}
