//! The file chooser drawn inside the window (the `egui_file` crate's dialog), used wherever the
//! system's dialog is unavailable (no XDG desktop portal, or it never answers): folders to
//! browse, a file-type filter, and the recent files beside it.
//!
//! `egui_file` is used because it is kept in step with egui (0.29 depends on egui 0.37, the
//! version the workstation uses; `egui-file-dialog` 0.15 still depends on egui 0.36 and would
//! link two eguis). It has no filter list or recent files of its own: the side panel adds them
//! (a filter change rebuilds the dialog in the folder it shows).

use std::path::{Path, PathBuf};

use egui_file::FileDialog;

use super::command::Command;
pub use super::file_dialog::FileType;
use super::file_dialog::SavePurpose;
use crate::project::Edit;

/// What the chooser is asked for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ChooserPurpose {
    /// A part (STEP, STL) or a project to open.
    OpenPart,
    /// A project to open.
    OpenProject,
    /// A machine definition (JSON).
    MachineFile,
    /// Where to save (a project, the program, a feature's file).
    Save(SavePurpose),
    /// A file for a feature that uses the chosen path itself (the profile editor): its title,
    /// file types, and whether it is saved.
    Feature {
        /// The chooser's title.
        title: &'static str,
        /// The file types offered, the default first.
        types: &'static [FileType],
        /// A file to save (else one to open).
        save: bool,
    },
}

const PARTS_AND_PROJECTS: FileType = (
    "Parts and projects (STEP, STL, Talas)",
    &["stp", "step", "stl", "talas"],
);
const STEP: FileType = ("STEP (.stp, .step)", &["stp", "step"]);
const STL: FileType = ("STL (.stl)", &["stl"]);
const PROJECT: FileType = ("Talas project (.talas)", &["talas"]);
const MACHINE: FileType = ("Machine definition (.json)", &["json"]);
const ALL_FILES: FileType = ("All files", &[]);

impl ChooserPurpose {
    /// The file types offered, the default first.
    #[must_use]
    pub fn file_types(self) -> &'static [FileType] {
        match self {
            Self::OpenPart => &[PARTS_AND_PROJECTS, STEP, STL, PROJECT, ALL_FILES],
            Self::OpenProject => &[PROJECT, ALL_FILES],
            Self::MachineFile => &[MACHINE, ALL_FILES],
            Self::Save(SavePurpose::Project) => &[PROJECT],
            Self::Save(SavePurpose::Feature(f)) => f.types,
            Self::Feature { types, .. } => types,
        }
    }

    /// Is a file to be saved (else opened)?
    #[must_use]
    pub fn is_save(self) -> bool {
        matches!(self, Self::Save(_) | Self::Feature { save: true, .. })
    }

    fn title(self) -> &'static str {
        match self {
            Self::OpenPart => "Open part or project",
            Self::OpenProject => "Open project",
            Self::MachineFile => "Machine definition file",
            Self::Save(SavePurpose::Project) => "Save project as",
            Self::Save(SavePurpose::Feature(f)) => f.title,
            Self::Feature { title, .. } => title,
        }
    }

    /// The command that uses the chosen `path` (none for a [`Self::Feature`]: the feature
    /// takes the path itself).
    #[must_use]
    pub fn command(self, mut path: PathBuf) -> Option<Command> {
        Some(match self {
            Self::Feature { .. } => return None,
            Self::OpenPart => Command::Open(path),
            Self::OpenProject => Command::OpenProject(path),
            Self::MachineFile => Command::Edit(Edit::SetMachine(path.display().to_string())),
            Self::Save(SavePurpose::Project) => {
                if path.extension().is_none() {
                    path.set_extension(crate::project::file::EXTENSION);
                }
                Command::SaveProjectAs(path)
            }
            Self::Save(SavePurpose::Feature(f)) => {
                let default = f.types.first().and_then(|(_, e)| e.first());
                if let (None, Some(ext)) = (path.extension(), default) {
                    path.set_extension(ext);
                }
                Command::FeatureFile {
                    feature: f.feature,
                    path,
                }
            }
        })
    }
}

/// Does `path` have one of `extensions` (any file when there are none)?
#[must_use]
pub fn matches_type(path: &Path, extensions: &[&str]) -> bool {
    extensions.is_empty()
        || path.extension().is_some_and(|e| {
            let e = e.to_string_lossy().to_ascii_lowercase();
            extensions.contains(&e.as_str())
        })
}

/// The chooser while it is open.
pub struct FileChooser {
    purpose: ChooserPurpose,
    /// Index into the purpose's file types.
    file_type: usize,
    dialog: FileDialog,
    /// The recent files of the kinds the chooser is for.
    recent: Vec<PathBuf>,
}

/// The id of the chooser's window (its side panel is placed beside it).
const WINDOW_ID: &str = "talas file chooser";

impl FileChooser {
    /// A chooser for `purpose` showing `start` (a folder, or a file whose folder and name are
    /// used), with the `recent` files of the kinds it shows listed beside it.
    #[must_use]
    pub fn new(purpose: ChooserPurpose, start: Option<PathBuf>, recent: &[PathBuf]) -> Self {
        let mut chooser = Self {
            purpose,
            file_type: 0,
            dialog: FileDialog::open_file(),
            recent: recent.to_vec(),
        };
        chooser.dialog = chooser.build(start);
        chooser
    }

    /// What the chooser is for.
    #[must_use]
    pub fn purpose(&self) -> ChooserPurpose {
        self.purpose
    }

    /// The file type shown (name and extensions).
    #[must_use]
    pub fn file_type(&self) -> FileType {
        let types = self.purpose.file_types();
        types.get(self.file_type).copied().unwrap_or(ALL_FILES)
    }

    fn build(&self, start: Option<PathBuf>) -> FileDialog {
        let (_, extensions) = self.file_type();
        let filter = move |p: &Path| p.is_dir() || matches_type(p, extensions);
        let mut dialog = if self.purpose.is_save() {
            FileDialog::save_file()
        } else {
            FileDialog::open_file()
        }
        .title(self.purpose.title())
        .id(egui::Id::unique(WINDOW_ID))
        .default_size([620.0, 420.0])
        .anchor(egui::Align2::CENTER_CENTER, [110.0, 0.0])
        .show_rename(false)
        .show_new_folder(self.purpose.is_save())
        .show_files_filter(Box::new(filter));
        if let Some(start) = start {
            if start.is_dir() {
                dialog = dialog.initial_path(start);
            } else {
                if let Some(dir) = start.parent().filter(|d| d.is_dir()) {
                    dialog = dialog.initial_path(dir);
                }
                if let (true, Some(name)) = (self.purpose.is_save(), start.file_name()) {
                    dialog = dialog.default_filename(name.to_string_lossy());
                }
            }
        }
        dialog.open();
        dialog
    }

    /// Draw the chooser; `Some(path)` once a file is chosen, `Some(None)` when cancelled,
    /// `None` while it is open.
    pub fn ui(&mut self, ctx: &egui::Context) -> Option<Option<PathBuf>> {
        let mut chosen = None;
        let mut new_type = None;
        let beside = ctx
            .memory(|m| m.area_rect(egui::Id::unique(WINDOW_ID)))
            .map_or(egui::pos2(20.0, 80.0), |r| {
                r.left_top() - egui::vec2(232.0, 0.0)
            });
        egui::Window::new("Files")
            .id(egui::Id::unique("talas file chooser side"))
            .title_bar(false)
            .resizable(false)
            .fixed_pos(beside)
            .fixed_size([210.0, 400.0])
            .show(ctx, |ui| {
                ui.label(egui::RichText::new("File type").strong());
                for (i, (name, _)) in self.purpose.file_types().iter().enumerate() {
                    if ui.radio(self.file_type == i, *name).clicked() && self.file_type != i {
                        new_type = Some(i);
                    }
                }
                ui.separator();
                ui.label(egui::RichText::new("Recent files").strong());
                let (_, extensions) = self.file_type();
                let mut any = false;
                for path in self.recent.iter().filter(|p| matches_type(p, extensions)) {
                    any = true;
                    // "name · folder": the file and where it is (the full path on hover).
                    let part = |p: Option<&std::ffi::OsStr>| {
                        p.map_or_else(String::new, |n| n.to_string_lossy().into_owned())
                    };
                    let folder = part(path.parent().and_then(Path::file_name));
                    let name = format!("{} · {folder}", part(path.file_name()));
                    if ui
                        .selectable_label(false, name)
                        .on_hover_text(path.display().to_string())
                        .clicked()
                    {
                        chosen = Some(path.clone());
                    }
                }
                if !any {
                    ui.weak("None of this type yet");
                }
            });
        if let Some(i) = new_type {
            self.file_type = i;
            let folder = self.dialog.directory().to_path_buf();
            self.dialog = self.build(Some(folder));
        }
        if let Some(path) = chosen {
            return Some(Some(path));
        }
        self.dialog.show(ctx);
        match self.dialog.state() {
            egui_file::State::Selected => Some(self.dialog.path().map(Path::to_path_buf)),
            egui_file::State::Cancelled | egui_file::State::Closed => Some(None),
            egui_file::State::Open => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_types_filter_by_extension_in_any_case() {
        let (_, step) = STEP;
        assert!(matches_type(Path::new("/a/b.STP"), step));
        assert!(matches_type(Path::new("b.step"), step));
        assert!(!matches_type(Path::new("b.stl"), step));
        assert!(!matches_type(Path::new("noext"), step));
        assert!(matches_type(Path::new("noext"), ALL_FILES.1));
        let save = ChooserPurpose::Save(SavePurpose::Project);
        assert_eq!(
            save.command(PathBuf::from("/tmp/bracket")),
            Some(Command::SaveProjectAs(PathBuf::from("/tmp/bracket.talas")))
        );
        assert_eq!(
            ChooserPurpose::OpenPart.command(PathBuf::from("/p.stp")),
            Some(Command::Open(PathBuf::from("/p.stp")))
        );
    }

    #[test]
    fn a_feature_save_goes_back_to_the_feature_with_its_default_extension() {
        use crate::app::file_dialog::FeatureSave;
        let save = ChooserPurpose::Save(SavePurpose::Feature(FeatureSave {
            feature: "profile",
            title: "Export profile",
            types: &[("CSV (.csv)", &["csv", "txt"]), ALL_FILES],
        }));
        assert_eq!(save.title(), "Export profile");
        let names: Vec<_> = save.file_types().iter().map(|(n, _)| *n).collect();
        assert_eq!(names, ["CSV (.csv)", "All files"]);
        assert!(save.is_save());
        let chosen = |p: &str| Command::FeatureFile {
            feature: "profile",
            path: PathBuf::from(p),
        };
        assert_eq!(
            save.command(PathBuf::from("/tmp/a")),
            Some(chosen("/tmp/a.csv"))
        );
        assert_eq!(
            save.command(PathBuf::from("/tmp/a.dxf")),
            Some(chosen("/tmp/a.dxf"))
        );
    }
}
