//! Import and export of the editor's profile (CSV, DXF, SVG through the engine's readers and
//! writers) and of the path's G-code (through a post dialect), with the in-window file chooser.

use std::path::{Path, PathBuf};

use super::rows::{Row, check_rows};
use super::{FileAction, ProfileEditor};
use crate::app::file_chooser::{ChooserPurpose, FileChooser, FileType};
use crate::post::Dialect;
use crate::profile::{GcodeOptions, read_profile, write_gcode, write_profile};

const PROFILES: FileType = (
    "Profiles (CSV, DXF, SVG)",
    &["csv", "txt", "xy", "dxf", "svg"],
);
const CSV: FileType = ("CSV (.csv)", &["csv"]);
const DXF: FileType = ("DXF (.dxf)", &["dxf"]);
const SVG: FileType = ("SVG (.svg)", &["svg"]);
const GCODE: FileType = (
    "G-code (.ngc, .nc, .tap, .mpf, .h, .gcode)",
    &["ngc", "nc", "tap", "mpf", "h", "gcode"],
);
const ALL: FileType = ("All files", &[]);

/// Chord tolerance for flattening SVG curves on import, mm.
const SVG_TOLERANCE_MM: f64 = 1e-3;

impl FileAction {
    fn purpose(self) -> ChooserPurpose {
        match self {
            Self::Import => ChooserPurpose::Feature {
                title: "Import profile",
                types: &[PROFILES, CSV, DXF, SVG, ALL],
                save: false,
            },
            Self::ExportProfile => ChooserPurpose::Feature {
                title: "Export profile (CSV, DXF or SVG by extension)",
                types: &[PROFILES, CSV, DXF, SVG],
                save: true,
            },
            Self::ExportGcode => ChooserPurpose::Feature {
                title: "Export electrode path G-code",
                types: &[GCODE, ALL],
                save: true,
            },
        }
    }
}

impl ProfileEditor {
    /// Open the file chooser for `action`, in the folder of the last profile file.
    pub(super) fn choose(&mut self, action: FileAction) {
        let start = self
            .file
            .clone()
            .or_else(|| std::env::current_dir().ok())
            .map(|p| match action {
                FileAction::ExportGcode => p.with_extension("ngc"),
                FileAction::ExportProfile if p.is_dir() => p.join("profile.csv"),
                _ => p,
            });
        self.chooser = Some((action, FileChooser::new(action.purpose(), start, &[])));
    }

    /// Draw the chooser while it is open and act on the chosen file.
    pub(super) fn files_ui(&mut self, ctx: &egui::Context) {
        let Some((action, chooser)) = &mut self.chooser else {
            return;
        };
        let action = *action;
        let Some(outcome) = chooser.ui(ctx) else {
            return;
        };
        self.chooser = None;
        let Some(path) = outcome else { return };
        let done = match action {
            FileAction::Import => self.import_from(&path),
            FileAction::ExportProfile => self.export_profile_to(&with_default_ext(path, "csv")),
            FileAction::ExportGcode => self.export_gcode_to(&with_default_ext(path, "ngc")),
        };
        self.note = Some(done);
    }

    /// Read a profile file into the table; the rule y = f(x) is turned off when the profile
    /// breaks it. Returns what was read, or the reader's error (file and place).
    ///
    /// # Errors
    /// The reader's one-line error.
    pub fn import_from(&mut self, path: &Path) -> Result<String, String> {
        let profile = read_profile(path, SVG_TOLERANCE_MM).map_err(|e| e.to_string())?;
        let rows: Vec<Row> = profile.vertices.iter().map(Row::from_vertex).collect();
        self.closed = profile.closed;
        self.function_rule = !profile.closed && !check_rows(&rows, false, true).has_errors();
        self.file = Some(path.to_path_buf());
        self.set_rows(rows);
        let text = format!(
            "Read {} points ({}) from {}{}",
            profile.vertices.len(),
            if profile.closed { "closed" } else { "open" },
            path.display(),
            if self.function_rule {
                ""
            } else {
                "; the rule y = f(x) is off (the profile is not a function of x)"
            }
        );
        Ok(text)
    }

    /// Write the table's profile (format by extension).
    ///
    /// # Errors
    /// Rows with errors, or the writer's error.
    pub fn export_profile_to(&mut self, path: &Path) -> Result<String, String> {
        let Some(p) = &self.checked.profile else {
            return Err("The table has errors: fix the rows marked in red first".into());
        };
        write_profile(p, path).map_err(|e| e.to_string())?;
        self.file = Some(path.to_path_buf());
        Ok(format!(
            "Wrote {} points to {}",
            p.vertices.len(),
            path.display()
        ))
    }

    /// Write the computed path as G-code through the chosen dialect, plane and feed.
    ///
    /// # Errors
    /// No current path, an unknown dialect, or the file cannot be written.
    pub fn export_gcode_to(&mut self, path: &Path) -> Result<String, String> {
        let result = match (&self.computed, self.is_current()) {
            (Some(c), true) => c.outcome.as_ref().map_err(ToString::to_string)?,
            _ => return Err("No path computed for the table as it is".into()),
        };
        if result.paths.is_empty() {
            return Err(format!(
                "No path: an electrode of R {} mm fits nowhere on the free side",
                result.radius_mm
            ));
        }
        let dialect = Dialect::resolve(&self.gcode.dialect).map_err(|e| e.to_string())?;
        let program_name = path
            .file_stem()
            .map(|s| {
                s.to_string_lossy()
                    .chars()
                    .filter(|c| c.is_ascii_alphanumeric() || *c == '_' || *c == '-')
                    .take(32)
                    .collect::<String>()
            })
            .filter(|s| !s.is_empty())
            .unwrap_or_else(|| "PROFILE".into());
        let opts = GcodeOptions {
            plane: self.gcode.plane,
            feed_mm_per_min: self.gcode.feed_mm_per_min,
            radius_mm: result.radius_mm,
            program_name,
            ..GcodeOptions::default()
        };
        let text = write_gcode(&result.paths, &dialect, &opts).map_err(|e| e.to_string())?;
        crate::storage::write_atomic(path, text.as_bytes())
            .map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(format!(
            "Wrote {} lines of {} G-code ({}) to {}",
            text.lines().count(),
            dialect.name,
            self.gcode.plane.code(),
            path.display()
        ))
    }
}

fn with_default_ext(mut path: PathBuf, ext: &str) -> PathBuf {
    if path.extension().is_none() {
        path.set_extension(ext);
    }
    path
}
