//! The open project: the document, its undo history, its file, autosave and crash recovery.
//! The workstation changes the document only through [`ProjectSession::edit`],
//! [`ProjectSession::undo`] and [`ProjectSession::redo`].
//!
//! Autosave writes the document (atomically) to a recovery file when it has unsaved changes:
//! `NAME.talas.autosave` beside a saved project, `untitled.talas.autosave` in the data folder for
//! a project never saved. Saving removes the recovery file; a recovery file newer than its project
//! at start means the last session ended with unsaved changes (a crash): the workstation offers
//! to recover it.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use super::document_loader::DEFAULT_PART_PATH;
use crate::project::{Edit, EditError, History, PartRef, PartStatus, Project, ProjectError};

/// Default autosave interval.
pub const AUTOSAVE_EVERY: Duration = Duration::from_secs(60);

/// The extension added to a project's path for its recovery file.
pub const RECOVERY_SUFFIX: &str = "autosave";

/// The project document with its history and file.
#[derive(Debug)]
pub struct ProjectSession {
    /// The document.
    pub project: Project,
    /// Undo/redo and the dirty flag.
    pub history: History,
    /// The file it was opened from or saved to.
    pub path: Option<PathBuf>,
    /// The folder of the recovery file of a project never saved.
    pub data_dir: PathBuf,
    /// How often a dirty project is written to its recovery file.
    pub autosave_every: Duration,
    last_autosave: Instant,
    /// Has the document changed since it was last written (saved or autosaved)?
    changed_since_autosave: bool,
}

impl ProjectSession {
    /// A new, clean, untitled project.
    #[must_use]
    pub fn new(project: Project, data_dir: PathBuf, autosave_every: Duration) -> Self {
        Self {
            project,
            history: History::new(),
            path: None,
            data_dir,
            autosave_every,
            last_autosave: Instant::now(),
            changed_since_autosave: false,
        }
    }

    /// Apply `edit` as an undoable step.
    ///
    /// # Errors
    /// Why the edit was refused (nothing changed).
    pub fn edit(&mut self, edit: Edit) -> Result<(), EditError> {
        if !self.history.is_dirty() {
            // The autosave interval counts from the first unsaved change.
            self.last_autosave = Instant::now();
        }
        self.history.apply(&mut self.project, edit)?;
        self.changed_since_autosave = true;
        Ok(())
    }

    /// Undo; the description of what was undone.
    pub fn undo(&mut self) -> Option<&'static str> {
        let label = self.history.undo(&mut self.project);
        self.changed_since_autosave |= label.is_some();
        label
    }

    /// Redo; the description of what was redone.
    pub fn redo(&mut self) -> Option<&'static str> {
        let label = self.history.redo(&mut self.project);
        self.changed_since_autosave |= label.is_some();
        label
    }

    /// Has the document unsaved changes?
    #[must_use]
    pub fn is_dirty(&self) -> bool {
        self.history.is_dirty()
    }

    /// Window title: project name, `*` when changed since the last save.
    #[must_use]
    pub fn title(&self) -> String {
        let star = if self.is_dirty() { "*" } else { "" };
        format!("{}{star} — Talas", self.project.name)
    }

    /// Read the project at `path` (the session is not changed; see [`ProjectSession::replace`]),
    /// with a warning for each key the file has that this build does not know (a newer Talas's
    /// setting or a typing error: it is ignored, and the warning names it and the file).
    ///
    /// # Errors
    /// The [`ProjectError`] naming the file and place.
    pub fn read(path: &Path) -> Result<(Project, Vec<String>), ProjectError> {
        Project::load_with_warnings(path)
    }

    /// Make `project`, read from `path`, the open project with a fresh history. `dirty` marks it
    /// as having unsaved changes (a recovered project).
    pub fn replace(&mut self, project: Project, path: Option<PathBuf>, dirty: bool) {
        self.project = project;
        self.history = History::new();
        if dirty {
            self.history.mark_unsaved();
        }
        self.path = path;
        self.last_autosave = Instant::now();
        self.changed_since_autosave = dirty;
    }

    /// A warning about the project's part (changed or missing on disk), if any.
    #[must_use]
    pub fn part_warning(&self) -> Option<String> {
        self.project.part.as_ref().and_then(|p| match p.status() {
            PartStatus::Unchanged => None,
            PartStatus::Changed => Some(format!(
                "{} has changed since the project was saved",
                p.path.display()
            )),
            PartStatus::Missing(why) => Some(format!("The project's part is missing: {why}")),
        })
    }

    /// Save to `path` (atomically), make it the project's file, and remove the recovery file.
    ///
    /// # Errors
    /// The [`ProjectError`]; the old file is unchanged then.
    pub fn save_as(&mut self, path: &Path) -> Result<(), ProjectError> {
        let old_recovery = self.recovery_path();
        self.project.save(path)?;
        self.path = Some(path.to_path_buf());
        self.history.mark_saved();
        self.changed_since_autosave = false;
        let _ = std::fs::remove_file(old_recovery);
        let _ = std::fs::remove_file(self.recovery_path());
        Ok(())
    }

    /// The edit that makes the document reference the part just loaded from `path`, when it
    /// references another file (the embedded default part is `None`).
    #[must_use]
    pub fn part_edit(&self, path: &Path) -> Option<Edit> {
        let current = self.project.part.as_ref().map(|p| p.path.as_path());
        let loaded = part_file(path);
        if current == loaded {
            return None;
        }
        let part = loaded.and_then(|p| PartRef::from_file(p).ok());
        Some(Edit::SetPart(part))
    }

    /// The recovery file of this project.
    #[must_use]
    pub fn recovery_path(&self) -> PathBuf {
        recovery_path(self.path.as_deref(), &self.data_dir)
    }

    /// Is an autosave due (unsaved changes not yet in the recovery file, and the interval has
    /// passed)?
    #[must_use]
    pub fn autosave_due(&self) -> bool {
        self.is_dirty()
            && self.changed_since_autosave
            && self.last_autosave.elapsed() >= self.autosave_every
    }

    /// Write the project to its recovery file now (atomically). Returns the file written.
    ///
    /// # Errors
    /// The [`ProjectError`] naming the recovery file.
    pub fn autosave(&mut self) -> Result<PathBuf, ProjectError> {
        self.last_autosave = Instant::now();
        let file = self.recovery_path();
        if let Some(dir) = file.parent() {
            let _ = std::fs::create_dir_all(dir);
        }
        self.project.save(&file)?;
        self.changed_since_autosave = false;
        Ok(file)
    }

    /// Remove the recovery file (its changes were discarded or saved).
    pub fn discard_recovery(&self) {
        let _ = std::fs::remove_file(self.recovery_path());
    }
}

/// The file a loaded part came from, as the project references it: `None` for the embedded
/// default part (or a path that is no file).
#[must_use]
pub fn part_file(path: &Path) -> Option<&Path> {
    (path != Path::new(DEFAULT_PART_PATH) && path.is_file()).then_some(path)
}

/// The recovery file of the project saved at `path` (or of an untitled project, in `data_dir`).
#[must_use]
pub fn recovery_path(path: Option<&Path>, data_dir: &Path) -> PathBuf {
    match path {
        Some(p) => {
            let mut name = p.as_os_str().to_owned();
            name.push(".");
            name.push(RECOVERY_SUFFIX);
            PathBuf::from(name)
        }
        None => data_dir.join(format!("untitled.talas.{RECOVERY_SUFFIX}")),
    }
}

/// The recovery file to offer for the project at `path` (or the untitled project): it exists and
/// is newer than the project file (or the project file is gone).
#[must_use]
pub fn pending_recovery(path: Option<&Path>, data_dir: &Path) -> Option<PathBuf> {
    let recovery = recovery_path(path, data_dir);
    let recovered = std::fs::metadata(&recovery)
        .and_then(|m| m.modified())
        .ok()?;
    match path.map(|p| std::fs::metadata(p).and_then(|m| m.modified())) {
        Some(Ok(saved)) if saved > recovered => None,
        _ => Some(recovery),
    }
}

/// The recovery file to offer at start, with the project it belongs to: the untitled
/// project's, else the first of the `recent` project files (`.talas`, newest first) that has a
/// pending one (a session killed with unsaved changes to a saved project leaves its recovery
/// file beside that project, which a plain restart would otherwise never look at).
#[must_use]
pub fn pending_recovery_at_start(
    recent: &[PathBuf],
    data_dir: &Path,
) -> Option<(PathBuf, Option<PathBuf>)> {
    if let Some(r) = pending_recovery(None, data_dir) {
        return Some((r, None));
    }
    recent
        .iter()
        .filter(|p| {
            p.extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("talas"))
        })
        .find_map(|p| pending_recovery(Some(p), data_dir).map(|r| (r, Some(p.clone()))))
}

/// The user's data folder for Talas: `$XDG_DATA_HOME/talas`, `~/.local/share/talas`, or the
/// temporary folder.
#[must_use]
pub fn default_data_dir() -> PathBuf {
    std::env::var_os("XDG_DATA_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".local/share")))
        .unwrap_or_else(std::env::temp_dir)
        .join("talas")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("talas-session-{}-{name}", std::process::id()));
        let _ = std::fs::create_dir_all(&d);
        d
    }

    #[test]
    fn autosave_and_recovery_follow_the_saved_file() {
        let dir = temp("recovery");
        let mut s = ProjectSession::new(Project::default(), dir.clone(), Duration::ZERO);
        assert!(!s.is_dirty() && !s.autosave_due());
        assert_eq!(pending_recovery(None, &dir), None);
        s.edit(Edit::Rename("Bracket".into())).expect("rename");
        assert!(s.title().starts_with("Bracket*"));
        assert!(s.autosave_due());
        let file = s.autosave().expect("autosaved");
        assert_eq!(file, dir.join("untitled.talas.autosave"));
        assert!(
            !s.autosave_due(),
            "nothing changed since the autosave: no second one"
        );
        assert_eq!(pending_recovery(None, &dir), Some(file.clone()));
        let recovered = Project::load(&file).expect("recovery file is a project");
        assert_eq!(recovered.name, "Bracket");

        let path = dir.join("bracket.talas");
        s.save_as(&path).expect("saved");
        assert!(!s.is_dirty() && !file.exists());
        assert_eq!(pending_recovery(Some(&path), &dir), None);
        s.edit(Edit::Rename("Bracket 2".into())).expect("rename");
        let file = s.autosave().expect("autosaved");
        assert_eq!(file, dir.join("bracket.talas.autosave"));
        // Written after the project: offered.
        assert_eq!(pending_recovery(Some(&path), &dir), Some(file.clone()));
        s.undo();
        assert!(!s.is_dirty(), "undo back to the saved state is clean");
        s.save_as(&path).expect("saved");
        assert_eq!(pending_recovery(Some(&path), &dir), None);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
