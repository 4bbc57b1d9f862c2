//! Edits: every change to a [`Project`]. [`Project::apply`] performs one and returns its inverse,
//! which is what makes undo and redo exact.

use super::{Operation, PartRef, PostConfig, Project, Setup, Stock, ToolEntry};

/// One change to the document.
#[derive(Clone, Debug, PartialEq)]
pub enum Edit {
    /// Rename the project.
    Rename(String),
    /// Reference another part (`None`: the embedded default part).
    SetPart(Option<PartRef>),
    /// Replace the stock.
    SetStock(Stock),
    /// Replace the setup (work offset, program origin).
    SetSetup(Setup),
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
            Self::AddTool { .. } => "Add tool",
            Self::SetTool { .. } => "Edit tool",
            Self::RemoveTool { .. } => "Delete tool",
            Self::SelectTool(_) => "Select tool",
            Self::SetMachine(_) => "Change machine",
            Self::AddOperation { .. } => "Add operation",
            Self::RemoveOperation { .. } => "Delete operation",
            Self::SetSetup(_) => "Edit setup",
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
            Edit::SetSetup(setup) => {
                setup.validate().map_err(EditError::Invalid)?;
                Edit::SetSetup(std::mem::replace(&mut self.setup, setup))
            }
            Edit::SetPost(post) => {
                post.validate().map_err(EditError::Invalid)?;
                Edit::SetPost(std::mem::replace(&mut self.post, post))
            }
            Edit::SetPart(part) => Edit::SetPart(std::mem::replace(&mut self.part, part)),
            Edit::SetStock(stock) => {
                stock.validate().map_err(EditError::Invalid)?;
                Edit::SetStock(std::mem::replace(&mut self.stock, stock))
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
            Edit::AddOperation { index, operation } => {
                if index > self.operations.len() {
                    return Err(no_such("operation", index, self.operations.len()));
                }
                check_operation(self, &operation)?;
                self.operations.insert(index, operation);
                Edit::RemoveOperation { index }
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
            Edit::RemoveOperation { index } => {
                if index >= self.operations.len() {
                    return Err(no_such("operation", index, self.operations.len()));
                }
                let operation = self.operations.remove(index);
                Edit::AddOperation { index, operation }
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
