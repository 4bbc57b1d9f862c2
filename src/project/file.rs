//! Reading and writing project files (TOML). Saving is atomic: the new content goes to a
//! temporary file in the same folder, is flushed to disk, then renamed over the old file, so a
//! failed save leaves the old file as it was.

use std::path::{Path, PathBuf};

use super::{PROJECT_VERSION, Project};

/// The extension of project files.
pub const EXTENSION: &str = "talas";

/// Why a project could not be read or written. Every variant names the file.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ProjectError {
    /// Reading or writing failed.
    #[error("{path}: {message}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What the system said, and what was being done.
        message: String,
    },
    /// The file is not a valid project (TOML syntax, a missing or mistyped field).
    #[error("{path}:{line}:{column}: {message}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// Line, 1-based.
        line: usize,
        /// Column in characters, 1-based.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// The file was written by a newer Talas.
    #[error(
        "{path}: project version {found} is newer than this Talas understands ({PROJECT_VERSION})"
    )]
    Version {
        /// The file.
        path: PathBuf,
        /// The version in the file.
        found: u32,
    },
    /// The content parsed but is inconsistent (a bad tool size, a selection past the end).
    #[error("{path}: {message}")]
    Invalid {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

/// 1-based line and column (in characters) of byte `offset` in `text`.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = text.get(..offset.min(text.len())).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let column = before
        .rsplit_once('\n')
        .map_or(before, |(_, last)| last)
        .chars()
        .count()
        + 1;
    (line, column)
}

impl Project {
    /// The project as TOML text.
    ///
    /// # Errors
    /// When a value cannot be written (a non-finite number).
    pub fn to_toml(&self) -> Result<String, String> {
        toml::to_string_pretty(self).map_err(|e| e.to_string())
    }

    /// Parse project TOML; `path` only names the source in errors.
    ///
    /// # Errors
    /// [`ProjectError::Parse`] with the line and column, [`ProjectError::Version`],
    /// [`ProjectError::Invalid`].
    pub fn from_toml(text: &str, path: &Path) -> Result<Self, ProjectError> {
        let project: Self = toml::from_str(text).map_err(|e| {
            let (line, column) = e.span().map_or((1, 1), |s| line_column(text, s.start));
            ProjectError::Parse {
                path: path.to_path_buf(),
                line,
                column,
                message: e.message().trim().to_string(),
            }
        })?;
        let invalid = |message: String| ProjectError::Invalid {
            path: path.to_path_buf(),
            message,
        };
        if project.version > PROJECT_VERSION {
            return Err(ProjectError::Version {
                path: path.to_path_buf(),
                found: project.version,
            });
        }
        for (i, t) in project.tools.iter().enumerate() {
            t.cutter
                .validate()
                .map_err(|e| invalid(format!("tool {} ('{}'): {e}", i + 1, t.name)))?;
        }
        if let Some(s) = project.selected_tool
            && s >= project.tools.len()
        {
            return Err(invalid(format!(
                "selected_tool = {s} but there are {} tools",
                project.tools.len()
            )));
        }
        project.stock.validate().map_err(invalid)?;
        // Version 1 is the first format: nothing to migrate yet.
        Ok(Self {
            version: PROJECT_VERSION,
            ..project
        })
    }

    /// Read the project file at `path`.
    ///
    /// # Errors
    /// [`ProjectError`] naming the file (and the line and column for syntax errors).
    pub fn load(path: &Path) -> Result<Self, ProjectError> {
        let text = std::fs::read_to_string(path).map_err(|e| ProjectError::Io {
            path: path.to_path_buf(),
            message: format!("cannot read: {e}"),
        })?;
        Self::from_toml(&text, path)
    }

    /// Write the project to `path` atomically (temporary file, flush, rename).
    ///
    /// # Errors
    /// [`ProjectError::Io`] naming the file; the old file (if any) is unchanged then.
    pub fn save(&self, path: &Path) -> Result<(), ProjectError> {
        let io = |what: &str, e: &dyn std::fmt::Display| ProjectError::Io {
            path: path.to_path_buf(),
            message: format!("{what}: {e}"),
        };
        let text = self.to_toml().map_err(|e| io("cannot encode", &e))?;
        crate::storage::write_atomic(path, text.as_bytes()).map_err(|e| io("cannot save", &e))
    }
}
