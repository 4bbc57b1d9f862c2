//! Edits: every change to a [`Project`]. [`Project::apply`] performs one and returns its inverse,
//! which is what makes undo and redo exact.

use super::{Frame, Operation, PartRef, PostConfig, Project, Setup, Stock, ToolEntry};

/// One change to the document.
#[derive(Clone, Debug, PartialEq)]
pub enum Edit {
    /// Rename the project.
    Rename(String),
    /// Reference another part (`None`: the embedded default part).
    SetPart(Option<PartRef>),
    /// Replace the stock.
    SetStock(Stock),
    /// Set the stock's work material (`None`: none; feeds typed).
    SetMaterial(Option<super::cutting::WorkMaterial>),
    /// Replace setup `index` (its frame, stock, workholding, tilt, machine and name; its
    /// operations must stay a valid share of the job's).
    SetSetup {
        /// Which setup.
        index: usize,
        /// Its new values.
        setup: Setup,
    },
    /// Replace the frame (work offset, program origin, orientation) of setup `setup`.
    SetFrame {
        /// Which setup.
        setup: usize,
        /// The new frame.
        frame: Frame,
    },
    /// Insert an empty setup at `index` (its operation list must be empty).
    AddSetup {
        /// Where it goes.
        index: usize,
        /// The setup.
        setup: Setup,
    },
    /// Remove setup `index`, which must hold no operation (and not be the only one).
    RemoveSetup {
        /// Which setup.
        index: usize,
    },
    /// Move operation `operation` into setup `setup` at `position` in its list (its place in
    /// [`Project::operations`] is unchanged).
    MoveOperation {
        /// Which operation.
        operation: usize,
        /// The setup that takes it.
        setup: usize,
        /// Where in that setup's list (0 ≤ position ≤ its length without the operation).
        position: usize,
    },
    /// Replace the post settings (dialect, TCP, spindle speed).
    SetPost(PostConfig),
    /// Insert a tool at `index` (0 ≤ index ≤ tool count); the selection keeps pointing at the
    /// same tool.
    AddTool {
        /// Where the tool goes.
        index: usize,
        /// The tool.
        tool: ToolEntry,
    },
    /// Replace the tool at `index`.
    SetTool {
        /// Which tool.
        index: usize,
        /// Its new name and sizes.
        tool: ToolEntry,
    },
    /// Remove the tool at `index`; a selection of it becomes none, later indices shift down.
    RemoveTool {
        /// Which tool.
        index: usize,
    },
    /// Select a tool (or none).
    SelectTool(Option<usize>),
    /// Choose the machine.
    SetMachine(String),
    /// Insert an operation at `index`.
    AddOperation {
        /// Where the operation goes.
        index: usize,
        /// The operation.
        operation: Operation,
    },
    /// Remove the operation at `index`.
    RemoveOperation {
        /// Which operation.
        index: usize,
    },
    /// Replace the operation at `index` (its parameters, tool or name).
    SetOperation {
        /// Which operation.
        index: usize,
        /// Its new values.
        operation: Operation,
    },
    /// Several edits as one undo step, applied in order.
    Batch(Vec<Edit>),
}

/// Why an edit was refused (the project is unchanged).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EditError {
    /// An index past the end of the list.
    #[error("no {what} number {index} (there are {count})")]
    NoSuchItem {
        /// "tool" or "operation".
        what: &'static str,
        /// The index asked for (0-based).
        index: usize,
        /// How many there are.
        count: usize,
    },
    /// A value out of range (a tool size, the stock, an empty name).
    #[error("{0}")]
    Invalid(String),
}

impl Edit {
    /// A short description for the Edit menu ("Undo Rename tool").
    #[must_use]
    pub fn describe(&self) -> &'static str {
        match self {
            Self::Rename(_) => "Rename project",
            Self::SetPart(_) => "Change part",
            Self::SetStock(_) => "Change stock",
            Self::SetMaterial(_) => "Change material",
            Self::AddTool { .. } => "Add tool",
            Self::SetTool { .. } => "Edit tool",
            Self::RemoveTool { .. } => "Delete tool",
            Self::SelectTool(_) => "Select tool",
            Self::SetMachine(_) => "Change machine",
            Self::AddOperation { .. } => "Add operation",
            Self::RemoveOperation { .. } => "Delete operation",
            Self::SetSetup { .. } | Self::SetFrame { .. } => "Edit setup",
            Self::AddSetup { .. } => "Add setup",
            Self::RemoveSetup { .. } => "Remove setup",
            Self::MoveOperation { .. } => "Move operation",
            Self::SetPost(_) => "Change post settings",
            Self::SetOperation { .. } => "Edit operation",
            Self::Batch(edits) => edits.first().map_or("Edit", Edit::describe),
        }
    }

    /// Duplicate the tool at `index` (inserted right after it, named "… copy", and selected).
    ///
    /// # Errors
    /// [`EditError::NoSuchItem`] when there is no such tool.
    pub fn duplicate_tool(project: &Project, index: usize) -> Result<Self, EditError> {
        let tool = project.tools.get(index).ok_or(EditError::NoSuchItem {
            what: "tool",
            index,
            count: project.tools.len(),
        })?;
        let copy = ToolEntry {
            name: format!("{} copy", tool.name),
            cutter: tool.cutter.clone(),
        };
        Ok(Self::Batch(vec![
            Self::AddTool {
                index: index + 1,
                tool: copy,
            },
            Self::SelectTool(Some(index + 1)),
        ]))
    }
}

fn no_such(what: &'static str, index: usize, count: usize) -> EditError {
    EditError::NoSuchItem { what, index, count }
}

fn check_tool(tool: &ToolEntry) -> Result<(), EditError> {
    tool.cutter
        .validate()
        .map_err(|e| EditError::Invalid(e.to_string()))
}

fn check_operation(project: &Project, operation: &Operation) -> Result<(), EditError> {
    if let Some(t) = operation
        .tools_used()
        .into_iter()
        .find(|t| *t >= project.tools.len())
    {
        return Err(no_such("tool", t, project.tools.len()));
    }
    if operation.name().trim().is_empty() {
        return Err(EditError::Invalid("the operation name is empty".into()));
    }
    operation.validate().map_err(EditError::Invalid)
}

impl Project {
    /// The setup holding operation `op` and its place in that setup's list.
    fn find_operation(&self, op: usize) -> Option<(usize, usize)> {
        self.setups.iter().enumerate().find_map(|(s, setup)| {
            setup
                .operations
                .iter()
                .position(|&o| o == op)
                .map(|p| (s, p))
        })
    }

    /// Take operation `op` out of its setup's list; where it was.
    fn take_operation(&mut self, op: usize) -> (Option<usize>, Option<usize>) {
        match self.find_operation(op) {
            Some((s, p)) => {
                self.setups[s].operations.remove(p);
                (Some(s), Some(p))
            }
            None => (None, None),
        }
    }

    /// Put operation `op` back where [`Project::take_operation`] took it from.
    fn put_operation(&mut self, op: usize, setup: Option<usize>, at: Option<usize>) {
        if let (Some(s), Some(p)) = (setup, at)
            && let Some(list) = self.setups.get_mut(s).map(|s| &mut s.operations)
        {
            list.insert(p.min(list.len()), op);
        }
    }

    /// [`Edit::MoveOperation`]: its inverse.
    fn move_operation(
        &mut self,
        operation: usize,
        setup: usize,
        position: usize,
    ) -> Result<Edit, EditError> {
        Ok({
            if operation >= self.operations.len() {
                return Err(no_such("operation", operation, self.operations.len()));
            }
            if setup >= self.setups.len() {
                return Err(no_such("setup", setup, self.setups.len()));
            }
            let (from, at) = self.take_operation(operation);
            let list = &mut self.setups[setup].operations;
            if position > list.len() {
                let len = list.len();
                self.put_operation(operation, from, at);
                return Err(no_such("place in the setup", position, len + 1));
            }
            list.insert(position, operation);
            match (from, at) {
                (Some(s), Some(p)) => Edit::MoveOperation {
                    operation,
                    setup: s,
                    position: p,
                },
                // It was in no setup (a project made in code): moving it back is a no-op
                // move to where it now is.
                _ => Edit::MoveOperation {
                    operation,
                    setup,
                    position,
                },
            }
        })
    }

    /// Apply an edit of the job's setups or of its operation list (see [`Project::apply`]).
    fn apply_job(&mut self, edit: Edit) -> Result<Edit, EditError> {
        Ok(match edit {
            Edit::SetSetup { index, setup } => {
                let count = self.setups.len();
                if index >= count {
                    return Err(no_such("setup", index, count));
                }
                let old = std::mem::replace(&mut self.setups[index], setup);
                if let Err(e) = super::setups::check(self) {
                    self.setups[index] = old;
                    return Err(EditError::Invalid(e));
                }
                Edit::SetSetup { index, setup: old }
            }
            Edit::SetFrame { setup, frame } => {
                frame.validate().map_err(EditError::Invalid)?;
                let count = self.setups.len();
                let slot = self
                    .setups
                    .get_mut(setup)
                    .ok_or_else(|| no_such("setup", setup, count))?;
                Edit::SetFrame {
                    setup,
                    frame: std::mem::replace(&mut slot.frame, frame),
                }
            }
            Edit::AddSetup { index, setup } => {
                if index > self.setups.len() {
                    return Err(no_such("setup", index, self.setups.len()));
                }
                if !setup.operations.is_empty() {
                    return Err(EditError::Invalid(
                        "a new setup starts with no operation (move them in afterwards)".into(),
                    ));
                }
                self.setups.insert(index, setup);
                if let Err(e) = super::setups::check(self) {
                    self.setups.remove(index);
                    return Err(EditError::Invalid(e));
                }
                Edit::RemoveSetup { index }
            }
            Edit::RemoveSetup { index } => {
                let count = self.setups.len();
                let setup = self
                    .setups
                    .get(index)
                    .ok_or_else(|| no_such("setup", index, count))?;
                if !setup.operations.is_empty() {
                    return Err(EditError::Invalid(format!(
                        "the setup '{}' still holds {} operations",
                        setup.name,
                        setup.operations.len()
                    )));
                }
                if count == 1 {
                    return Err(EditError::Invalid(
                        "the project's only setup cannot be removed".into(),
                    ));
                }
                let setup = self.setups.remove(index);
                if let Err(e) = super::setups::check(self) {
                    self.setups.insert(index, setup);
                    return Err(EditError::Invalid(e));
                }
                Edit::AddSetup { index, setup }
            }
            Edit::MoveOperation {
                operation,
                setup,
                position,
            } => self.move_operation(operation, setup, position)?,
            Edit::AddOperation { index, operation } => {
                if index > self.operations.len() {
                    return Err(no_such("operation", index, self.operations.len()));
                }
                check_operation(self, &operation)?;
                self.operations.insert(index, operation);
                for s in &mut self.setups {
                    for op in &mut s.operations {
                        if *op >= index {
                            *op += 1;
                        }
                    }
                }
                // Into the setup of the operation before it, else at the front of the setup of
                // the one after it, else the last setup.
                let before = index
                    .checked_sub(1)
                    .and_then(|b| self.find_operation(b))
                    .map(|(s, p)| (s, p + 1));
                let after = || self.find_operation(index + 1);
                let place = before.or_else(after).or_else(|| {
                    self.setups
                        .len()
                        .checked_sub(1)
                        .map(|s| (s, self.setups[s].operations.len()))
                });
                if let Some((s, p)) = place {
                    self.setups[s].operations.insert(p, index);
                }
                Edit::RemoveOperation { index }
            }
            Edit::RemoveOperation { index } => {
                if index >= self.operations.len() {
                    return Err(no_such("operation", index, self.operations.len()));
                }
                let (from, at) = self.take_operation(index);
                let operation = self.operations.remove(index);
                for s in &mut self.setups {
                    for op in &mut s.operations {
                        if *op > index {
                            *op -= 1;
                        }
                    }
                }
                match (from, at) {
                    (Some(setup), Some(position)) => Edit::Batch(vec![
                        Edit::AddOperation { index, operation },
                        Edit::MoveOperation {
                            operation: index,
                            setup,
                            position,
                        },
                    ]),
                    _ => Edit::AddOperation { index, operation },
                }
            }
            other => return self.apply(other),
        })
    }

    /// Apply `edit` and return the edit that undoes it exactly.
    ///
    /// # Errors
    /// [`EditError`] when the edit is refused; the project is then unchanged.
    pub fn apply(&mut self, edit: Edit) -> Result<Edit, EditError> {
        Ok(match edit {
            Edit::Rename(name) => {
                if name.trim().is_empty() {
                    return Err(EditError::Invalid("the project name is empty".into()));
                }
                Edit::Rename(std::mem::replace(&mut self.name, name))
            }
            e @ (Edit::SetSetup { .. }
            | Edit::SetFrame { .. }
            | Edit::AddSetup { .. }
            | Edit::RemoveSetup { .. }
            | Edit::MoveOperation { .. }
            | Edit::AddOperation { .. }
            | Edit::RemoveOperation { .. }) => self.apply_job(e)?,
            Edit::SetPost(post) => {
                post.validate().map_err(EditError::Invalid)?;
                Edit::SetPost(std::mem::replace(&mut self.post, post))
            }
            Edit::SetPart(part) => Edit::SetPart(std::mem::replace(&mut self.part, part)),
            Edit::SetStock(stock) => {
                stock.validate().map_err(EditError::Invalid)?;
                Edit::SetStock(std::mem::replace(&mut self.stock, stock))
            }
            Edit::SetMaterial(material) => {
                if let Some(m) = &material {
                    m.material().map_err(EditError::Invalid)?;
                }
                Edit::SetMaterial(std::mem::replace(&mut self.material, material))
            }
            Edit::AddTool { index, tool } => {
                if index > self.tools.len() {
                    return Err(no_such("tool", index, self.tools.len()));
                }
                check_tool(&tool)?;
                let before = self.selected_tool;
                self.tools.insert(index, tool);
                if let Some(s) = self.selected_tool.as_mut()
                    && *s >= index
                {
                    *s += 1;
                }
                // Operations keep their tools.
                for op in &mut self.operations {
                    *op = op
                        .clone()
                        .remap_tools(|t| if t >= index { t + 1 } else { t });
                }
                Edit::Batch(vec![Edit::RemoveTool { index }, Edit::SelectTool(before)])
            }
            Edit::SetTool { index, tool } => {
                check_tool(&tool)?;
                let count = self.tools.len();
                let slot = self
                    .tools
                    .get_mut(index)
                    .ok_or_else(|| no_such("tool", index, count))?;
                Edit::SetTool {
                    index,
                    tool: std::mem::replace(slot, tool),
                }
            }
            Edit::RemoveTool { index } => {
                if index >= self.tools.len() {
                    return Err(no_such("tool", index, self.tools.len()));
                }
                if let Some(op) = self
                    .operations
                    .iter()
                    .find(|op| op.tools_used().contains(&index))
                {
                    return Err(EditError::Invalid(format!(
                        "the tool is used by the operation '{}'",
                        op.name()
                    )));
                }
                let before = self.selected_tool;
                let tool = self.tools.remove(index);
                for op in &mut self.operations {
                    *op = op
                        .clone()
                        .remap_tools(|t| if t > index { t - 1 } else { t });
                }
                self.selected_tool = match before {
                    Some(s) if s == index => None,
                    Some(s) if s > index => Some(s - 1),
                    s => s,
                };
                Edit::Batch(vec![
                    Edit::AddTool { index, tool },
                    Edit::SelectTool(before),
                ])
            }
            Edit::SelectTool(sel) => {
                if let Some(i) = sel
                    && i >= self.tools.len()
                {
                    return Err(no_such("tool", i, self.tools.len()));
                }
                Edit::SelectTool(std::mem::replace(&mut self.selected_tool, sel))
            }
            Edit::SetMachine(name) => {
                if name.trim().is_empty() {
                    return Err(EditError::Invalid("the machine name is empty".into()));
                }
                Edit::SetMachine(std::mem::replace(&mut self.machine, name))
            }
            Edit::SetOperation { index, operation } => {
                check_operation(self, &operation)?;
                let count = self.operations.len();
                let slot = self
                    .operations
                    .get_mut(index)
                    .ok_or_else(|| no_such("operation", index, count))?;
                Edit::SetOperation {
                    index,
                    operation: std::mem::replace(slot, operation),
                }
            }
            Edit::Batch(edits) => {
                let mut inverses = Vec::with_capacity(edits.len());
                for e in edits {
                    match self.apply(e) {
                        Ok(inv) => inverses.push(inv),
                        Err(err) => {
                            // Roll back what was applied so the project is unchanged.
                            for inv in inverses.into_iter().rev() {
                                let _ = self.apply(inv);
                            }
                            return Err(err);
                        }
                    }
                }
                inverses.reverse();
                Edit::Batch(inverses)
            }
        })
    }
}
