//! Reading and writing project files (TOML). Saving is atomic: the new content goes to a
//! temporary file in the same folder, is flushed to disk, then renamed over the old file, so a
//! failed save leaves the old file as it was.

use std::path::{Path, PathBuf};

use super::{Orientation, PROJECT_VERSION, Project};

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

/// One step of a key's path in a TOML document.
#[derive(Clone, Debug)]
enum Step {
    Key(String),
    Index(usize),
}

fn path_text(steps: &[Step]) -> String {
    let mut out = String::new();
    for s in steps {
        match s {
            Step::Key(k) => {
                if !out.is_empty() {
                    out.push('.');
                }
                out.push_str(k);
            }
            Step::Index(i) => out.push_str(&format!("[{i}]")),
        }
    }
    out
}

/// The keys of `input` with no counterpart in `written` (the project as it writes itself).
fn missing_keys(
    input: &toml::Value,
    written: &toml::Value,
    at: &mut Vec<Step>,
    out: &mut Vec<Vec<Step>>,
) {
    match (input, written) {
        (toml::Value::Table(a), toml::Value::Table(b)) => {
            for (k, v) in a {
                at.push(Step::Key(k.clone()));
                match b.get(k) {
                    Some(w) => missing_keys(v, w, at, out),
                    None => out.push(at.clone()),
                }
                at.pop();
            }
        }
        (toml::Value::Array(a), toml::Value::Array(b)) if a.len() == b.len() => {
            for (i, (v, w)) in a.iter().zip(b).enumerate() {
                at.push(Step::Index(i));
                missing_keys(v, w, at, out);
                at.pop();
            }
        }
        _ => {}
    }
}

fn value_at<'a>(v: &'a mut toml::Value, steps: &[Step]) -> Option<&'a mut toml::Value> {
    let Some((first, rest)) = steps.split_first() else {
        return Some(v);
    };
    let next = match (v, first) {
        (toml::Value::Table(t), Step::Key(k)) => t.get_mut(k)?,
        (toml::Value::Array(a), Step::Index(i)) => a.get_mut(*i)?,
        _ => return None,
    };
    value_at(next, rest)
}

/// Keys of the project text that the project does not read: each key the written project
/// lacks (a default left out, or unknown) is given a date-time, which no setting of a project
/// accepts; where the project still reads, the key was ignored.
fn unread_keys(text: &str, project: &Project) -> Vec<String> {
    let (Ok(input), Ok(written)) = (
        toml::from_str::<toml::Value>(text),
        toml::Value::try_from(project),
    ) else {
        return Vec::new();
    };
    let mut candidates = Vec::new();
    missing_keys(&input, &written, &mut Vec::new(), &mut candidates);
    let probe = toml::Value::Datetime(toml::value::Datetime {
        date: Some(toml::value::Date {
            year: 1979,
            month: 5,
            day: 27,
        }),
        time: None,
        offset: None,
    });
    candidates
        .into_iter()
        .take(100)
        .filter(|steps| {
            let mut doc = input.clone();
            let Some(slot) = value_at(&mut doc, steps) else {
                return false;
            };
            *slot = probe.clone();
            toml::to_string(&doc)
                .ok()
                .is_some_and(|t| toml::from_str::<Project>(&t).is_ok())
        })
        .map(|steps| path_text(&steps))
        .collect()
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
        Self::read_toml(text, path, false).map(|(p, _)| p)
    }

    /// [`Project::from_toml`], and one warning for every key the format does not know
    /// (`FILE: unknown key 'operations[0].scalop' ignored`): a misspelt setting is read as its
    /// default, so the user is told which key and which file.
    ///
    /// # Errors
    /// As [`Project::from_toml`].
    pub fn from_toml_with_warnings(
        text: &str,
        path: &Path,
    ) -> Result<(Self, Vec<String>), ProjectError> {
        Self::read_toml(text, path, true)
    }

    fn read_toml(text: &str, path: &Path, warn: bool) -> Result<(Self, Vec<String>), ProjectError> {
        let parse_error = |e: toml::de::Error| {
            let (line, column) = e.span().map_or((1, 1), |s| line_column(text, s.start));
            ProjectError::Parse {
                path: path.to_path_buf(),
                line,
                column,
                message: e.message().trim().to_string(),
            }
        };
        let project: Self = toml::from_str(text).map_err(parse_error)?;
        // Every key the project does not read, wherever it sits (inside an operation too, an
        // internally tagged enum that a deserializer wrapper such as serde_ignored never sees
        // into).
        let unread = if warn {
            unread_keys(text, &project)
        } else {
            Vec::new()
        };
        let warnings: Vec<String> = unread
            .into_iter()
            .map(|k| format!("{}: unknown key '{k}' ignored", path.display()))
            .collect();
        let mut project = project;
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
        project.migrate_setups().map_err(invalid)?;
        project.check().map_err(invalid)?;
        project.resolve_part_path(path);
        // Version 1 is the first format: nothing to migrate yet.
        Ok((
            Self {
                version: PROJECT_VERSION,
                ..project
            },
            warnings,
        ))
    }

    /// A relative part path names a file beside the project file, wherever the program that
    /// reads it was started: it is made absolute against the project file's folder (a bare
    /// name, as `path = "part.stp"`, is the part in the project's folder).
    fn resolve_part_path(&mut self, project_file: &Path) {
        let Some(part) = self.part.as_mut() else {
            return;
        };
        if part.path.is_absolute() || part.path.as_os_str().is_empty() {
            return;
        }
        let folder = project_file.parent().unwrap_or(Path::new(""));
        let folder = if folder.as_os_str().is_empty() {
            Path::new(".")
        } else {
            folder
        };
        let joined = folder.join(&part.path);
        part.path = std::path::absolute(&joined).unwrap_or(joined);
    }

    /// Every check an edit would make, applied to the whole document (a file may have been
    /// written by hand or by another program): tools, selected tool, stock, setup, post
    /// settings, machine and dialect (resolvable), every operation (its tool and values), the
    /// view. Face indices are checked against the part with [`Project::check_faces`] once the
    /// part is read.
    ///
    /// # Errors
    /// What is wrong and where, in words.
    pub fn check(&self) -> Result<(), String> {
        for (i, t) in self.tools.iter().enumerate() {
            t.cutter
                .validate()
                .map_err(|e| format!("tool {} ('{}'): {e}", i + 1, t.name))?;
        }
        if let Some(s) = self.selected_tool
            && s >= self.tools.len()
        {
            return Err(format!(
                "selected_tool = {s} but there are {} tools",
                self.tools.len()
            ));
        }
        self.stock.validate()?;
        if self.legacy_setup.is_some() {
            return Err("setup: the old single setup is read from files only (use setups)".into());
        }
        self.post.validate().map_err(|e| format!("post: {e}"))?;
        crate::machine::Machine::resolve(&self.machine)
            .map_err(|e| format!("machine {:?}: {e}", self.machine))?;
        crate::post::Dialect::resolve(&self.post.dialect)
            .map_err(|e| format!("post: dialect {:?}: {e}", self.post.dialect))?;
        for (i, op) in self.operations.iter().enumerate() {
            let place = format!("operation {} ('{}')", i + 1, op.name());
            if op.tool() >= self.tools.len() {
                return Err(format!(
                    "{place}: tool {} but there are {} tools",
                    op.tool() + 1,
                    self.tools.len()
                ));
            }
            op.validate().map_err(|e| format!("{place}: {e}"))?;
        }
        super::setups::check(self)?;
        let v = &self.view;
        let finite = v.target_mm.iter().all(|x| x.is_finite())
            && v.yaw_rad.is_finite()
            && v.pitch_rad.is_finite();
        if !(finite && v.distance_mm.is_finite() && v.distance_mm > 0.0) {
            return Err("view: the camera must be finite with a positive distance (mm)".into());
        }
        Ok(())
    }

    /// Check the operations' face indices against a part with `face_count` faces.
    ///
    /// # Errors
    /// The first operation whose face the part does not have.
    pub fn check_faces(&self, face_count: usize) -> Result<(), String> {
        for (i, s) in self.setups.iter().enumerate() {
            if let Orientation::FaceOnTable { face, .. } = s.frame.orientation
                && face >= face_count
            {
                return Err(format!(
                    "setup {} ('{}'): face {} but the part has {face_count} faces",
                    i + 1,
                    s.name,
                    face + 1
                ));
            }
        }
        for (i, op) in self.operations.iter().enumerate() {
            // The face and every face of its group.
            if let Some(face) = op.faces().into_iter().find(|&f| f >= face_count) {
                return Err(format!(
                    "operation {} ('{}'): face {} but the part has {face_count} faces",
                    i + 1,
                    op.name(),
                    face + 1
                ));
            }
        }
        Ok(())
    }

    /// Read the project file at `path`.
    ///
    /// # Errors
    /// [`ProjectError`] naming the file (and the line and column for syntax errors).
    pub fn load(path: &Path) -> Result<Self, ProjectError> {
        Self::load_with_warnings(path).map(|(p, _)| p)
    }

    /// [`Project::load`] and the warnings of [`Project::from_toml_with_warnings`].
    ///
    /// # Errors
    /// As [`Project::load`].
    pub fn load_with_warnings(path: &Path) -> Result<(Self, Vec<String>), ProjectError> {
        let text = crate::storage::read_text_bounded(path, crate::storage::TEXT_LIMIT_BYTES)
            .map_err(|e| ProjectError::Io {
                path: path.to_path_buf(),
                message: format!("cannot read: {e}"),
            })?;
        Self::from_toml_with_warnings(&text, path)
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
