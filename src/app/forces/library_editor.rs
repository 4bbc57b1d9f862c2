//! The coefficient library editor: one row per entry (material, tool, mode, model and its
//! coefficients with their units), each row checked as it is edited ([`Entry::coefficients`]:
//! the model's coefficients present and in range); Save writes the TOML file in the data
//! folder atomically (only when every entry is valid), Revert reads it again, Built-in puts
//! back the Al7075-T651 calibration.

use std::path::Path;

use crate::force::library::{Entry, Library};

/// The editor's state.
#[derive(Default)]
pub struct LibraryEditor {
    /// Whether the editor is shown.
    pub open: bool,
    /// The library being edited (read on first show).
    pub library: Option<Library>,
    /// The outcome of the last load or save (true: fine).
    pub message: Option<(bool, String)>,
}

/// The linear model's fields: key, label, unit.
const LINEAR: [(&str, &str, &str); 6] = [
    ("ktc", "K_tc", "N/mm²"),
    ("krc", "K_rc", "N/mm²"),
    ("kac", "K_ac", "N/mm²"),
    ("kte", "K_te", "N/mm"),
    ("kre", "K_re", "N/mm"),
    ("kae", "K_ae", "N/mm"),
];

/// The exponential model's fields.
const EXPONENTIAL: [(&str, &str, &str); 6] = [
    ("kt", "K_t", "N/mm²"),
    ("pt", "exp t", "–"),
    ("kr", "K_r", "–"),
    ("pr", "exp r", "–"),
    ("ka", "K_a", "–"),
    ("pa", "exp a", "–"),
];

fn field<'a>(e: &'a mut Entry, key: &str) -> Option<&'a mut Option<f64>> {
    Some(match key {
        "ktc" => &mut e.ktc_n_mm2,
        "krc" => &mut e.krc_n_mm2,
        "kac" => &mut e.kac_n_mm2,
        "kte" => &mut e.kte_n_mm,
        "kre" => &mut e.kre_n_mm,
        "kae" => &mut e.kae_n_mm,
        "kt" => &mut e.kt_n_mm2,
        "pt" => &mut e.kt_exponent,
        "kr" => &mut e.kr,
        "pr" => &mut e.kr_exponent,
        "ka" => &mut e.ka,
        "pa" => &mut e.ka_exponent,
        _ => return None,
    })
}

impl LibraryEditor {
    /// Read the library of `data_dir` (the built-in one when there is none).
    pub fn load(&mut self, data_dir: &Path) {
        match super::library_text(data_dir).and_then(|t| Library::parse(&t)) {
            Ok(lib) => {
                self.library = Some(lib);
                self.message = None;
            }
            Err(e) => {
                self.library = Library::parse(super::DEFAULT_COEFFICIENTS_TOML).ok();
                self.message = Some((false, format!("{e} (showing the built-in library)")));
            }
        }
    }

    /// Problems of the edited library, one per invalid entry (`entry K: ...`).
    #[must_use]
    pub fn problems(&self) -> Vec<String> {
        let Some(lib) = &self.library else {
            return Vec::new();
        };
        let mut out: Vec<String> = lib
            .entries
            .iter()
            .enumerate()
            .filter_map(|(i, e)| {
                e.coefficients()
                    .err()
                    .map(|m| format!("entry {}: {m}", i + 1))
            })
            .collect();
        if lib.entries.is_empty() {
            out.push("the library needs at least one entry".into());
        }
        out
    }

    /// Write the library to the data folder.
    ///
    /// # Errors
    /// The validation problems or the write error.
    pub fn save(&mut self, data_dir: &Path) -> Result<(), String> {
        let problems = self.problems();
        if let Some(p) = problems.first() {
            return Err(format!("not saved: {p}"));
        }
        let lib = self.library.as_ref().ok_or("nothing to save")?;
        let text = lib.to_toml()?;
        // What is written must read back.
        Library::parse(&text)?;
        let path = super::coefficients_path(data_dir);
        std::fs::create_dir_all(data_dir).map_err(|e| format!("{}: {e}", data_dir.display()))?;
        crate::storage::write_atomic(
            &path,
            format!("# Talas cutting-force coefficient library\n\n{text}").as_bytes(),
        )
        .map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Draw the editor.
    pub fn ui(&mut self, ui: &mut egui::Ui, data_dir: &Path) {
        if self.library.is_none() {
            self.load(data_dir);
        }
        ui.horizontal(|ui| {
            ui.label(
                egui::RichText::new("COEFFICIENT LIBRARY")
                    .small()
                    .strong()
                    .weak(),
            );
            ui.label(super::coefficients_path(data_dir).display().to_string());
        });
        let mut remove = None;
        if let Some(lib) = &mut self.library {
            egui::ScrollArea::vertical()
                .id_salt("force coefficient rows")
                .max_height(180.0)
                .show(ui, |ui| {
                    for (i, e) in lib.entries.iter_mut().enumerate() {
                        if entry_row(ui, i, e) {
                            remove = Some(i);
                        }
                    }
                });
            if let Some(i) = remove {
                lib.entries.remove(i);
            }
        }
        for p in self.problems() {
            ui.colored_label(ui.visuals().error_fg_color, p);
        }
        ui.horizontal(|ui| {
            if ui.button("Add entry").clicked()
                && let Some(lib) = &mut self.library
            {
                let copy = lib.entries.last().cloned();
                lib.entries.extend(copy);
            }
            if ui.button("Save").clicked() {
                self.message = Some(match self.save(data_dir) {
                    Ok(()) => (true, "Saved".into()),
                    Err(e) => (false, e),
                });
            }
            if ui.button("Revert").clicked() {
                self.load(data_dir);
            }
            if ui
                .button("Built-in")
                .on_hover_text("The Al7075-T651 calibration (Table 8.4)")
                .clicked()
            {
                self.library = Library::parse(super::DEFAULT_COEFFICIENTS_TOML).ok();
            }
            if let Some((ok, m)) = &self.message {
                let c = if *ok {
                    ui.visuals().text_color()
                } else {
                    ui.visuals().error_fg_color
                };
                ui.colored_label(c, m);
            }
        });
    }
}

/// One entry's row; true when its Remove button was clicked.
fn entry_row(ui: &mut egui::Ui, i: usize, e: &mut Entry) -> bool {
    let mut remove = false;
    ui.horizontal_wrapped(|ui| {
        ui.label(format!("{}.", i + 1));
        ui.add(egui::TextEdit::singleline(&mut e.material).desired_width(90.0))
            .on_hover_text("Work material");
        egui::ComboBox::from_id_salt(("coef mode", i))
            .width(60.0)
            .selected_text(e.mode.clone())
            .show_ui(ui, |ui| {
                for m in ["any", "up", "down", "slot"] {
                    ui.selectable_value(&mut e.mode, m.to_string(), m);
                }
            });
        egui::ComboBox::from_id_salt(("coef model", i))
            .width(90.0)
            .selected_text(e.model.clone())
            .show_ui(ui, |ui| {
                for m in ["linear", "exponential"] {
                    ui.selectable_value(&mut e.model, m.to_string(), m);
                }
            });
        let fields = if e.model == "exponential" {
            EXPONENTIAL
        } else {
            LINEAR
        };
        for (key, label, unit) in fields {
            let Some(slot) = field(e, key) else { continue };
            let mut v = slot.unwrap_or(0.0);
            ui.label(label);
            let r = ui.add(
                egui::DragValue::new(&mut v)
                    .speed(0.1)
                    .max_decimals(4)
                    .suffix(if unit == "–" {
                        String::new()
                    } else {
                        format!(" {unit}")
                    }),
            );
            if r.changed() {
                *slot = Some(v);
            }
        }
        if ui.small_button("Remove").clicked() {
            remove = true;
        }
    });
    remove
}
