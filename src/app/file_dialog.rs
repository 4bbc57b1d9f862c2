//! The Open and Save dialogs: the native dialog (rfd, through the XDG desktop portal) on a
//! background [`Job`].
//! Where no portal answers, rfd returns "no file" at once; then the workstation shows its own
//! file chooser ([`super::file_chooser`]) instead.

use std::path::PathBuf;
use std::time::Duration;

use super::job::{Finished, Job, JobSlot};

/// The dialog's answer: the file, or `None` when it was cancelled or did not open.
type DialogJob<K> = JobSlot<Option<PathBuf>, K>;

/// A dialog that returns within this time without a file most likely never opened.
const NO_DIALOG_WITHIN: Duration = Duration::from_millis(250);
/// A dialog that has not answered by now may never appear (a portal that hangs): the chooser
/// opens beside it.
const OFFER_PATH_FIELD_AFTER: Duration = Duration::from_secs(2);

/// Can the system's dialogs (the XDG desktop portal, over the D-Bus session bus) answer at all?
/// Without a session bus rfd fails only after a delay that looks like a cancel, so the chooser
/// is used at once.
#[must_use]
pub fn portal_reachable() -> bool {
    std::env::var_os("DBUS_SESSION_BUS_ADDRESS").is_some()
        || std::env::var_os("XDG_RUNTIME_DIR")
            .is_some_and(|d| std::path::Path::new(&d).join("bus").exists())
}

/// State of the Open dialog.
#[derive(Debug, Default)]
pub struct OpenDialog {
    pending: DialogJob<()>,
    /// The native dialog failed to open before: go straight to the chooser.
    native_unavailable: bool,
}

/// What the dialog produced this frame.
#[derive(Debug, PartialEq, Eq)]
pub enum DialogOutcome {
    /// Nothing yet.
    Waiting,
    /// The user picked this file.
    Picked(PathBuf),
    /// The user cancelled.
    Cancelled,
    /// No dialog could be shown: choose the file another way.
    Unavailable,
}

impl OpenDialog {
    /// A dialog that never tries the native one (scripted runs, tests): the chooser is used.
    #[must_use]
    pub fn without_native() -> Self {
        Self {
            pending: JobSlot::default(),
            native_unavailable: true,
        }
    }

    /// Open the native dialog; false when it is known not to work (choose the file another
    /// way). `wake` is called from the dialog thread when it returns.
    pub fn open(
        &mut self,
        start_dir: Option<PathBuf>,
        wake: impl FnOnce() + Send + 'static,
    ) -> bool {
        if self.native_unavailable {
            return false;
        }
        if self.pending.is_running() {
            return true;
        }
        // A thread that cannot start ends the job without an answer at once: "unavailable".
        let job = Job::spawn(
            "Open dialog",
            move |_| {
                let mut dialog = rfd::FileDialog::new()
                    .set_title("Open part")
                    .add_filter(
                        "Parts and projects (STEP, STL, Talas)",
                        &["stp", "step", "STP", "STEP", "stl", "STL", "talas"],
                    )
                    .add_filter("All files", &["*"]);
                if let Some(dir) = start_dir {
                    dialog = dialog.set_directory(dir);
                }
                dialog.pick_file()
            },
            wake,
        );
        self.pending.start((), job);
        true
    }

    /// Is the native dialog open?
    #[must_use]
    pub fn is_waiting(&self) -> bool {
        self.pending.is_running()
    }

    /// Check whether the dialog has returned.
    pub fn poll(&mut self) -> DialogOutcome {
        let Some(elapsed_s) = self.pending.job().map(Job::elapsed_s) else {
            return DialogOutcome::Waiting;
        };
        let Some(done) = self.pending.poll() else {
            if elapsed_s > OFFER_PATH_FIELD_AFTER.as_secs_f64() && !self.native_unavailable {
                // The dialog may never appear (a portal that hangs). Keep listening, so a late
                // answer is still used, and offer the chooser now.
                self.native_unavailable = true;
                return DialogOutcome::Unavailable;
            }
            return DialogOutcome::Waiting;
        };
        match answer(&done) {
            Some(path) => DialogOutcome::Picked(path),
            None if done.elapsed_s < NO_DIALOG_WITHIN.as_secs_f64() => {
                self.native_unavailable = true;
                DialogOutcome::Unavailable
            }
            None => DialogOutcome::Cancelled,
        }
    }
}

/// The file a finished dialog job chose, if any.
fn answer<K>(done: &Finished<Option<PathBuf>, K>) -> Option<PathBuf> {
    done.result.clone().flatten()
}

/// A file type a dialog offers: its name and extensions (lower case; empty: every file).
pub type FileType = (&'static str, &'static [&'static str]);

/// What a save dialog is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SavePurpose {
    /// Save the project as.
    Project,
    /// A file a workstation feature writes: the chosen path goes back to that feature as
    /// [`Command::FeatureFile`](super::command::Command::FeatureFile).
    Feature(FeatureSave),
}

/// A feature's save dialog: which feature, the dialog's title and the file types offered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FeatureSave {
    /// The feature's id ([`super::feature::Feature::id`]); the chosen path goes to it.
    pub feature: &'static str,
    /// The dialog's title.
    pub title: &'static str,
    /// The file types offered, the default first (its first extension is added to a chosen
    /// name without one in the in-window chooser).
    pub types: &'static [FileType],
}

/// The native Save dialog on a worker thread (as [`OpenDialog`]); when no dialog answers, the
/// workstation shows its own file chooser instead.
#[derive(Debug, Default)]
pub struct SaveDialog {
    pending: DialogJob<SavePurpose>,
    native_unavailable: bool,
}

/// What the save dialog produced this frame.
#[derive(Debug, PartialEq, Eq)]
pub enum SaveOutcome {
    /// Nothing yet.
    Waiting,
    /// Save there.
    Picked(SavePurpose, PathBuf),
    /// The user cancelled.
    Cancelled,
    /// No dialog could be shown: ask for the path another way.
    Unavailable(SavePurpose),
}

impl SaveDialog {
    /// A dialog that never tries the native one (scripted runs, tests): the chooser is used.
    #[must_use]
    pub fn without_native() -> Self {
        Self {
            pending: JobSlot::default(),
            native_unavailable: true,
        }
    }

    /// Ask where to save for `purpose`, starting at `start` (a suggested file path).
    pub fn open(
        &mut self,
        purpose: SavePurpose,
        start: Option<PathBuf>,
        wake: impl FnOnce() + Send + 'static,
    ) -> SaveOutcome {
        if self.native_unavailable {
            return SaveOutcome::Unavailable(purpose);
        }
        if self.pending.is_running() {
            return SaveOutcome::Waiting;
        }
        // A thread that cannot start ends the job without an answer at once: "unavailable".
        let job = Job::spawn(
            "Save dialog",
            move |_| {
                let mut dialog = rfd::FileDialog::new();
                dialog = match purpose {
                    SavePurpose::Project => dialog
                        .set_title("Save project as")
                        .add_filter("Talas project", &["talas"]),
                    SavePurpose::Feature(f) => {
                        let every: &[&str] = &["*"];
                        f.types
                            .iter()
                            .fold(dialog.set_title(f.title), |d, &(name, ext)| {
                                d.add_filter(name, if ext.is_empty() { every } else { ext })
                            })
                    }
                };
                if let Some(start) = start {
                    if let Some(dir) = start.parent().filter(|d| d.is_dir()) {
                        dialog = dialog.set_directory(dir);
                    }
                    if let Some(name) = start.file_name() {
                        dialog = dialog.set_file_name(name.to_string_lossy());
                    }
                }
                dialog.save_file()
            },
            wake,
        );
        self.pending.start(purpose, job);
        SaveOutcome::Waiting
    }

    /// Is the native dialog open?
    #[must_use]
    pub fn is_waiting(&self) -> bool {
        self.pending.is_running()
    }

    /// Check whether the dialog has returned.
    pub fn poll(&mut self) -> SaveOutcome {
        let (Some(elapsed_s), Some(&purpose)) =
            (self.pending.job().map(Job::elapsed_s), self.pending.key())
        else {
            return SaveOutcome::Waiting;
        };
        let Some(done) = self.pending.poll() else {
            if elapsed_s > OFFER_PATH_FIELD_AFTER.as_secs_f64() && !self.native_unavailable {
                // The dialog may never appear: ask another way (a late answer is dropped).
                self.native_unavailable = true;
                self.pending = JobSlot::default();
                return SaveOutcome::Unavailable(purpose);
            }
            return SaveOutcome::Waiting;
        };
        match answer(&done) {
            Some(path) => SaveOutcome::Picked(purpose, path),
            None if done.elapsed_s < NO_DIALOG_WITHIN.as_secs_f64() => {
                self.native_unavailable = true;
                SaveOutcome::Unavailable(purpose)
            }
            None => SaveOutcome::Cancelled,
        }
    }
}
