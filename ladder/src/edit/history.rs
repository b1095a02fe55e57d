//! `Editor`: a model, the instruction set it is checked against, and its history. Each
//! edit is applied atomically by `super::apply`'s rules; undo restores what the edit
//! replaced, redo applies the undone edit again, and a new edit clears redo. Every
//! answer says which networks changed, so the caller rewrites only those.

use std::borrow::Cow;

use gutta_catalog::InstructionSet;

use super::{perform, Change, Edit, Undo};
use crate::json::{Model, ModelError, ModelErrorCode as Code};

/// An applied edit and what takes it back.
#[derive(Debug, Clone)]
struct Done {
    edit: Edit,
    changes: Vec<Change>,
    undo: Undo,
}

/// A model being edited, with undo and redo. It borrows the instruction set
/// ([`Editor::new`]) or owns a copy ([`Editor::owning`]: a session that keeps editors
/// beside the target they came from).
#[derive(Debug, Clone)]
pub struct Editor<'s> {
    set: Cow<'s, InstructionSet>,
    model: Model,
    done: Vec<Done>,
    undone: Vec<Edit>,
}

impl<'s> Editor<'s> {
    /// An editor of `model` (which should validate against `set`), with no history.
    pub fn new(model: Model, set: &'s InstructionSet) -> Editor<'s> {
        Editor {
            set: Cow::Borrowed(set),
            model,
            done: Vec::new(),
            undone: Vec::new(),
        }
    }

    /// An editor of `model` that owns its instruction set, with no history.
    pub fn owning(model: Model, set: InstructionSet) -> Editor<'static> {
        Editor {
            set: Cow::Owned(set),
            model,
            done: Vec::new(),
            undone: Vec::new(),
        }
    }

    /// The model as it is now.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The model, the history dropped.
    pub fn into_model(self) -> Model {
        self.model
    }

    /// `edit` applied: what changed; refused, the model and the history are unchanged.
    /// An applied edit clears what could be redone.
    pub fn apply(&mut self, edit: Edit) -> Result<Vec<Change>, ModelError> {
        let (changes, undo) = perform(&mut self.model, &self.set, &edit)?;
        self.done.push(Done {
            edit,
            changes: changes.clone(),
            undo,
        });
        self.undone.clear();
        Ok(changes)
    }

    /// The last applied edit taken back: what changed (L0019 when there is none).
    pub fn undo(&mut self) -> Result<Vec<Change>, ModelError> {
        let done = self
            .done
            .pop()
            .ok_or_else(|| ModelError::new(Code::NothingToUndo, "", "nothing to undo"))?;
        done.undo.restore(&mut self.model);
        self.undone.push(done.edit);
        Ok(done.changes.iter().rev().map(Change::inverse).collect())
    }

    /// The last undone edit applied again: what changed (L0019 when there is none).
    pub fn redo(&mut self) -> Result<Vec<Change>, ModelError> {
        let edit = self
            .undone
            .pop()
            .ok_or_else(|| ModelError::new(Code::NothingToUndo, "", "nothing to redo"))?;
        match perform(&mut self.model, &self.set, &edit) {
            Ok((changes, undo)) => {
                self.done.push(Done {
                    edit,
                    changes: changes.clone(),
                    undo,
                });
                Ok(changes)
            }
            Err(e) => {
                self.undone.push(edit);
                Err(e)
            }
        }
    }

    /// Whether `undo` has an edit to take back.
    pub fn can_undo(&self) -> bool {
        !self.done.is_empty()
    }

    /// Whether `redo` has an edit to apply again.
    pub fn can_redo(&self) -> bool {
        !self.undone.is_empty()
    }
}
