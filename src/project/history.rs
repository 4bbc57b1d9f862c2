//! Undo and redo: stacks of inverse edits, and whether the document changed since it was saved.

use super::{Edit, EditError, Project};

/// The undo/redo history of one project.
///
/// Every state the project passes through gets a number; the history remembers which number was
/// saved, so undoing back to the saved state makes the document clean again.
#[derive(Debug, Default)]
pub struct History {
    /// (edit that undoes a step, state number before the step, description of the step).
    undo: Vec<(Edit, u64, &'static str)>,
    /// (edit that redoes a step, state number after the step, description of the step).
    redo: Vec<(Edit, u64, &'static str)>,
    state: u64,
    next_state: u64,
    saved_state: Option<u64>,
}

impl History {
    /// An empty history of a document that has been saved (or just opened).
    #[must_use]
    pub fn new() -> Self {
        Self {
            saved_state: Some(0),
            next_state: 1,
            ..Self::default()
        }
    }

    /// Apply `edit` to `project` as a new undo step (the redo stack is dropped).
    ///
    /// # Errors
    /// The [`EditError`] of a refused edit; nothing changes then.
    pub fn apply(&mut self, project: &mut Project, edit: Edit) -> Result<(), EditError> {
        // The step is described by what the user did, not by the inverse that undoes it.
        let label = edit.describe();
        let inverse = project.apply(edit)?;
        self.undo.push((inverse, self.state, label));
        self.redo.clear();
        self.state = self.next_state;
        self.next_state += 1;
        Ok(())
    }

    /// Undo the last step. Returns its description, or `None` when there is nothing to undo.
    pub fn undo(&mut self, project: &mut Project) -> Option<&'static str> {
        let (edit, before, label) = self.undo.pop()?;
        match project.apply(edit) {
            Ok(redo) => {
                self.redo.push((redo, self.state, label));
                self.state = before;
                Some(label)
            }
            // Cannot happen for inverses produced by `Project::apply`; drop the history rather
            // than leave it inconsistent.
            Err(_) => {
                self.undo.clear();
                self.redo.clear();
                None
            }
        }
    }

    /// Redo the last undone step. Returns its description, or `None` when there is none.
    pub fn redo(&mut self, project: &mut Project) -> Option<&'static str> {
        let (edit, after, label) = self.redo.pop()?;
        match project.apply(edit) {
            Ok(undo) => {
                self.undo.push((undo, self.state, label));
                self.state = after;
                Some(label)
            }
            Err(_) => {
                self.undo.clear();
                self.redo.clear();
                None
            }
        }
    }

    /// Is there a step to redo?
    #[must_use]
    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }

    /// Description of the step [`History::undo`] would undo.
    #[must_use]
    pub fn undo_label(&self) -> Option<&'static str> {
        self.undo.last().map(|(_, _, label)| *label)
    }

    /// Description of the step [`History::redo`] would redo.
    #[must_use]
    pub fn redo_label(&self) -> Option<&'static str> {
        self.redo.last().map(|(_, _, label)| *label)
    }

    /// Has the document changed since it was last saved?
    #[must_use]
    pub fn is_dirty(&self) -> bool {
        self.saved_state != Some(self.state)
    }

    /// Record that the current state has been saved.
    pub fn mark_saved(&mut self) {
        self.saved_state = Some(self.state);
    }

    /// Record that the document has never been saved (it stays dirty until it is).
    pub fn mark_unsaved(&mut self) {
        self.saved_state = None;
    }
}
