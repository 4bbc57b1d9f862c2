//! The editor's side panel: the point table with a message under every bad row, the results
//! (path, largest gouge-free radius, accuracy, time), the list of flags (a click centres the
//! canvas on one) and the G-code settings.

use super::ProfileEditor;
use super::canvas::flag_colour;
use super::rows::{Level, Row};
use crate::app::number_field::{NumberField, format_number};
use crate::app::theme;
use crate::post::Dialect;
use crate::profile::{FlagKind, ProfilePlane, ProfileResult};

fn mm(v: f64) -> String {
    format!("{} mm", format_number(v, 4))
}

impl ProfileEditor {
    pub(super) fn panel_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading("Points");
        egui::ScrollArea::vertical()
            .id_salt("profile rows")
            .max_height(ui.available_height() * 0.45)
            .auto_shrink([false, true])
            .show(ui, |ui| self.table_ui(ui));
        ui.horizontal(|ui| {
            if ui.button("+ Row").clicked() {
                let next = self.rows.last().map_or(Row::default(), |r| Row {
                    bulge: String::new(),
                    ..r.clone()
                });
                self.rows.push(next);
                self.changed();
            }
            ui.weak("click the canvas to add, drag to move, right-click to delete");
        });
        if let Some(m) = &self.checked.profile_message {
            ui.colored_label(theme::WARNING, m);
        }
        ui.separator();
        egui::ScrollArea::vertical()
            .id_salt("profile results")
            .auto_shrink([false, false])
            .show(ui, |ui| {
                self.results_ui(ui);
                ui.separator();
                self.gcode_ui(ui);
            });
    }

    fn table_ui(&mut self, ui: &mut egui::Ui) {
        let mut edited = false;
        let mut delete = None;
        let cell = egui::vec2(82.0, 18.0);
        ui.horizontal(|ui| {
            ui.add_sized(
                [28.0, 18.0],
                egui::Label::new(egui::RichText::new("#").strong()),
            );
            for head in ["x (mm)", "y (mm)", "bulge"] {
                ui.add_sized(cell, egui::Label::new(egui::RichText::new(head).strong()));
            }
        });
        for i in 0..self.rows.len() {
            ui.horizontal(|ui| {
                let selected = self.selected_row == Some(i);
                let n = ui.add_sized(
                    [28.0, 18.0],
                    egui::Button::selectable(selected, format!("{}", i + 1)),
                );
                if n.clicked() {
                    self.selected_row = Some(i);
                }
                if let Some(row) = self.rows.get_mut(i) {
                    for (text, name) in [
                        (&mut row.x, "x"),
                        (&mut row.y, "y"),
                        (&mut row.bulge, "bulge"),
                    ] {
                        let r = ui
                            .add_sized(cell, egui::TextEdit::singleline(text))
                            .accessible_name(format!("{name}, row {}", i + 1));
                        edited |= r.changed();
                    }
                }
                if ui
                    .small_button("×")
                    .accessible_name(format!("delete row {}", i + 1))
                    .on_hover_text("Delete this row")
                    .clicked()
                {
                    delete = Some(i);
                }
            });
            self.row_notes_ui(ui, i);
        }
        if let Some(i) = delete {
            self.delete_row(i);
            edited = true;
        }
        if edited {
            self.changed();
        }
    }

    /// The messages of row `i` and, once computed, its flags, under the row.
    fn row_notes_ui(&self, ui: &mut egui::Ui, i: usize) {
        let mut notes: Vec<(egui::Color32, String)> = self
            .checked
            .row_messages(i)
            .map(|m| {
                let c = match m.level {
                    Level::Error => theme::ERROR,
                    Level::Warning => theme::WARNING,
                };
                (c, format!("row {}: {}", i + 1, m.text))
            })
            .collect();
        if self.is_current()
            && let Some(r) = self.result()
        {
            for f in r.flags.iter().filter(|f| f.point_index == i) {
                notes.push((
                    flag_colour(f.kind),
                    format!("{}: {} deep", kind_name(f.kind), mm(f.depth_mm)),
                ));
            }
        }
        for (colour, text) in notes {
            ui.horizontal(|ui| {
                ui.add_space(34.0);
                ui.add(egui::Label::new(egui::RichText::new(text).color(colour)).wrap());
            });
        }
    }

    fn results_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading("Electrode path");
        let Some(c) = &self.computed else {
            if self.checked.has_errors() {
                ui.colored_label(
                    theme::ERROR,
                    "Fix the rows marked in red: the path is computed from valid input only",
                );
            } else if self.is_computing() {
                ui.spinner();
            }
            return;
        };
        let r = match &c.outcome {
            Ok(r) => r,
            Err(e) => {
                ui.colored_label(theme::ERROR, format!("{}: {}", e.place, e.message));
                return;
            }
        };
        summary_ui(ui, r, c.elapsed_s, self.is_current());
        let mut pick = None;
        if !r.flags.is_empty() {
            ui.label(egui::RichText::new("Gouges of the per-point path (click to show)").strong());
        }
        for (k, f) in r.flags.iter().enumerate() {
            let text = format!(
                "{} at point {} (x {}, y {}): {} deep, span {}–{}",
                kind_name(f.kind),
                f.point_index + 1,
                mm(f.point.x),
                mm(f.point.y),
                mm(f.depth_mm),
                mm(f.span_mm.0),
                mm(f.span_mm.1)
            );
            let label = egui::RichText::new(text).color(flag_colour(f.kind));
            if ui
                .selectable_label(self.selected_flag == Some(k), label)
                .on_hover_text("Centre the canvas on this gouge")
                .clicked()
            {
                pick = Some(k);
            }
        }
        if let Some(k) = pick {
            self.pick_flag(k);
        }
    }

    fn gcode_ui(&mut self, ui: &mut egui::Ui) {
        ui.heading("G-code");
        egui::Grid::new("profile gcode")
            .num_columns(2)
            .show(ui, |ui| {
                ui.label("Dialect");
                egui::ComboBox::from_id_salt("profile dialect")
                    .selected_text(self.gcode.dialect.clone())
                    .show_ui(ui, |ui| {
                        for name in Dialect::builtin_names() {
                            ui.selectable_value(&mut self.gcode.dialect, name.to_string(), name);
                        }
                    });
                ui.end_row();
                ui.label("Plane");
                ui.horizontal(|ui| {
                    for (p, text) in [
                        (ProfilePlane::G17, "G17 (x on X, y on Y)"),
                        (ProfilePlane::G18, "G18 (x on X, y on Z)"),
                        (ProfilePlane::G19, "G19 (x on Y, y on Z)"),
                    ] {
                        ui.radio_value(&mut self.gcode.plane, p, text);
                    }
                });
                ui.end_row();
                let label = ui.label("Feed");
                NumberField::new("profile feed", &mut self.gcode.feed_mm_per_min)
                    .unit("mm/min")
                    .range(0.001..=100_000.0)
                    .labelled_by(label.id)
                    .show(ui);
                ui.end_row();
            });
    }
}

fn kind_name(k: FlagKind) -> &'static str {
    match k {
        FlagKind::Plunge => "Plunge",
        FlagKind::Collision => "Side collision",
    }
}

fn summary_ui(ui: &mut egui::Ui, r: &ProfileResult, elapsed_s: f64, current: bool) {
    let vertices: usize = r.paths.iter().map(|p| p.vertices.len()).sum();
    let length: f64 = r.paths.iter().map(crate::profile::ClPath::length_mm).sum();
    if r.paths.is_empty() {
        ui.colored_label(
            theme::ERROR,
            format!(
                "An electrode of R {} fits nowhere on the free side",
                mm(r.radius_mm)
            ),
        );
    } else {
        ui.label(format!(
            "Centre path: {vertices} vertices in {} piece(s), {} long",
            r.paths.len(),
            mm(length)
        ));
    }
    let gf = r.max_gouge_free_radius_mm;
    let colour = if r.radius_mm > gf {
        theme::WARNING
    } else {
        ui.visuals().text_color()
    };
    ui.colored_label(colour, format!("Largest gouge-free radius: {}", mm(gf)))
        .on_hover_text(
            "The largest electrode that touches every point of the profile from the free \
             side: the smallest concave radius (0 at a sharp concave corner) or half the \
             narrowest gap",
        );
    if r.max_radius_within_tolerance_mm > gf {
        ui.label(format!(
            "Largest radius within the gouge tolerance: {}",
            mm(r.max_radius_within_tolerance_mm)
        ))
        .on_hover_text(
            "The largest electrode whose gouge stays within the gouge tolerance at every \
             point: for a profile digitised as dense points, whose every concave kink is \
             sharp, the radius to choose",
        );
    }
    if let Some(s) = r.min_concave_radius_sampled_mm {
        ui.label(format!(
            "Smallest concave radius through 3 points: {}",
            mm(s)
        ));
    }
    let plunges = r
        .flags
        .iter()
        .filter(|f| f.kind == FlagKind::Plunge)
        .count();
    let collisions = r.flags.len() - plunges;
    ui.label(format!(
        "Per-point path: {plunges} plunge(s), {collisions} side collision(s)"
    ));
    ui.label(format!(
        "Largest |distance − R| of the path: {:.1e} mm",
        r.max_distance_error_mm
    ));
    let time = format!("Computed in {:.2} ms on a worker thread", elapsed_s * 1e3);
    if current {
        ui.weak(time);
    } else {
        ui.horizontal(|ui| {
            ui.spinner();
            ui.weak(format!("{time}; updating"));
        });
    }
}
